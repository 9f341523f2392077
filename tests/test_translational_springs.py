"""Translational springs between a moving line and its members (``docs/method.md`` section
10.4): :math:`\\mathbf f_i = k_{t,i}(1 + j\\zeta_{t,i})(\\mathbf X_J - \\mathbf X_i)`, the
line translating with its first member rigid in translation.

The structure is the T junction of ``tests/test_moving_lines.py`` (a 1 mm skin of two plates
and a 2 mm stiffener 0.1 m high, shear-diaphragm ends, 1 N on the skin) at 1 kHz, with a
spring on the stiffener.
"""

from __future__ import annotations

import numpy as np
import pytest
from support import folded_reference, folded_w, inner_grid
from test_moving_lines import L_FOLD, LY, T_JUNCTION, _description

from assembly import AssemblyError, parse_case
from solver.power import power_flow
from solver.substructure import solve_assembly

FREQUENCY = 1000.0


def _tee(log10_translational_stiffness: float | None = None,
         loss_factor: float = 0.0) -> dict:
    description = _description(*T_JUNCTION, FREQUENCY, None)
    if log10_translational_stiffness is not None:
        description["joints"]["W"]["log10_translational_stiffness"] = {
            "T1": log10_translational_stiffness}
        description["joints"]["W"]["translational_loss_factor"] = {"T1": loss_factor}
    return description


def _grid_w(solution) -> dict[str, np.ndarray]:
    return folded_w(solution, T_JUNCTION[0], LY)


def test_a_stiff_translational_spring_is_a_rigid_tie():
    """log10 k_t = 14 (N/m^2) on the stiffener leaves every plate's w within 3.6e-7 to 9.9e-7
    of the rigid tie (measured; the difference falls as 1/k_t: 4e-3 to 1.1e-2 at 10), so
    within 1e-5; at log10 k_t = 10 the fields differ by more than 1e-3."""
    rigid = _grid_w(solve_assembly(parse_case(_tee()), FREQUENCY, residuals=False))
    for log10_stiffness, within in ((14.0, True), (10.0, False)):
        sprung = _grid_w(solve_assembly(parse_case(_tee(log10_stiffness)), FREQUENCY,
                                        residuals=False))
        differences = [np.linalg.norm(sprung[p] - rigid[p]) / np.linalg.norm(rigid[p])
                       for p in rigid]
        if within:
            assert max(differences) < 1e-5, differences
        else:
            assert min(differences) > 1e-3, differences


def test_the_power_balances_with_a_lossy_translational_spring():
    """The spring (log10 k_t = 8, loss factor 0.2) dissipates 0.9 % of the injected power,
    :math:`\\tfrac12\\omega\\,\\mathrm{Im}(k_t^*)\\int|\\mathbf X_J - \\mathbf X_i|^2`
    (``PowerFlow.joint_dissipated``); the members' deliveries sum to minus the line's
    dissipation and each plate balances. Measured: 2.9e-11 of the injected power on the line,
    2.0e-11 on the worst plate, 1.2e-11 overall; tolerances 1e-9 and 1e-8. Counting the spring
    in the line's dissipation is what closes the line's balance (0.9 % without it)."""
    case = parse_case(_tee(8.0, 0.2))
    power = power_flow(case, solve_assembly(case, FREQUENCY))
    injected = power.total_injected
    assert power.joint_dissipated["W"] > 5e-3 * injected
    assert abs(sum(power.delivered["W"].values()) + power.joint_dissipated["W"]) < 1e-9 * injected
    assert power.imbalance < 1e-8
    for plate in case.plates:
        balance = power.injected[plate] + power.delivered["W"][plate] - power.dissipated[plate]
        assert abs(balance) < 1e-8 * injected, plate


@pytest.mark.parametrize("shape, frequency, log10_stiffness, loss_factor", [
    ("T", 1000.0, 8.0, 0.2), ("L", 300.0, 6.0, 0.0)])
def test_translational_springs_match_the_exact_folded_plate(shape, frequency, log10_stiffness,
                                                             loss_factor):
    """Against the exact prismatic solution with the same spring (``tests/exact_prismatic.py``,
    ``PrismaticLine.translational``), written independently of the solver: the worst plate's
    relative L2 error of w at resolution 1.5. Measured 1.7e-9 (T, spring on the stiffener,
    1 kHz) and 2.3e-7 (L, spring on leg B, 300 Hz); over the L, U and T at 300 Hz, 1 kHz and 3
    kHz with log10 k_t = 6 and 8, at most 1.5e-6. The springs change the fields by 5e-2 to
    2 (T at 1 kHz), so the bound 1e-5 tells a spring from none and from a wrong law."""
    plates, lines, load = {"T": T_JUNCTION, "L": L_FOLD}[shape]
    (line, members), = lines.items()
    member = list(members)[-1]
    description = _description(plates, lines, load, frequency, None)
    description["joints"][line].update(
        log10_translational_stiffness={member: log10_stiffness},
        translational_loss_factor={member: loss_factor})
    solution = solve_assembly(parse_case(description), frequency, residuals=False)
    reference = folded_reference(plates, lines, load, frequency, False, LY, 600, translational={
        line: {member: 10.0**log10_stiffness * (1.0 + 1j * loss_factor)}})
    for name, w in folded_w(solution, plates, LY).items():
        exact = reference.w(name, *inner_grid(plates[name][0], LY).T)
        assert np.linalg.norm(w - exact) < 1e-5 * np.linalg.norm(exact), name


@pytest.mark.parametrize("change, message", [
    (lambda d: d["joints"]["W"].update(held=True), "held in translation"),
    (lambda d: d["joints"]["W"].update(log10_translational_stiffness=8.0),
     "leave at least one member rigid"),
    (lambda d: d["joints"]["W"].update(log10_translational_stiffness={"B9": 8.0}),
     "is not a member"),
    (lambda d: d["joints"]["W"].update(log10_translational_stiffness={"T1": float("nan")}),
     "got nan; write a number"),
    (lambda d: d["joints"]["W"].update(translational_loss_factor={"S1": 0.1}),
     "S1 have a translational loss factor but no translational spring"),
    (lambda d: d["joints"]["W"].update(held=1), "must be true or false, got 1"),
])
def test_line_settings_that_would_do_nothing_or_mean_nothing_are_refused(change, message):
    """Each setting that would do nothing or mean nothing is refused, naming what to write."""
    description = _tee(8.0)
    change(description)
    with pytest.raises(AssemblyError, match=message):
        parse_case(description)


def test_spring_problems_are_reported_beside_the_others():
    """A problem elsewhere in the description (another joint invalid, which leaves the lines'
    motion undecided) does not hide what a joint's springs decide alone: the message lists
    both."""
    description = _tee(8.0)
    description["joints"]["W"].update(log10_translational_stiffness=8.0)
    description["joints"]["X"] = {"kind": "junction", "between": ["S1.left", "S2.right"],
                                  "log10_stiffness": 2.0, "translational_loss_factor": -1.0}
    with pytest.raises(AssemblyError) as raised:
        parse_case(description)
    assert "leave at least one member rigid" in str(raised.value)
    assert "X.translational_loss_factor" in str(raised.value)


def test_check_shows_the_translational_springs():
    from assembly.summary import summary_text

    (row,) = [line for line in summary_text(parse_case(_tee(8.0, 0.2))).splitlines()
              if "junction" in line]
    assert "junction (moving; log10 k_t T1 8)" in row
