"""Tool-fits-the-feature geometry (``ncverify.pocket``): pockets, slots, bores, contours."""
from __future__ import annotations

import math

import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from ncverify.pocket import arc_points, circle_fit, clearing_radius, outline, polygon_fit, rectangle_fit, slot_fit

_L_SHAPE = shapely.Polygon([(0, 0), (40, 0), (40, 6), (6, 6), (6, 40), (0, 40)])  # two 6 mm wide arms


def test_a_tool_narrower_than_the_arms_of_an_l_pocket_reaches_everything():
    assert polygon_fit(_L_SHAPE, 2.9).fits


def test_a_tool_wider_than_the_arms_misses_their_ends_and_says_which_radius_would_do():
    fit = polygon_fit(_L_SHAPE, 3.5)
    assert not fit.fits
    assert fit.unreached and all(_L_SHAPE.exterior.distance(shapely.Point(spot)) < 1e-6 for spot in fit.unreached)
    assert 2.99 <= fit.largest_radius <= 3.0
    assert "diameter 7" in fit.reason


def test_a_tool_larger_than_the_pocket_cannot_enter():
    fit = polygon_fit(shapely.box(0, 0, 40, 30), 16)
    assert not fit.fits and fit.unreached == [] and "cannot enter" in fit.reason
    assert 14.9 <= fit.largest_radius <= 15.0


def test_the_gap_between_an_island_and_the_wall_limits_the_tool():
    pocket = shapely.box(0, 0, 50, 50).difference(shapely.box(20, 20, 30, 30))  # 20 mm gaps
    assert polygon_fit(pocket, 9.9).fits
    fit = polygon_fit(pocket, 11)
    assert not fit.fits and fit.unreached
    assert 9.9 <= fit.largest_radius <= 10.0


def test_a_programmed_fillet_smaller_than_the_tool_is_left_uncut():
    pocket = shapely.box(2, 2, 38, 28).buffer(2, quad_segs=16)  # corner radius 2
    assert polygon_fit(pocket, 1.9).fits
    fit = polygon_fit(pocket, 5)
    assert not fit.fits and len(fit.unreached) == 4
    assert 1.9 <= fit.largest_radius <= 2.01  # the fillet is drawn in 5.6 degree chords


def test_sharp_corners_between_arcs_are_filled_like_straight_ones():
    """The lens two overlapping circles share and the crescent one leaves of the other have
    sharp corners between arcs: every tool that fits leaves only its own fillet there."""
    first = outline((20.0, 50.0), [("arc", (20.0, 50.0), (40.0, 50.0), False)])
    second = outline((80.0, 50.0), [("arc", (80.0, 50.0), (60.0, 50.0), False)])
    for pocket in (first.intersection(second), first.difference(second)):
        assert all(polygon_fit(pocket, radius).fits for radius in (1, 5, 8))


def test_the_end_of_a_slot_narrower_than_the_tool_is_no_fillet_however_short():
    for length in (20, 4):
        pocket = shapely.box(0, 0, 40, 40).union(shapely.box(40, 18, 40 + length, 22))  # 4 mm wide
        assert polygon_fit(pocket, 1.9).fits
        fit = polygon_fit(pocket, 5)
        assert not fit.fits and 1.99 <= fit.largest_radius <= 2.0
        assert [round(clearing_radius(pocket, spot), 2) for spot in fit.unreached] == [2.0]


def test_a_full_circle_outline_is_a_circular_pocket():
    circle = outline((10.0, 0.0), [("arc", (10.0, 0.0), (0.0, 0.0), False)])
    assert math.isclose(circle.area, math.pi * 100, rel_tol=0.01)
    assert polygon_fit(circle, 9.9).fits
    assert not polygon_fit(circle, 10.5).fits


def test_arc_points_run_the_requested_way_round():
    clockwise = arc_points((10.0, 0.0), (0.0, 10.0), (0.0, 0.0), True)  # the long way: 270 degrees
    counter = arc_points((10.0, 0.0), (0.0, 10.0), (0.0, 0.0), False)  # the short way: 90 degrees
    assert len(clockwise) > 2 * len(counter)
    assert clockwise[0][1] < 0 < counter[0][1]
    assert clockwise[-1] == counter[-1] == (0.0, 10.0)


def test_feature_fits_answer_the_largest_tool_and_respect_strictness():
    assert rectangle_fit(40, 20, 0, 10).fits and not rectangle_fit(40, 20, 0, 10, strict=True).fits
    corner = rectangle_fit(40, 20, 3, 5)
    assert not corner.fits and corner.largest_radius == 3 and "corner radius 3" in corner.reason
    assert circle_fit(20, 10).fits and not circle_fit(20, 10.5).fits and circle_fit(20, 10.5).largest_radius == 10
    assert not slot_fit(8, 4.5).fits and slot_fit(8, 4.5).largest_radius == 4


_SIDES = st.floats(min_value=2.0, max_value=200.0, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(length=_SIDES, width=_SIDES, share=st.floats(min_value=0.05, max_value=1.2))
def test_a_sharp_rectangle_as_a_polygon_agrees_with_the_rectangle_rule(length, width, share):
    radius = share * min(length, width) / 2.0
    if abs(share - 1.0) < 1e-3:
        return  # the tool exactly as wide as the pocket: both answers are borderline
    assert polygon_fit(shapely.box(0, 0, length, width), radius).fits == rectangle_fit(length, width, 0, radius).fits


@settings(max_examples=40, deadline=None)
@given(points=st.lists(st.tuples(st.integers(0, 60), st.integers(0, 60)), min_size=3, max_size=8, unique=True),
       radius=st.floats(min_value=0.2, max_value=10.0))
def test_a_smaller_tool_fits_wherever_a_larger_one_does(points, radius):
    pocket = shapely.Polygon(points).buffer(0)
    if pocket.geom_type != "Polygon" or pocket.area < 1.0:
        return
    if polygon_fit(pocket, radius).fits:
        assert polygon_fit(pocket, radius * 0.8).fits
    else:
        assert polygon_fit(pocket, radius).largest_radius <= radius * 1.001
