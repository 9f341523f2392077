"""Moving lines with free ends (``docs/method.md`` section 10.4): the line's ends are junction
points that nothing holds, free to translate in 3D; and ends that slide along the line, on
supports free in plane (:func:`sliding_fold`).

The bracket: plates A (0.4 x 0.5 m) and B (0.3 x 0.5 m) of 2 mm steel folded at 90 degrees
along the line F (A rigid, B's weld log10 k = 3 with loss factor 0.1), their far edges simply
supported, their ends y = 0 and y = 0.5 m free; 1 N on A. No exact solution covers free ends,
so the checks are identities (reciprocity, power balance) and convergence under refinement.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from support import folded_description, folded_w, inner_grid
from test_moving_lines import L_FOLD, LY, _finite_element_errors

from assembly import parse_case
from solver.estimate import enriched_solve, estimate_error
from solver.guards import check_description
from solver.line_ends import free_end_plates
from solver.power import power_flow
from solver.substructure import solve_assembly

PLATES = L_FOLD[0]  # the L fold's plates, with their own weld below
LINE = {"F": {"A": ("right", math.inf), "B": ("left", 3.0)}}
ON_A, ON_B = ("A", (0.15, 0.2)), ("B", (0.21, 0.07))


def _with_free_ends(description: dict) -> dict:
    """A folded plate's ``description`` with every end ``y = 0, 0.5`` free (bending and in
    plane): its lines end free."""
    for boundary in description["boundaries"]:
        if boundary["edge"].endswith(("bottom", "top")):
            boundary["condition"] = "free"
            boundary.pop("in_plane", None)
    return description


def _bracket(frequency: float, resolution: float = 1.5, held: bool | None = None,
             load: tuple[str, tuple[float, float]] = ON_A) -> dict:
    description = _with_free_ends(folded_description(PLATES, LINE, (load[0], *load[1]),
                                                     frequency, held, LY, resolution))
    description["joints"]["F"]["loss_factor"] = {"B": 0.1}
    return description


def _w_errors(description: dict, plates: dict, reference_path: Path, key: str
              ) -> list[tuple[float, float]]:
    """Per plate of ``plates``, the error of ``w`` of ``description`` (at its frequency)
    against the finite elements of ``reference_path`` (keys ``w_<plate><key>``) on the plate's
    :func:`support.inner_grid`, and its estimate."""
    reference = np.load(reference_path)
    case = parse_case(description)
    frequency = description["frequency"]
    solution = solve_assembly(case, frequency)
    estimate = estimate_error(case, solution)
    out = []
    for name, (length, *_) in plates.items():
        w, exact = (solution.plates[name].field(inner_grid(length, LY))["w"],
                    reference[f"w_{name}{key}"])
        out.append((float(np.linalg.norm(w - exact) / np.linalg.norm(exact)),
                    estimate.plates[name]))
    return out


def _grid_w(solution) -> dict[str, np.ndarray]:
    return folded_w(solution, PLATES, LY)


def test_a_free_ended_fold_moves_by_default():
    """Its ends on free edges, the line moves without being asked and without a warning, and
    its members' edge waves reach :data:`solver.line_ends.FREE_END_REACH` times further."""
    case = parse_case(_bracket(300.0))
    assert case.moving_lines() == ("F",)
    assert check_description(case, "bracket.toml") == []
    assert free_end_plates(case) == {"A", "B"}
    assert parse_case(_bracket(300.0, held=True)).moving_lines() == ()


def test_reciprocity_across_a_free_ended_fold():
    """A unit force on A gives at a point of B what a unit force there gives on A. Measured
    at resolution 1.5: 3.2e-7 (1.0e-7 at 2.25: discretisation); tolerance 1e-5."""
    def response(source, target):
        case = parse_case(_bracket(300.0, load=source))
        return solve_assembly(case, 300.0, residuals=False).w(target[0], np.array([target[1]]))[0]

    there, back = response(ON_A, ON_B), response(ON_B, ON_A)
    assert abs(there - back) < 1e-5 * abs(there)


def test_the_power_balances_on_a_free_ended_fold():
    """Per plate, injected plus delivered equals dissipated (bending and in-plane); the
    members' deliveries balance the weld's dissipation (22 % of the injected power). Measured at
    resolution 1.5: 1.2e-7 and 6.2e-8 of the injected power on the plates, 7e-12 on the line;
    tolerances 1e-5 and 1e-9."""
    case = parse_case(_bracket(300.0))
    power = power_flow(case, solve_assembly(case, 300.0))
    injected = power.total_injected
    delivered = power.delivered["F"]
    assert power.joint_dissipated["F"] > 0.1 * injected
    assert abs(sum(delivered.values()) + power.joint_dissipated["F"]) < 1e-9 * injected
    for plate in case.plates:
        balance = power.injected[plate] + delivered[plate] - power.dissipated[plate]
        assert abs(balance) < 1e-5 * injected, (plate, balance / injected)


FINITE_ELEMENTS = Path(__file__).parent / "data" / "fem_fold_free_ends.npz"
"""``w`` and ``(u, v)`` of the L fold with a rigid line and free ends at 300 Hz on each plate's
:func:`support.inner_grid`, by the independent finite elements of ``bench/fem_folded.py``
(Argyris and P5 triangles, conforming at the fold; ``python bench/fem_folded.py
--free-ends``: level 6, ``w`` changed by 3.5e-8 and 2.6e-8 from level 4, and within 3e-8 of
a mesh graded at the far corners too, whose own error is about 5e-9; reciprocity between the
legs to 4e-9). The same at 1 kHz under keys ending ``_1000``, for
``bench/bench_free_ends.py`` (``w`` changed by 4e-7 and 6e-7 from level 4)."""


def _rigid_bracket(resolution: float) -> dict:
    """The bracket with a rigid line (both members ``inf``, no loss): the finite elements'."""
    description = _bracket(300.0, resolution)
    description["joints"]["F"] = description["joints"]["F"] | {
        "log10_stiffness": {"A": math.inf, "B": math.inf}}
    del description["joints"]["F"]["loss_factor"]
    return description


def _errors_and_estimates(resolution: float) -> list[tuple[float, float, float]]:
    """Per plate, ``(true error of w against the finite elements, estimate, true error of the
    estimate's enriched solve)``."""
    reference = np.load(FINITE_ELEMENTS)
    case = parse_case(_rigid_bracket(resolution))
    enriched = enriched_solve(case, 300.0)
    solution = solve_assembly(case, 300.0)
    estimate = estimate_error(case, solution, enriched=enriched)

    def error(fields: dict, plate: str) -> float:
        return float(np.linalg.norm(fields[plate] - reference[f"w_{plate}"])
                     / np.linalg.norm(reference[f"w_{plate}"]))

    fields = _grid_w(solution)
    finer = {p: enriched.plates[p].field(inner_grid(PLATES[p][0], LY))["w"] for p in PLATES}
    return [(error(fields, p), estimate.plates[p], error(finer, p)) for p in PLATES]


def test_a_free_ended_fold_meets_independent_finite_elements():
    """Against :data:`FINITE_ELEMENTS`, worst plate's ``w``: 5.6e-3, 2.5e-4, 1.0e-4, 2.1e-5,
    7.3e-6 at resolutions 1, 1.5, 2.25, 3.375, 5 (the free corners slow the line's loads'
    convergence; the members' reach grows with the resolution from 1.5 on,
    :data:`solver.line_ends.REACH_GROWTH_FROM`, and the line's count has a floor from 1.5 on,
    :func:`solver.joint_rules.end_layer_count`: without it 2.4e-3, 5.3e-4, 4.4e-5 at 1.5, 2.25,
    3.375); the estimate is 0.59 to 1.04 times the error on every plate at 1.5, 2.25 and 3.375:
    the issue's bounds [0.5, 3] (``bench/bench_free_ends.py --finite-elements``). Tolerances,
    about twice the measured: 5e-4 at 1.5, 2e-4 at 2.25 and 5e-5 at 3.375, where a fixed reach
    stalled at 3.4e-4, and 2e-5 for the enriched solves of 2.25 and 3.375 (resolutions 3.375
    and 5.06: 2.1e-5, 5.9e-6)."""
    bounds = {1.5: (5e-4, 2e-4), 2.25: (2e-4, 5e-5), 3.375: (5e-5, 2e-5)}
    for resolution in (1.5, 2.25, 3.375):
        for true, estimate, finer in _errors_and_estimates(resolution):
            assert 0.5 < estimate / true < 3.0, (resolution, true, estimate)
            if resolution in bounds:
                error_bound, enriched_bound = bounds[resolution]
                assert true < error_bound and finer < enriched_bound, (resolution, true, finer)


CHANNEL_PLATES = {"A": (0.4, (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), 0.002, "simply_supported"),
                  "B": (0.3, (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 0.002, "simply_supported"),
                  "C": (0.2, (0.4, 0.0, 0.0), (0.0, 0.0, 1.0), 0.002, "simply_supported")}
"""The U channel's web A and flanges B (0.3 m high, on A's left edge) and C (0.2 m, on its
right edge), 2 mm steel, 0.5 m long; the flanges' far edges simply supported, fixed in
plane."""
CHANNEL_LINES = {"AB": {"A": ("left", math.inf), "B": ("left", math.inf)},
                 "AC": {"A": ("right", math.inf), "C": ("left", math.inf)}}
ON_WEB = ("A", 0.17, 0.13)


def channel(frequency: float, resolution: float = 1.5) -> dict:
    """The U channel of :data:`CHANNEL_PLATES` joined by two rigid folds, every end ``y = 0,
    0.5`` free: both lines end free at both ends; 1 N on the web."""
    return _with_free_ends(folded_description(CHANNEL_PLATES, CHANNEL_LINES, ON_WEB, frequency,
                                              None, LY, resolution))


CHANNEL_FINITE_ELEMENTS = Path(__file__).parent / "data" / "fem_channel.npz"
"""``w`` and ``(u, v)`` of :func:`channel` at 300 Hz and 1 kHz (keys ``w_A_300``,
``uv_C_1000``, ...) on each plate's :func:`support.inner_grid`, by the independent finite
elements of ``bench/fem_channel.py`` (``python bench/fem_channel.py --write``)."""


def _channel_errors(resolution: float) -> list[tuple[float, float]]:
    """Per plate of the channel at 300 Hz, the error of ``w`` against
    :data:`CHANNEL_FINITE_ELEMENTS` and its estimate."""
    return _w_errors(channel(300.0, resolution), CHANNEL_PLATES, CHANNEL_FINITE_ELEMENTS, "_300")


def test_the_count_floor_holds_on_a_channel_of_two_free_ended_lines(monkeypatch):
    """A third structure for the count's floor (:func:`solver.joint_rules.end_layer_count`,
    set on the bracket, the sliding fold and the corner): the U channel, two lines free at both
    ends. Against :data:`CHANNEL_FINITE_ELEMENTS`, worst plate's ``w`` at resolutions 1.5, 2.25,
    3.375 (300 Hz): 5.6e-4, 2.7e-4, 5.0e-5 with the floor (25, 30, 37 functions), the
    estimates 0.55 to 1.04 times the errors; without it 6.2e-3, 1.0e-3, 1.3e-4 (16, 23, 34
    functions). Scanned at resolution 1.5, the best count is 28 to 32 (2.4e-4 to 2.8e-4), about
    4.6 to 5.2 times the square root of the reach's wavenumber times the length; 36 to 56 give
    4.8e-4 to 1.0e-3: the floor, at four times, stays below the best, as on the bracket
    (``bench/bench_free_ends.py --channel``). Checked at 1.5: below 1.2e-3 with the floor,
    above 3e-3 without, the estimates within the issue's [0.5, 3]."""
    import solver.joint_rules

    assert parse_case(channel(300.0)).moving_lines() == ("AB", "AC")
    for true, estimate in _channel_errors(1.5):
        assert true < 1.2e-3 and 0.5 < estimate / true < 3.0, (true, estimate)
    monkeypatch.setattr(solver.joint_rules, "END_LAYER_FROM", math.inf)
    assert max(true for true, _ in _channel_errors(1.5)) > 3e-3


SLIDING_FINITE_ELEMENTS = Path(__file__).parent / "data" / "fem_fold_sliding_ends.npz"
"""``w`` and ``(u, v)`` of the rigid L fold whose ends are simply supported and free in plane
(:func:`sliding_fold`) at 300 Hz and (keys ending ``_1000``) 1 kHz on each plate's
:func:`support.inner_grid`, by the finite elements of ``bench/fem_folded.py`` (``python
bench/fem_folded.py --sliding-ends``; level 4 to 6 changed ``w`` by 3.6e-8 and 6.9e-9 at 300
Hz)."""


def _with_sliding_ends(description: dict) -> dict:
    """A folded plate's ``description`` with every end ``y = 0, 0.5`` free in plane (its
    bending condition kept): its lines' ends slide."""
    for boundary in description["boundaries"]:
        if boundary["edge"].endswith(("bottom", "top")):
            boundary["in_plane"] = "free"
    return description


def sliding_fold(frequency: float, resolution: float) -> dict:
    """The L fold with a rigid line, its ends ``y = 0, 0.5`` simply supported and free in
    plane (``in_plane = "free"``): the line's ends slide along it, held across it by the
    members' bending supports alone; its far edges simply supported, 1 N on A."""
    return _with_sliding_ends(folded_description(
        PLATES, {"F": {"A": ("right", math.inf), "B": ("left", math.inf)}},
        (ON_A[0], *ON_A[1]), frequency, None, LY, resolution))


def sliding_channel(frequency: float, resolution: float) -> dict:
    """The U channel of :data:`CHANNEL_PLATES` with every end ``y = 0, 0.5`` simply supported
    and free in plane: each line's ends pin its members, and the web, held in its plane by
    neither of its ends, hangs on both lines; 1 N on the web."""
    return _with_sliding_ends(folded_description(CHANNEL_PLATES, CHANNEL_LINES, ON_WEB,
                                                 frequency, None, LY, resolution))


def test_a_fold_sliding_at_its_ends_meets_independent_finite_elements(monkeypatch):
    """A line whose ends are held across it by the members' bending supports alone, free in
    plane (``in_plane = "free"``), has the free end's slow loads: its members reach like a
    free end's (:func:`solver.line_ends.free_end_plates`). Each member's supported end holds
    the deflection that is the other's displacement across the line, so its ends are pinned
    (:func:`assembly.lines.pinned_ends`): the members carry logarithmic families there, their
    reach stops at :data:`solver.line_ends.PINNED_END_REACH`, and from resolution 1.5 the line
    has :func:`solver.joint_rules.pinned_line_count` functions (no member hangs on it: 7
    sqrt(kappa_a L)). Against :data:`SLIDING_FINITE_ELEMENTS` at 300 Hz and
    resolution 1.5, worst plate's ``w`` 7.0e-7 and ``(u, v)`` 4.6e-4, the estimates 1.34 to
    1.50 and 0.94 to 1.12 times the errors (``bench/bench_free_ends.py --sliding-ends``); with
    the usual count and the free end's floor, as in 0.3.14, 4.1e-5 and 2.7e-2, the estimate
    of ``(u, v)`` 0.45 to 0.49. At 1 kHz and 2.25, ``w`` 5.2e-7; without the families (nor
    the count, which comes with them), as until 2026-11-28, 6.3e-5. Asked: ``w`` within 3e-6
    and ``(u, v)`` within 2e-3 (about four times the measured, ten times below the usual
    count's), the estimates within the issue's [0.5, 3]; the usual count and the families'
    absence beyond 3e-6."""
    import solver.layout
    import solver.line_ends

    case = parse_case(sliding_fold(300.0, 1.5))
    assert case.moving_lines() == ("F",) and free_end_plates(case) == {"A", "B"}
    assert len(case.pinned_ends("F")) == 4 and solver.line_ends.pinned_lines(case) == {"F": False}
    reference = np.load(SLIDING_FINITE_ELEMENTS)

    def errors(frequency: float, resolution: float) -> tuple[dict, object]:
        case = parse_case(sliding_fold(frequency, resolution))
        solution = solve_assembly(case, frequency, residuals=False)
        suffix = "" if frequency == 300.0 else f"_{frequency:.0f}"
        return _finite_element_errors(solution, PLATES, reference, suffix), (case, solution)

    at_300, (case, solution) = errors(300.0, 1.5)
    estimate = estimate_error(case, solution)
    for plate, (w, uv) in at_300.items():
        assert w < 3e-6 and uv < 2e-3, at_300
        assert 0.5 < estimate.plates[plate] / w < 3.0, (plate, estimate.plates, w)
        assert 0.5 < estimate.in_plane[plate] / uv < 3.0, (plate, estimate.in_plane, uv)
    assert max(w for w, _ in errors(1000.0, 2.25)[0].values()) < 3e-6
    with monkeypatch.context() as patch:
        patch.setattr(solver.layout, "pinned_lines", lambda case: {})
        assert max(w for w, _ in errors(300.0, 1.5)[0].values()) > 3e-6
    monkeypatch.setattr(solver.line_ends, "singular_end_edges",
                        lambda case, jid, meeting=None: set(case.singular_ends(jid)))
    assert max(w for w, _ in errors(1000.0, 2.25)[0].values()) > 3e-6


def test_a_channel_whose_web_hangs_on_both_lines_takes_the_pinned_count(monkeypatch):
    """Where a member hangs on more than one line (the web of :func:`sliding_channel`), no member
    hangs on either line alone: both lines take the pinned count of a line on which none
    hangs, 7 sqrt(kappa_a L) (:func:`solver.joint_rules.pinned_line_count`), not the hanging
    stiffener's 8.5. No reference covers it; refinement does (``bench/bench_free_ends.py
    --sliding-channel``): at 300 Hz the worst plate's ``w`` changes by 1.6e-5 from resolution
    1.5 to 2.25 and 2.9e-6 from 2.25 to 3.375, against 4.8e-5 and 1.1e-5 with 8.5 and 9.2e-4
    and 5.1e-4 with the usual count. Asked: the classification, the last change within 1e-5
    and, with the usual count, beyond 1e-4."""
    import solver.layout
    import solver.line_ends

    case = parse_case(sliding_channel(300.0, 1.5))
    assert case.hanging_members("AB") == case.hanging_members("AC") == ["A"]
    assert solver.line_ends.pinned_lines(case) == {"AB": False, "AC": False}

    def last_change() -> float:
        fields = []
        for resolution in (2.25, 3.375):
            solution = solve_assembly(parse_case(sliding_channel(300.0, resolution)), 300.0,
                                      residuals=False)
            fields.append({name: solution.plates[name].field(inner_grid(length, LY))["w"]
                           for name, (length, *_) in CHANNEL_PLATES.items()})
        return max(np.linalg.norm(fields[0][name] - fields[1][name])
                   / np.linalg.norm(fields[1][name]) for name in CHANNEL_PLATES)

    assert last_change() < 1e-5
    monkeypatch.setattr(solver.layout, "pinned_lines", lambda case: {})
    assert last_change() > 1e-4


def test_check_names_the_ends_that_set_a_lines_rule():
    """``vtcr check``'s summary says, for each moving line, what its ends are where they set
    its rule and cost (free to slide, pinned, meeting other lines, mixed) and, at pinned ends,
    the members that hang on it; a line whose ends are none of those reads as before."""
    from test_held_ends import pinned_stiffener

    from assembly import load_case
    from assembly.summary import summary_text

    def text(description: dict) -> str:
        return summary_text(parse_case(description))

    assert "junction (moving; ends free to slide, pinned)" in text(sliding_fold(300.0, 1.5))
    assert "junction (moving; ends free to slide, pinned; A hangs)" in text(
        sliding_channel(300.0, 1.5))
    assert "junction (moving; ends free to slide, pinned; T1 hangs)" in text(
        pinned_stiffener(300.0, 1.5))
    assert "junction (moving; ends free to slide)" in text(_bracket(300.0))
    box = summary_text(load_case(Path(__file__).parents[1] / "cases" / "box_with_wall.toml"))
    assert "hinge (moving; ends meeting other lines)" in box
    assert " hangs)" not in box and " hang)" not in box
    panel = summary_text(load_case(Path(__file__).parents[1] / "cases" / "stiffened_panel.toml"))
    assert "junction (moving)" in panel and "; ends " not in panel


def test_the_line_functions_follow_the_members_reach_on_a_free_ended_fold(monkeypatch):
    """The line's Legendre count stops at the wavenumber its members' rays answer, which the
    free ends make three times the usual and more (:func:`solver.layout.answered_wavenumber`).
    Stopped at the usual one with the reach fixed, as until 2026-11-27, it stalled from
    resolution 5/3 on: at 2.25 ``w`` is 1.7e-3 off the finite elements on the worst plate,
    while the estimate, whose enriched solve then refined the rays alone, says 5e-6 (and
    resolutions 2.25 and 3.375 agreed to 1e-6: a convergence the count hid). Thresholds:
    1.5e-3 and 1e-4."""
    import solver.layout
    import solver.line_ends

    monkeypatch.setattr(solver.line_ends, "REACH_GROWTH_FROM", math.inf)
    monkeypatch.setattr(solver.layout, "answered_wavenumber",
                        lambda case, jid, problems, resolution=None:
                        solver.layout.members_wavenumber(case, jid, problems))
    errors = _errors_and_estimates(2.25)
    assert max(true for true, _, _ in errors) > 1.5e-3
    assert max(estimate for _, estimate, _ in errors) < 1e-4


def test_a_tolerance_is_not_claimed_where_the_estimate_cannot_see_the_lines(monkeypatch):
    """Where a line's count does not grow, the enriched solve adds no function
    (:func:`solver.estimate.unrefined_lines`) and the estimate cannot see the line's error.
    With the reach growing with the resolution the count never meets its stop; a description
    that fixes it (``interface_functions``) does not grow it. With the reach fixed at three
    times, as until 2026-11-27, the bracket's count met its stop at resolution 5: the
    estimate, 5e-5 there for a field 8.5e-4 off the finite elements, names the line
    (``unseen_lines``), cannot check a tolerance of 1e-3, and the solve says so rather than
    claim it. A pinned end caps the reach (:data:`solver.line_ends.PINNED_END_REACH`): the fold
    with sliding ends meets its stop at 300 Hz from resolution 3.375 on, and the message says
    which of the two stops the count."""
    import solver.line_ends
    from solver.errors import ToleranceError
    from solver.estimate import (
        _resolutions,
        unrefined_lines,
        unseen_lines_remedy,
        unseen_lines_text,
    )
    from solver.tolerance import solve_to_tolerance

    case = parse_case(_rigid_bracket(1.5))
    resolutions = [_resolutions(case, r) for r in (2.25, 3.375, 5.0, 7.5)]
    assert [unrefined_lines(case, 300.0, *pair) for pair in resolutions] == [()] * 4
    fixed_count = _rigid_bracket(1.5)
    fixed_count["discretisation"]["interface_functions"] = 30
    assert unrefined_lines(parse_case(fixed_count), 300.0, *resolutions[0]) == ("F",)
    sliding = parse_case(sliding_fold(300.0, 1.5))
    assert [unrefined_lines(sliding, 300.0, *_resolutions(sliding, r)) for r in (2.25, 3.375)
            ] == [(), ("F",)]
    assert "interface_functions" in unseen_lines_text(("F",), 1e-5, True) + unseen_lines_remedy(
        True)
    assert "PINNED_END_REACH" in unseen_lines_text(("F",), 1e-5, False)
    assert "interface_functions" not in unseen_lines_remedy(False)
    monkeypatch.setattr(solver.line_ends, "REACH_GROWTH_FROM", math.inf)
    assert [unrefined_lines(case, 300.0, *pair) for pair in resolutions[:3]] \
        == [(), (), ("F",)]
    with pytest.raises(ToleranceError, match="Legendre functions of F"):
        solve_to_tolerance(parse_case(_rigid_bracket(5.0)), 300.0, 1e-3)


def test_an_estimate_blind_to_a_line_says_so():
    """A plain solve's estimate that cannot see a line's error (``unseen_lines``, the
    resolution-5 estimate of the test above) is flagged where it is reported: a warning naming
    the line beside the estimate, and ``unseen_lines`` in its JSON; an estimate that sees
    every line has neither."""
    import io

    from rich.console import Console

    from solver.estimate import ErrorEstimate
    from updating.cli.common import print_estimates

    def report(unseen: tuple[str, ...]) -> tuple[str, dict]:
        estimate = ErrorEstimate(5e-5, {"A": 5e-5, "B": 4e-5}, 5.0, 7.5, 1.0,
                                 unseen_lines=unseen)
        buffer = io.StringIO()
        print_estimates(Console(file=buffer, width=300), {300.0: estimate})
        return buffer.getvalue(), estimate.to_json()

    text, json = report(("F",))
    assert "warning" in text and "Legendre functions of F" in text
    assert json["unseen_lines"] == ["F"]
    text, json = report(())
    assert "warning" not in text and "unseen_lines" not in json


def test_a_stalled_tolerance_names_the_slow_line():
    """When refinement stops lowering the estimate of a member of a line whose loads converge
    slowly (:func:`solver.estimate.slow_lines`), the message blames that line, not the rays'
    round-off: asked 1e-4 from resolution 1.5 with the reach fixed (until 2026-11-27), the
    bracket's estimate went 1.9e-3, 8.0e-4, 4.7e-4 (the error against
    finite elements 2.4e-3, 5.0e-4, 3.4e-4) and stopped. The same history on the held
    bracket, which has no such line, keeps the round-off cause."""
    from solver.estimate import ErrorEstimate
    from solver.tolerance import _tolerance_message
    from solver.vtcr import solve_case

    history = [ErrorEstimate(e, {"A": e / 3, "B": e}, r, 1.5 * r, 1.0)
               for e, r in ((1.9e-3, 1.5), (8.0e-4, 2.25), (4.7e-4, 3.375))]
    for description, cause in ((_rigid_bracket(1.0), "loads of F converge slowly"),
                               (_bracket(300.0, 1.0, held=True), "round-off floor")):
        case = parse_case(description)
        solution = solve_case(case, 300.0, residuals=False, check=False)
        message = _tolerance_message(case, 300.0, 1e-4, history, solution, stalled=True)
        assert cause in message and "plate B" in message, message


def test_a_line_whose_end_slides_has_the_end_layer_count():
    r"""From resolution 1.5 the line of an end free to slide has at least
    :math:`\lceil 4\sqrt{\kappa_a L}\rceil` functions (:func:`solver.joint_rules.end_layer_count`,
    capped by what the members' reach answers); below, the wavenumbers' count stands. The
    bracket's line at 300 Hz: 25 functions at resolution 1.5, where the wavenumbers ask 16;
    with the ends held (``held`` lines' members do not reach further) the wavenumbers'."""
    from solver.estimate import _resolutions
    from solver.joint_rules import end_layer_count, interface_function_count
    from solver.layout import answered_wavenumber, interface_layout
    from solver.problems import plate_problems

    assert end_layer_count(73.5, 0.5, 1.0) == 0
    assert end_layer_count(73.5, 0.5, 1.5) == math.ceil(4.0 * math.sqrt(36.75)) == 25
    assert end_layer_count(8.0, 0.5, 2.25) == math.ceil(1.25 * 4.0) + 2 == 7  # the cap
    for resolution, usual in ((1.0, True), (1.5, False), (2.25, False)):
        case = parse_case(_rigid_bracket(resolution))
        problems = plate_problems(case, 300.0)
        count = interface_layout(case, problems, _resolutions(case, resolution)[0]).counts["F"]
        kappa0 = min(problems[p].kappa.real for p in PLATES)
        answered = answered_wavenumber(case, "F", problems, resolution)
        waves = interface_function_count(kappa0, LY, resolution, 2.5, answered)
        floor = end_layer_count(answered, LY, resolution)
        assert count == (waves if usual else max(waves, floor)), (resolution, count)
        assert usual or floor > waves, (resolution, floor, waves)
