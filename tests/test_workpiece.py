"""The in-process workpiece: its two bounds hold the true material between them, checked
against an independent brute-force sweep and exact volumes; rapids are judged from them."""
from __future__ import annotations

import json
import math
import platform
import resource
import tempfile
from pathlib import Path
from unittest.mock import patch

import numpy
import pytest
import shapely
from hypothesis import assume, example, given, settings, strategies as st

from ncverify.context import Stock
from ncverify.workpiece import NO_MATERIAL, Cutter, ModelTooLarge, Workpiece, distance_to_segment

BLANK = Stock.box((0, 40), (0, 30), (-10, 0))


def true_top(points, moves, cutter: Cutter, top: float, samples: int = 4001):
    """Material top at points (x, y), by sampling each move densely: the tool's lower
    surface over every point it passes within reach of (written apart from the model)."""
    points = numpy.asarray(points, float)
    heights = numpy.full(len(points), top, float)
    t = numpy.linspace(0.0, 1.0, samples)
    for start, end in moves:
        path = numpy.asarray(start, float) + t[:, None] * (numpy.asarray(end, float) - numpy.asarray(start, float))
        distance = numpy.hypot(points[:, :1] - path[None, :, 0], points[:, 1:2] - path[None, :, 1])
        surface = numpy.where(distance <= cutter.radius, path[None, :, 2] + _lift(cutter, distance), numpy.inf)
        heights = numpy.minimum(heights, surface.min(axis=1))
    return heights


def _lift(cutter: Cutter, distance):
    if not cutter.known:
        return _lift(Cutter(cutter.radius, corner=cutter.corner, point_angle=cutter.point_angle), distance)
    if cutter.point_angle:
        return distance / math.tan(math.radians(cutter.point_angle) / 2)
    flat = cutter.radius - cutter.corner
    if cutter.corner <= 0:
        return numpy.zeros_like(distance)
    return numpy.where(distance <= flat, 0.0, cutter.corner - numpy.sqrt(numpy.clip(cutter.corner ** 2 - (distance - flat) ** 2, 0, None)))


cutters = st.one_of(
    st.builds(Cutter, st.floats(1.0, 6.0)),
    st.floats(1.0, 6.0).map(lambda r: Cutter(r, corner=r)),
    st.tuples(st.floats(2.0, 6.0), st.floats(0.2, 0.9)).map(lambda rc: Cutter(rc[0], corner=rc[0] * rc[1])),
    st.tuples(st.floats(1.0, 5.0), st.sampled_from([90.0, 118.0, 140.0])).map(lambda ra: Cutter(ra[0], point_angle=ra[1])),
    # a tool whose shape was not given, and which really is one of the shapes it allows
    st.tuples(st.floats(1.0, 6.0), st.sampled_from([0.0, 0.5, 1.0]), st.sampled_from([None, 90.0, 118.0]))
    .map(lambda shape: Cutter(shape[0], corner=shape[0] * shape[1] if shape[2] is None else 0.0, point_angle=shape[2], known=False)),
)
points = st.tuples(st.floats(-5, 45), st.floats(-5, 35), st.floats(-8, 3))


@settings(max_examples=40, deadline=None)
@given(cutters, st.lists(st.tuples(points, points), min_size=1, max_size=4), st.sampled_from([0.5, 1.0]))
def test_the_bounds_hold_the_material_sampled_by_brute_force(cutter, moves, resolution):
    piece = Workpiece(BLANK, resolution)
    for start, end in moves:
        piece.cut([start], [end], cutter)
    rng = numpy.random.default_rng(7)
    sample = numpy.column_stack([rng.uniform(0, 40, 300), rng.uniform(0, 30, 300)])
    tops = true_top(sample, moves, cutter, 0.0)
    rows = numpy.minimum((sample[:, 1] / resolution).astype(int), piece.ny - 1)
    columns = numpy.minimum((sample[:, 0] / resolution).astype(int), piece.nx - 1)
    present = tops > -10.0
    tolerance = 0.02  # the sampled sweep misses the true minimum by up to a sample step's rise
    assert (piece.upper[rows, columns][present] >= tops[present] - tolerance).all()
    assert (piece.lower[rows, columns][present] <= tops[present] + tolerance).all()


@settings(max_examples=25, deadline=None)
@given(cutters, st.lists(st.tuples(points, points), min_size=2, max_size=5), st.randoms(use_true_random=False))
def test_the_order_of_the_cuts_does_not_change_the_result(cutter, moves, random):
    forward, shuffled = Workpiece(BLANK, 0.5), Workpiece(BLANK, 0.5)
    for start, end in moves:
        forward.cut([start], [end], cutter)
    moves = list(moves)
    random.shuffle(moves)
    for start, end in moves:
        shuffled.cut([start], [end], cutter)
    assert numpy.array_equal(forward.upper, shuffled.upper) and numpy.array_equal(forward.lower, shuffled.lower)


@pytest.mark.parametrize("resolution", [0.5, 0.25, 0.1])
def test_a_slot_removes_its_exact_volume_within_the_resolution(resolution):
    piece = Workpiece(BLANK, resolution)
    piece.cut([[10, 15, -4]], [[30, 15, -4]], Cutter(3.0))
    least, most = piece.removed_volume()
    exact = (2 * 3.0 * 20 + math.pi * 9) * 4
    assert least <= exact <= most
    assert most - least <= (2 * 20 + 2 * math.pi * 3) * 4 * 4 * resolution  # a band of a few cells along the outline


@pytest.mark.parametrize("cutter", [Cutter(3.0), Cutter(3.0, corner=3.0), Cutter(3.0, point_angle=118.0)])
def test_a_plunge_far_past_the_blank_cuts_and_meets_as_one_just_past_it(cutter):
    """A plunge to Z-1e8 (a typo a fuzzer found) is laid on the slab around the blank: the
    same field as a plunge well below the bottom, not a hundred million cell-high steps."""
    far, near = Workpiece(BLANK, 0.5), Workpiece(BLANK, 0.5)
    far.cut([[20, 15, 50]], [[20, 15, -1e8]], cutter)
    near.cut([[20, 15, 50]], [[20, 15, BLANK.z_range[0] - 10.0]], cutter)
    assert numpy.array_equal(far.upper, near.upper) and numpy.array_equal(far.lower, near.lower)
    assert Workpiece(BLANK, 0.5).rapid((25, 15, 50), (25, 15, -1e8), cutter).outcome == "hits"


def test_a_drilled_hole_removes_a_cylinder_and_its_cone():
    piece = Workpiece(BLANK, 0.1)
    drill = Cutter(4.0, point_angle=118.0)
    piece.cut([[20, 15, 2]], [[20, 15, -6]], drill)
    cone = 4.0 / math.tan(math.radians(59))
    exact = math.pi * 16 * (6 - cone) + math.pi * 16 * cone / 3
    least, most = piece.removed_volume()
    assert least <= exact <= most and most - least < 0.3 * exact  # the rim band and the cone's slope across a cell


def test_many_tiny_moves_remove_what_one_long_move_removes():
    """CAM output's tiny collinear moves are merged into chords: same material either way."""
    one, many = Workpiece(BLANK, 0.5), Workpiece(BLANK, 0.5)
    one.cut([[5, 15, -3]], [[35, 15, -3]], Cutter(4.0))
    x = numpy.linspace(5, 35, 601)
    path = numpy.column_stack([x, numpy.full_like(x, 15), numpy.full_like(x, -3)])
    many.cut(path[:-1], path[1:], Cutter(4.0))
    assert numpy.array_equal(one.upper, many.upper) and numpy.array_equal(one.lower, many.lower)


def test_rapids_in_the_cut_slot_are_clear_and_into_uncut_material_hit():
    piece = Workpiece(BLANK, 0.25)
    piece.cut([[10, 15, -4]], [[30, 15, -4]], Cutter(5.0))
    small = Cutter(2.0)
    assert piece.rapid((12, 15, -3), (28, 15, -3), small).outcome == "clear"
    hit = piece.rapid((20, 15, -3), (20, 28, -3), small)
    assert hit.outcome == "hits" and hit.point[1] > 20 - 0.25
    assert piece.rapid((20, 15, 1), (20, 28, 1), small).outcome == "clear"  # above the top
    # the cutter itself retracing the slot at its walls: within the grid's error, never a pass
    assert piece.rapid((12, 15, -3), (28, 15, -3), Cutter(5.0)).outcome == "unsure"


def test_a_cut_that_cannot_be_placed_makes_hits_unsure_but_keeps_clear_answers():
    piece = Workpiece(BLANK, 0.5)
    piece.cut_anywhere()
    assert piece.rapid((20, 15, -3), (20, 28, -3), Cutter(2.0)).outcome == "unsure"
    assert piece.rapid((20, 15, 1), (20, 28, 1), Cutter(2.0)).outcome == "clear"


def test_cuts_placed_between_unplaced_ones_still_clear_what_they_cover_and_no_hit_becomes_sure():
    """The lower bound is emptied once, by the first unplaced cut: later ones have nothing
    left to empty, whatever placed cuts came between."""
    piece = Workpiece(BLANK, 0.5)
    piece.cut_anywhere()
    piece.cut([[5, 15, -4]], [[35, 15, -4]], Cutter(3.0))
    piece.cut_anywhere()
    assert (piece.lower == NO_MATERIAL).all() and piece.cuts == 3
    assert piece.rapid((10, 15, -2), (30, 15, -2), Cutter(1.0)).outcome == "clear"  # inside the slot, placed
    assert piece.rapid((20, 5, -3), (20, 8, -3), Cutter(1.0)).outcome == "unsure"  # beside it: may be gone, may not


def test_a_polygon_blank_keeps_material_only_inside_its_outline():
    triangle = Stock.polygon([(0, 0), (40, 0), (0, 30)], (-10, 0))
    piece = Workpiece(triangle, 0.5)
    assert piece.rapid((35, 25, -2), (39, 29, -2), Cutter(1.0)).outcome == "clear"
    assert piece.rapid((5, 5, -2), (10, 5, -2), Cutter(1.0)).outcome == "hits"


def test_a_model_over_the_memory_cap_is_refused_with_its_size():
    with pytest.raises(ModelTooLarge, match="MiB"):
        Workpiece(Stock.box((0, 500), (0, 500), (-10, 0)), 0.01, memory_cap=64 << 20)


def test_a_500mm_blank_at_a_tenth_fits_in_200_mib():
    piece = Workpiece(Stock.box((0, 500), (0, 500), (-10, 0)), 0.1)
    assert piece.upper.nbytes + piece.lower.nbytes <= 200 * 2 ** 20


def test_moves_above_the_material_count_as_air_and_cutting_ones_do_not():
    piece = Workpiece(BLANK, 0.5)
    assert piece.cut([[5, 5, 2]], [[35, 5, 2]], Cutter(3.0)) == pytest.approx(30.0)
    assert piece.cut([[5, 15, -2]], [[35, 15, -2]], Cutter(3.0)) == 0.0
    assert piece.cut([[5, 15, -2]], [[35, 15, -2]], Cutter(2.0)) == pytest.approx(30.0)  # the same slot again, narrower


def test_the_stl_encloses_the_volume_of_the_upper_bound(tmp_path):
    piece = Workpiece(BLANK, 0.5)
    piece.cut([[10, 15, 1]], [[10, 15, -6]], Cutter(3.0, point_angle=118.0))
    piece.cut([[20, 5, -3]], [[30, 25, -3]], Cutter(4.0, corner=1.0))
    piece.save_stl(tmp_path / "part.stl")
    raw = (tmp_path / "part.stl").read_bytes()
    count = int(numpy.frombuffer(raw[80:84], numpy.uint32)[0])
    record = numpy.frombuffer(raw[84:], dtype=[("normal", "<f4", 3), ("corners", "<f4", (3, 3)), ("attribute", "<u2")], count=count)
    a, b, c = (record["corners"][:, k].astype(float) for k in range(3))
    enclosed = numpy.einsum("ij,ij->i", a, numpy.cross(b, c)).sum() / 6.0
    heights = numpy.where(numpy.isfinite(piece.upper), piece.upper, piece.bottom) - piece.bottom
    assert enclosed == pytest.approx(heights.sum() * 0.25, rel=1e-4)
    piece.save_npz(tmp_path / "part.npz")
    assert numpy.array_equal(numpy.load(tmp_path / "part.npz")["upper"], piece.upper)


def test_a_copy_is_cut_on_its_own():
    piece = Workpiece(BLANK, 0.5)
    twin = piece.copy()
    twin.cut([[5, 15, -2]], [[35, 15, -2]], Cutter(3.0))
    assert piece.rapid((5, 15, -1), (35, 15, -1), Cutter(1.0)).outcome == "hits"
    assert twin.rapid((5, 15, -1), (35, 15, -1), Cutter(1.0)).outcome == "clear"


BAR = Stock.cylinder(40.0, (-60.0, 0.0))  # radius 20


def test_a_turned_diameter_is_clear_for_a_rapid_along_it_and_the_bar_beyond_is_hit():
    from ncverify.workpiece import Bar

    bar = Bar(BAR)
    nose, centre = 0.8, (0.8, 0.8)  # edge position 3: the nose centre up and behind the tip
    for radius in (19.0, 18.0, 17.0, 16.0):  # rough the bar down to radius 16 over 30 mm
        bar.cut((radius, 1.0), (radius, -30.0), nose, centre)
    assert bar.rapid((18.0, 2.0), (18.0, -20.0), nose, centre).outcome == "clear"
    assert bar.rapid((16.5, -20.0), (16.5, -31.0), nose, centre).outcome == "unsure"  # into the shoulder's fillet left by the nose
    assert bar.rapid((25.0, 2.0), (25.0, -50.0), nose, centre).outcome == "clear"
    hit = bar.rapid((18.0, -40.0), (18.0, -45.0), nose, centre)
    assert hit.outcome == "hits" and 16.0 < hit.point[0] < 20.0


def test_without_the_edge_position_nothing_is_surely_turned_away():
    from ncverify.workpiece import Bar

    bar = Bar(BAR)
    bar.cut((16.0, 1.0), (16.0, -30.0), 0.8)
    assert bar.rapid((17.0, -5.0), (17.0, -25.0), 0.4, (0.4, 0.4)).outcome != "clear"
    # 2 mm deep in the uncut bar: wherever the edge position puts the nose, its centre is in the material
    assert bar.rapid((18.0, -40.0), (18.0, -45.0), 0.8).outcome == "hits"
    assert bar.rapid((19.5, -40.0), (19.5, -45.0), 0.8).outcome == "unsure"  # 0.5 mm: the nose may lie outside the bar


@settings(max_examples=30, deadline=None)
@given(st.floats(2, 12), st.floats(0, 6.28), st.floats(0.1, 6.28), st.booleans(), cutters)
def test_an_arc_cut_as_chords_keeps_the_bounds_around_the_true_arc(radius, begin, sweep, clockwise, cutter):
    from ncverify.workpiece import arc_chords

    centre = (20.0, 15.0)
    direction = -1 if clockwise else 1
    start = (centre[0] + radius * math.cos(begin), centre[1] + radius * math.sin(begin), -2.0)
    finish_angle = begin + direction * sweep
    end = (centre[0] + radius * math.cos(finish_angle), centre[1] + radius * math.sin(finish_angle), -3.0)
    starts, ends, sagitta, _ = arc_chords([start], [end], [centre], [clockwise], [(0, 1, 2)], tolerance=0.05)
    assert (sagitta <= 0.05 + 1e-12).all()
    piece = Workpiece(BLANK, 0.5)
    piece.cut(starts, ends, cutter, stray=sagitta)
    angles = begin + direction * sweep * numpy.linspace(0, 1, 400)
    dense = numpy.column_stack([centre[0] + radius * numpy.cos(angles), centre[1] + radius * numpy.sin(angles), numpy.linspace(-2, -3, 400)])
    moves = list(zip(dense[:-1], dense[1:]))
    rng = numpy.random.default_rng(3)
    sample = numpy.column_stack([rng.uniform(0, 40, 200), rng.uniform(0, 30, 200)])
    tops = true_top(sample, moves, cutter, 0.0, samples=50)
    rows, columns = (sample[:, 1] / 0.5).astype(int), (sample[:, 0] / 0.5).astype(int)
    assert (piece.upper[rows, columns] >= tops - 0.02).all()
    assert (piece.lower[rows, columns] <= tops + 0.02).all()


_ARC = st.tuples(st.floats(0.01, 50), st.floats(-7, 7), st.floats(-7, 7), st.booleans(), st.floats(-5, 5),
                 st.sampled_from([(0, 1, 2), (2, 0, 1), (1, 2, 0)]))  # radius, start and end angles, cw, rise, G17/G18/G19


@settings(max_examples=60, deadline=None)
@given(st.lists(_ARC, min_size=1, max_size=8))
def test_many_arcs_are_cut_into_the_chords_each_gives_alone_and_every_chord_point_is_on_its_arc(arcs):
    """The material model cuts every buffered arc's chords at once: arc ``k``'s chords are
    the ones it gives alone, each within the tolerance of the true arc (full circles too:
    an arc that ends where it starts turns once)."""
    from ncverify.workpiece import arc_chords

    rows = []
    for radius, begin, finish, clockwise, rise, plane in arcs:
        start, end, centre = numpy.zeros(3), numpy.zeros(3), (3.0, -2.0)
        for point, angle, height in ((start, begin, 1.0), (end, finish, 1.0 + rise)):
            point[plane[0]], point[plane[1]], point[plane[2]] = centre[0] + radius * math.cos(angle), centre[1] + radius * math.sin(angle), height
        rows.append((start, end, centre, clockwise, plane))
    together = arc_chords(*[[row[field] for row in rows] for field in range(5)], tolerance=0.05)
    for index, row in enumerate(rows):
        alone = arc_chords(*[[field] for field in row], tolerance=0.05)
        mine = together[3] == index
        for part in range(3):
            numpy.testing.assert_array_equal(together[part][mine], alone[part])
        start, end, centre, _, plane = row
        assert numpy.allclose(alone[0][0], start) and numpy.array_equal(alone[1][-1], end)
        points = numpy.vstack([alone[0], alone[1][-1:]])
        radius = math.hypot(start[plane[0]] - centre[0], start[plane[1]] - centre[1])
        assert numpy.allclose(numpy.hypot(points[:, plane[0]] - centre[0], points[:, plane[1]] - centre[1]), radius, atol=1e-9)
        assert (alone[2] <= 0.05 + 1e-12).all()
        assert numpy.allclose(alone[1][:-1], alone[0][1:])  # joined, start to end


def test_a_rapid_of_a_tool_of_unknown_size_is_never_shown_clear_beside_its_axis():
    """Without a radius the tool is only its axis: that can show a crash, but not that the
    tool's side misses the material, even along the line the same axis just cut."""
    from ncverify import Settings, check_text
    from ncverify.diagnostics import Status

    program = ("(ncverify: stock box X0:100 Y0:60 Z-20:0)\nG21 G90 G17 G54\nT1 M06\nG43 H01 Z50.\nS6000 M03\nG00 X10. Y30.\n"
               "Z2.\nG01 Z-2. F200.\nX90. F400.\nG00 Z-1.\nX10.\nG00 Z50.\nM30\n")
    result = check_text(program, "t.nc", Settings(stock_resolution=None))
    along = [d for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.span.line == 11]
    assert [d.status for d in along] == [Status.UNKNOWN]
    assert not [d for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.span.line == 10]  # straight up its own axis


def test_a_circle_ending_on_its_start_s_ray_off_the_circle_cuts_nowhere_sure():
    """G2 from X62 Y66 about X50 Y50 to X62.0024 Y66.0032: the end lies on the start's own
    ray, 0.004 mm off the circle, so whether the arc turns once or not at all is a matter of
    rounding (here the arc tangents make it a full turn). A smaller tool's rapid down where
    the full turn would have cut is then neither clear (as it was when the model took the
    full turn) nor a crash: unknown."""
    from ncverify import Settings, check_text
    from ncverify.diagnostics import Status
    from ncverify.workpiece import unsettled_turns

    program = ("(ncverify: stock box X0:100 Y0:100 Z-20:0)\n(ncverify: tool 1 radius 3 type endmill)\n(ncverify: tool 2 radius 1 type endmill)\n"
               "G21 G90 G17 G54\nT1 M06\nG43 H01 Z50.\nS6000 M03\nG00 X62. Y66.\nZ2.\nG01 Z-5. F200.\nG02 X62.0024 Y66.0032 I-12. J-16.\n"
               "G00 Z50.\nT2 M06\nG43 H02 Z50.\nX38. Y34.\nG00 Z-4.\nG00 Z50.\nM30\n")
    result = check_text(program, "t.nc", Settings())
    down = [d for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.span.line == 16]
    assert [d.status for d in down] == [Status.UNKNOWN]
    starts, ends = numpy.array([[62.0, 66.0, -5.0]] * 3), numpy.array([[62.0024, 66.0032, -5.0], [62.0, 66.0, -5.0], [38.0, 34.0, -5.0]])
    assert unsettled_turns(starts, ends, numpy.array([[50.0, 50.0]] * 3), numpy.array([[0, 1, 2]] * 3)).tolist() == [True, False, False]


# --------------------------------------------------------------------------- the turned bar

def _centre_distance(points, moves, offset):
    """Distance of (z, radius) points from the nose centre's paths, sampled densely (apart
    from the model's shapely sweep)."""
    t = numpy.linspace(0.0, 1.0, 2001)
    nearest = numpy.full(len(points), numpy.inf)
    for start, end in moves:
        path = numpy.asarray(start, float) + t[:, None] * (numpy.asarray(end, float) - numpy.asarray(start, float)) + offset
        nearest = numpy.minimum(nearest, numpy.hypot(points[:, 1:2] - path[None, :, 0], points[:, :1] - path[None, :, 1]).min(axis=1))
    return nearest


section_points = st.tuples(st.floats(8.0, 24.0), st.floats(-40.0, 4.0))  # (radius, z) tips around a D40 bar


@settings(max_examples=30, deadline=None)
@given(st.lists(st.tuples(section_points, section_points), min_size=1, max_size=4), st.floats(0.2, 1.6), st.integers(1, 9))
def test_the_bar_s_bounds_hold_the_material_sampled_by_brute_force(moves, nose, edge_position):
    from ncverify.workpiece import Bar, nose_centre

    bar = Bar(BAR)
    offset = nose_centre(float(edge_position), nose)
    for start, end in moves:
        bar.cut(start, end, nose, offset)
    rng = numpy.random.default_rng(11)
    sample = numpy.column_stack([rng.uniform(-60.0, 0.0, 400), rng.uniform(0.0, 20.0, 400)])  # (z, radius)
    swept = _centre_distance(sample, moves, numpy.asarray(offset)) < nose - 1e-3  # surely under the true nose
    clear_of_nose = _centre_distance(sample, moves, numpy.asarray(offset)) > nose + 0.01  # surely not
    inside_most = shapely.contains_xy(bar.most, sample[:, 0], sample[:, 1])
    inside_least = shapely.contains_xy(bar.least, sample[:, 0], sample[:, 1])
    assert not (swept & inside_least).any()  # what the nose took is never counted as surely there
    assert inside_most[clear_of_nose].all()  # what it never reached is always counted as maybe there


@settings(max_examples=20, deadline=None)
@given(st.lists(st.tuples(section_points, section_points), min_size=2, max_size=4), st.randoms(use_true_random=False))
def test_the_order_of_the_turning_cuts_does_not_change_the_bar(moves, random):
    from ncverify.workpiece import Bar, nose_centre

    forward, shuffled = Bar(BAR), Bar(BAR)
    offset = nose_centre(3.0, 0.8)
    for start, end in moves:
        forward.cut(start, end, 0.8, offset)
    moves = list(moves)
    random.shuffle(moves)
    for start, end in moves:
        shuffled.cut(start, end, 0.8, offset)
    assert forward.most.symmetric_difference(shuffled.most).area < 1e-6
    assert forward.least.symmetric_difference(shuffled.least).area < 1e-6


def test_the_edge_position_puts_the_nose_centre_on_the_side_away_from_the_cut():
    from ncverify.workpiece import nose_centre

    assert nose_centre(3.0, 0.8) == (0.8, 0.8)  # external, towards the chuck: the centre outwards and behind the tip
    assert nose_centre(2.0, 0.4) == (-0.4, 0.4)  # internal, towards the chuck
    assert nose_centre(8.0, 0.5) == (0.5, -0.0)  # the tip below the centre
    assert nose_centre(9.0, 0.5) == (-0.0, -0.0)  # the centre is the point
    assert nose_centre(None, 0.5) is None and nose_centre(3.5, 0.5) is None


def _lathe_findings(program: str, **options):
    from ncverify import Settings, check_text

    result = check_text(program, "t.nc", Settings(machine="lathe", **options))
    return {(d.span.line, d.status.value) for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.span.line > 8}


_TURNED = ("(ncverify: stock cylinder D40 Z-60:0)\n(ncverify: tool 1 radius 0.8 nose-radius 0.8 edge-position 3 type turning)\n"
           "G21 G40 G99 G54\nT0101\nG97 S1500 M03\nG00 X44. Z2.\nG00 X37.\nG01 Z-30. F0.2\nG01 X38.\nG00 Z2.\n")


def test_a_rapid_back_over_the_turned_diameter_passes_and_one_past_the_shoulder_fails():
    assert _lathe_findings(_TURNED + "G00 X100. Z100.\nM30\n") == set()
    assert _lathe_findings(_TURNED + "G00 X38. Z-35.\nG00 X100.\nM30\n") >= {(11, "violated")}
    assert (10, "violated") in _lathe_findings(_TURNED + "M30\n", stock_resolution=0.0)  # the blank alone: the same retract is a crash


def test_without_the_edge_position_a_rapid_over_the_turned_diameter_is_unknown_never_passed():
    program = _TURNED.replace(" edge-position 3", "") + "M30\n"
    assert _lathe_findings(program) == {(10, "unknown")}


def test_under_nose_radius_compensation_a_rapid_over_the_turned_diameter_is_unknown_never_passed():
    """With G42 the nose runs beside the programmed contour, by an offset the program does
    not fix: the rapid back over the diameter is not passed."""
    program = _TURNED.replace("G00 X37.\nG01 Z-30. F0.2\nG01 X38.\n", "G00 X37.\nG42 G01 Z-30. F0.2\nG40 G01 X38.\n") + "M30\n"
    assert _lathe_findings(program) == {(10, "unknown")}


def test_a_rounded_corner_on_the_lathe_makes_the_rapid_over_the_turned_diameter_unknown():
    """``,R`` rounds the shoulder's corner: the nose leaves the programmed contour near it."""
    program = _TURNED.replace("G01 Z-30. F0.2\n", "G01 Z-30. F0.2 ,R0.5\n") + "M30\n"
    assert _lathe_findings(program) == {(10, "unknown")}


_SLOT = ("(ncverify: stock box X0:100 Y0:100 Z-20:0)\n(ncverify: tool 1 radius 5 type endmill)\nG21 G90 G17 G54\nT1 M06\nG43 H01 Z50.\n"
         "S6000 M03\nG00 X20. Y50.\nZ2.\nG01 Z-5. F200.\n{on}G01 X40. Y50.\n{moves}{off}G01 X85. Y50.\nG00 Z2.\nG00 X60. Y50.\nG00 Z-4.\nG00 Z50.\nM30\n")


@pytest.mark.parametrize("moves", ["G01 X80. Y50.\n",  # one move: the block path
                                   "".join(f"G01 X{40 + step}. Y50.\n" for step in range(1, 41)),  # a batch of straight moves
                                   "".join(f"G01 X{40 + step}. Y50.\n" for step in range(1, 5)) + "G02 X45. Y50. R0.5\n"
                                   + "".join(f"G01 X{45 + step}. Y50.\n" for step in range(1, 36))])  # and an arc among them
def test_a_slot_cut_under_radius_compensation_never_clears_a_rapid_down_into_its_programmed_path(moves):
    """G42 puts the tool's centre 5 mm to the right of the programmed line (Y45, when the
    control's offset is the tool's radius): the slot is Y40..50, and the rapid down at Y50
    meets the uncut wall above Y50. The programmed path taken for the tool's centre said
    the rapid was clear (it lies inside the programmed slot); the offset is not fixed by
    the program (the register, a wear value, an allowance), so the rapid is unknown. The
    same slot cut without compensation clears it."""
    from ncverify import Settings, check_text

    def rapid_findings(program):
        return [(d.span.line, d.status.value) for d in check_text(program, "t.nc", Settings()).diagnostics if d.rule == "core.rapid-into-stock"]

    rapid_line = 14 + moves.count("\n")
    assert rapid_findings(_SLOT.format(on="", off="", moves=moves)) == []
    assert rapid_findings(_SLOT.format(on="G42 D1 ", off="G40 ", moves=moves)) == [(rapid_line, "unknown")]


@pytest.mark.parametrize("path, program", [
    ("slot.h", "0 BEGIN PGM SLOT MM\n1 BLK FORM 0.1 Z X+0 Y+0 Z-20\n2 BLK FORM 0.2 X+100 Y+100 Z+0\n3 ; ncverify: tool 1 radius 5 type endmill\n"
               "4 TOOL CALL 1 Z S6000\n5 L Z+50 R0 FMAX M3\n6 L X+20 Y+50 R0 FMAX\n7 L Z+2 R0 FMAX\n8 L Z-5 R0 F200\n9 L X+40 Y+50 RR F200\n"
               "10 L X+80 Y+50\n11 L X+85 Y+50 R0\n12 L Z+2 R0 FMAX\n13 L X+60 Y+{y} R0 FMAX\n14 L Z-4 R0 FMAX\n15 L Z+50 R0 FMAX\n16 END PGM SLOT MM\n"),
    ("slot.mpf", "; ncverify: stock box X0:100 Y0:100 Z-20:0\n; ncverify: tool 1 radius 5 type endmill\nG17 G90 G54\nT1 D1\nM6\nS6000 M3\n"
                 "G0 X20 Y50\nG0 Z2\nG1 Z-5 F200\nG42 G1 X40 Y50\nG1 X80 Y50\nG40 G1 X85 Y50\nG0 Z2\nG0 X60 Y{y}\nG0 Z-4\nG0 Z50\nM30\n"),
    ("slot.nc", _SLOT.replace("G00 X60. Y50.", "G00 X60. Y{y}.").format(on="G42 D1 ", off="G40 ", moves="G01 X80. Y50.\n", y="{y}"))])
def test_a_compensated_slot_still_shows_a_crash_away_from_it_where_the_offset_is_the_tool_s_radius(path, program):
    """Klartext RR and SINUMERIK G42 offset the tool by its own radius, which the model
    sweeps with: the compensated slot may have cut within two radii of its programmed
    path, and nowhere else, so a rapid down 30 mm away still meets the blank (violated);
    beside the programmed path it is unknown. ISO G42 offsets by the D register's value,
    which the program does not give: both are unknown."""
    from ncverify import Settings, check_text

    def rapid(y):
        result = check_text(program.format(y=y), path, Settings(dialect="sinumerik" if path.endswith(".mpf") else None))
        return [status for status, rule in ((d.status.value, d.rule) for d in result.diagnostics) if rule == "core.rapid-into-stock"]

    assert rapid("50") == ["unknown"]
    assert rapid("80") == (["unknown"] if path.endswith(".nc") else ["violated"])


def test_a_klartext_slot_cut_with_rr_never_clears_a_rapid_down_into_its_programmed_path():
    """The same slot in Klartext: ``RR`` is compensation as G42 is, its offset the tool's
    radius plus deltas the machine's table may hold."""
    from ncverify import Settings, check_text

    program = ("0 BEGIN PGM SLOT MM\n1 BLK FORM 0.1 Z X+0 Y+0 Z-20\n2 BLK FORM 0.2 X+100 Y+100 Z+0\n3 ; ncverify: tool 1 radius 5 type endmill\n"
               "4 TOOL CALL 1 Z S6000\n5 L Z+50 R0 FMAX M3\n6 L X+20 Y+50 R0 FMAX\n7 L Z+2 R0 FMAX\n8 L Z-5 R0 F200\n9 L X+40 Y+50 {on} F200\n"
               "10 L X+80 Y+50\n11 L X+85 Y+50 R0\n12 L Z+2 R0 FMAX\n13 L X+60 Y+50 R0 FMAX\n14 L Z-4 R0 FMAX\n15 L Z+50 R0 FMAX\n16 END PGM SLOT MM\n")
    findings = {on: [(d.span.line, d.status.value) for d in check_text(program.format(on=on), "slot.h", Settings()).diagnostics
                     if d.rule == "core.rapid-into-stock"] for on in ("R0", "RR")}
    assert findings == {"R0": [], "RR": [(15, "unknown")]}


_CORNER_ISO = ("(ncverify: stock box X0:100 Y0:100 Z-20:0)\n(ncverify: tool 1 radius 5 type endmill)\nG21 G90 G17 G54\nT1 M06\nG43 H01 Z50.\n"
               "S6000 M03\nG00 X20. Y20.\nZ2.\nG01 Z-5. F200.\nG01 X80.{corner}\nG01 Y80.\nG00 Z2.\nG00 X80. Y20.\nG00 Z-4.\nG00 Z50.\nM30\n")
_CORNER_SINUMERIK = ("; ncverify: stock box X0:100 Y0:100 Z-20:0\n; ncverify: tool 1 radius 5 type endmill\nG17 G90 G54\nT1 D1\nM6\nS6000 M3\n"
                     "G0 X20 Y20\nG0 Z2\nG1 Z-5 F200{modal}\nG1 X80{corner}\nG1 Y80\nG0 Z2\nG0 X80 Y20\nG0 Z-4\nG0 Z50\nM30\n")
_CORNER_KLARTEXT = ("0 BEGIN PGM C MM\n1 BLK FORM 0.1 Z X+0 Y+0 Z-20\n2 BLK FORM 0.2 X+100 Y+100 Z+0\n3 ; ncverify: tool 1 radius 5 type endmill\n"
                    "4 TOOL CALL 1 Z S6000\n5 L Z+50 R0 FMAX M3\n6 L X+20 Y+20 R0 FMAX\n7 L Z+2 R0 FMAX\n8 L Z-5 R0 F200\n9 L X+80 Y+20 R0 F200\n{corner}"
                    "10 L X+80 Y+80\n11 L Z+2 R0 FMAX\n12 L X+80 Y+20 R0 FMAX\n13 L Z-4 R0 FMAX\n14 L Z+50 R0 FMAX\n15 END PGM C MM\n")


@pytest.mark.parametrize("path, program, corner, line", [
    ("t.nc", _CORNER_ISO.format(corner=" ,C20."), "", 14), ("t.nc", _CORNER_ISO.format(corner=" ,R10."), "", 14),
    ("t.mpf", _CORNER_SINUMERIK.format(corner=" CHF=20", modal=""), "", 14), ("t.mpf", _CORNER_SINUMERIK.format(corner=" RND=10", modal=""), "", 14),
    ("t.mpf", _CORNER_SINUMERIK.format(corner="", modal=" RNDM=10"), "", 14),
    ("c.h", _CORNER_KLARTEXT.format(corner="9 RND R10\n"), "", 15), ("c.h", _CORNER_KLARTEXT.format(corner="9 CHF 20\n"), "", 15)])
def test_a_rapid_down_into_a_rounded_or_chamfered_corner_is_unknown_never_passed(path, program, corner, line):
    """The contour turns at X80 Y20, but the corner is chamfered (20 mm) or rounded (R10):
    the tool never got there, and the rapid down onto the programmed corner meets the
    material it left. Sweeping the programmed lines said it was clear (the corner lies
    inside both lines' swept tool); the two moves beside a rounded corner now may have cut
    anywhere, so the rapid is unknown. The same contour with a sharp corner clears it."""
    from ncverify import Settings, check_text

    dialect = {"t.mpf": "sinumerik"}.get(path)

    def rapid(text):
        return [(d.span.line, d.status.value) for d in check_text(text, path, Settings(dialect=dialect)).diagnostics if d.rule == "core.rapid-into-stock"]

    sharp = {"t.nc": _CORNER_ISO.format(corner=""), "t.mpf": _CORNER_SINUMERIK.format(corner="", modal=""), "c.h": _CORNER_KLARTEXT.format(corner="")}[path]
    assert rapid(sharp) == []
    assert rapid(program) == [(line, "unknown")]


def test_a_rounded_corner_among_batched_moves_leaves_what_block_by_block_leaves():
    """The corner's block ends the batch; the moves before it and after it are cut as the
    block path cuts them (the move before it taken back from the buffer)."""
    from ncverify import Settings, check_text

    moves = "".join(f"G01 X{20 + step}.\n" for step in range(1, 60)) + "G01 X80. ,R10.\n" + "".join(f"G01 Y{20 + step}.\n" for step in range(1, 61))
    program = _CORNER_ISO.format(corner="").replace("G01 X80.\nG01 Y80.\n", moves)
    with tempfile.TemporaryDirectory() as folder:
        fields, findings = [], []
        for alone in (False, True):
            left = Path(folder) / f"left-{alone}.npz"
            result = check_text(program, "t.nc", Settings(per_block_only=alone, stock_out=left))
            findings.append([(d.rule, d.status.value, d.span.line) for d in result.diagnostics])
            with numpy.load(left) as saved:
                fields.append((saved["upper"], saved["lower"]))
    assert findings[0] == findings[1]
    assert ("core.rapid-into-stock", "unknown", 132) in findings[0]  # the rapid down onto the corner
    assert all(numpy.array_equal(batched, alone) for batched, alone in zip(*fields))


# --------------------------------------------------------------------------- the holder and the shank

def _holder_findings(program: str, **options):
    from ncverify import Settings, check_text

    result = check_text(program, "t.nc", Settings(**options))
    return [(d.span.line, d.status.value) for d in result.diagnostics if d.rule == "core.holder-collision"]


def _plunge(depth: float, tool: str) -> str:
    return (f"(ncverify: stock box X0:100 Y0:60 Z-60:0)\n(ncverify: tool 1 {tool})\nG21 G90 G17 G54\nT1 M06\nG43 H01 Z50.\nS6000 M03\n"
            f"G00 X50. Y30.\nZ2.\nG01 Z{-depth:.4f} F200.\nG00 Z50.\nM30\n")


@settings(max_examples=25, deadline=None)
@given(st.floats(0.5, 40.0), st.floats(1.0, 30.0))
def test_a_plunge_deeper_than_the_flutes_is_a_shank_collision_and_one_within_them_is_not(depth, flutes):
    assume(abs(depth - flutes) > 1e-3)
    found = _holder_findings(_plunge(depth, f"radius 4 cutting-length {flutes} type endmill"))
    assert found == ([(9, "violated")] if depth > flutes else [])


def test_the_holder_meets_the_blank_beside_a_hole_deeper_than_the_tool_sticks_out():
    tool = "radius 3 length 80 holder-length 60 holder-diameter 30 type endmill"  # 20 mm out of the holder
    assert _holder_findings(_plunge(25.0, tool)) == [(9, "violated")]
    assert _holder_findings(_plunge(15.0, tool)) == []


def test_a_tool_without_flute_length_or_holder_gets_no_holder_finding():
    assert _holder_findings(_plunge(40.0, "radius 4 type endmill")) == []
    assert _holder_findings(_plunge(40.0, "radius 4 cutting-length 10 type endmill"), stock_resolution=0.0) == []  # no model: not checked


def test_a_shank_in_a_slot_cut_before_meets_nothing():
    program = ("(ncverify: stock box X0:100 Y0:60 Z-60:0)\n(ncverify: tool 1 radius 4 cutting-length 10 type endmill)\nG21 G90 G17 G54\nT1 M06\n"
               "G43 H01 Z50.\nS6000 M03\nG00 X20. Y30.\nZ2.\nG01 Z-8. F200.\nX80.\nZ-16.\nX20.\nG00 Z50.\nM30\n")
    assert _holder_findings(program) == []


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.floats(0, 100), st.floats(0, 60), st.floats(-24, 1)), min_size=1, max_size=40), st.sampled_from([8.0, 12.0, 20.0]),
       st.booleans())
def test_the_shank_is_judged_alike_in_batches_and_block_by_block_and_only_where_it_can_reach_the_blank(moves, flutes, arcs):
    """Feed moves at depths above and below the flute length: batched and block by block,
    the same shank findings (each move judged against what the moves before it left),
    and the shank is judged only on moves deep enough for it to reach below the blank's
    top (a shallow move is swept in its batch, not one by one)."""
    from ncverify import Settings, check_text, workpiece

    body = [f"G01 X{x:.3f} Y{y:.3f} Z{z:.3f} F800." for x, y, z in moves]
    if arcs:
        body = [line if index % 3 else line.replace("G01", "G02") + " R80." for index, line in enumerate(body)]
    program = (f"(ncverify: stock box X0:100 Y0:60 Z-60:0)\n(ncverify: tool 1 radius 4 cutting-length {flutes} type endmill)\nG21 G90 G17 G54\n"
               "T1 M06\nG43 H01 Z50.\nS6000 M03\nG00 X50. Y30.\nZ2.\n" + "\n".join(body) + "\nG00 Z50.\nM30\n")
    judged = []  # the lowest point of each part asked about (every question the model answers here is the shank's)
    original = workpiece.Workpiece.rapid

    def recorded(self, start, end, cutter):
        judged.append(min(start[2], end[2]))
        return original(self, start, end, cutter)

    with patch.object(workpiece.Workpiece, "rapid", recorded), tempfile.TemporaryDirectory() as folder:
        findings, fields = [], []
        for alone in (False, True):
            left = Path(folder) / f"left-{alone}.npz"
            findings.append([(d.rule, d.status, d.span, d.message) for d in check_text(program, "t.nc", Settings(per_block_only=alone, stock_out=left)).diagnostics])
            with numpy.load(left) as saved:
                fields.append((saved["upper"], saved["lower"]))
    assert findings[0] == findings[1]
    assert all(numpy.array_equal(batched, alone) for batched, alone in zip(*fields))  # the same cuts, swept in the same groups
    assert all(lowest <= 0.0 for lowest in judged)


# --------------------------------------------------------------------------- the memory cap

def _rapid_rules(program: str, **options):
    from ncverify import Settings, check_text

    result = check_text(program, "t.nc", Settings(**options))
    note = [(0, d.rule, d.status.value) for d in result.diagnostics if d.rule == "core.stock-model-too-large"]  # said once, at the first move
    return note + sorted((d.span.line, d.rule, d.status.value) for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.span.line > 7)


_RETRACT = ("(ncverify: stock box X0:500 Y0:500 Z-20:0)\n(ncverify: tool 1 radius 4 type endmill)\nG21 G90 G17 G54\nT1 M06\nG43 H01 Z50.\nS6000 M03\n"
            "G00 X50. Y30.\nZ2.\nG01 Z-5. F200.\nX80.\nG00 Z50.\nM30\n")


def test_a_model_over_the_cap_gives_a_note_and_the_blank_s_verdicts_not_an_out_of_memory_kill():
    assert _rapid_rules(_RETRACT) == []  # the retract out of the slot: clear against the cut stock
    too_fine = _rapid_rules(_RETRACT, stock_resolution=0.01)  # 500 x 500 mm at 0.01 mm: 19 GiB
    assert too_fine == [(0, "core.stock-model-too-large", "unknown"), (11, "core.rapid-into-stock", "violated")]
    assert _rapid_rules(_RETRACT, stock_memory=1 << 16) == too_fine  # auto: cells of the tool's radius (4 mm) need 122 KiB
    assert _rapid_rules(_RETRACT, stock_resolution=0.0) == [(11, "core.rapid-into-stock", "violated")]  # off: no note


def test_forked_paths_that_would_copy_the_workpiece_past_the_cap_fall_back_to_the_blank():
    program = ("(ncverify: stock box X0:100 Y0:100 Z-20:0)\n(ncverify: tool 1 radius 4 type endmill)\n(ncverify: assume 0 <= #1 <= 10)\n"
               "G21 G90 G17 G54\nT1 M06\nG43 H01 Z50.\nS6000 M03\nG00 X50. Y30.\nZ2.\nG01 Z-5. F200.\nIF [#1 GT 5.] GOTO 10\nX60.\n"
               "N10 X80.\nG00 X65.\nG00 Z50.\nM30\n")  # back along the slot at its depth: clear against the cut stock only
    one_field = 8 * 100 * 100 + 1000  # room for one field of 1 mm cells (a quarter of the radius), not for two
    found = _rapid_rules(program, stock_memory=one_field)
    assert ("core.stock-model-too-large", "unknown") in {(rule, status) for _, rule, status in found}
    assert (14, "core.rapid-into-stock", "violated") in found  # one path is judged against the blank
    assert _rapid_rules(program) == []


def test_the_project_file_takes_auto_and_off_for_the_resolution(tmp_path):
    from ncverify.project import ConfigError, load_project_text

    assert load_project_text('[settings]\nstock_resolution = "off"\n', tmp_path / "ncverify.toml").settings == {"stock_resolution": 0.0}
    assert load_project_text('[settings]\nstock_resolution = "auto"\n', tmp_path / "ncverify.toml").settings == {"stock_resolution": None}
    with pytest.raises(ConfigError, match="auto, off"):
        load_project_text('[settings]\nstock_resolution = "fine"\n', tmp_path / "ncverify.toml")


def test_paths_that_fork_and_only_look_at_the_workpiece_share_it_without_a_copy():
    program = ("(ncverify: stock box X0:100 Y0:100 Z-20:0)\n(ncverify: tool 1 radius 4 type endmill)\n(ncverify: assume 0 <= #1 <= 10)\n"
               "G21 G90 G17 G54\nT1 M06\nG43 H01 Z50.\nS6000 M03\nG00 X50. Y30.\nZ2.\nG01 Z-5. F200.\nX80.\nIF [#1 GT 5.] GOTO 10\n"
               "G00 X60.\nN10 G00 X65.\nG00 Z50.\nM30\n")
    assert _rapid_rules(program, stock_memory=8 * 100 * 100 + 1000) == []  # room for one field: the rapids on both paths read it


def test_the_command_line_takes_auto_off_or_a_size_and_refuses_anything_else(capsys):
    from ncverify.cli import build_parser

    def resolution(word):
        return build_parser().parse_args(["check", "p.nc", "--stock-resolution", word]).stock_resolution

    assert resolution("auto") is None and resolution("off") == 0.0 and resolution("0.2") == 0.2
    with pytest.raises(SystemExit):
        resolution("fine")
    assert "'fine' is not a number, 'auto' or 'off'" in capsys.readouterr().err
    assert build_parser().parse_args(["check", "p.nc"]).stock_resolution is None  # the default: the cut stock, cells from the tools


def test_a_checked_file_leaves_no_checker_and_no_workpiece_behind():
    """The language server, a batch in one process and the fuzzer check file after file: the
    checker and the cut stock it made must be freed after each (the workpiece's finalizer once
    held them for good, about 0.1 MB a file)."""
    import gc

    from ncverify import Settings, check_file
    from ncverify.check import Checker

    def alive():
        gc.collect()
        return sum(isinstance(item, (Checker, Workpiece)) for item in gc.get_objects())

    before = alive()
    program = Path(__file__).resolve().parents[1] / "corpus" / "iso" / "clean-pocket-rapid-retract.nc"
    for _ in range(3):
        check_file(program, Settings())
    assert alive() == before


# The sweep's fast paths against brute force -------------------------------------------------
# The sweep measures only the cells of each row of a piece's box that can be near it, and
# screens chord groups before judging them whole; these tests hold both to the plain
# computation: every cell of the grid measured against every piece, every group judged on
# every vertex. Equal means bit for bit: the same cells, distances and heights.

_GRIDS = st.sampled_from([(BLANK, 0.5), (BLANK, 1.0), (Stock.box((-3.3, 7.1), (2.2, 9.0), (-5, 0)), 0.37)])
_NEAR = st.floats(-12, 50, allow_nan=False)
_COORDINATE = st.one_of(_NEAR, _NEAR, _NEAR, st.floats(-3e6, 3e6), st.sampled_from([0.0, 0.25, 0.5, 2e6, -1.5e6, 1e9, -1e9, 1e308, math.inf, -math.inf]))
# Farther out than 1e9 (short of the float range) rounding misplaces the nearest point of a
# path by more than a cell, for the plain distance as for the sweep: the rapid check does not
# measure there (test_a_rapid_from_past_the_measured_reach_is_unsure), and no control writes it.


@st.composite
def _pieces(draw):
    """XY pieces: anywhere, along a row or a column, level or nearly, of no length, far away."""
    a = (draw(_COORDINATE), draw(_COORDINATE))
    form = draw(st.sampled_from(["any", "row", "column", "level", "shallow", "point"]))
    b = (draw(_COORDINATE), draw(_COORDINATE))
    if form == "row":
        b = (b[0], a[1])
    elif form == "shallow":
        b = (b[0], a[1] + draw(st.floats(-3, 3)))
    elif form == "column":
        b = (a[0], b[1])
    elif form == "level":
        b = (b[0], a[1] + draw(st.floats(-1e-9, 1e-9)))
    elif form == "point":
        b = a
    return a, b


def _every_cell_near(piece, a, b, slack, reach):
    """(piece, flat cell, distance) of every cell, piece by piece in row-major order,
    measured by the plain distance to each segment."""
    rows, columns = numpy.divmod(numpy.arange(piece.nx * piece.ny), piece.nx)
    found = []
    for k in range(len(a)):
        distance = distance_to_segment(piece._x(columns), piece._y(rows), numpy.repeat(a[k:k + 1, :2], len(rows), axis=0),
                                       numpy.repeat(b[k:k + 1, :2], len(rows), axis=0))
        near = numpy.flatnonzero(distance <= reach + slack[k])
        found.append((numpy.full(len(near), k), near, distance[near]))
    return [numpy.concatenate(column) for column in zip(*found)]


@settings(max_examples=150, deadline=None)
@given(_GRIDS, st.lists(st.tuples(_pieces(), st.floats(0, 2), st.integers(1, 3)), min_size=1, max_size=6), st.floats(0, 6),
       st.sampled_from([1 << 18, 7, 40]))
def test_the_cells_near_each_piece_are_those_every_cell_measured_finds_in_the_same_order(grid, drawn, reach, chunk):
    """Pieces anywhere, some repeated (a plunge's steps: measured once, their cells handed on),
    in chunks of every size: every cell measured against every piece finds the same."""
    from ncverify import workpiece

    piece = Workpiece(*grid)
    repeated = [(segment, slack) for segment, slack, times in drawn for _ in range(times)]
    a = numpy.array([[*start, 0.0] for (start, _), _ in repeated])
    b = numpy.array([[*end, 0.0] for (_, end), _ in repeated])
    slack = numpy.array([slack for _, slack in repeated])
    with patch.object(workpiece, "_CHUNK_CELLS", chunk), numpy.errstate(all="ignore"):  # small chunks: pieces spread over many
        found = [numpy.concatenate(column) for column in zip(*(near.each_piece() for near in piece._cells_near(a, b, slack, reach)))]
        expected = _every_cell_near(piece, a, b, slack, reach)
    for got, wanted in zip(found, expected):
        assert numpy.array_equal(got, wanted)


def _plain_merge(starts, ends, strays, tolerance, rise):
    """The merge as its rule says, group by group: groups of 64 moves, each kept whole when
    its moves join end to start, every vertex lies within ``tolerance`` of its chord and its
    heights within ``rise``, else split in halves (the first the larger) and those judged."""
    kept = []

    def judge(begin, count):
        moves = numpy.arange(begin, begin + count)
        joined = (starts[moves[1:]] == ends[moves[:-1]]).all()
        stray = distance_to_segment(ends[moves, 0], ends[moves, 1], numpy.repeat(starts[begin:begin + 1, :2], count, axis=0),
                                    numpy.repeat(ends[moves[-1]:moves[-1] + 1, :2], count, axis=0)).max()
        climb = numpy.maximum(starts[moves, 2], ends[moves, 2]).max() - numpy.minimum(starts[moves, 2], ends[moves, 2]).min()
        if count == 1 or (joined and stray <= tolerance and climb <= rise):
            kept.append((begin, count, stray))
        else:
            half = (count + 1) // 2
            judge(begin, half)
            judge(begin + half, count - half)

    for begin in range(0, len(starts), 64):
        judge(begin, min(64, len(starts) - begin))
    first, length, stray = (numpy.array(column) for column in zip(*kept))
    last = first + length - 1
    groups = [numpy.arange(begin, end + 1) for begin, end in zip(first, last)]
    z_low = numpy.array([numpy.minimum(starts[moves, 2], ends[moves, 2]).min() for moves in groups])
    z_high = numpy.array([numpy.maximum(starts[moves, 2], ends[moves, 2]).max() for moves in groups])
    return starts[first], ends[last], z_low, z_high, stray, numpy.array([strays[moves].max() for moves in groups])


@st.composite
def _paths(draw):
    """Connected runs of short moves, bent, stepped in Z, now and then broken or standing still,
    or all apart."""
    count = draw(st.integers(1, 300))
    turn, step = draw(st.floats(0, 0.6)), draw(st.floats(0.01, 1.0))
    angles = numpy.cumsum(numpy.full(count, turn)) + draw(st.floats(0, 6.3))
    points = numpy.zeros((count + 1, 3))
    points[1:, 0], points[1:, 1] = numpy.cumsum(step * numpy.cos(angles)), numpy.cumsum(step * numpy.sin(angles))
    points[1:, 2] = numpy.cumsum(numpy.where(numpy.arange(count) % draw(st.integers(1, 80)) == 0, -draw(st.floats(0, 0.8)), 0.0))
    starts, ends = points[:-1].copy(), points[1:].copy()
    for broken in draw(st.lists(st.integers(1, max(1, count - 1)), max_size=3)):
        if broken < count:
            starts[broken, 0] += 0.1
    if draw(st.integers(0, 4)) == 0:  # every move apart from the one before (lines buffered between arcs, a cycle's plunges)
        starts[1:, 1] += 0.05
    standing = draw(st.lists(st.integers(0, count - 1), max_size=8))  # moves of no length (a move split at the slab's faces leaves them)
    return numpy.insert(starts, standing, starts[standing], axis=0), numpy.insert(ends, standing, starts[standing], axis=0)


@settings(max_examples=150, deadline=None)
@given(_paths(), st.sampled_from([0.125, 0.0125, 0.25]), st.sampled_from([0, 100, 4096]))
def test_the_merge_keeps_the_groups_that_judging_group_by_group_keeps(path, tolerance, at_once):
    """Judged level by level (``at_once`` 0), every group at once, or the levels until the groups
    left hold at most ``at_once`` moves and then all of those at once, with the groups screened
    before they are judged whole: the same chords as judging each group on every vertex."""
    from ncverify import workpiece

    starts, ends = path
    strays = numpy.linspace(0.0, 0.01, len(starts))
    with patch.object(workpiece, "_TREE_AT_ONCE", at_once):
        merged = workpiece._merge_runs(starts, ends, strays, tolerance, 0.5)
    for got, wanted in zip(merged, _plain_merge(starts, ends, strays, tolerance, 0.5)):
        assert numpy.array_equal(got, wanted)


def _sweep_every_cell(piece, starts, ends, cutter, stray, joined=True):
    """The sweep written plainly: each piece against every cell of the grid (the same
    pieces, bounds and rounding as the model's own)."""
    from ncverify.workpiece import _as_given, _merge_runs, _sink

    starts, ends, strays = piece._within_slab(starts, ends, cutter, numpy.broadcast_to(numpy.asarray(stray, float), len(starts)))
    pieces = _merge_runs(starts, ends, strays, piece.resolution / 4.0, piece.resolution) if joined else _as_given(starts, ends, strays)
    a, b, z_low, z_high, slack, stray = piece._split_steep(*pieces)
    z_low, z_high, slack = z_low - stray, z_high + stray, slack + stray
    may_cut = numpy.zeros(len(a), bool)
    owner, flat, distance = _every_cell_near(piece, a, b, slack, cutter.radius + piece.half_diagonal)
    outer = numpy.maximum(distance - piece.half_diagonal - slack[owner], 0.0)
    touched = outer <= cutter.radius
    surface_low = z_low[owner] + cutter.lowest_lift(outer)
    may_cut[owner[touched & (piece.upper.reshape(-1)[flat] > surface_low)]] = True
    inner = distance + piece.half_diagonal + slack[owner]
    covered = inner <= cutter.radius
    _sink(piece.upper, flat[covered], z_high[owner][covered] + cutter.lift(inner[covered]), up=True)
    _sink(piece.lower, flat[touched], surface_low[touched], up=False)
    for field in (piece.upper, piece.lower):
        field[field <= piece.bottom] = NO_MATERIAL
    return float(numpy.linalg.norm(b - a, axis=1)[~may_cut].sum())


_SWEPT = st.one_of(cutters, st.sampled_from([Cutter(0.0), Cutter(0.2), Cutter(0.3, corner=0.3)]))


@settings(max_examples=60, deadline=None)
@given(_SWEPT, st.lists(st.tuples(points, points), min_size=1, max_size=3), _paths(), st.floats(0, 0.05))
def test_the_sweep_leaves_the_field_that_every_cell_measured_against_every_piece_leaves(cutter, moves, path, stray):
    piece, plain = Workpiece(BLANK, 0.5), Workpiece(BLANK, 0.5)
    starts, ends = path
    batches = [(numpy.array([start]), numpy.array([end]), 0.0) for start, end in moves]
    batches.append((starts * [2.0, 2.0, 1.0] + [20.0, 15.0, 1.0], ends * [2.0, 2.0, 1.0] + [20.0, 15.0, 1.0], stray))
    for starts, ends, stray in batches:
        assert piece.cut(starts, ends, cutter, stray) == _sweep_every_cell(plain, starts, ends, cutter, stray)
        assert numpy.array_equal(piece.upper, plain.upper) and numpy.array_equal(piece.lower, plain.lower)


@settings(max_examples=60, deadline=None)
@given(_SWEPT, _paths(), st.lists(st.floats(-9, 2), min_size=2, max_size=5), st.floats(0, 0.05), st.booleans())
def test_laps_of_one_path_at_several_depths_leave_the_field_that_every_cell_measured_leaves(cutter, path, depths, stray, joined):
    """A profile stepped down lap by lap meets the same cells lap after lap: the sweep
    measures each path once for all its laps, and leaves what measuring every lap leaves
    (each time over, the second judged against what the first cut). All in one chunk, as
    the plain sweep judges every piece against the field before the batch."""
    from ncverify import workpiece

    piece, plain = Workpiece(BLANK, 0.5), Workpiece(BLANK, 0.5)
    starts, ends = (numpy.concatenate([points * [2.0, 2.0, 1.0] + [20.0, 15.0, depth] for depth in depths]) for points in path)
    for _ in range(2):
        with patch.object(workpiece, "_CHUNK_CELLS", 1 << 24):
            assert piece.cut(starts, ends, cutter, stray, joined) == _sweep_every_cell(plain, starts, ends, cutter, stray, joined)
        assert numpy.array_equal(piece.upper, plain.upper) and numpy.array_equal(piece.lower, plain.lower)


@settings(max_examples=200, deadline=None)
@given(_GRIDS, st.lists(st.tuples(_pieces(), st.floats(-8, 1), st.floats(0, 0.3)), min_size=1, max_size=6),
       st.one_of(st.floats(0.01, 8.0), st.sampled_from([0.25, 0.5, 1.0, 2.0])), st.sampled_from([1 << 24, 7, 40]))
@example((BLANK, 0.5), [(((-1e200, 10.0), (1e200, 10.0)), -1.0, 0.0), (((5.0, -1e160), (5.0, 1e160)), -1.0, 0.0)], 2.0, 1 << 24)  # squares past the float range
def test_a_flat_end_touches_and_covers_the_cells_every_cell_measured_finds(grid, drawn, radius, chunk):
    """A flat end's cells are not measured but taken a row's stretch at a time, the few at
    each stretch's ends measured: pieces anywhere (far out, off to infinity, along a row or
    a column, nearly level, of no length), with strays, radii from below a cell's half
    diagonal (measured cell by cell, as below two cells) to many cells, in chunks of every
    size, leave the field of every cell measured, and in one chunk (each is judged against
    the field before it) its air."""
    from ncverify import workpiece

    piece, plain = Workpiece(*grid), Workpiece(*grid)
    starts = numpy.array([[*start, depth] for (start, _), depth, _ in drawn])
    ends = numpy.array([[*end, depth] for (_, end), depth, _ in drawn])
    strays = numpy.array([stray for _, _, stray in drawn])
    with patch.object(workpiece, "_CHUNK_CELLS", chunk), numpy.errstate(all="ignore"):
        air, plain_air = piece.cut(starts, ends, Cutter(radius), strays, joined=False), _sweep_every_cell(plain, starts, ends, Cutter(radius), strays, joined=False)
    if chunk == 1 << 24:
        assert air == plain_air or math.isnan(air) and math.isnan(plain_air)  # a piece off to infinity has no finite length
    assert numpy.array_equal(piece.upper, plain.upper) and numpy.array_equal(piece.lower, plain.lower)


_HEIGHT = st.one_of(st.floats(-12, 3), st.sampled_from([0.5, -10.5, 0.0, -10.0, 1e6, -1e6]))  # the slab's faces among them


@settings(max_examples=100, deadline=None)
@given(st.lists(st.tuples(_COORDINATE, _COORDINATE, _HEIGHT, _COORDINATE, _COORDINATE, _HEIGHT), min_size=1, max_size=6))
def test_moves_leaving_the_slab_are_cut_at_its_faces_as_the_plain_formula_cuts_them(moves):
    """Rapids and plunges into and through the blank, ramps out of it, far away in XY: each
    move that leaves the slab is cut at the faces it crosses (no piece of no length in
    ``t`` is left where a face clips to an end), every point ``start + t * (end - start)``
    with its Z kept on the slab, exactly as that formula gives it move by move; a move
    within the slab stays as given."""
    piece = Workpiece(BLANK, 0.5)
    rows = numpy.array(moves)
    starts, ends, strays = rows[:, :3], rows[:, 3:], numpy.linspace(0.0, 0.1, len(rows))
    with numpy.errstate(all="ignore"):
        got = piece._within_slab(starts, ends, Cutter(1.0), strays)
        low, high = piece.bottom - 0.0 - piece.resolution, piece.top + piece.resolution
        pieces, piece_strays = [], []
        for start, end, stray in zip(starts, ends, strays):
            if low <= min(start[2], end[2]) and max(start[2], end[2]) <= high:
                pieces.append((start, end))
                piece_strays.append(stray)
                continue
            rise = end[2] - start[2]
            faces = [(level - start[2]) / rise if rise != 0.0 else 0.0 for level in (low, high)]
            ts = numpy.sort(numpy.clip([0.0, *faces, 1.0], 0.0, 1.0))
            points = [start + t * (end - start) for t in ts]
            for point in points:
                point[2] = min(max(point[2], low), high)
            for t0, t1, a, b in zip(ts[:-1], ts[1:], points[:-1], points[1:]):
                if not t1 <= t0:
                    pieces.append((a, b))
                    piece_strays.append(stray)
        wanted = numpy.array([a for a, _ in pieces]), numpy.array([b for _, b in pieces]), numpy.array(piece_strays)
    for got_part, wanted_part in zip(got, wanted):
        assert numpy.array_equal(got_part, wanted_part, equal_nan=True)


@settings(max_examples=40, deadline=None)
@given(_SWEPT, st.lists(_ARC, min_size=1, max_size=6), st.floats(-3, 1), st.booleans())
def test_arcs_and_helices_swept_as_chords_leave_the_field_every_cell_measured_leaves(cutter, arcs, depth, joined):
    """Arcs of every plane, full circles and helices (some starting above the blank, some
    reaching below it), their chords swept at once with each chord's sagitta as its stray,
    merged where they join or each alone (as the model sweeps arcs): the same field and air
    as measuring every cell against every chord."""
    from ncverify import workpiece

    piece, plain = Workpiece(BLANK, 0.5), Workpiece(BLANK, 0.5)
    centre = numpy.array([20.0, 15.0, depth])
    starts, ends = numpy.tile(centre, (len(arcs), 1)), numpy.tile(centre, (len(arcs), 1))
    for k, (radius, begin, finish, _, rise, (first, second, normal)) in enumerate(arcs):
        starts[k, [first, second]] += [radius * math.cos(begin), radius * math.sin(begin)]
        ends[k, [first, second]] += [radius * math.cos(finish), radius * math.sin(finish)]
        ends[k, normal] += rise
    planes = [arc[5] for arc in arcs]
    chords = workpiece.arc_chords(starts, ends, [centre[list(plane[:2])] for plane in planes], [arc[3] for arc in arcs], planes, tolerance=0.0625)
    with patch.object(workpiece, "_CHUNK_CELLS", 1 << 40), numpy.errstate(all="ignore"):  # one step, as the plain sweep judges the air
        assert piece.cut(chords[0], chords[1], cutter, chords[2], joined) == _sweep_every_cell(plain, chords[0], chords[1], cutter, chords[2], joined)
    assert numpy.array_equal(piece.upper, plain.upper) and numpy.array_equal(piece.lower, plain.lower)


@pytest.mark.parametrize("top", [0.0, -0.0, 5.0])
def test_a_box_blank_at_any_top_holds_it_on_every_cell_and_is_surely_there_but_where_cells_stick_out(top):
    """A top at +0 is laid out as zeroed memory, any other (-0 too) filled in: the same tops.
    The cells that stick out are counted out where the lower bound is read, whole or cell
    by cell, and are not written (which would write every row)."""
    piece = Workpiece(Stock.box((0, 40.3), (0, 30.2), (top - 10, top)), 0.5)
    assert piece.upper.tobytes() == numpy.full((61, 81), top, numpy.float32).tobytes()
    inside = numpy.full((61, 81), top, numpy.float32)
    inside[-1, :] = inside[:, -1] = NO_MATERIAL  # centres within half a cell of the far sides: their cells stick out
    assert piece._lower_field().tobytes() == inside.tobytes()
    assert piece._lower_at(numpy.arange(61 * 81)[::-1]).tobytes() == inside.reshape(-1)[::-1].tobytes()
    assert piece.lower.tobytes() == numpy.full((61, 81), top, numpy.float32).tobytes()


def test_a_copy_of_a_workpiece_whose_lower_bound_was_emptied_cuts_its_upper_bound_on_its_own():
    piece = Workpiece(BLANK, 0.5)
    piece.cut_anywhere()
    twin = piece.copy()
    twin.cut([[5, 15, -4]], [[35, 15, -4]], Cutter(3.0))
    assert (piece.upper == 0.0).all() and (twin.upper[30, 20:60] == -4.0).all()
    assert (piece.lower == NO_MATERIAL).all() and (twin.lower == NO_MATERIAL).all()
    assert twin.rapid((10, 15, -2), (30, 15, -2), Cutter(1.0)).outcome == "clear"
    assert piece.rapid((10, 15, -2), (30, 15, -2), Cutter(1.0)).outcome == "unsure"


@pytest.mark.skipif(platform.libc_ver()[0] != "glibc", reason="the allocator's settings are glibc's")
def test_sweeping_a_large_batch_again_reuses_its_scratch_memory_instead_of_paging_it_in_anew():
    """Left to glibc's defaults, each repeat of this sweep faulted about 18,000 pages in
    (its scratch arrays handed back to the system and mapped again); kept, a few hundred."""
    piece = Workpiece(Stock.box((0, 100), (0, 2000), (-20, 0)), 0.5)
    turns = numpy.linspace(0.0, 400 * math.pi, 40001)
    path = numpy.column_stack([50 + 40 * numpy.cos(turns), 1000 + 900 * numpy.sin(turns / 200), numpy.full(len(turns), -1.0)])
    piece.cut(path[:-1], path[1:], Cutter(3.0))
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    for _ in range(5):
        piece.cut(path[:-1], path[1:], Cutter(3.0))
    assert resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before < 10_000


@pytest.mark.parametrize("far", [-1e17, -3e15, 2e9])
def test_a_rapid_from_past_the_measured_reach_is_unsure(far):
    """From Y-1e17 the nearest points of the path were rounded 16 mm off, and a rapid
    through 4 mm of stock was judged clear: so far out the path is not measured."""
    piece = Workpiece(Stock.box((0, 40), (5, 30), (-10, 0)), 0.5)
    assert piece.rapid((5.0, far, -2.0), (5.0, 9.0, -2.0), Cutter(1.0)).outcome == "unsure"
    assert piece.rapid((5.0, -1e6, -2.0), (5.0, 9.0, -2.0), Cutter(1.0)).outcome == "hits"


_PLUNGE_AT = st.one_of(st.floats(-3, 43), st.sampled_from([0.0, 40.0, 30.0, 0.25, -0.5, 39.75]), st.floats(-3e6, 3e6), st.sampled_from([2e6, -1e9]))
_DEPTH = st.one_of(st.floats(-12, 3), st.sampled_from([1.0, 0.0, -10.0, -10.5, -5.0, 1e6, -1e6]))


@st.composite
def _plunges(draw):
    """Drilling-cycle moves: vertical plunges (down, up, of no length) at holes inside the
    blank, on its edges and far away, into it, through it or above it; now and then a hole
    made twice, a peck continuing where the last one ended, or a move that is not vertical."""
    moves = []
    for _ in range(draw(st.integers(1, 24))):
        x, y = draw(_PLUNGE_AT), draw(_PLUNGE_AT)
        if moves and draw(st.integers(0, 5)) == 0:
            x, y = moves[-1][0][:2]  # the same hole again
        start = (x, y, draw(_DEPTH))
        if moves and draw(st.integers(0, 5)) == 0:
            start = moves[-1][1]  # a peck going on from where the one before ended
        end = (start[0], start[1], draw(_DEPTH))
        if draw(st.integers(0, 15)) == 0:
            end = (end[0] + draw(st.floats(-2, 2)), end[1], end[2])
        moves.append((start, end))
    return numpy.array([start for start, _ in moves], float), numpy.array([end for _, end in moves], float)


@settings(max_examples=150, deadline=None)
@given(_SWEPT, _plunges(), st.sampled_from([0.0, 0.0, 0.02]), st.sampled_from([(BLANK, 0.5), (Stock.box((-3.3, 7.1), (2.2, 9.0), (-5, 0)), 0.37)]))
def test_plunges_leave_the_field_and_air_that_every_cell_measured_against_every_piece_leaves(cutter, plunges, stray, grid):
    """Hole cycles cut batches of vertical moves: each plunge is split at the slab's faces
    and into steps of a cell's height, every step over the same cells. Flat, ball, bull-nose,
    pointed and unknown cutters, the tool's axis alone: the same field and air, bit for bit,
    as measuring every cell of the grid against every step, before and after other cuts."""
    piece, plain = Workpiece(*grid), Workpiece(*grid)
    starts, ends = plunges
    with numpy.errstate(all="ignore"):
        for batch in (slice(None), slice(None, None, -1)):  # the second time over what the first cut
            assert piece.cut(starts[batch], ends[batch], cutter, stray) == _sweep_every_cell(plain, starts[batch], ends[batch], cutter, stray)
            assert piece.upper.tobytes() == plain.upper.tobytes() and piece.lower.tobytes() == plain.lower.tobytes()


@settings(max_examples=100, deadline=None)
@given(_plunges(), st.sampled_from([0.5, 0.37, 2.0]))
def test_plunges_cut_at_the_slab_s_faces_merge_as_judging_group_by_group_merges_them(plunges, resolution):
    """A batch of plunges laid on the slab's faces: up to three connected pieces a plunge,
    most too steep to join; the merge keeps the groups the plain rule keeps."""
    from ncverify.workpiece import _merge_runs

    piece = Workpiece(BLANK, resolution)
    with numpy.errstate(all="ignore"):
        starts, ends, strays = piece._within_slab(*plunges, Cutter(1.0), numpy.zeros(len(plunges[0])))
        assume(numpy.isfinite(starts).all() and numpy.isfinite(ends).all())
        merged = _merge_runs(starts, ends, strays, resolution / 4.0, resolution)
    for got, wanted in zip(merged, _plain_merge(starts, ends, strays, resolution / 4.0, resolution)):
        assert numpy.array_equal(got, wanted)


_STORED_HEIGHT = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(-1e-40, 1e-40),  # below float32's smallest normal: rounding to zero and subnormals
    st.sampled_from([0.0, -0.0, 3.4028235e38, -3.4028235e38, 3.5e38, -3.5e38, 1e-46, -1e-46]),  # around float32's ends
)


@settings(max_examples=300, deadline=None)
@given(st.lists(_STORED_HEIGHT, min_size=1, max_size=40), st.booleans())
def test_heights_are_stored_rounded_outwards_as_nextafter_rounds_them(heights, up):
    """The bounds are stored as float32 rounded away from the material they bound: the bit
    step gives what numpy.nextafter gives towards the infinity on the rounding's wrong side,
    signed zeros, subnormals, values past float32's range, infinities and NaN included."""
    from ncverify.workpiece import _float32_outwards

    values = numpy.array(heights, float)
    with numpy.errstate(all="ignore"):
        wanted = values.astype(numpy.float32)
        wrong = wanted < values if up else wanted > values
        wanted[wrong] = numpy.nextafter(wanted[wrong], numpy.float32(numpy.inf if up else -numpy.inf))
        got = _float32_outwards(values, up)
    assert got.tobytes() == wanted.tobytes()


_MOVE_ROW = st.tuples(*[st.floats(-1e6, 1e6)] * 6)


@settings(max_examples=200, deadline=None)
@given(st.lists(_MOVE_ROW, max_size=30))
def test_the_summed_length_of_moves_is_numpy_s_norm_summed_bit_for_bit(rows):
    """The air and path lengths in the report are summed from the moves' lengths: the same
    bits as numpy.linalg.norm along the rows, summed."""
    from ncverify.workpiece import total_length

    moves = numpy.array(rows, float).reshape(-1, 6)
    starts, ends = moves[:, :3], moves[:, 3:]
    assert total_length(starts, ends) == float(numpy.linalg.norm(ends - starts, axis=1).sum())


_COORDINATE = st.one_of(st.floats(-60, 60, allow_nan=False), st.sampled_from([-10.0, 0.0, 30.0, 40.0, 5.0]))  # on the faces too
_POINT = st.tuples(_COORDINATE, _COORDINATE, _COORDINATE)


@settings(max_examples=300, deadline=None)
@given(segments=st.lists(st.tuples(_POINT, _POINT), max_size=12), bar=st.booleans())
def test_rapids_judged_together_are_judged_as_each_alone(segments, bar):
    """A run's rapids are tested against the blank at once (geometry.enters_many); the
    answer for each is the one a lone rapid gets (geometry._clip_box)."""
    from ncverify import geometry

    stock = Stock.cylinder(50.0, (-10, 0)) if bar else BLANK
    starts = numpy.array([start for start, _end in segments], float).reshape(-1, 3)
    ends = numpy.array([end for _start, end in segments], float).reshape(-1, 3)
    box = geometry.stock_box(stock)
    alone = [geometry._clip_box(start, end, box) is not None for start, end in segments]
    assert geometry.enters_many(stock, starts, ends).tolist() == alone


# Arcs and helices about Z measured as arcs ------------------------------------------------
# An arc about the Z axis is swept in parts, each one piece. Its distance is held to the arc
# sampled densely (an independent model); the cells and the field it leaves are held, bit
# for bit, to every cell of the grid measured with that distance; and the bounds to the
# material the tool really leaves, sampled by brute force.

_XY_ARC = st.tuples(st.floats(-10, 50), st.floats(-10, 40), st.floats(0.05, 30), st.floats(-7, 7), st.floats(-7, 7), st.booleans(),
                    st.sampled_from([0.0, 0.0, 1e-7, -0.04]), st.floats(-14, 4), st.sampled_from([0.0, 0.0, 0.3, -2.0, 15.0]))
# centre, radius, start and end angles, clockwise, end off the circle, start height, climb


@st.composite
def _wide_arc(draw):
    """An arc of a circle of up to a kilometre's radius, passing through the blank near its middle."""
    radius, facing, half_length = draw(st.sampled_from([1e2, 1e4, 1e6])), draw(st.floats(0, 6.28)), draw(st.floats(0.01, 1.0))
    half_angle = half_length / radius  # counterclockwise the short way, clockwise nearly the whole circle
    return (20.0 - radius * math.cos(facing), 15.0 - radius * math.sin(facing), radius, facing - half_angle, facing + half_angle,
            draw(st.booleans()), 0.0, draw(st.floats(-14, 4)), 0.0)


_ANY_ARC = st.one_of(_XY_ARC, _XY_ARC, _XY_ARC, _wide_arc())


def _xy_arcs(drawn, longest=4.0, rise=0.5):
    from ncverify.xy_arcs import XYArcs

    rows = numpy.array([[cx + r * math.cos(a), cy + r * math.sin(a), z, cx + (r + off) * math.cos(b), cy + (r + off) * math.sin(b), z + climb, cx, cy]
                        for cx, cy, r, a, b, _, off, z, climb in drawn])
    clockwise = numpy.array([arc[5] for arc in drawn])
    arcs, arc = XYArcs.of(rows[:, 0:3], rows[:, 3:6], rows[:, 6:8], clockwise, longest, rise)
    return arcs, arc, rows, clockwise


def _arc_points(start, end, centre, clockwise, count=20001):
    """Points along the arc from ``start`` to ``end`` (on the circle through ``start``), by angle,
    and its length seen from above."""
    radius = math.hypot(start[0] - centre[0], start[1] - centre[1])
    begin = math.atan2(start[1] - centre[1], start[0] - centre[0])
    finish = math.atan2(end[1] - centre[1], end[0] - centre[0])
    sweep = ((begin - finish) if clockwise else (finish - begin)) % (2 * math.pi) or 2 * math.pi
    angles = begin + (-1 if clockwise else 1) * sweep * numpy.linspace(0.0, 1.0, count)
    return numpy.column_stack([centre[0] + radius * numpy.cos(angles), centre[1] + radius * numpy.sin(angles)]), radius * sweep


@settings(max_examples=80, deadline=None)
@given(st.lists(_XY_ARC, min_size=1, max_size=4), st.lists(st.tuples(st.floats(-20, 60), st.floats(-20, 50)), min_size=1, max_size=20))
def test_a_point_s_distance_from_an_arc_s_parts_is_its_least_distance_from_the_arc_sampled_densely(drawn, sampled):
    """Each arc cut into parts (of a half turn, 4 mm and half a millimetre's climb at
    most): the nearest part is as near as the arc sampled, and the parts' lengths add up to
    the arc's along its helix."""
    arcs, arc, rows, clockwise = _xy_arcs(drawn)
    points = numpy.array(sampled)
    for k, row in enumerate(rows):
        along, flat_length = _arc_points(row[0:2], row[3:5], row[6:8], clockwise[k])
        sampled_distance = numpy.hypot(points[:, :1] - along[None, :, 0], points[:, 1:] - along[None, :, 1]).min(axis=1)
        parts = numpy.flatnonzero(arc == k)
        got = numpy.min([arcs.distance(numpy.full(len(points), part), points[:, 0], points[:, 1]) for part in parts], axis=0)
        step = flat_length / 20000
        assert (got <= sampled_distance + 1e-9).all() and (got >= sampled_distance - step / 2 - 1e-9).all()
        assert arcs.length[parts].sum() == pytest.approx(math.hypot(flat_length, drawn[k][8]))
        assert arcs.low[parts].min() == min(row[2], row[5]) and arcs.high[parts].max() == max(row[2], row[5])
        assert (arcs.high[parts] - arcs.low[parts] <= 0.5 + 1e-9).all() and (arcs.length[parts] <= numpy.hypot(4.0, 0.5) + 1e-9).all()
        assert (arcs.drift[parts] == pytest.approx(abs(drawn[k][6]), abs=1e-9))


def _every_cell_near_arcs(piece, arcs, reach):
    rows, columns = numpy.divmod(numpy.arange(piece.nx * piece.ny), piece.nx)
    found = []
    for k in range(len(arcs)):
        distance = arcs.distance(numpy.full(len(rows), k), piece._x(columns), piece._y(rows))
        near = numpy.flatnonzero(distance <= reach + arcs.drift[k])
        found.append((numpy.full(len(near), k), near, distance[near]))
    return [numpy.concatenate(column) for column in zip(*found)]


def _laps(drawn):
    """Each drawn arc (with how many laps) repeated that many times, a millimetre deeper each lap."""
    return [(*arc[:7], arc[7] - lap, arc[8]) for arc, laps in drawn for lap in range(laps)]


@settings(max_examples=150, deadline=None)
@given(_GRIDS, st.lists(st.tuples(_ANY_ARC, st.integers(1, 3)), min_size=1, max_size=6), st.floats(0, 6), st.sampled_from([1 << 18, 7, 40]),
       st.sampled_from([0.3, 4.0, 1e9]))
def test_the_cells_near_each_arc_are_those_every_cell_measured_finds_in_the_same_order(grid, drawn, reach, chunk, longest):
    """The spans where each row crosses an arc's annulus, inside its box, hold every cell
    the arc's distance finds near it, in chunks of every size; an arc's laps at other
    heights (measured once, their cells handed on) too, and arcs of circles of up to a
    kilometre's radius, whose annulus is worked out from squares of a million and more."""
    from ncverify import workpiece

    piece = Workpiece(*grid)
    arcs, _, _, _ = _xy_arcs(_laps(drawn), longest)
    with patch.object(workpiece, "_CHUNK_CELLS", chunk):
        found = [numpy.concatenate(column) for column in zip(*(near.each_piece() for near in piece._cells_near_arcs(arcs, reach)))]
    for got, wanted in zip(found, _every_cell_near_arcs(piece, arcs, reach)):
        assert numpy.array_equal(got, wanted)


def _sweep_arcs_every_cell(piece, arcs, cutter):
    """The arc sweep written plainly: each part against every cell of the grid."""
    from ncverify.workpiece import _sink

    z_low, z_high = (numpy.clip(heights, *piece._slab(cutter)) for heights in (arcs.low, arcs.high))
    owner, flat, distance = _every_cell_near_arcs(piece, arcs, cutter.radius + piece.half_diagonal)
    outer = numpy.maximum(distance - piece.half_diagonal - arcs.drift[owner], 0.0)
    touched = outer <= cutter.radius
    surface_low = z_low[owner] + cutter.lowest_lift(outer)
    may_cut = numpy.zeros(len(arcs), bool)
    may_cut[owner[touched & (piece.upper.reshape(-1)[flat] > surface_low)]] = True
    inner = distance + piece.half_diagonal + arcs.drift[owner]
    covered = inner <= cutter.radius
    _sink(piece.upper, flat[covered], z_high[owner][covered] + cutter.lift(inner[covered]), up=True)
    _sink(piece.lower, flat[touched], surface_low[touched], up=False)
    for field in (piece.upper, piece.lower):
        field[field <= piece.bottom] = NO_MATERIAL
    return float(arcs.length[~may_cut].sum())


@settings(max_examples=60, deadline=None)
@given(_SWEPT, st.lists(st.tuples(_ANY_ARC, st.integers(1, 3)), min_size=1, max_size=6))
def test_arcs_swept_leave_the_field_and_air_that_every_cell_measured_against_every_part_leaves(cutter, drawn):
    """Arcs and helices above, through and below the blank, some lapped at other heights,
    each time over judged against what the time before cut."""
    from ncverify import workpiece

    piece, plain = Workpiece(BLANK, 0.5), Workpiece(BLANK, 0.5)
    arcs, _, _, _ = _xy_arcs(_laps(drawn))
    for _ in range(2):
        with patch.object(workpiece, "_CHUNK_CELLS", 1 << 40):  # one step, as the plain sweep judges the air
            assert piece.cut_arcs(arcs, cutter) == _sweep_arcs_every_cell(plain, arcs, cutter)
        assert numpy.array_equal(piece.upper, plain.upper) and numpy.array_equal(piece.lower, plain.lower)


@settings(max_examples=40, deadline=None)
@given(st.floats(0.3, 12), st.floats(0, 6.28), st.floats(-6.28, 6.28), st.booleans(), cutters, st.sampled_from([0.25, 0.5, 1.0]),
       st.sampled_from([0.0, -1.5, 3.0, -40.0]), st.sampled_from([0.0, 0.0, 0.05, -0.2]))
def test_an_arc_s_or_a_helix_s_bounds_hold_the_material_sampled_by_brute_force(radius, begin, finish, clockwise, cutter, resolution, climb, off):
    """Arcs, helices (one falling 40 mm through the blank, past the parts' limit: its parts
    climb more than a cell each) and arcs whose end lies off their circle (the path then spirals from
    the start's radius to the end's, as controls that accept it move). An end off the
    circle on the start's own ray is left out: whether that is a full turn or none is
    decided by the last bit of an arc tangent, which numpy's and math's may round apart."""
    from ncverify.xy_arcs import XYArcs

    assume(off == 0.0 or abs(math.remainder(finish - begin, 2 * math.pi)) > 1e-9)

    centre = (20.0, 15.0)
    start = (centre[0] + radius * math.cos(begin), centre[1] + radius * math.sin(begin), -2.5)
    end = (centre[0] + (radius + off) * math.cos(finish), centre[1] + (radius + off) * math.sin(finish), -2.5 + climb)
    piece = Workpiece(BLANK, resolution)
    piece.cut_arcs(XYArcs.of(numpy.array([start]), numpy.array([end]), numpy.array([centre]), numpy.array([clockwise]), 8 * resolution, resolution)[0], cutter)
    along, _ = _arc_points(start, end, centre, clockwise, count=600)
    spiral = 1.0 + off / radius * numpy.linspace(0.0, 1.0, len(along))[:, None]
    dense = numpy.column_stack([centre + (along - centre) * spiral, numpy.linspace(-2.5, -2.5 + climb, len(along))])
    sample = numpy.column_stack([numpy.random.default_rng(5).uniform(0, 40, 300), numpy.random.default_rng(6).uniform(0, 30, 300)])
    tops = true_top(sample, list(zip(dense[:-1], dense[1:])), cutter, 0.0, samples=40)
    rows, columns = (sample[:, 1] / resolution).astype(int), (sample[:, 0] / resolution).astype(int)
    present = tops > BLANK.z_range[0]  # below the blank's bottom nothing is left, whatever the depth
    assert (piece.upper[rows, columns][present] >= tops[present] - 0.02).all()
    assert (piece.lower[rows, columns][present] <= tops[present] + 0.02).all()


def test_an_arc_of_a_kilometre_s_radius_or_a_helix_a_kilometre_high_is_cut_into_few_parts():
    """A typing slip in a radius or a depth must not make millions of pieces: past 64 parts
    for its length and climb, an arc's parts grow instead (a half turn still splits)."""
    from ncverify.xy_arcs import XYArcs

    starts = numpy.array([[1e6, 0.0, 0.0], [5.0, 0.0, 1e6], [5.0, 0.0, 0.0]])
    ends = numpy.array([[1e6, 0.0, 0.0], [5.0, 0.0, 0.0], [-5.0, 0.0, -0.1]])
    arcs, arc = XYArcs.of(starts, ends, numpy.zeros((3, 2)), numpy.array([True, False, False]), 8.0, 0.5)
    assert numpy.bincount(arc).tolist() == [64, 64, 2]
    assert arcs.length[arc == 0].sum() == pytest.approx(2 * math.pi * 1e6)
    assert arcs.low[arc == 1].min() == 0.0 and arcs.high[arc == 1].max() == 1e6


def test_an_arc_whose_end_lies_off_its_circle_or_on_its_centre_is_left_to_the_chords():
    from ncverify.xy_arcs import measurable

    centre = numpy.array([[0.0, 0.0]] * 4)
    starts = numpy.array([[5.0, 0.0], [5.0, 0.0], [5.0, 0.0], [0.0, 0.0]])
    ends = numpy.array([[0.0, 5.06], [0.0, 5.07], [0.0, 0.0], [0.0, 5.0]])
    assert measurable(starts, ends, centre, 0.5, 1e9).tolist() == [True, False, False, False]
    assert measurable(starts + 2e9, ends + 2e9, centre + 2e9, 0.5, 1e9).tolist() == [False] * 4


def test_a_rapid_through_cells_that_stick_out_past_the_blank_is_no_sure_hit():
    """The last column's cells reach past the far side: a rapid there, outside the blank, may
    meet material (the cell may hold it) but surely does not, while one a cell inside does."""
    piece = Workpiece(Stock.box((0, 40.3), (0, 30.2), (-10, 0)), 0.5)
    assert piece.rapid((40.45, 10.0, -1.0), (40.45, 20.0, -1.0), Cutter(0.05)).outcome == "unsure"
    assert piece.rapid((10.0, 30.45, -1.0), (20.0, 30.45, -1.0), Cutter(0.05)).outcome == "unsure"
    assert piece.rapid((39.0, 10.0, -1.0), (39.0, 20.0, -1.0), Cutter(0.05)).outcome == "hits"


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 5), st.integers(0, 60)), max_size=40), st.sampled_from([1, 30, 100, 1 << 18]))
def test_chunks_by_path_count_each_path_once_and_keep_the_pieces_in_order(pieces, budget):
    """Consecutive chunks of every piece, in order; a chunk counts each path's window once
    (its first piece's), stays within the budget unless one path alone passes it, and ends
    only where the next piece's new path would pass it."""
    from ncverify import workpiece

    words = numpy.array([path for path, _ in pieces], numpy.uint64)
    sizes = numpy.array([size for _, size in pieces], numpy.int64)
    with patch.object(workpiece, "_CHUNK_CELLS", budget):
        chunks = [chunk.tolist() for chunk in workpiece._chunks_by_path(sizes, words)]
    assert [index for chunk in chunks for index in chunk] == list(range(len(pieces)))
    for number, chunk in enumerate(chunks):
        counted = {}
        for index in chunk:
            counted.setdefault(pieces[index][0], pieces[index][1])
        assert sum(counted.values()) <= budget or len(counted) == 1
        if number + 1 < len(chunks):
            path, size = pieces[chunks[number + 1][0]]
            assert path not in counted and sum(counted.values()) + size > budget


@settings(max_examples=60, deadline=None)
@given(st.sampled_from([Cutter(1.5), Cutter(0.3), Cutter(2.0, known=False)]), _paths(), st.lists(st.floats(-9, 2), min_size=2, max_size=5),
       st.sampled_from([7, 40, 300]))
def test_laps_in_chunks_filled_by_path_leave_the_field_every_cell_measured_leaves(cutter, path, depths, chunk):
    """A profile's laps fill a chunk once for a flat lowest surface: in chunks of every size
    the field is the one measuring every lap leaves."""
    from ncverify import workpiece

    piece, plain = Workpiece(BLANK, 0.5), Workpiece(BLANK, 0.5)
    starts, ends = (numpy.concatenate([points * [2.0, 2.0, 1.0] + [20.0, 15.0, depth] for depth in depths]) for points in path)
    with patch.object(workpiece, "_CHUNK_CELLS", chunk):
        piece.cut(starts, ends, cutter, 0.0, joined=False)
    _sweep_every_cell(plain, starts, ends, cutter, 0.0, joined=False)
    assert numpy.array_equal(piece.upper, plain.upper) and numpy.array_equal(piece.lower, plain.lower)


_OPERATIONS = st.lists(st.one_of(
    st.tuples(st.just("lines"), cutters, st.lists(st.tuples(points, points), min_size=1, max_size=4)),
    st.tuples(st.just("path"), cutters, _paths(), st.floats(0, 0.05)),
    st.tuples(st.just("arcs"), cutters, st.lists(st.tuples(_ANY_ARC, st.integers(1, 2)), min_size=1, max_size=4)),
    st.tuples(st.just("rapid"), cutters, points, points),
    st.tuples(st.just("beside"), cutters, cutters, points, st.floats(0, 5), st.floats(0, 1.3), st.floats(-2, 2)),
    st.tuples(st.just("anywhere")), st.tuples(st.just("fork")),
), min_size=1, max_size=12)


@settings(max_examples=120, deadline=None)
@given(_GRIDS, _OPERATIONS, st.sampled_from([(1 << 28, 1), (100, 1), (2000, 1), (1 << 28, 3)]))
def test_deferred_sweeps_answer_every_rapid_and_leave_every_cell_as_sweeping_each_cut_in_turn(grid, operations, bounds):
    """A deferred workpiece applies a cut only where a rapid looks (or when too much
    waits): each rapid gets the verdict the workpiece that sweeps every cut at once gives,
    and once everything is applied both fields are the same to the bit; a fork's copy
    too, whatever the original cut after it. Tiny bounds on the bytes that wait apply the
    oldest sweeps part-way through; sweeps of one move are kept (the smallest kept
    otherwise is larger than these), or only those of three and more. The bytes counted
    are those the waiting sweeps hold."""
    from ncverify import workpiece

    eager, deferred = Workpiece(*grid), Workpiece(*grid, deferred=True)
    deferred._most_waiting = bounds[0]  # bytes
    forks = []
    with patch.object(workpiece, "_FEWEST_DEFERRED", bounds[1]), numpy.errstate(all="ignore"):
        for kind, *given_ in operations:
            if kind == "lines":
                cutter, moves = given_
                starts, ends = numpy.array([move[0] for move in moves], float), numpy.array([move[1] for move in moves], float)
                assert deferred.cut(starts, ends, cutter) is None
                eager.cut(starts, ends, cutter)
            elif kind == "path":
                cutter, (starts, ends), stray = given_
                deferred.cut(starts, ends, cutter, stray)
                eager.cut(starts, ends, cutter, stray)
            elif kind == "arcs":
                cutter, drawn = given_
                arcs, _, _, _ = _xy_arcs(_laps(drawn))
                assert deferred.cut_arcs(arcs, cutter) is None
                eager.cut_arcs(arcs, cutter)
            elif kind in ("rapid", "beside"):
                if kind == "beside":  # a short cut, then a rapid beside it, as far off as the two tools' reach and a little more
                    cutter, rapid_cutter, (x, y, z), length, apart, below = given_
                    for piece in (eager, deferred):
                        piece.cut([(x, y, z)], [(x + length, y, z)], cutter)
                    apart *= cutter.radius + rapid_cutter.radius + 2 * eager.resolution
                    cutter, start, end = rapid_cutter, (x, y + apart, z + below), (x + length, y + apart, z + below)
                else:
                    cutter, start, end = given_
                assert deferred.rapid(start, end, cutter) == eager.rapid(start, end, cutter)
                looked_at = _cells_within(eager, start, end, cutter.radius + eager.half_diagonal)
                for field in ("upper", "lower"):
                    assert numpy.array_equal(getattr(eager, field)[looked_at], getattr(deferred, field)[looked_at])
            elif kind == "anywhere":
                deferred.cut_anywhere()
                eager.cut_anywhere()
            else:
                forks.append((eager.copy(), deferred.copy()))
            assert deferred._waiting.nbytes == sum(waiting.nbytes for waiting in deferred._waiting.sweeps)
        for first, second in [(eager, deferred), *forks]:
            second.settle()
            assert numpy.array_equal(first.upper, second.upper) and numpy.array_equal(first.lower, second.lower)
            assert not second._waiting and second._waiting.nbytes == 0 and len(second._waiting.boxes) == 0


def _cells_within(piece, start, end, reach):
    """(rows, columns) of the cells whose centres lie within ``reach`` of the XY path start-end."""
    rows, columns = numpy.indices((piece.ny, piece.nx))
    distance = distance_to_segment(piece._x(columns.reshape(-1)), piece._y(rows.reshape(-1)), numpy.array([start[:2]]), numpy.array([end[:2]]))
    return (distance <= reach).reshape(rows.shape)


def test_a_deferred_cut_far_from_a_rapid_waits_and_one_under_it_is_applied():
    """The rapid's question applies the cuts that reach the cells it looks at, no others;
    a cut of a few moves is applied at once."""
    from ncverify import workpiece

    piece = Workpiece(BLANK, 0.5, deferred=True)
    cutter, smaller = Cutter(2.0), Cutter(1.0)
    piece.cut([(20.0, 15.0, -2.0)], [(21.0, 15.0, -2.0)], cutter)
    assert not piece._waiting and piece.upper[30, 40] == -2.0
    with patch.object(workpiece, "_FEWEST_DEFERRED", 1):
        piece.cut([(5.0, 5.0, -2.0)], [(10.0, 5.0, -2.0)], cutter)
        piece.cut([(30.0, 25.0, -2.0)], [(35.0, 25.0, -2.0)], cutter)
    assert piece.rapid((5.0, 5.0, -1.0), (10.0, 5.0, -1.0), smaller).outcome == "clear"
    assert [(waiting.size, waiting.boxes) for waiting in piece._waiting.sweeps] == [(1, None)]  # the far one still waits, its move not even made a piece
    assert piece.rapid((30.0, 25.0, -1.0), (35.0, 25.0, -1.0), smaller).outcome == "clear"
    assert not piece._waiting
    assert piece.rapid((20.0, 20.0, -1.0), (21.0, 20.0, -1.0), smaller).outcome == "hits"


_AIR = ("(ncverify: stock box X0:100 Y0:100 Z-20:0)\n(ncverify: tool 1 radius 4 type endmill)\nG21 G90 G17 G54\nT1 M06\nG43 H01 Z50.\n"
        "S6000 M03\nG00 X10. Y50.\nZ0.5\nG01 X90. F200.\nZ-5.\nX10.\nG00 Z50.\nM30\n")


def test_the_air_statistic_is_reported_when_asked_for_on_the_command_line_or_in_the_project_file(tmp_path, capsys):
    """The first feed move runs 0.5 mm above the blank: its 80 mm cut only air, of the
    165.5 mm fed (then a plunge and a slot). A plain check does not judge air (its sweeps
    wait for a rapid that needs them) and says nothing of it."""
    from ncverify.cli import main

    program = tmp_path / "slot.nc"
    program.write_text(_AIR)
    outputs = {}
    for name, arguments in (("plain", []), ("asked", ["--air-cutting"])):
        main(["check", str(program), "--no-cache", "--format", "json", "--output", str(tmp_path / f"{name}.json"), *arguments])
        outputs[name] = json.loads((tmp_path / f"{name}.json").read_text())
    assert "air_cutting" not in outputs["plain"]["files"][0]
    assert outputs["asked"]["files"][0]["air_cutting"] == {"T1": {"feed_mm": 165.5, "air_mm": 80.0}}
    outputs["asked"]["files"][0].pop("air_cutting")
    assert outputs["plain"] == outputs["asked"]
    (tmp_path / "ncverify.toml").write_text("[settings]\nair_cutting = true\n")
    main(["check", str(program), "--no-cache"])
    assert f"{program}: note: feed moves that cut only air, per tool: T1 48% of 166 mm" in capsys.readouterr().out


def test_the_project_file_takes_only_true_or_false_for_the_air_statistic(tmp_path):
    from ncverify.project import ConfigError, load_project_text

    assert load_project_text("[settings]\nair_cutting = false\n", tmp_path / "ncverify.toml").settings == {"air_cutting": False}
    with pytest.raises(ConfigError, match="expected a bool"):
        load_project_text("[settings]\nair_cutting = 1\n", tmp_path / "ncverify.toml")
