"""Moving junction lines (``held = false``, ``docs/method.md`` section 10.4) against the exact
prismatic folded plate of ``tests/exact_prismatic.py``, written independently of the solver.

Folded plates of steel, shear diaphragms on y = 0 and y = Ly (``simply_supported`` with
``in_plane = "diaphragm"``), the other outer edges simply supported and fixed in-plane (free
for a stiffener's top), a 1 N normal force; the lines move as one body. The exact solution
models bending and in-plane motion of every plate, so it differs from the held-line model by
0.2 % (300 Hz) to 5 % (3 kHz) on an L fold: a VTCR that left the lines held, or coupled the
in-plane waves wrongly, fails by that much.
"""

from __future__ import annotations

import cmath
import json
import math
from pathlib import Path

import numpy as np
import pytest
from support import folded_description, folded_reference, folded_w, inner_grid

from assembly import AssemblyError, load_case, parse_case
from assembly.generate import description_toml
from assembly.summary import summary_text
from solver.errors import ToleranceError
from solver.estimate import _slow_lines, estimate_error, plate_l2_rule
from solver.guards import check_description
from solver.interface_loads import load_values, member_axes, member_load
from solver.layout import answered_wavenumber, interface_layout, members_wavenumber
from solver.membrane_basis import membrane_grid_displacement
from solver.near_forces import forces_near_joints
from solver.power import plate_gauss_axes, power_flow
from solver.problems import plate_problems, plate_wedges
from solver.substructure import solve_assembly
from solver.tolerance import refined_together, solve_to_tolerance
from solver.vtcr import solve_case
from updating.api import update_case
from updating.cli import main
from updating.cli.common import estimates_json
from updating.data.measurements import (
    Measurements,
    add_noise,
    measurement_layout,
    simulate_measurements,
)
from updating.forward.sweep import frequency_sweep
from updating.inverse.plan import identifiability_plan

LY = 0.5
UP, DOWN, ALONG_X = (0.0, 0.0, 1.0), (0.0, 0.0, -1.0), (1.0, 0.0, 0.0)
N_TERMS = 600  # the reference's harmonics: 1.5e-8 from 1000 at 1 kHz on these grids
RESOLUTION = 1.5

# plates: name -> (length, origin, x_axis, thickness, right edge); lines: joint -> {plate:
# (edge, log10 k)}; the force: (plate, x0, y0)
L_FOLD = ({"A": (0.4, (0.0, 0.0, 0.0), ALONG_X, 0.002, "simply_supported"),
           "B": (0.3, (0.4, 0.0, 0.0), UP, 0.002, "simply_supported")},
          {"F": {"A": ("right", math.inf), "B": ("left", math.inf)}}, ("A", 0.15, 0.2))
U_CHANNEL = ({"A": (0.3, (0.0, 0.0, 0.0), UP, 0.002, "simply_supported"),
              "B": (0.4, (0.0, 0.0, 0.3), ALONG_X, 0.002, "simply_supported"),
              "C": (0.25, (0.4, 0.0, 0.3), DOWN, 0.002, "simply_supported")},
             {"F1": {"A": ("right", math.inf), "B": ("left", math.inf)},
              "F2": {"B": ("right", math.inf), "C": ("left", math.inf)}}, ("B", 0.17, 0.21))
T_JUNCTION = ({"S1": (0.4, (0.0, 0.0, 0.0), ALONG_X, 0.001, "simply_supported"),
               "S2": (0.35, (0.4, 0.0, 0.0), ALONG_X, 0.001, "simply_supported"),
               "T1": (0.1, (0.4, 0.0, 0.0), UP, 0.002, "free")},
              {"W": {"S1": ("right", math.inf), "S2": ("left", math.inf), "T1": ("left", 2.5)}},
              ("S1", 0.17, 0.13))
SHAPES = {"L": L_FOLD, "U": U_CHANNEL, "T": T_JUNCTION}

# faces that meet at other angles than 90 degrees: a V fold whose faces are 120 degrees apart,
# and a T junction whose stiffener leans at 135 degrees to the skin (on a spring)
V_FOLD = ({"A": L_FOLD[0]["A"],
           "B": (0.3, (0.4, 0.0, 0.0), (0.5, 0.0, math.sqrt(0.75)), 0.002, "simply_supported")},
          L_FOLD[1], L_FOLD[2])
LEANING_T = ({"S1": T_JUNCTION[0]["S1"], "S2": T_JUNCTION[0]["S2"],
              "T1": (0.1, (0.4, 0.0, 0.0), (-math.sqrt(0.5), 0.0, math.sqrt(0.5)), 0.002,
                     "free")},
             {"W": {"S1": ("right", math.inf), "S2": ("left", math.inf), "T1": ("left", 3.0)}},
             T_JUNCTION[2])
OBLIQUE = {"V": V_FOLD, "leaning T": LEANING_T}
SKIN_MEASURED = {"plates": ["S1", "S2"], "spacing": 0.1, "noise": 0.05}
"""The T junction's ``[measurement]``: its skin, as a vibrometer sees it."""


def _description(plates, lines, load, frequency, held):
    return folded_description(plates, lines, load, frequency, held, LY, RESOLUTION)


def _reference(plates, lines, load, frequency, held):
    return folded_reference(plates, lines, load, frequency, held, LY, N_TERMS)


def _grid_errors(solution, reference, plates) -> tuple[dict[str, float], dict[str, float]]:
    """Per plate, the relative L2 difference between the VTCR and the exact solution on a
    15 x 15 grid: of ``w``, and of ``(u, v)`` along the plate's axes."""
    w_errors, in_plane_errors = {}, {}
    for name, w in folded_w(solution, plates, LY).items():
        points = inner_grid(plates[name][0], LY)
        exact_w = reference.w(name, *points.T)
        exact_uv = np.column_stack([reference.u(name, *points.T), reference.v(name, *points.T)])
        w_errors[name] = float(np.linalg.norm(w - exact_w) / np.linalg.norm(exact_w))
        in_plane_errors[name] = float(np.linalg.norm(solution.in_plane(name, points) - exact_uv)
                                      / np.linalg.norm(exact_uv))
    return w_errors, in_plane_errors


def _errors(shape, frequency, held_model=False, held_reference=False) -> dict[str, float]:
    """Per plate, the relative L2 difference of ``w`` on a 15 x 15 grid between the VTCR and
    the exact solution (:func:`_grid_errors`)."""
    plates, lines, load = shape
    case = parse_case(_description(plates, lines, load, frequency, held_model))
    solution = solve_assembly(case, frequency, residuals=False)
    return _grid_errors(solution, _reference(plates, lines, load, frequency, held_reference),
                        plates)[0]


# every shape at every frequency is the slow study; the default run keeps one frequency of each
# shape and the L fold across the band (the same property, a third of the time)
CASES = [("L", 300.0), ("L", 1000.0), ("L", 3000.0), ("U", 1000.0), ("T", 3000.0)]
SLOW = [(s, f) for s in sorted(SHAPES) for f in (300.0, 1000.0, 3000.0) if (s, f) not in CASES]


@pytest.mark.parametrize("shape, frequency",
                         CASES + [pytest.param(*c, marks=pytest.mark.slow) for c in SLOW])
def test_moving_lines_match_the_exact_folded_plate(shape, frequency):
    """The issue's target is 2e-3 on every plate. Measured at resolution 1.5: L 9.0e-8 / 5.5e-9
    / 2.2e-9, U 7.6e-7 / 1.1e-7 / 7.3e-9, T 1.2e-7 / 1.5e-9 / 2.0e-9 (300 Hz / 1 kHz / 3 kHz,
    worst plate; 3.5e-8 to 1.9e-6 before the boundary-layer in-plane basis, and the T's 1 mm
    skin and 2 mm stiffener 6e-7 / 4e-6 / 7e-5 before its line's functions stopped at the
    stiffener's rays); at resolution 1, 7e-4 to 7.7e-3."""
    errors = _errors(SHAPES[shape], frequency)
    assert max(errors.values()) < 2e-3, errors


def test_the_moving_model_is_not_the_held_one():
    """At 1 kHz the held-line model is 1 % from the moving truth on the L fold, 100 times the
    moving model's error: the comparison above tells the two apart."""
    moving = _errors(L_FOLD, 1000.0)
    held = _errors(L_FOLD, 1000.0, held_model=True)
    assert max(held.values()) > 5e-3 > 50 * max(moving.values()), (held, moving)


def test_held_lines_keep_their_exact_solution():
    """``held = true`` is the held-line model: against the reference with held lines (where
    the in-plane waves play no part) it is as accurate as before (test_junction_accuracy)."""
    errors = _errors(L_FOLD, 1000.0, held_model=True, held_reference=True)
    assert max(errors.values()) < 2e-3, errors


HINGED_L = ({"A": L_FOLD[0]["A"], "B": L_FOLD[0]["B"]},
            {"F": {"A": ("right", math.inf), "B": ("left", 2.5)}}, L_FOLD[2])
"""The L fold with a rotational spring of log10 k = 2.5 on B, as a junction; the same fold
written as a hinge of that stiffness is :func:`_as_hinge`."""


def _as_hinge(description: dict, loss_factor: float = 0.0) -> dict:
    """``description`` with its junction F written as a hinge of log10 k 2.5 (``held`` kept)."""
    joint = description["joints"]["F"]
    description["joints"]["F"] = {"kind": "hinge", "between": joint["between"],
                                  "log10_stiffness": 2.5, "loss_factor": loss_factor} | (
        {"held": joint["held"]} if "held" in joint else {})
    return description


@pytest.mark.parametrize("frequency", [300.0, 1000.0])
def test_a_hinge_between_non_coplanar_plates_moves_as_a_line_of_two_members(frequency):
    r"""A hinge between framed, non-coplanar plates moves by default: a junction line of two
    members, the first rigid and the second on the hinge's spring (the same law,
    :math:`M_n^A = M_n^B = k(\theta_A + \theta_B)`), its one channel named by the joint.
    Against that junction, the fields agree to round-off (0 measured: the same system); against
    the exact prismatic fold with the spring and the line free in translation, to 3.9e-8
    (tolerance 2e-7). ``held = true`` keeps the held hinge, the exact held fold's to 2e-8."""
    plates, lines, load = HINGED_L
    junction = parse_case(_description(plates, lines, load, frequency, None))
    hinge = parse_case(_as_hinge(_description(plates, lines, load, frequency, None)))
    assert hinge.moving_lines() == ("F",) and "hinge (moving)" in summary_text(hinge)
    by_junction, by_hinge = solve_assembly(junction, frequency), solve_assembly(hinge, frequency)
    assert list(by_hinge.residuals) == ["F"]
    exact = _reference(plates, lines, load, frequency, False)
    for name, (length, *_) in plates.items():
        points = inner_grid(length, LY)
        w = by_hinge.plates[name].field(points)["w"]
        same = by_junction.plates[name].field(points)["w"]
        assert np.linalg.norm(w - same) < 1e-12 * np.linalg.norm(same), name
        reference = exact.w(name, *points.T)
        assert np.linalg.norm(w - reference) < 2e-7 * np.linalg.norm(reference), name
    held = parse_case(_as_hinge(_description(plates, lines, load, frequency, True)))
    assert held.moving_lines() == () and "hinge (held)" in summary_text(held)
    solution, exact = solve_assembly(held, frequency), _reference(plates, lines, load,
                                                                  frequency, True)
    for name, (length, *_) in plates.items():
        points = inner_grid(length, LY)
        reference = exact.w(name, *points.T)
        assert (np.linalg.norm(solution.plates[name].field(points)["w"] - reference)
                < 2e-7 * np.linalg.norm(reference)), name


def test_a_moving_lossy_hinge_balances_its_power():
    """The hinge's loss factor (0.2) dissipates on the moving line; each plate balances and
    the line's deliveries sum to minus its dissipation (tolerances as for the junctions:
    1e-9 of the injected power on the line, 1e-8 per plate)."""
    case = parse_case(_as_hinge(_description(*HINGED_L, 300.0, None), loss_factor=0.2))
    power = power_flow(case, solve_assembly(case, 300.0))
    injected = power.total_injected
    assert power.joint_dissipated["F"] > 1e-3 * injected
    assert abs(sum(power.delivered["F"].values()) + power.joint_dissipated["F"]) < 1e-9 * injected
    for plate in case.plates:
        balance = power.injected[plate] + power.delivered["F"][plate] - power.dissipated[plate]
        assert abs(balance) < 1e-8 * injected, plate


def test_a_moving_line_needs_frames():
    """(Its ends may be free: ``tests/test_free_ends.py``.)"""
    description = _description(*L_FOLD, 300.0, False)
    description["plates"]["B"].pop("frame")
    with pytest.raises(AssemblyError, match="frame"):
        parse_case(description)


@pytest.mark.parametrize("shape", ["T", "leaning T"])
def test_the_power_balances_with_the_in_plane_waves(shape):
    """Per plate, injected plus delivered equals dissipated, the in-plane dissipation and the
    power the line delivers through its forces included; the members' deliveries balance the
    weld's law (a lossy stiffener spring, 4 % of the injected power; 3 % leaning). Exact for
    the exact field; measured at resolution 1.5, 7e-11 of the injected power on the plates and
    1e-11 on the junction (leaning: 2.2e-11 and 8.7e-12), so 1e-8 and 1e-9: the in-plane waves
    dissipate 7e-5 (skin) to 5e-4 (stiffener) of it, which a balance without them would miss
    by four decades."""

    plates, lines, load = (SHAPES | OBLIQUE)[shape]
    description = _description(plates, lines, load, 1000.0, False)
    description["joints"]["W"]["loss_factor"] = {"T1": 0.2}
    case = parse_case(description)
    power = power_flow(case, solve_assembly(case, 1000.0))
    injected = power.total_injected
    delivered = power.delivered["W"]
    assert power.joint_dissipated["W"] > 1e-3 * injected
    assert abs(sum(delivered.values()) + power.joint_dissipated["W"]) < 1e-9 * injected
    for plate in case.plates:
        balance = power.injected[plate] + delivered[plate] - power.dissipated[plate]
        assert abs(balance) < 1e-8 * injected, (plate, balance / injected)


@pytest.mark.parametrize("frequency", [300.0, 3000.0])
def test_the_in_plane_displacements_are_the_exact_ones(frequency):
    """``u``, ``v`` along each plate's local axes (what ``vtcr solve`` reports at the probes):
    measured 1.8e-6 to 3.6e-6 of their own norm on the L fold at resolution 1.5 and 300 Hz,
    2.5e-8 to 2.8e-8 at 3 kHz (2e-5 to 5e-5 when this test was written), where they are 4e-4
    to 2e-2 of ``w``; asked 1e-3."""
    plates, lines, load = L_FOLD
    case = parse_case(_description(plates, lines, load, frequency, False))
    _, in_plane_errors = _grid_errors(solve_assembly(case, frequency, residuals=False),
                                      _reference(plates, lines, load, frequency, False), plates)
    assert max(in_plane_errors.values()) < 1e-3, in_plane_errors


def test_solve_reports_u_v_w_at_the_probes_in_each_plate_frame(tmp_path):
    """``vtcr solve --probes --json`` on the V fold at 1 kHz: each probe's ``w``, ``u`` and
    ``v`` (along the plate's own x and y axes) are the exact folded plate's, to 1e-6 of the
    largest of each over the probes (measured at the description's resolution 1.5: ``w``
    4.5e-9, ``u`` 1.0e-7, ``v`` 7.2e-7). On the oblique face B the plate's ``u`` is no global
    component, so a field reported on other axes would be off by its own size."""
    plates, lines, load = V_FOLD
    path, probes, out = tmp_path / "v.toml", tmp_path / "probes.csv", tmp_path / "v.json"
    path.write_text(description_toml(_description(plates, lines, load, 1000.0, False)))
    points = {"A": [(0.1, 0.12), (0.33, 0.41), (0.39, 0.25)],
              "B": [(0.02, 0.3), (0.15, 0.07), (0.27, 0.44)]}
    probes.write_text("plate,x,y\n" + "".join(f"{name},{x},{y}\n" for name, at in points.items()
                                              for x, y in at))
    assert main(["solve", str(path), "--probes", str(probes), "--json", str(out),
                 "--no-estimate", "--max-rows", "0"]) == 0
    rows = json.loads(out.read_text())["probes"]
    reference = _reference(plates, lines, load, 1000.0, False)
    for field in ("w", "u", "v"):
        computed = np.array([complex(*row[field]) for row in rows])
        exact = np.array([getattr(reference, field)(row["plate"], row["x"], row["y"])
                          for row in rows])
        assert np.abs(computed - exact).max() < 1e-6 * np.abs(exact).max(), field


def test_plan_reads_a_moving_line_as_direct_solves_do():
    """``vtcr plan``'s sensitivities and damping share for the stiffener spring of the moving T
    junction (skin measured, 1 kHz; a loss factor of 0.05 on the spring): the field change per
    +0.1 decade of its log10 k and per +0.1 of its loss factor at the planned points, against
    solves of the changed descriptions, and the share of the injected power the spring
    dissipates, against the power flow. Measured to 4e-13, 2e-11 and 7e-13: the condensation
    the plan goes through holds the line's translation unknowns as the solve does."""
    plates, lines, load = T_JUNCTION
    description = _description(plates, lines, load, 1000.0, False)
    description["measurement"] = dict(SKIN_MEASURED)
    description["joints"]["W"]["loss_factor"] = {"T1": 0.05}
    case = parse_case(description)
    plans, _, _ = identifiability_plan(case, simulate_measurements(case))
    plan, layout = plans["W.T1"], measurement_layout(case)

    def at_probes(changed):
        solution = solve_case(changed, 1000.0)
        return np.concatenate([solution.w(pid, points) for pid, points in sorted(layout.items())])

    base = at_probes(case)
    for change, planned in (({"log10_stiffness": {"T1": 2.6}}, plan.stiffness_sensitivity),
                            ({"loss_factor": {"T1": 0.15}}, plan.damping_sensitivity)):
        moved = at_probes(case.with_joint_parameters({"W": change}))
        direct = np.linalg.norm(moved - base) / np.linalg.norm(base)
        assert planned[1000.0] == pytest.approx(direct, rel=1e-6), change
    flow = power_flow(case, solve_case(case, 1000.0))
    share = flow.joint_dissipated["W"] / flow.total_injected
    assert plan.damping_share[1000.0] == pytest.approx(share, rel=1e-6)


def test_a_sweep_of_a_moving_line_matches_the_exact_folded_plate_and_balances():
    """``vtcr frf``'s sweep (``updating.forward.sweep.frequency_sweep``) over 990-1010 Hz on the
    T junction, its stiffener spring lossy (loss factor 0.2): at every swept frequency ``w``
    at the probes is the exact folded plate's (with the complex spring stiffness) and the power
    balances, the spring's dissipation (a few % of the injected power) and the in-plane
    waves' counted. Measured: ``w`` within 8.5e-10 of the largest probe value, the imbalance
    5.9e-11 of the injected power at most; asked 1e-6 and 1e-8."""
    plates, lines, load = T_JUNCTION
    description = _description(plates, lines, load, 1000.0, False)
    description["joints"]["W"]["loss_factor"] = {"T1": 0.2}
    lossy = {"W": {**lines["W"], "T1": ("left", cmath.log10(10.0**2.5 * (1.0 + 0.2j)))}}
    points = {"S1": np.array([[0.1, 0.2], [0.3, 0.4]]), "T1": np.array([[0.05, 0.2]])}
    sweep = frequency_sweep(parse_case(description), (990.0, 1010.0), points, count=3,
                            tolerance=1.0)
    assert len(sweep.frequencies) == 3 and max(sweep.imbalances) < 1e-8, sweep.imbalances
    for frequency, values in zip(sweep.frequencies, sweep.values):
        reference = _reference(plates, lossy, load, float(frequency), False)
        for plate, at in points.items():
            exact = reference.w(plate, *at.T)
            assert np.abs(values[plate] - exact).max() < 1e-6 * np.abs(exact).max(), plate


def test_a_spring_identified_from_exact_data_needs_the_moving_lines():
    """The issue's identification in small: the T junction's stiffener spring at log10 k =
    1.5 (the model says 2.5), its skin "measured" by the exact folded plate (an independent
    solution, lines moving) on the 0.1 m grid at 300 Hz, 600 Hz and 1 kHz with +-5 % noise.
    ``update_case`` with moving lines corrects W.T1 to 1.54 with the truth inside its 90 %
    interval [1.44, 1.52] (the estimate itself outside it, as the README's G2: the noise biases
    the estimate, the interval is calibrated at each candidate value). With ``held = true`` no
    value of the spring explains the data: W.T1
    still stands out of its threshold 28 times, its correction undone (status 1, no interval),
    the held line's error being far above the noise the data carry."""
    plates, lines, load = T_JUNCTION
    frequencies = [300.0, 600.0, 1000.0]
    truth = {"W": {**lines["W"], "T1": ("left", 1.5)}}

    def case(held):
        description = _description(plates, lines, load, frequencies, held)
        description["measurement"] = dict(SKIN_MEASURED)
        return parse_case(description)

    points = {plate: np.array([[x, y] for p, x, y in case(False).measurement_points()
                               if p == plate]) for plate in ("S1", "S2")}
    rng, data = np.random.default_rng(1), {}
    for frequency in frequencies:
        reference = _reference(plates, truth, load, frequency, False)
        data[frequency] = {plate: (at, add_noise(reference.w(plate, *at.T), 0.05, rng))
                           for plate, at in points.items()}
    measured = Measurements(data)
    moving = update_case(case(False), measured)
    interval = moving.intervals["W.T1"]
    assert moving.status == 0 and interval.low <= 1.5 <= interval.high, (moving.parameters,
                                                                         interval)
    held = update_case(case(True), measured)
    assert held.status == 1 and "W.T1" not in held.intervals
    assert held.parameters["W.T1"]["log10_stiffness"] == 2.5
    assert "W.T1" in held.message


def test_check_shows_the_moving_lines_and_the_in_plane_conditions():

    text = summary_text(parse_case(_description(*L_FOLD, 300.0, False)))
    assert "junction (moving)" in text and "in-plane diaphragm" in text
    assert "in-plane fixed" in text  # the default of a simply supported edge
    held = summary_text(parse_case(_description(*L_FOLD, 300.0, True)))
    assert "junction (held)" in held and "in-plane" not in held


def _true_errors(solution, reference, plates) -> tuple[dict, dict, float]:
    """Per plate, the relative L2 error of ``w`` and of ``(u, v)`` on the estimate's Gauss rule
    against the exact folded plate, and that of ``w`` over the assembly."""

    w_errors, in_plane_errors, error, norm = {}, {}, 0.0, 0.0
    for name in plates:
        points, weights = plate_l2_rule(solution.plates[name].problem)
        x, y = points[:, 0], points[:, 1]
        exact = reference.w(name, x, y)
        w_error, w_norm = (weights @ abs(solution.w(name, points) - exact) ** 2,
                           weights @ abs(exact) ** 2)
        w_errors[name] = math.sqrt(w_error / w_norm)
        error, norm = error + w_error, norm + w_norm
        exact_uv = np.column_stack([reference.u(name, x, y), reference.v(name, x, y)])
        in_plane_errors[name] = math.sqrt(
            (weights @ np.sum(abs(solution.in_plane(name, points) - exact_uv) ** 2, axis=1))
            / (weights @ np.sum(abs(exact_uv) ** 2, axis=1)))
    return w_errors, in_plane_errors, math.sqrt(error / norm)


@pytest.mark.parametrize("shape, frequency", [("L", 1000.0), ("U", 300.0),
                                              pytest.param("U", 3000.0, marks=pytest.mark.slow)])
def test_the_error_estimate_stays_honest(shape, frequency):
    """The estimate (an enriched solve, which refines the in-plane waves with the rays) against
    the true error at resolution 1, of ``w`` over the assembly and per plate, and of the
    in-plane displacement ``(u, v)`` per plate: measured ratios 0.99-1.01 for both on the L, U
    and T shapes at 300 Hz, 1 kHz and 3 kHz (true errors of ``w`` 5e-5 to 7e-3, of ``(u, v)``
    3e-5 to 2.6e-2; ``bench/bench_estimate_moving.py``); the issue asks [0.5, 3] wherever the
    true error is above 1e-5."""

    plates, lines, load = SHAPES[shape]
    description = _description(plates, lines, load, frequency, False)
    description["discretisation"]["resolution"] = 1.0
    case = parse_case(description)
    solution = solve_assembly(case, frequency)
    estimate = estimate_error(case, solution)
    w_errors, in_plane_errors, total = _true_errors(
        solution, _reference(plates, lines, load, frequency, False), plates)
    assert 0.5 <= estimate.total / total <= 3.0
    assert set(estimate.in_plane) == set(plates) == set(estimate.displacement)
    for name in plates:
        for estimated, true in ((estimate.plates[name], w_errors[name]),
                                (estimate.in_plane[name], in_plane_errors[name])):
            assert true > 1e-5 and 0.5 <= estimated / true <= 3.0, (name, estimated, true)
        # the displacement (u, v, w) lies between its parts
        low, high = sorted((estimate.plates[name], estimate.in_plane[name]))
        assert low <= estimate.displacement[name] <= high
    assert estimate.to_json()["in_plane"]["plates"] == estimate.in_plane


@pytest.mark.parametrize("shape", sorted(OBLIQUE))
def test_oblique_lines_match_the_exact_folded_plate(shape):
    """At right angles a member's axes along the line (``solver.interface_loads.member_axes``)
    only permute the components of the line's translation and force; at other angles each
    component mixes the member's in-plane and bending fields, and the balancing member takes
    the others' forces on axes that are not theirs. At 1 kHz and resolution 1.5, relative L2
    on each plate's 15 x 15 grid against the exact folded plate: ``w`` measured within 6.6e-9
    (V) and 4.2e-9 (leaning T) on the worst plate, ``(u, v)`` within 1.0e-6 and 1.8e-8. The
    bounds, 1e-6 and 1e-4, are a hundred times those and far below what the angle changes in
    the exact fields (the same shapes at 90 degrees: the stiffener's ``w`` 53 % apart, the
    V's face B 2.3 %), so a component taken on a wrong axis fails by orders of magnitude."""
    plates, lines, load = OBLIQUE[shape]
    case = parse_case(_description(plates, lines, load, 1000.0, False))
    w_errors, in_plane_errors = _grid_errors(solve_assembly(case, 1000.0, residuals=False),
                                             _reference(plates, lines, load, 1000.0, False),
                                             plates)
    assert max(w_errors.values()) < 1e-6 and max(in_plane_errors.values()) < 1e-4, (
        w_errors, in_plane_errors)


def test_the_estimate_of_an_oblique_fold_stays_honest():
    """The V fold at 1 kHz and resolution 1, as :func:`test_the_error_estimate_stays_honest`:
    the estimate measured 1.00 times the true errors of ``w`` (8.4e-4 and 2.1e-3) and of
    ``(u, v)`` (1.9e-2 and 1.0e-2) on its two plates."""
    plates, lines, load = V_FOLD
    description = _description(plates, lines, load, 1000.0, False)
    description["discretisation"]["resolution"] = 1.0
    case = parse_case(description)
    solution = solve_assembly(case, 1000.0)
    estimate = estimate_error(case, solution)
    w_errors, in_plane_errors, _ = _true_errors(
        solution, _reference(plates, lines, load, 1000.0, False), plates)
    for name in plates:
        for estimated, true in ((estimate.plates[name], w_errors[name]),
                                (estimate.in_plane[name], in_plane_errors[name])):
            assert true > 1e-5 and 0.5 <= estimated / true <= 3.0, (name, estimated, true)


def test_the_tolerance_holds_on_every_plate():
    """``--tolerance`` asks every plate, not the assembly's total: the L fold at 1 kHz and
    resolution 1 has a total estimate of 8.4e-4 but 2.0e-3 on its leg B (true errors the same),
    which a total criterion accepted. Per plate, the solve is refined to resolution 1.5 and
    every plate's estimate and true error fall below 1e-3 (measured 1.3e-7 / 6.8e-7 estimated,
    5.2e-8 / 2.9e-7 true)."""

    plates, lines, load = L_FOLD
    description = _description(plates, lines, load, 1000.0, False)
    description["discretisation"]["resolution"] = 1.0
    case = parse_case(description)
    coarse = estimate_error(case, solve_assembly(case, 1000.0))
    assert coarse.total < 1e-3 < coarse.plates["B"]  # what the total criterion accepted
    solution, estimate = solve_to_tolerance(case, 1000.0, 1e-3)
    assert max(estimate.plate_errors().values()) <= 1e-3
    w_errors, _, _ = _true_errors(solution, _reference(plates, lines, load, 1000.0, False),
                                  plates)
    assert max(w_errors.values()) <= 1e-3, w_errors


def test_a_stalled_tolerance_names_a_force_next_to_a_line():
    """The U channel at 300 Hz with its force moved onto leg A, 2 cm from the fold F1
    (kappa0 d = 0.49): asked 1e-3 from resolution 1.5, plate C's estimate rises
    (1.0e-2, then 1.6e-2 at 2.25) and the refinement stops. The message blames the force next
    to the fold and says what helps (``docs/accuracy.md`` section 8), not the rays' round-off
    as it did. With the force on the middle leg, 17 cm from either fold, no force is near a
    joint."""
    plates, lines, _ = U_CHANNEL
    case = parse_case(_description(plates, lines, ("A", 0.28, 0.2), 300.0, False))
    with pytest.raises(ToleranceError) as stalled:
        solve_to_tolerance(case, 300.0, 1e-3)
    message = str(stalled.value)
    assert "the point force on plate A is 0.02 m from its joint F1" in message, message
    assert "edge_wavenumber_ratio" in message and "round-off" not in message, message
    far = parse_case(_description(*U_CHANNEL, 300.0, False))
    assert forces_near_joints(far, plate_problems(far, 300.0)) == []


def test_a_line_whose_members_reach_as_described_is_never_slow():
    r"""A moving line converges slowly (``docs/accuracy.md`` section 8) only where its members
    reach further than ``edge_wavenumber_ratio`` says (a free, pinned or meeting end): then
    :func:`solver.estimate.slow_lines` names it, the estimate may call it unseen and
    ``--tolerance`` refuses. Its answered wavenumber was :math:`\kappa_0\tau/\tau`, which
    rounds above :math:`\kappa_0` at 5 to 9 % of the frequencies: the folds, the T junction,
    ``cases/stiffened_panel.toml`` were "slow" at 341.8, 361.9, 417.5 Hz, ... (the issue's
    panel, ``bench/bench_moving_lines.py``, at 1200 and 1500 Hz too, where ``--tolerance 1e-3``
    refused to answer). Here they and :data:`PANEL`, at every frequency of a 120-point log grid
    from 100 Hz to 3 kHz, the plates' problems only."""
    cases = {name: lambda f, shape=shape: parse_case(_description(*shape, f, False))
             for name, shape in (SHAPES | {"panel": PANEL}).items()}
    panel = load_case(Path(__file__).parents[1] / "cases" / "stiffened_panel.toml")
    cases["stiffened_panel.toml"] = lambda f: panel
    for name, case_at in cases.items():
        for frequency in np.geomspace(100.0, 3000.0, 120):
            case = case_at(frequency)
            problems = plate_problems(case, frequency)
            assert _slow_lines(case, problems) == (), (name, frequency)
            for jid in case.moving_lines():
                assert (answered_wavenumber(case, jid, problems)
                        == members_wavenumber(case, jid, problems)), (name, frequency, jid)


# a three-bay skin with two stiffeners (1 mm and 2 mm: the stiffeners' rays answer shorter
# wavenumbers along the lines than the skin's)
PANEL = ({"S1": (0.5, (0.0, 0.0, 0.0), ALONG_X, 0.001, "simply_supported"),
          "S2": (0.5, (0.5, 0.0, 0.0), ALONG_X, 0.001, "simply_supported"),
          "S3": (0.5, (1.0, 0.0, 0.0), ALONG_X, 0.001, "simply_supported"),
          "T1": (0.15, (0.5, 0.0, 0.0), UP, 0.002, "free"),
          "T2": (0.15, (1.0, 0.0, 0.0), UP, 0.002, "free")},
         {"W1": {"S1": ("right", math.inf), "S2": ("left", math.inf), "T1": ("left", 3.5)},
          "W2": {"S2": ("right", math.inf), "S3": ("left", math.inf), "T2": ("left", 3.5)}},
         ("S1", 0.17, 0.13))


def clamped_t_junction(frequency: float, resolution: float) -> dict:
    """The T junction of :data:`SHAPES` with its ends clamped (its line moving by default):
    four clamped-free corners on its stiffener T1."""
    plates, lines, load = SHAPES["T"]
    description = folded_description(plates, lines, load, frequency, None, LY, resolution)
    for boundary in description["boundaries"]:
        if boundary["edge"].endswith(("bottom", "top")):
            boundary["condition"] = "clamped"
            boundary.pop("in_plane")
    return description


def test_a_stiffener_with_clamped_ends_converges_with_its_corner_functions():
    """The T junction of ``tests/test_moving_lines.py`` with clamped ends: its stiffener T1's
    free top and its moving line's edge meet the clamped ends at four clamped-free corners,
    which carry the corner functions of ``solver.plate_corners``. At 300 Hz ``--tolerance
    1e-3`` is met at the first step (estimate 1.3e-5 on T1, true error 1.1e-5; on every plate
    at 300 Hz and 1 kHz, resolutions 1 and 1.5, the estimate is 0.76 to 1.5 times the error),
    and T1's w changes by 1.9e-6 between resolutions 1.5 and 2.25. Without the functions it changed by 7.4e-3, 6.2e-3
    between resolutions 1.5, 2.25, 3.4, and the tolerance stopped."""
    plates = SHAPES["T"][0]
    case = parse_case(clamped_t_junction(300.0, 1.0))
    assert len(plate_wedges(case, "T1", plate_problems(case, 300.0)["T1"])) == 4
    solution, estimate = solve_to_tolerance(case, 300.0, 1e-3)
    assert estimate.resolution_of("T1") == 1.0 and estimate.plates["T1"] < 1e-4
    fields = [folded_w(solve_assembly(parse_case(clamped_t_junction(300.0, resolution)), 300.0,
                                      residuals=False), plates, LY)["T1"]
              for resolution in (1.5, 2.25)]
    assert np.linalg.norm(fields[1] - fields[0]) < 1e-5 * np.linalg.norm(fields[1])
    # the estimate stays honest there: 1.3e-5 against 1.1e-5
    true = np.linalg.norm(folded_w(solution, plates, LY)["T1"] - fields[1]) / np.linalg.norm(
        fields[1])
    assert 0.5 < estimate.plates["T1"] / true < 3.0


def test_two_moving_lines_with_fixed_ends_converge():
    """Two moving lines whose ends are fixed in-plane (the default of a supported edge):
    resolutions 1.5 and 1.875 agree on every plate at 2500 Hz. With the line's functions up to
    the skin's wavenumber, beyond what the stiffeners' rays answer, the interface problem had
    72 near-null directions, loads of 1e5 N/m for a 1 N force and fields wrong by order 1
    (``solver.joint_rules.interface_function_count``). With the members reaching twice as far
    from the fixed ends (``solver.line_ends.HELD_END_REACH``) and the lines' loads carrying
    their singular terms there, with the members' corner functions of those degrees
    (``docs/method.md`` section 10.4, *The loads' singular terms*), they agree to 1.4e-7 to
    7.8e-7 (1.5 and 2.25: 8.3e-8 to 6.5e-7); with the count following the doubled reach
    instead (0.3.7) 4.3e-6 to 1.8e-5, with the usual reach alone 6.5e-5 to 3.1e-4. Bound:
    three times the measured."""
    plates, lines, load = PANEL
    fields = {}
    for resolution in (1.5, 1.875):
        description = _description(plates, lines, load, 2500.0, False)
        for boundary in description["boundaries"]:
            if "in_plane" in boundary:
                boundary["in_plane"] = "fixed"
        description["discretisation"]["resolution"] = resolution
        case = parse_case(description)
        solution = solve_assembly(case, 2500.0, residuals=False)
        for name, w in folded_w(solution, plates, LY).items():
            fields[name, resolution] = w
    errors = {name: float(np.linalg.norm(fields[name, 1.5] - fields[name, 1.875])
                          / np.linalg.norm(fields[name, 1.875])) for name in plates}
    assert max(errors.values()) < 2.5e-6, errors


# An L fold whose horizontal leg is two plates on a coplanar joint (log10 k 2, a hinge-like
# spring): the exact reference's coplanar line of two members of stiffness 2k.
SPLIT_LEG = ({"A1": (0.25, (0.0, 0.0, 0.0), ALONG_X, 0.002, "simply_supported"),
              "A2": (0.2, (0.25, 0.0, 0.0), ALONG_X, 0.002, "simply_supported"),
              "B": (0.3, (0.45, 0.0, 0.0), UP, 0.002, "simply_supported")},
             {"G": {"A1": ("right", 2.0 + math.log10(2.0)), "A2": ("left", 2.0 + math.log10(2.0))},
              "F": {"A2": ("right", math.inf), "B": ("left", math.inf)}}, ("A1", 0.11, 0.2))


@pytest.mark.parametrize("frequency", [300.0, 3000.0])
def test_a_coplanar_joint_carries_the_in_plane_field(frequency):
    """A coplanar joint between plates with in-plane waves ties their in-plane displacements and
    passes their tractions (``docs/method.md`` section 10.4). Measured 2e-6 (300 Hz) and 8e-8
    (3 kHz) on the worst plate at resolution 1.5; a coplanar joint without in-plane continuity
    would let the leg's halves slide apart along the fold."""
    plates, lines, load = SPLIT_LEG
    description = _description(plates, lines, load, frequency, None)
    description["joints"]["G"] = {"kind": "coplanar", "between": ["A1.right", "A2.left"],
                                  "log10_stiffness": 2.0, "loss_factor": 0.1}
    case = parse_case(description)
    assert case.moving_lines() == ("F",)
    solution = solve_assembly(case, frequency)
    lossy = {p: (e, cmath.log10(2.0 * 100.0 * (1.0 + 0.1j))) for p, (e, _) in lines["G"].items()}
    reference = folded_reference(plates, {**lines, "G": lossy}, load, frequency, False, LY,
                                 N_TERMS)
    for name, w in folded_w(solution, plates, LY).items():
        exact = reference.w(name, *inner_grid(plates[name][0], LY).T)
        assert np.linalg.norm(w - exact) < 1e-4 * np.linalg.norm(exact), name

    power = power_flow(case, solution)
    for plate in case.plates:
        delivered = sum(p.get(plate, 0.0) for p in power.delivered.values())
        balance = power.injected[plate] + delivered - power.dissipated[plate]
        assert abs(balance) < 1e-8 * power.total_injected, plate


def test_a_line_of_springs_alone_turns_by_its_own_unknown():
    """The T junction with every member on a spring (log10 k 3, 3.5, 2.5: no rigid member):
    the line's rotation is an unknown of its own (``T``) and the last member balances the
    others' loads, its moment then entering its spring's channel. Against the exact folded
    plate at 1 kHz and resolution 1.5, ``w`` measured within 1.6e-9 on the worst plate
    (1.4e-7 at 300 Hz); asked 1e-6."""
    plates, _, load = T_JUNCTION
    lines = {"W": {"S1": ("right", 3.0), "S2": ("left", 3.5), "T1": ("left", 2.5)}}
    case = parse_case(_description(plates, lines, load, 1000.0, False))
    slots = interface_layout(case, plate_problems(case, 1000.0)).slots["W"]
    assert "T" in slots and not any(name.endswith(".T1") for name in slots)
    errors = _errors((plates, lines, load), 1000.0)
    assert max(errors.values()) < 1e-6, errors


def test_the_balancing_member_takes_the_loads_the_others_leave():
    r"""A moving line's balances hold by construction (``docs/method.md`` section 10.4): for
    any interface unknowns, the moments on the T's members sum to zero and so do the 3D forces
    :math:`N_{nn}\mathbf n_i + N_{nt}\mathbf t_i + K_n\mathbf e_{z,i}`, to round-off; the
    balancing member (the last rigid one) has no unknowns of its own."""
    case = parse_case(_description(*T_JUNCTION, 1000.0, False))
    arrangement = interface_layout(case, plate_problems(case, 1000.0))
    slots = arrangement.slots["W"]
    assert not any(name.endswith(".S2") for name in slots)  # the last rigid member balances
    s = np.random.default_rng(3).standard_normal(arrangement.n_s) * (1.0 + 0.5j)
    n_f = arrangement.counts["W"]
    moments, forces = np.zeros(n_f, complex), np.zeros((3, n_f), complex)
    for side in case.joints["W"].sides:
        def load(name):
            return load_values(member_load(case, "W", slots, side.plate, name), s)
        moments += load("C")
        for name, axis in zip(("Nn", "Nt", "K"), member_axes(case, side)):
            forces += np.outer(axis, load(name))
    scale = np.linalg.norm(s)
    assert np.linalg.norm(moments) < 1e-14 * scale
    assert np.linalg.norm(forces) < 1e-14 * scale


def test_the_members_of_moving_lines_are_refined_together():
    """A moving line's members (and, through both lines, the whole three-bay panel) share their
    refinements; plates of held lines and of flat joints keep their own."""

    panel = parse_case(_description(*PANEL, 1000.0, False))
    assert set(refined_together(panel)["S3"]) == set(PANEL[0])
    held = parse_case(_description(*T_JUNCTION, 1000.0, True))
    assert all(group == {pid} for pid, group in refined_together(held).items())


def test_the_in_plane_estimate_is_reported_only_where_there_is_one():
    """``error_estimate.in_plane`` in the JSON of a moving assembly, absent from a held one
    (whose keys stay those of before)."""

    keys = {"total", "plates", "resolution", "enriched_resolution", "method", "enrichment",
            "reason"}
    for held in (False, True):
        description = _description(*L_FOLD, 300.0, held)
        description["discretisation"]["resolution"] = 1.0
        case = parse_case(description)
        estimate = estimate_error(case, solve_assembly(case, 300.0))
        both = estimates_json({300.0: estimate})
        if held:
            assert set(estimate.to_json()) == keys and "in_plane" not in both
            assert estimate.plate_errors() == estimate.plates
        else:
            assert set(estimate.to_json()) == keys | {"in_plane"}
            assert both["in_plane"] == {"total": estimate.in_plane_total,
                                        "plates": estimate.in_plane}


def test_the_estimate_evaluates_the_in_plane_field_on_its_grid_exactly():
    """The estimate's tensor-grid evaluation of ``(u, v)`` (the exponentials separated in x
    and y, 50 times faster on ``cases/stiffened_panel.toml``) against the field at the same
    points: equal to round-off (measured 1.3e-12 of the largest value on the T at 3 kHz, the
    amplitudes' cancellation; asked 1e-10: a wrong factor or polarisation is of order 1)."""

    case = parse_case(_description(*T_JUNCTION, 3000.0, False))
    solution = solve_assembly(case, 3000.0, residuals=False)
    for name, membrane in solution.membranes.items():
        (x, _), (y, _) = plate_gauss_axes(solution.plates[name].problem)
        grid = membrane_grid_displacement(membrane.basis, membrane.amplitudes, x, y)
        X, Y = np.meshgrid(x, y, indexing="ij")
        direct = membrane.u(np.column_stack([X.ravel(), Y.ravel()]))
        expected = np.moveaxis(direct.reshape(len(x), len(y), 2), -1, 0)
        assert np.max(abs(grid - expected)) < 1e-10 * np.max(abs(expected)), name


def test_the_in_plane_field_converges_under_refinement():
    """The in-plane basis carries the quasi-static boundary layers without lost digits
    (``docs/method.md`` section 10.3): on the L fold at 1 kHz (in-plane wavelengths 8 and 13
    times the plates) the error of ``(u, v)`` falls from resolution 1.5 to 2.25. Measured
    1.0e-7 -> 3.3e-8 (A) and 1.1e-7 -> 3.8e-8 (B); with longitudinal and shear edge waves
    in place of the boundary-layer pairs it rose, 3.7e-5 -> 7.5e-4 and 4.8e-5 -> 5.1e-4, the
    noise of their near-dependence on the plates' edges. Asked: a decrease and 1e-6 at 2.25,
    26 times the measured error and 500 times below the old one."""
    plates, lines, load = L_FOLD
    reference = _reference(plates, lines, load, 1000.0, False)
    errors = {name: [] for name in plates}
    for resolution in (1.5, 2.25):
        case = parse_case(folded_description(plates, lines, load, 1000.0, False, LY, resolution))
        solution = solve_assembly(case, 1000.0, residuals=False)
        for name, (length, *_) in plates.items():
            points = inner_grid(length, LY)
            exact = np.column_stack([reference.u(name, *points.T), reference.v(name, *points.T)])
            in_plane = solution.in_plane(name, points)
            errors[name].append(np.linalg.norm(in_plane - exact) / np.linalg.norm(exact))
    for name, (coarse, fine) in errors.items():
        assert fine < coarse and fine < 1e-6, (name, errors)


def _roller_fold(held, ends="roller", frequency=1000.0, resolution=RESOLUTION):
    description = _description(*L_FOLD, frequency, held)
    description["discretisation"]["resolution"] = resolution
    for boundary in description["boundaries"]:
        if "in_plane" in boundary:
            boundary["in_plane"] = ends
    return parse_case(description)


def test_a_line_with_roller_ends_stays_held_unless_asked_and_then_warns():
    """In-plane ``roller`` ends (``docs/method.md`` section 10.4): held by default, the moving
    solve costing 30 to 50 times more, and ``vtcr check`` warns of what the held line leaves
    out unless ``held = true`` says so; with ``held = false`` the line moves and ``vtcr check``
    warns of the cost, naming the joint, its roller edges and the alternatives; with
    ``diaphragm`` ends it moves by default, without a warning."""

    assert _roller_fold(None).moving_lines() == ()
    (held,) = check_description(_roller_fold(None), "fold.toml")
    assert held.startswith("fold.toml: joints.F.held: junction line F is held in translation "
                           "by default")
    assert "A.bottom" in held and "held = false" in held and "held = true" in held
    assert check_description(_roller_fold(True), "fold.toml") == []
    (warning,) = check_description(_roller_fold(False), "fold.toml")
    assert warning.startswith("fold.toml: joints.F.held: junction line F moves")
    assert "A.bottom" in warning and "held = true" in warning and "diaphragm" in warning
    assert _roller_fold(None, "diaphragm").moving_lines() == ("F",)
    assert check_description(_roller_fold(False, "diaphragm"), "fold.toml") == []


def _field_and_ends(case, frequency):
    """``w`` of every plate on a 15 x 15 grid, and ``|w|`` of plate B at the line's two ends (a
    simply supported corner: 0 exactly) over B's largest ``|w|`` on the grid."""
    solution = solve_assembly(case, frequency, residuals=False)
    fields = folded_w(solution, L_FOLD[0], LY)
    ends = solution.plates["B"].field(np.array([[0.0, 0.0], [0.0, LY]]))["w"]
    return fields, float(np.abs(ends).max() / np.abs(fields["B"]).max())


def _without_logarithmic_families(monkeypatch) -> None:
    """The rays alone at a mixed end, with the usual reach, as before the families."""
    import solver.in_plane
    import solver.line_ends

    monkeypatch.setattr(solver.line_ends, "SINGULAR_END_REACH", 1.0)
    for module in (solver.problems, solver.in_plane):
        monkeypatch.setattr(module, "singular_end_corners", lambda case, plate_id: ())


def test_a_line_with_roller_ends_holds_its_ends_and_converges(monkeypatch):
    """With roller ends only the leg B's bending support holds the line's end along x, under
    line loads that are log-singular at the ends (``docs/method.md`` section 10.4). With the
    logarithmic families at the line's ends and three times the reach
    (:func:`solver.line_ends.singular_end_corners`, :data:`solver.line_ends.SINGULAR_END_REACH`)
    ``w`` at that supported corner is 3e-12 of B's largest (300 Hz, resolution 1.5), and
    resolutions 1.5 and 2.25 agree to 1.6e-7 (A) and 6.4e-7 (B). With the rays alone and the
    usual reach: 4.1e-8 at the corner, 8.1e-5 and 2.3e-4 between the resolutions. (Until the
    line's translation rows took the members' in-plane moments on the plates' own edge rules,
    as their loads do, the rays alone left 3.1e-3 at the corner and differed by 9.0e-4 and
    1.1e-3; the families' fields did not move.) Bounds: 1e-9 at the corner with the families
    (round-off), five times their difference, and a tenth of the rays' figures alone."""
    corner, difference = _roller_corner_and_refinement()
    assert corner < 1e-9, corner
    assert difference < 3.2e-6, difference
    _without_logarithmic_families(monkeypatch)
    corner, difference = _roller_corner_and_refinement()
    assert corner > 4.1e-9, corner
    assert difference > 2.3e-5, difference


def _roller_corner_and_refinement() -> tuple[float, float]:
    """The roller-ended fold at 300 Hz: ``w`` at B's supported corner on the line over B's
    largest (resolution 1.5), and the worst plate's relative change of ``w`` from 1.5 to
    2.25."""
    coarse, corner = _field_and_ends(_roller_fold(False, frequency=300.0), 300.0)
    fine, _ = _field_and_ends(_roller_fold(False, frequency=300.0, resolution=2.25), 300.0)
    return corner, max(np.linalg.norm(coarse[name] - fine[name]) / np.linalg.norm(fine[name])
                       for name in coarse)


def test_a_member_hanging_on_a_line_with_mixed_ends_converges_with_families_and_reach(
        monkeypatch):
    """The L fold with roller ends and B's far edge ``diaphragm`` in-plane: nothing but the
    line holds B across it in its plane (it hangs: :func:`assembly.lines.hanging_members`), and
    the line's ends hold it only at A's supported corners. At 1 kHz resolutions 2.25 and 3.4
    agree to 2.9e-5 in ``w`` and 9.6e-4 in ``(u, v)`` with the logarithmic families and three
    times the reach; with the usual reach ``(u, v)`` differs by 1.9e-2
    (``bench/bench_roller_ends.py --hanging``). Before the line's logarithmic load functions
    the usual reach left 6.8e-2 in ``w`` too, and the rule 7.9e-5."""
    description = _description(*L_FOLD, 1000.0, False)
    for boundary in description["boundaries"]:
        if "in_plane" in boundary:
            boundary["in_plane"] = "roller"
        if boundary["edge"] == "B.right":
            boundary["in_plane"] = "diaphragm"

    def change() -> tuple[float, float]:
        """The largest relative change over the plates of ``w``, then of ``(u, v)``."""
        fields = []
        for resolution in (2.25, 3.4):
            description["discretisation"]["resolution"] = resolution
            case = parse_case(description)
            assert case.hanging_members("F") == ["B"]
            solution = solve_assembly(case, 1000.0, residuals=False)
            fields.append({name: (solution.plates[name].field(points)["w"],
                                  solution.in_plane(name, points))
                           for name, points in ((name, inner_grid(length, LY))
                                                for name, (length, *_) in L_FOLD[0].items())})
        coarse, fine = fields
        return tuple(max(np.linalg.norm(fine[n][part] - coarse[n][part])
                         / np.linalg.norm(coarse[n][part]) for n in coarse) for part in (0, 1))

    w_change, uv_change = change()
    assert w_change < 3e-4 and uv_change < 3e-3, (w_change, uv_change)
    import solver.line_ends

    monkeypatch.setattr(solver.line_ends, "SINGULAR_END_REACH", 1.0)
    assert change()[1] > 5e-3


@pytest.mark.parametrize("far, resolution, reciprocity, balance", [
    ("fixed", 1.5, 3e-6, 5e-7), ("diaphragm", 2.25, 4e-5, 3e-5)])
def test_mixed_ends_keep_reciprocity_and_the_power_balance(far, resolution, reciprocity,
                                                           balance):
    """The L fold with roller ends at 1 kHz, B's far edge fixed in-plane or, B hanging on the
    line, ``diaphragm``: a unit force on A at (0.15, 0.2) gives at B's (0.12, 0.07) what a unit
    force there gives at A's point, and each plate's power balances (injected plus delivered
    equals dissipated, its domain integrals through the corner functions). Measured under the
    rule: reciprocity 3.1e-7 and 3.7e-6, balance 4.8e-8 and 2.3e-6 of the injected power (the
    hanging fold at resolution 2.25: at 1.5 it is not converged yet); with the rays alone and
    the usual reach, 1.7e-4 and 2.1e-3, 3.1e-5 and 4.8e-4. Tolerances about ten times the
    rule's, below the rays'."""
    def fold(force):
        description = _description(L_FOLD[0], L_FOLD[1], force, 1000.0, False)
        description["discretisation"]["resolution"] = resolution
        for boundary in description["boundaries"]:
            if "in_plane" in boundary:
                boundary["in_plane"] = "roller"
            if boundary["edge"] == "B.right":
                boundary["in_plane"] = far
        return parse_case(description)

    source, target = ("A", 0.15, 0.2), ("B", 0.12, 0.07)
    on_a = solve_assembly(fold(source), 1000.0)
    there = on_a.w("B", np.array([target[1:]]))[0]
    back = solve_assembly(fold(target), 1000.0).w("A", np.array([source[1:]]))[0]
    assert abs(there - back) < reciprocity * abs(there)
    power = power_flow(fold(source), on_a)
    for plate in ("A", "B"):
        residual = (power.injected[plate] + power.delivered["F"][plate]
                    - power.dissipated[plate])
        assert abs(residual) < balance * power.total_injected, plate


FINITE_ELEMENT_FOLD = Path(__file__).parent / "data" / "fem_fold_mixed_ends.npz"
"""``w`` and ``(u, v)`` of the L fold with ``simply_supported`` + ``roller`` ends at 300 Hz and
1 kHz on each plate's :func:`inner_grid`, by the independent finite elements of
``bench/fem_folded.py`` (Argyris and P5 triangles, conforming at the fold; level 8, estimated
error 3e-10 to 3e-8; with shear-diaphragm ends they meet the exact solution to 1e-9 to 2e-8).
With them, the same fold with ``symmetric`` + ``diaphragm`` ends (level 6, changed by 6e-9 to
3e-7 in ``w`` from level 4), keys ``symmetric_diaphragm_w_A_300``, ..., and with ``symmetric``
+ ``fixed`` ends (level 6, changed by 6e-9 to 2.9e-7 in ``w`` from level 4), keys
``symmetric_fixed_w_A_300``, ...; and the roller fields at 100 Hz (level 6, changed by 5e-10
and 9e-9 in ``w`` from level 4), ``w_A_100``, ... Regenerated by ``python bench/fem_folded.py`` then ``python
bench/fem_folded.py --test-data``."""


def _finite_element_errors(solution, plates, reference, key: str
                           ) -> dict[str, tuple[float, float]]:
    """Per plate, the relative L2 differences of ``w`` and ``(u, v)`` on its
    :func:`inner_grid` to the finite-element fields ``reference[f"w_{plate}{key}"]`` and
    ``reference[f"uv_{plate}{key}"]``."""
    errors = {}
    for name, (length, *_) in plates.items():
        points = inner_grid(length, LY)
        w, uv = reference[f"w_{name}{key}"], reference[f"uv_{name}{key}"]
        errors[name] = (np.linalg.norm(solution.plates[name].field(points)["w"] - w)
                        / np.linalg.norm(w),
                        np.linalg.norm(solution.in_plane(name, points) - uv) / np.linalg.norm(uv))
    return errors


@pytest.mark.parametrize("in_plane", ["diaphragm", "fixed"])
@pytest.mark.parametrize("frequency", [300.0, 1000.0])
def test_symmetric_mixed_ends_meet_independent_finite_elements(frequency, in_plane):
    """The other mixes of the halves of a plane of symmetry that the finite elements take:
    ``symmetric`` in bending with ``diaphragm`` or ``fixed`` in-plane on every end edge. Their
    kink is in a member's deflection, not derived, and the rule gives them no logarithmic load
    functions (:func:`assembly.lines.singular_line_ends`). At resolution 1.5 ``w`` is within
    4.1e-6 and 5.2e-6 (A, B; diaphragm) and 3.5e-6 and 5.0e-6 (fixed) of
    :data:`FINITE_ELEMENT_FOLD` at 300 Hz, 3.9e-6 and 6.8e-6, and 3.4e-6 and 6.0e-6, at 1 kHz;
    ``(u, v)`` within 2e-4 to 4.4e-4. Tolerances about three times the largest; with the usual
    reach and no logarithmic families (the rule off) ``w`` is 2.3e-5 to 1e-4 off and
    ``(u, v)`` 1.2e-3 to 6.7e-2."""
    description = _description(*L_FOLD, frequency, False)
    for boundary in description["boundaries"]:
        if "in_plane" in boundary:
            boundary["condition"], boundary["in_plane"] = "symmetric", in_plane
    case = parse_case(description)
    assert case.singular_ends("F") and case.singular_line_ends("F") == (False, False)
    solution = solve_assembly(case, frequency, residuals=False)
    # keyed symmetric_diaphragm_w_A_300, symmetric_fixed_uv_B_1000, ...
    prefix = f"symmetric_{in_plane}_"
    reference = {key.removeprefix(prefix): value
                 for key, value in np.load(FINITE_ELEMENT_FOLD).items() if key.startswith(prefix)}
    errors = _finite_element_errors(solution, L_FOLD[0], reference, f"_{frequency:.0f}")
    for name, (w_error, uv_error) in errors.items():
        assert w_error < 2e-5 and uv_error < 1.3e-3, (name, w_error, uv_error)


def _singular_load_functions_off(monkeypatch) -> None:
    """The line's load functions without their logarithmic terms at mixed ends."""
    import assembly.case

    monkeypatch.setattr(assembly.case.Case, "singular_line_ends",
                        lambda self, joint_id: (False, False))


@pytest.mark.parametrize("frequency", [300.0, 1000.0])
def test_mixed_ends_meet_independent_finite_elements_with_the_lines_logarithmic_loads(
        frequency, monkeypatch):
    r"""The L fold with roller ends, moving under the rule, against the finite elements of
    :data:`FINITE_ELEMENT_FOLD`. Its line's loads go like :math:`a\ln t + b + c\,t\ln t`
    at both ends (``docs/method.md`` section 10.4); with those terms among the line's load
    functions (:func:`solver.joint_rules.load_function_values`) and at least 27 Legendre
    functions (:func:`solver.joint_rules.mixed_end_legendre_count`) ``w`` is within 2.8e-7
    and 1.1e-6 (A, B) of the finite elements at 300 Hz and 1.3e-6 and 2.4e-6 at 1 kHz,
    ``(u, v)`` within 1.3e-4 at both (resolution 1.5; at 300 Hz the count of the wavenumbers
    alone, 16, left 5.8e-6 and 1.6e-5 in ``w``, 1.4e-3 in ``(u, v)``). On Legendre
    functions alone, as before, the solve converged under refinement to a field 1e-4 off in
    ``w`` and 1e-2 to 1e-1 in ``(u, v)``. Tolerances three times the measured errors."""
    reference = np.load(FINITE_ELEMENT_FOLD)

    def errors() -> dict[str, tuple[float, float]]:
        solution = solve_assembly(_roller_fold(False, frequency=frequency), frequency,
                                  residuals=False)
        return _finite_element_errors(solution, L_FOLD[0], reference, f"_{frequency:.0f}")

    with_terms = errors()
    for name, (w_error, uv_error) in with_terms.items():
        assert w_error < (3.5e-6 if frequency < 500.0 else 7.5e-6) and uv_error < 4e-4, (
            name, with_terms)
    _singular_load_functions_off(monkeypatch)
    without = errors()
    assert max(w_error for w_error, _ in without.values()) > 5e-5, without
    assert max(uv_error for _, uv_error in without.values()) > 1e-2, without


FINITE_ELEMENT_JUNCTION = Path(__file__).parent / "data" / "fem_junction_roller.npz"
"""``w`` and ``(u, v)`` of the T junction of :data:`SHAPES` with ``simply_supported`` +
``roller`` ends at 1 kHz, its stiffener's top free (it hangs on the line) or simply supported
and fixed, on each plate's :func:`inner_grid`, by the independent finite elements of
``bench/fem_junction.py`` (Argyris and P5 triangles; S1 and S2 tied rigidly, T1 through its
spring; level 8, changed by 5e-8 to 2e-7 from level 6, T1's ``(u, v)`` with the fixed top by
1.5e-5; with diaphragm ends they meet the exact solution to 6e-9 to 2.4e-6). Regenerated by
``python bench/fem_junction.py --levels 2 4 6 8 --frequencies 1000 --ends roller`` then
``python bench/fem_junction.py --test-data``."""


@pytest.mark.parametrize("top", ["free", "fixed"])
def test_a_t_junction_with_mixed_ends_meets_independent_finite_elements(top, monkeypatch):
    """The T junction with roller ends at 1 kHz, moving under the rule, against
    :data:`FINITE_ELEMENT_JUNCTION`: at resolution 1.5 ``w`` is within 1.7e-5 (top free) and
    9.1e-6 (fixed) of the finite elements on every plate, ``(u, v)`` within 7.2e-4 and
    2.7e-4. With the line's loads on Legendre functions alone, their count following the
    members' reach (:func:`solver.layout.answered_wavenumber`), they are 6.0e-3 and 3.7e-4
    off in ``w``, 0.25 and 1.7e-2 in ``(u, v)``. (With the count stopped at the usual reach,
    as before 2026-11-27, they converged under refinement, 1e-6 to 4e-6 between resolutions
    2.25 and 3.4, to a field 2.9e-2 and 1.3e-3 off in ``w``, up to 1.2 and 4.6e-2 in
    ``(u, v)``.) Tolerances three times the measured errors; without the logarithmic loads,
    about a third of the measured."""
    plates, lines, load = SHAPES["T"]
    if top == "fixed":
        plates = {**plates, "T1": plates["T1"][:4] + ("simply_supported",)}
    reference = np.load(FINITE_ELEMENT_JUNCTION)

    def errors() -> tuple[float, float]:
        description = _description(plates, lines, load, 1000.0, False)
        for boundary in description["boundaries"]:
            if boundary["edge"].endswith(("bottom", "top")):
                boundary["in_plane"] = "roller"
        solution = solve_assembly(parse_case(description), 1000.0, residuals=False)
        errors = _finite_element_errors(solution, plates, reference, f"_{top}").values()
        return max(w_error for w_error, _ in errors), max(uv_error for _, uv_error in errors)

    w_error, uv_error = errors()
    assert w_error < (5e-5 if top == "free" else 3e-5) and uv_error < 2e-3, (w_error, uv_error)
    _singular_load_functions_off(monkeypatch)
    w_before, uv_before = errors()
    assert w_before > 1e-4 and uv_before > 1e-2, (w_before, uv_before)


def _roller_ends_estimate(shape: str, frequency: float, top: str | None, resolution: float
                          ) -> list[tuple[str, float, float]]:
    """Per plate, ``(name, estimate, true error)`` of ``w`` with roller ends, moving under the
    rule, the true error against :data:`FINITE_ELEMENT_FOLD` or
    :data:`FINITE_ELEMENT_JUNCTION`."""
    plates, lines, load = SHAPES[shape]
    case = parse_case(folded_description(plates, lines, load, frequency, False, LY, resolution,
                                         ends="roller"))
    solution = solve_assembly(case, frequency)
    estimate = estimate_error(case, solution)
    reference = np.load(FINITE_ELEMENT_FOLD if shape == "L" else FINITE_ELEMENT_JUNCTION)
    key = f"_{frequency:.0f}" if shape == "L" else f"_{top}"
    return [(name, estimate.plates[name], true) for name, (true, _) in
            _finite_element_errors(solution, plates, reference, key).items()]


@pytest.mark.parametrize("shape, frequency, top, resolution", [
    ("L", 100.0, None, 2.25), ("L", 300.0, None, 1.0), ("L", 1000.0, None, 1.0),
    ("T", 1000.0, "free", 1.0)])
def test_the_estimate_of_a_line_with_mixed_ends_is_honest_against_finite_elements(
        shape, frequency, top, resolution):
    """With roller ends, moving under the rule: the error estimate of ``w`` per plate against
    the true error, the difference to the finite elements. Measured ratios 0.97 to 1.03 at
    resolution 1 (true errors 4.5e-6 to 1.2e-2) and 1.4 at 100 Hz and resolution 2.25 (true
    errors 3e-7 and 8.4e-7, well above the finite elements' 1e-8); within [0.5, 3] asked.
    Before the line carried at least :func:`solver.joint_rules.mixed_end_legendre_count`
    Legendre functions, the L fold's error stopped at 1e-5 at 100 Hz, where the count of its
    wavenumbers (11) leaves it, and the estimate, whose enriched solve keeps that count, said
    1/50 of it (:func:`test_the_legendre_floor_is_what_the_estimate_sees`)."""
    for name, estimate, true in _roller_ends_estimate(shape, frequency, top, resolution):
        assert true > 1e-7 and 0.5 <= estimate / true <= 3.0, (name, estimate, true)


def test_the_legendre_floor_is_what_the_estimate_sees(monkeypatch):
    """The L fold with roller ends at 100 Hz and resolution 2.25 on the 11 Legendre functions
    of its wavenumbers alone (the floor off): ``w`` 1e-5 and 1.3e-5 off the finite elements,
    the estimate 1/50 of that; with the floor of 27 (the first test) 3e-7 and 8.4e-7, the
    estimate 1.4 times that. The count's remainder is what the estimate cannot see; the
    floor is what removes it."""
    import solver.layout

    monkeypatch.setattr(solver.layout, "legendre_count_floor", lambda ends: 0)
    for name, estimate, true in _roller_ends_estimate("L", 100.0, None, 2.25):
        assert true > 5e-6 and estimate < 0.1 * true, (name, estimate, true)


def test_the_mixed_end_legendre_count_leaves_what_it_says_of_the_next_term():
    r""":func:`solver.joint_rules.mixed_end_legendre_count` against its definition on another
    rule: with :math:`t = u^4` the integrands of :math:`(t^2\ln t)\,P_m(2t - 1)` are smooth
    in :math:`u`, so plain Gauss points in :math:`u` integrate them; the part of
    :math:`t^2\ln t` outside the first 27 Legendre functions is then below 1e-6 of its norm,
    outside 26 above, and outside 17 near 1e-5 (the count of the L fold's wavenumbers at
    300 Hz is 16 to 18)."""
    from solver.joint_rules import SINGULAR_REMAINDER, mixed_end_legendre_count

    u, weights = np.polynomial.legendre.leggauss(400)
    u, weights = 0.5 * (u + 1.0), 0.5 * weights
    t, weights = u**4, weights * 4.0 * u**3
    f = t**2 * np.log(t)

    def left(count: int) -> float:
        legendre = np.polynomial.legendre.legvander(2.0 * t - 1.0, count - 1)
        coefficients = (2.0 * np.arange(count) + 1.0) * (legendre.T @ (weights * f))
        return math.sqrt((weights @ (f - legendre @ coefficients) ** 2) / (weights @ f**2))

    count = mixed_end_legendre_count()
    assert count == 27 and SINGULAR_REMAINDER == 1e-6
    assert left(count) <= SINGULAR_REMAINDER < left(count - 1)
    assert 5e-6 < left(17) < 2e-5


@pytest.mark.parametrize("mixed", ["bottom", "top"])
def test_the_logarithmic_loads_sit_at_the_mixed_end_of_a_line_with_one(mixed, monkeypatch):
    """The L fold at 1 kHz with one end ``simply_supported`` + ``roller`` (mixed) and the
    other ``simply_supported`` + ``diaphragm``: the logarithmic load functions go to the
    mixed end only (:func:`assembly.lines.singular_line_ends`, in the line's direction, which
    B runs against). The reference is the same fold with 50 Legendre functions and no
    logarithmic ones, a finer discretisation of the loads (with both ends mixed it is within
    7.6e-7 and 1.7e-6 of the finite elements, ``bench/bench_roller_ends.py --fem``). Measured
    at resolution 2.25: the rule 9.4e-7 (mixed bottom) and 2.8e-6 (top) from it; the
    logarithmic functions at the other end, or none, 1.1e-4 and 1.9e-4."""
    description = _description(*L_FOLD, 1000.0, False)
    description["discretisation"]["resolution"] = 2.25
    for boundary in description["boundaries"]:
        if "in_plane" in boundary:
            boundary["in_plane"] = "roller" if boundary["edge"].endswith(mixed) else "diaphragm"
    expected = (True, False) if mixed == "bottom" else (False, True)
    assert parse_case(description).singular_line_ends("F") == expected

    def fields(settings: dict | None = None) -> dict[str, np.ndarray]:
        case = parse_case(description | {"discretisation": description["discretisation"]
                                         | (settings or {})})
        return folded_w(solve_assembly(case, 1000.0, residuals=False), L_FOLD[0], LY)

    def difference(a: dict, b: dict) -> float:
        return max(np.linalg.norm(a[name] - b[name]) / np.linalg.norm(b[name]) for name in b)

    rule = fields()
    _singular_load_functions_off(monkeypatch)
    finer = fields({"interface_functions": 50})
    assert difference(rule, finer) < 5e-6
    import assembly.case

    monkeypatch.setattr(assembly.case.Case, "singular_line_ends",
                        lambda self, joint_id: expected[::-1])
    assert difference(fields(), finer) > 5e-5


def test_the_logarithmic_families_sit_where_a_moving_line_meets_its_mixed_end():
    """:func:`solver.line_ends.singular_end_corners`: on the T junction with roller ends and
    its line moving, the corners of each member's line edge (S1's right edge: corners 1 and 2;
    S2's and T1's left edges: 0 and 3); none with shear-diaphragm ends, where the end is
    consistent, nor with the line held. Bending and in-plane bases carry one family there."""
    from solver.in_plane import membrane_bases, membrane_problems
    from solver.line_ends import singular_end_corners
    from solver.problems import plate_bases

    plates, lines, load = SHAPES["T"]
    description = folded_description(plates, lines, load, 1000.0, False, LY)
    for boundary in description["boundaries"]:
        if "in_plane" in boundary:
            boundary["in_plane"] = "roller"
    case = parse_case(description)
    assert {p: singular_end_corners(case, p) for p in plates} == {
        "S1": (1, 2), "S2": (0, 3), "T1": (0, 3)}
    problems = plate_problems(case, 1000.0)
    bases = plate_bases(case, problems, None)
    assert [len(bases[p].wedges) for p in plates] == [2, 2, 2]
    membranes = membrane_bases(case, membrane_problems(case, 1000.0), problems)
    assert [len(membranes[p].corners) for p in plates] == [2, 2, 2]
    for held in (None, True):  # roller ends hold the line by default
        description["joints"]["W"].pop("held", None)
        if held:
            description["joints"]["W"]["held"] = True
        assert all(singular_end_corners(parse_case(description), p) == () for p in plates)
    consistent = parse_case(folded_description(plates, lines, load, 1000.0, False, LY))
    assert all(singular_end_corners(consistent, p) == () for p in plates)


def test_a_balancing_member_solved_on_its_functions_gives_the_field_of_its_loads(monkeypatch):
    """The balancing members of :data:`PANEL`'s two lines (its bays S2 and S3) load 144 and 96
    unknowns through 96 and 48 distinct functions at 600 Hz, bending and in-plane alike:
    their transfer operators are solved on the functions and spread by the balances'
    coefficients (``solver.interface_loads.PlateLoads``). The fields are those of the
    operators solved on the loads themselves, to their rounding: measured 2.3e-10 in ``w``
    and 8.1e-8 in ``(u, v)`` on the worst plate (the ray amplitudes differ more, 3e-8 of the
    largest, along the near-null directions that the truncated factorisations leave
    undetermined and the fields do not see). The bounds, 1e-8 and 1e-6, fail where the
    solutions are spread otherwise than the functions (checked with their columns reversed);
    a wrong coefficient, which both routes share, fails this module's comparisons with the
    exact folded plates (checked: seven of them)."""
    from solver import interface_loads

    case = parse_case(_description(*PANEL, 600.0, False))
    compressed = []
    spread = interface_loads.PlateLoads.spread

    def counted(self, values):
        compressed.append(self.compressed)
        return spread(self, values)

    monkeypatch.setattr(interface_loads.PlateLoads, "spread", counted)
    solved = solve_assembly(case, 600.0, residuals=False)
    assert sum(compressed) == 4  # S2 and S3, bending and in-plane
    monkeypatch.setattr(interface_loads.PlateLoads, "compressed", property(lambda self: False))
    direct = solve_assembly(case, 600.0, residuals=False)
    plates = PANEL[0]
    ours, theirs = folded_w(solved, plates, LY), folded_w(direct, plates, LY)
    for name in plates:
        points = inner_grid(plates[name][0], LY)
        assert (np.linalg.norm(ours[name] - theirs[name])
                <= 1e-8 * np.linalg.norm(theirs[name])), name
        in_plane = direct.in_plane(name, points)
        assert (np.linalg.norm(solved.in_plane(name, points) - in_plane)
                <= 1e-6 * np.linalg.norm(in_plane)), name


def test_identical_plates_share_their_factorisations_and_solves_and_nothing_changes(monkeypatch):
    """A four-bay stiffened panel's inner bays have the same in-plane problem, and so have its
    stiffeners: four in-plane matrices are assembled and factorised for seven plates. The
    inner bays' loads are the same too, so they hold one transfer operator, bending and
    in-plane. Every transfer operator is that of a factorisation and a solve of its own for
    every plate, to the bit."""
    from assembly.generate import stiffened_panel
    from solver import admissibility
    from solver.substructure import build_assembly_system

    case = parse_case(stiffened_panel(4, frequency=600.0))
    assembled = []
    assemble = admissibility.assemble_membrane

    def counted(problem, basis, cache=None):
        assembled.append(problem)
        return assemble(problem, basis, cache)

    monkeypatch.setattr(admissibility, "assemble_membrane", counted)
    system = build_assembly_system(case, 600.0)
    shared = system.membranes
    # B1 (its outer edge fixed), B2 = B3 (both lines free), B4 (mirror of B1), T1 = T2 = T3
    assert len(assembled) == 4 and len(shared) == 7
    for inner in (system.transfer, {pid: block.transfer for pid, block in shared.items()}):
        assert np.shares_memory(inner["B2"], inner["B3"]) and not inner["B2"].flags.writeable
        assert not np.shares_memory(inner["B1"], inner["B2"])
    assembled.clear()
    monkeypatch.setattr(admissibility, "_membrane_signature", lambda problem, basis: object())
    monkeypatch.setattr(admissibility._SharedSolves, "get",
                        lambda self, signature, loads, solve: solve(loads))
    alone_system = build_assembly_system(case, 600.0)
    alone = alone_system.membranes
    assert len(assembled) == 7
    for pid, block in shared.items():
        assert np.array_equal(block.transfer, alone[pid].transfer), pid
        assert block.rcond == alone[pid].rcond
        assert np.array_equal(system.transfer[pid], alone_system.transfer[pid]), pid
        assert np.array_equal(system.u0[pid], alone_system.u0[pid]), pid
