"""Moving lines with free ends (``docs/method.md`` section 10.4): the line's ends are junction
points that nothing holds, free to translate in 3D.

The bracket: plates A (0.4 x 0.5 m) and B (0.3 x 0.5 m) of 2 mm steel folded at 90 degrees
along the line F (A rigid, B's weld log10 k = 3 with loss factor 0.1), their far edges simply
supported, their ends y = 0 and y = 0.5 m free; 1 N on A. No exact solution covers free ends,
so the checks are identities (reciprocity, power balance) and convergence under refinement.
"""

from __future__ import annotations

import math

import numpy as np
from support import folded_description, folded_w
from test_moving_lines import L_FOLD, LY

import solver.problems
from assembly import parse_case
from solver.estimate import estimate_error
from solver.guards import check_description
from solver.power import power_flow
from solver.problems import free_end_plates
from solver.substructure import solve_assembly

PLATES = L_FOLD[0]  # the L fold's plates, with their own weld below
LINE = {"F": {"A": ("right", math.inf), "B": ("left", 3.0)}}
ON_A, ON_B = ("A", (0.15, 0.2)), ("B", (0.21, 0.07))


def _bracket(frequency: float, resolution: float = 1.5, held: bool | None = None,
             load: tuple[str, tuple[float, float]] = ON_A) -> dict:
    description = folded_description(PLATES, LINE, (load[0], *load[1]), frequency, held, LY,
                                     resolution)
    for boundary in description["boundaries"]:
        if boundary["edge"].endswith(("bottom", "top")):
            boundary["condition"] = "free"
            boundary.pop("in_plane", None)
    description["joints"]["F"]["loss_factor"] = {"B": 0.1}
    return description


def _grid_w(solution) -> dict[str, np.ndarray]:
    return folded_w(solution, PLATES, LY)


def test_a_free_ended_fold_moves_by_default():
    """Its ends on free edges, the line moves without being asked and without a warning, and
    its members' edge waves reach :data:`solver.problems.FREE_END_REACH` times further."""
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


def test_a_free_ended_fold_converges(monkeypatch):
    """Resolutions 2.25 and 3.375 agree to 1.1e-6 (A) and 2.7e-6 (B) at 300 Hz; with the usual
    edge reach (:data:`solver.problems.FREE_END_REACH` = 1) to 4.6e-5 and 2.4e-4: the line's
    loads vary near its free ends faster than the members' usual edge waves reach. Tolerance
    2e-5, and 1e-4 for the usual reach to exceed."""
    def change() -> float:
        coarse, fine = (_grid_w(solve_assembly(parse_case(_bracket(300.0, r)), 300.0,
                                               residuals=False)) for r in (2.25, 3.375))
        return max(np.linalg.norm(coarse[p] - fine[p]) / np.linalg.norm(fine[p]) for p in fine)

    assert change() < 2e-5
    monkeypatch.setattr(solver.problems, "FREE_END_REACH", 1.0)
    assert change() > 1e-4


def test_the_error_estimate_stays_honest_on_a_free_ended_fold():
    """The estimate (the enriched solve at 1.5 times the resolution) against the field at
    resolution 3.375 (which the convergence test above puts within 3e-6 of the limit), at 300
    Hz and resolution 1: measured 1.3e-3 / 1.5e-3 on A and 7.0e-3 / 8.3e-3 on B (ratios 0.85);
    0.90 to 1.00 at 1 and 3 kHz and at resolution 1.5 (``docs/method.md`` section 10.4). The
    issue's bounds for the ratio, [0.5, 3]."""
    case = parse_case(_bracket(300.0, 1.0))
    solution = solve_assembly(case, 300.0, residuals=False)
    estimate = estimate_error(case, solution, 1.0)
    reference = _grid_w(solve_assembly(parse_case(_bracket(300.0, 3.375)), 300.0,
                                       residuals=False))
    fields = _grid_w(solution)
    for plate in PLATES:
        true = np.linalg.norm(fields[plate] - reference[plate]) / np.linalg.norm(reference[plate])
        assert 0.5 < estimate.plates[plate] / true < 3.0, (plate, estimate.plates[plate], true)
