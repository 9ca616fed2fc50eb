"""Stage 4, check: rules read the interpreted trace and report findings.

Rule *definitions* (id, category, default severity, page, parameter constraints) are data
in ``rules/``; rule *logic* that needs more than a constraint is a class in
``ncverify/checks/`` registered with :func:`rule`. The :class:`Checker` is the
interpreter's observer: it hands each trace event to the rules that handle it.
"""
from __future__ import annotations

import ast
from dataclasses import replace

from . import modelled, values
from .material import Material
from .context import RuleContext
from .dialect import DIALECTS
from .diagnostics import Diagnostic, Severity, Status, Suppressed
from .rule_pages import Constraint, RuleDefinition, RuleFileError, parse_rule_file, rule_definitions  # noqa: F401  (re-exported)
from .source import Span
from .verdict import Verdict, evaluate_constraint, hazard, judge, show  # noqa: F401  (hazard, show: re-exported for the rules)

# --------------------------------------------------------------------------- rule logic

_RULE_CLASSES: list[type] = []

# Segment.kind values, and those that move at a feed
SEGMENT_KINDS = frozenset({"rapid", "feed", "arc", "thread"})
CUTTING = frozenset({"feed", "arc", "thread"})
ARCS = frozenset({"arc"})


def rule(*ids: str):
    """Register a rule class reporting the given rule ids. Unless the class declares its
    ``dialects``, they are the dialect its ids are named after (``heidenhain.usable-length``
    judges Klartext programs only); a ``core.`` rule judges every dialect."""

    def register(cls):
        cls.ids = ids
        if "dialects" not in vars(cls):
            cls.dialects = _dialects_named_in(ids)
        _RULE_CLASSES.append(cls)
        return cls

    return register


def _dialects_named_in(ids: tuple[str, ...]) -> frozenset | None:
    prefixes = frozenset(rule_id.split(".", 1)[0] for rule_id in ids)
    return prefixes if prefixes <= DIALECTS.keys() else None


def in_scope(rule_class: type, dialect: str | None, machine: str | None = None) -> bool:
    """Can the rule class judge a program of ``dialect`` on a ``machine`` (``mill``,
    ``lathe``)? A rule of another dialect waits for cycles, state or words only that
    dialect's lowering and run time produce, a lathe rule for a lathe, so it is not asked
    at all (not once per move and hole). What is not known (None) leaves every rule in."""
    return ((dialect is None or rule_class.dialects is None or dialect in rule_class.dialects)
            and (machine is None or rule_class.machines is None or machine in rule_class.machines))


def rule_classes() -> list[type]:
    """Every registered rule class, in registration order (the order events reach them).
    The package :mod:`ncverify.checks` registers them when it is imported, which the
    package's own import does (through :mod:`ncverify.api`), before any checker exists."""
    return _RULE_CLASSES



class Rule:
    """Base of rule classes. Override the event methods a rule needs; per-path memory goes
    in ``state.rule_state`` so that forked paths do not share it."""

    ids: tuple[str, ...] = ()
    # The kinds of machine state this rule's proofs account for (ncverify.modelled);
    # under any other that is active, its proved becomes unknown. Nothing by default.
    reads: frozenset = frozenset()
    # The kinds of segment its ``segment`` handler judges: the checker hands it no other. A
    # rule narrows it where the handler would return at once on the rest (moves are many).
    segment_kinds: frozenset = SEGMENT_KINDS
    # Does ``motion_run`` judge arcs (kinds 2 and 3, ``run.arcs``) itself? Otherwise it gets
    # a run's stretches of straight moves, and ``segment`` each arc between them.
    handles_arcs: bool = False
    # Does ``motion_run`` judge a run of canned-cycle moves (``run.cycle_moves``) as
    # ``segment`` judges each of them, by its role and cycle? Only then do a hole pattern's
    # moves reach the rules as runs (:attr:`Checker.gathers_hole_moves`).
    judges_cycle_runs: bool = False
    # Does ``hole`` read nothing the moves before the hole change (the cut stock, what other
    # handlers keep in ``state.rule_state``)? Only then may a hole of a pattern reach it while
    # the moves of the holes before it wait to reach the rules as one run. One that reads the
    # cut stock now and then calls ``checker.hand_on_held_moves()`` first.
    judges_holes_before_moves: bool = False
    # The dialects whose programs it judges (None: every dialect; see :func:`rule`) and the
    # machine types it judges them on (None: every type): the checker asks no other.
    dialects: frozenset | None = None
    machines: frozenset | None = None

    def __init__(self, checker: "Checker"):
        self.checker = checker
        self.report = checker.report

    @staticmethod
    def first_time(state, key) -> bool:
        """True the first time ``key`` is seen on this path (one finding per cycle
        definition, per episode ...)."""
        if key in state.rule_state:
            return False
        state.rule_state[key] = True
        return True

    def word(self, key: str, form: str = "{}") -> str:
        """The control's own word for ``key`` (``dialects/<dialect>/wording.toml``) put into
        ``form``, or "" when this dialect has none."""
        found = self.checker.context.wording.get(key)
        return form.format(found) if found else ""

    def segment(self, segment, state): ...

    def motion_run(self, run, state): ...

    def hole(self, hole, state): ...

    def cycle_run(self, run, state): ...

    def change(self, change, state): ...

    def finish(self): ...


# --------------------------------------------------------------------------- the observer


class Checker:
    """Collects findings from the trace: dedups them, caps them per rule, applies the
    configured severities and disabled rules."""

    def __init__(self, settings, context: RuleContext, severity_overrides: dict | None = None, suppressions: dict | None = None):
        self.settings = settings
        self.context = context  # stock, tools, machine, register limits: what rules may assume
        self.suppressions = suppressions or {}  # line -> rule ids / categories from "ignore" annotations
        self.suppressed: list[Suppressed] = []
        self.definitions = rule_definitions()
        self.severity_overrides = severity_overrides or {}
        self.diagnostics: list[Diagnostic] = []
        self._seen: set = set()
        self._per_rule: dict[str, int] = {}
        self.truncated: dict[str, int] = {}
        self.path_condition: list = []
        self.material = Material(self)
        self.call_site = lambda: None  # the interpreter's: where the checked file called into another
        # the interpreter's: hands on the moves it holds back to give the rules as one run (a
        # hole pattern's), so that the cut stock holds them before a hole is judged against it
        self.hand_on_held_moves = lambda: None
        self.unexplored: str | None = None  # why some path was not followed to its end (no proof covers it)
        rules = [cls(self) for cls in rule_classes() if not set(cls.ids) <= settings.disabled_rules and in_scope(cls, context.dialect, context.machine.kind)]
        self.rules = rules
        self._segment = _handlers(rules, "segment")
        self._segment_by_kind = {kind: [instance.segment for instance in rules if _overrides(instance, "segment") and kind in instance.segment_kinds]
                                 for kind in SEGMENT_KINDS}
        self._motion_run = _handlers(rules, "motion_run")
        self._arc_run = [instance.motion_run for instance in rules if _overrides(instance, "motion_run") and instance.handles_arcs]
        self._straight_run = [instance.motion_run for instance in rules if _overrides(instance, "motion_run") and not instance.handles_arcs]
        self._arc_segment = [instance.segment for instance in rules
                             if _overrides(instance, "motion_run") and not instance.handles_arcs and _overrides(instance, "segment")
                             and "arc" in instance.segment_kinds]
        self._segment_only = [instance.segment for instance in rules if _overrides(instance, "segment") and not _overrides(instance, "motion_run")]
        self._hole = _handlers(rules, "hole") + [self._constraints_on_hole]
        # A hole pattern's moves may reach the rules as runs when every rule that judges moves
        # judges cycle runs alike and every rule that judges holes may see one before the moves
        # ahead of it (the rule constraints on holes read the hole's words and levels alone).
        self.gathers_hole_moves = (all(one.judges_cycle_runs for one in rules if _overrides(one, "segment") or _overrides(one, "motion_run"))
                                   and all(one.judges_holes_before_moves for one in rules if _overrides(one, "hole")))
        self._cycle_run = _handlers(rules, "cycle_run") + [self._constraints_on_run]
        self._change = _handlers(rules, "change")
        self._finish = _handlers(rules, "finish")
        self._unread = modelled.unread
        # what each rule's proofs read: its class's declaration; a constraint from rules/
        # compares cycle parameters as written; a division by zero is the value's alone
        self._reads = {rule_id: cls.reads for cls in rule_classes() for rule_id in cls.ids}
        constrained = self.definitions.constrained()
        self._reads.update({definition.id: modelled.AS_WRITTEN for definition in constrained if definition.id not in self._reads})
        self._reads.setdefault("core.arithmetic-domain", modelled.EVERY)
        self._constraints: dict[str, list] = {}  # cycle -> (definition, constraint) that judge it, in definition order
        self._kept_outcomes: dict = {}  # (cycle, concrete names) -> outcomes of its constraints (_outcomes)
        for definition in constrained:
            if definition.id in settings.disabled_rules:
                continue
            for constraint in definition.constraints:
                for cycle in dict.fromkeys(constraint.cycles):
                    self._constraints.setdefault(cycle, []).append((definition, constraint))

    def finish(self) -> None:
        """After every path: rules that report what was never seen (missing context), and
        one verdict per place: violated on any path wins over unknown, unknown over proved."""
        for handler in self._finish:
            handler()
        if self.unexplored is not None:
            self.diagnostics = [_unproved(d, self.unexplored, self._severity(self.definitions[d.rule])) if d.status is Status.PROVED else d for d in self.diagnostics]
        worst: dict[tuple, int] = {}
        rank = {Status.VIOLATED: 2, Status.UNKNOWN: 1, Status.PROVED: 0}
        for diagnostic in self.diagnostics:
            key = (diagnostic.rule, diagnostic.span)
            worst[key] = max(worst.get(key, 0), rank[diagnostic.status])
        self.diagnostics = [d for d in self.diagnostics if rank[d.status] == worst[(d.rule, d.span)]]

    # -- events from the interpreter
    def segment(self, segment, state) -> None:
        for handler in self._segment_by_kind.get(segment.kind, self._segment):
            handler(segment, state)
        self.material.segment(segment, state)  # after the rules: they judge a move against the material before it

    def motion_run(self, run, state) -> None:
        self.material.begin_run(run)
        if run.arcs is None:
            for handler in self._motion_run:
                handler(run, state)
        else:
            self._pieces_of_run(run, state)
        if self._segment_only:
            for index in range(len(run)):
                segment = run.segment(index)
                for handler in self._segment_only:
                    handler(segment, state)
        self.material.motion_run(run, state)

    def _pieces_of_run(self, run, state) -> None:
        """A run with arcs: the rules that judge arcs in runs get it whole; the others get
        its stretches of straight moves as runs and each arc as the block path's segment,
        after the material has taken the moves before it."""
        for handler in self._arc_run:
            handler(run, state)
        if not self._straight_run and not self._arc_segment:
            return  # every rule judged the arcs itself
        for start, stop, straight in run.pieces():
            if straight:
                part = run.part(start, stop)
                for handler in self._straight_run:
                    handler(part, state)
            elif self._arc_segment:
                self.material.motion_run(run, state, upto=start)
                segment = run.segment(start)
                run.state_at(segment, start)
                for handler in self._arc_segment:
                    handler(segment, state)

    def path_end(self, state) -> None:
        self.material.finish(state)

    def hole(self, hole, state) -> None:
        for handler in self._hole:
            handler(hole, state)

    def cycle_run(self, run, state) -> None:
        for handler in self._cycle_run:
            handler(run, state)

    def change(self, change, state) -> None:
        for handler in self._change:
            handler(change, state)
        if change.what == "corner_rounding":
            self.material.corner_rounded(state)

    def note(self, note) -> None:
        self.report(note.rule, note.span, note.message, Status(note.status), note.reason)

    def fault(self, fault) -> None:
        if fault.rule in _PATH_ENDS and fault.status == "unknown":
            self.unexplored = fault.reason or fault.rule
        self.report(fault.rule, fault.span, fault.message, Status(fault.status), fault.reason,
                    severity=Severity(fault.severity) if fault.severity else None)

    # -- reporting
    def report(self, rule_id: str, span: Span, message: str, status: Status = Status.VIOLATED,
               reason: str | None = None, witness: dict | None = None, severity: Severity | None = None) -> None:
        if rule_id in self.settings.disabled_rules:
            return
        definition = self.definitions.get(rule_id)
        if definition is None:
            raise KeyError(f"rule {rule_id} has no definition in rules/")
        if definition.category in self.settings.disabled_rules:
            return
        key = (rule_id, span.path, span.line, span.column, message)
        if key in self._seen:
            return
        self._seen.add(key)
        ignored = self.suppressions.get(span.line) if span.path is None else None
        if ignored and (rule_id in ignored or definition.category in ignored):
            self.suppressed.append(Suppressed(rule_id, span.line, "annotation"))
            return
        count = self._per_rule.get(rule_id, 0) + 1
        self._per_rule[rule_id] = count
        if definition.once_per_file and count > 1:
            return
        if count > self.settings.max_findings_per_rule:
            self.truncated[rule_id] = self.truncated.get(rule_id, 0) + 1
            return
        severity = self._severity(definition, severity)
        if status is Status.PROVED:
            severity = Severity.INFO
        related = self.call_site() if span.path is not None else None
        self.diagnostics.append(Diagnostic(rule_id, definition.category, severity, span, message, status, reason, witness or {}, related))

    def judge(self, condition, state) -> "Verdict | None":
        """:func:`judge` under the path's condition and the configured solver timeout."""
        return judge(condition, state.path_condition, self.settings.solver_timeout_s)

    def report_verdict(self, rule_id: str, span: Span, message: str, verdict: Verdict | None, state) -> None:
        """Report a judged hazard: violated with its witness, unknown with the reason, or a
        ``proved`` entry when symbolic values were shown safe, under state the rule reads
        (``Rule.reads``; otherwise unknown, naming the state)."""
        if verdict is None:
            return
        if verdict.status is Status.PROVED:
            unread = self._unread(state, self._reads.get(rule_id, frozenset()), self.context)
            if unread is not None:
                self.report(rule_id, span, f"not proved: {unread}, which this rule does not model: {message}", Status.UNKNOWN, f"not modelled: {unread}")
                return
            message = f"{_PROVED_PREFIX}{message}"
        self.report(rule_id, span, message, verdict.status, verdict.reason, verdict.witness)

    def _severity(self, definition: RuleDefinition, suggested: Severity | None = None) -> Severity:
        """The project file's severity for the rule or its category, else the one the rule
        suggests for this finding (a guard exit is info), else the rule's default."""
        override = self.severity_overrides.get(definition.id) or self.severity_overrides.get(definition.category)
        return Severity(override) if override else suggested or definition.severity

    # -- constraints from rules/
    def _constraints_on_hole(self, hole, state) -> None:
        if hole.cycle not in self._constraints:
            return
        names = dict(hole.params)
        names.update(initial=hole.initial, r_point=hole.r_point, bottom=hole.bottom, up=hole.up)
        if hole.r_point is not None and hole.bottom is not None:
            names["depth"] = values.mul(hole.up, values.sub(hole.r_point, hole.bottom))
        self._apply_constraints(hole.cycle, names, hole.param_spans, hole.span, state)

    def _constraints_on_run(self, run, state) -> None:
        if run.cycle not in self._constraints:
            return
        self._apply_constraints(run.cycle, dict(run.params), run.param_spans, run.span, state)

    def _apply_constraints(self, cycle: str, names: dict, spans: dict, span: Span, state) -> None:
        constraints = self._constraints.get(cycle, ())
        for (definition, constraint), outcome in zip(constraints, self._outcomes(cycle, constraints, names)):
            verdict = self.judge(outcome, state)
            if verdict is None:
                continue
            where = _first_span(constraint.tree, spans) or span
            self.report_verdict(definition.id, where, _format_message(constraint.message, names), verdict, state)

    def _outcomes(self, cycle: str, constraints, names: dict) -> list:
        """Each constraint evaluated on ``names``. Where every name is a number (or absent),
        the outcomes are kept for the next hole with the same words and levels: a pattern
        asks the same questions at each of its holes."""
        key = (cycle, tuple(names.items())) if all(value is None or type(value) is float for value in names.values()) else None
        outcomes = self._kept_outcomes.get(key) if key is not None else None
        if outcomes is None:
            outcomes = [evaluate_constraint(constraint.tree, names) for _definition, constraint in constraints]
            if key is not None:
                if len(self._kept_outcomes) >= _OUTCOMES_KEPT:
                    self._kept_outcomes.clear()
                self._kept_outcomes[key] = outcomes
        return outcomes


_OUTCOMES_KEPT = 256  # constraint outcomes kept by cycle and concrete words (Checker._outcomes)


# Faults after which the rest of a path is not analysed: a proof covers only the paths
# explored, so none stands (whether or not the rule reporting the fault is enabled).
_PATH_ENDS = ("core.path-limit", "core.loop-bound")
_PROVED_PREFIX = "proved impossible for every value of the free parameters: "


def _unproved(diagnostic: Diagnostic, why: str, severity: Severity) -> Diagnostic:
    """A ``proved`` entry turned ``unknown``: some path the proof would need was left unexplored."""
    claim = diagnostic.message.removeprefix(_PROVED_PREFIX)
    return replace(diagnostic, status=Status.UNKNOWN, severity=severity,
                   message=f"not proved: paths were left unexplored ({why}), and the hazard could happen on one of them: {claim}",
                   reason=f"paths left unexplored: {why}")


def _overrides(instance: Rule, name: str) -> bool:
    return getattr(type(instance), name) is not getattr(Rule, name)


def _handlers(rules: list[Rule], name: str) -> list:
    return [getattr(instance, name) for instance in rules if _overrides(instance, name)]


def _first_span(tree: ast.Expression, spans: dict) -> Span | None:
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and node.id in spans:
            return spans[node.id]
    return None


def _format_message(message: str, names: dict) -> str:
    class Shown(dict):
        def __missing__(self, key):
            return "(not given)"

    return message.format_map(Shown({key: show(value) for key, value in names.items() if value is not None}))
