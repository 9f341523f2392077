"""The a-posteriori error estimate (``solver.estimate``) against exact errors (issue 10).

The true error is the relative L2 error of w over the plates against exact series (Navier for
the simply supported plate, Levy chains for the jointed ones), integrated with the estimate's
own Gauss rule; the estimate never sees the series. The issue asks for an effectivity
(estimate / true error) within [0.3, 3] wherever the true error exceeds 1e-4; the rule is
held to that band here; the measured effectivities are 0.92–1.43 (0.58 for a point force
40 um from an edge, the closest accepted).
"""

import json
import math

import numpy as np
import pytest
from exact import Section, complex_rigidity, levy_chain, navier_point_force
from support import CASES, LENGTHS, LY, NU, OMEGA, RHO, D, H, chain_description, exact_joint

from assembly import parse_case
from solver import solve_case
from solver.errors import ToleranceError
from solver.estimate import estimate_error, plate_l2_rule, relative_l2_errors
from solver.problems import plate_problem, plate_ray_counts
from solver.tolerance import solve_to_tolerance
from updating.cli import main

TWO_PLATES = CASES / "two_plates.toml"

E, PLATE_NU, PLATE_RHO, PLATE_H = 210e9, 0.3, 7800.0, 1e-3
SIZE = (0.5, 0.4)
EFFECTIVITY = (0.3, 3.0)


def plate_description(eta=0.01, at=(0.12, 0.31), resolution=1.0):
    return {
        "name": "ss-plate", "frequency": 155.0,
        "materials": {"steel": {"young_modulus": E, "poisson_ratio": PLATE_NU,
                                "density": PLATE_RHO, "loss_factor": eta}},
        "plates": {"P1": {"material": "steel", "thickness": PLATE_H, "size": list(SIZE)}},
        "boundaries": [{"edge": f"P1.{e}", "condition": "simply_supported"}
                       for e in ("left", "right", "bottom", "top")],
        "loads": [{"kind": "point_force", "plate": "P1", "at": list(at), "amplitude": 1.0}],
        "discretisation": {"resolution": resolution},
    }


def plate_error(frequency, resolution, eta=0.01, at=(0.12, 0.31)):
    """(true error, estimate) of the simply supported plate against the Navier series."""
    case = parse_case(plate_description(eta, at, resolution))
    # some cases sit where the guard rails refuse a solve (below the first resonance, forces
    # next to an edge): the estimate must say so there too
    solution = solve_case(case, frequency, check=False)
    estimate = estimate_error(case, solution)
    points, weights = plate_l2_rule(solution.plates["P1"].problem)
    exact = navier_point_force(*SIZE, complex_rigidity(E, PLATE_H, PLATE_NU, eta),
                               PLATE_RHO * PLATE_H, 2 * math.pi * frequency, *at, 1.0,
                               points[:, 0], points[:, 1], n_terms=400)
    w = solution.w("P1", points)
    error = math.sqrt(weights @ abs(w - exact) ** 2 / (weights @ abs(exact) ** 2))
    return error, estimate.total


def first_resonance():
    """25.28 Hz: the (1, 1) mode of the 0.5 x 0.4 m steel plate, h = 1 mm."""
    d = E * PLATE_H**3 / (12 * (1 - PLATE_NU**2))
    return 0.5 * math.pi * math.sqrt(d / (PLATE_RHO * PLATE_H)) * sum(1 / s**2 for s in SIZE)


@pytest.mark.parametrize("frequency, resolution, eta, at", [
    (1.0, 1.0, 0.01, (0.12, 0.31)),          # quasi-static (was 18 % with 28 unknowns)
    (0.1, 1.0, 0.01, (0.12, 0.31)),          # far below: large error, and the estimate says so
    (60.0, 0.8, 0.01, (0.12, 0.31)),
    (155.0, 0.6, 0.01, (0.12, 0.31)),
    (155.0, 0.8, 0.01, (0.12, 0.31)),
    (400.0, 0.8, 0.01, (0.12, 0.31)),
    (155.0, 1.0, 0.01, (0.01, 0.2)),          # force 1 cm from an edge
    (155.0, 1.0, 0.01, (0.001, 0.2)),         # force 1 mm from an edge (27 %)
    (155.0, 1.0, 0.01, (1e-4, 0.2)),          # 0.1 mm (289 %)
    (155.0, 1.0, 0.01, (4e-5, 0.2)),          # 40 um, the closest accepted (720 %)
    (25.281030306075202, 1.0, 1e-12, (0.12, 0.31)),  # first resonance, eta 1e-12 (98 %)
])
def test_single_plate_effectivity(frequency, resolution, eta, at):
    error, estimate = plate_error(frequency, resolution, eta, at)
    assert error > 1e-4, "the case must sit where the issue's band applies"
    assert EFFECTIVITY[0] <= estimate / error <= EFFECTIVITY[1], (error, estimate)


@pytest.mark.parametrize("eta", [1e-4, 1e-6])
def test_light_damping_at_the_first_resonance(eta):
    """At the first resonance with eta down to 1e-6 the field stays accurate (the issue
    measured 1.1 % and 73 % before the low-frequency sizing), and the estimate says so."""
    error, estimate = plate_error(first_resonance(), 1.0, eta)
    assert error < 1e-4 and estimate < 1e-4, (error, estimate)


def test_estimate_decreases_with_the_error():
    """Refining lowers the true error and the estimate together."""
    pairs = [plate_error(155.0, r) for r in (0.6, 0.8, 1.0)]
    errors, estimates = zip(*pairs)
    assert errors[0] > errors[1] > errors[2]
    assert estimates[0] > estimates[1] > estimates[2], pairs


@pytest.mark.parametrize("joints, resolution", [
    ([{"kind": "coplanar", "log10_stiffness": 1.5, "loss_factor": 0.1, "mass": 0.05}], 0.85),
    ([{"kind": "coplanar", "log10_stiffness": 3.5}], 1.0),
    ([{"kind": "hinge", "log10_stiffness": 2.5}], 1.0),
    ([{"kind": "coplanar", "log10_stiffness": 1.5, "loss_factor": 0.1, "mass": 0.05},
      {"kind": "hinge", "log10_stiffness": 3.5}], 0.85),
], ids=["coplanar-damped-mass", "coplanar-stiff", "hinge", "three-plates"])
def test_chain_effectivity(joints, resolution):
    """Jointed chains against the Levy series: total and per-plate estimates."""
    force = (0, 0.12, 0.31)
    case = parse_case(chain_description(joints, resolution, force=force))
    solution = solve_case(case)
    estimate = estimate_error(case, solution)
    n = len(joints) + 1
    reference = levy_chain([Section(LENGTHS[i], D, NU, RHO * H) for i in range(n)], LY, OMEGA,
                           joints=[exact_joint(j) for j in joints], left="simply_supported",
                           right="clamped", point_forces=[(*force, 1.0)])
    total_error = total_norm = 0.0
    for i in range(n):
        plate = f"P{i + 1}"
        points, weights = plate_l2_rule(solution.plates[plate].problem)
        w = solution.w(plate, points)
        exact = reference.w(points[:, 0], points[:, 1], plate=i)
        error, norm = weights @ abs(w - exact) ** 2, weights @ abs(exact) ** 2
        total_error, total_norm = total_error + error, total_norm + norm
        if math.sqrt(error / norm) > 1e-4:
            ratio = estimate.plates[plate] / math.sqrt(error / norm)
            assert EFFECTIVITY[0] <= ratio <= EFFECTIVITY[1], (plate, ratio)
    error = math.sqrt(total_error / total_norm)
    assert error > 1e-4
    assert EFFECTIVITY[0] <= estimate.total / error <= EFFECTIVITY[1], (error, estimate.total)


def test_tolerance_is_reached_and_true():
    """solve_to_tolerance refines until the estimate is below the tolerance, and the true
    error (Levy) is then below it too, within the effectivity band."""
    joint = {"kind": "hinge", "log10_stiffness": 2.5}
    case = parse_case(chain_description([joint], 0.85))
    solution, estimate = solve_to_tolerance(case, case.frequencies[0], 1e-3)
    assert estimate.total <= 1e-3 and estimate.resolution > 0.85
    reference = levy_chain([Section(LENGTHS[i], D, NU, RHO * H) for i in range(2)], LY, OMEGA,
                           joints=[exact_joint(joint)], left="simply_supported",
                           right="clamped", point_forces=[(0, 0.12, 0.31, 1.0)])
    num = den = 0.0
    for i in range(2):
        points, weights = plate_l2_rule(solution.plates[f"P{i + 1}"].problem)
        exact = reference.w(points[:, 0], points[:, 1], plate=i)
        num += weights @ abs(solution.w(f"P{i + 1}", points) - exact) ** 2
        den += weights @ abs(exact) ** 2
    assert math.sqrt(num / den) <= EFFECTIVITY[1] * 1e-3


def test_a_refinement_of_every_plate_takes_the_enriched_solve_as_its_next_solve(monkeypatch):
    """Where every plate is refined, the next solve is the one the estimate just made (every
    count times ENRICHMENT): solve_to_tolerance solves each resolution once, and returns what a
    solve at its final resolution returns."""
    import solver.estimate
    import solver.tolerance

    joint = {"kind": "hinge", "log10_stiffness": 2.5}
    case = parse_case(chain_description([joint], 0.85))
    resolutions = []
    original = solver.estimate.solve_case

    def recording(*args, **kwargs):
        resolutions.append(tuple(sorted(kwargs["resolution"].items())))
        return original(*args, **kwargs)

    # the solves of the refinement and those of its estimates (the enriched ones)
    monkeypatch.setattr(solver.tolerance, "solve_case", recording)
    monkeypatch.setattr(solver.estimate, "solve_case", recording)
    solution, estimate = solve_to_tolerance(case, case.frequencies[0], 1e-3)
    assert len(resolutions) == len(set(resolutions)) == 3, resolutions  # 0.85, 1.275, 1.9125
    monkeypatch.undo()
    again = solve_case(case, case.frequencies[0], resolution=estimate.resolution, check=False)
    points = np.array([[0.1, 0.2], [0.3, 0.1]])
    for plate in case.plates:
        assert np.array_equal(solution.w(plate, points), again.w(plate, points))
    assert solution.residuals == again.residuals


def test_unreachable_tolerance_names_the_plate_and_the_cause():
    case = parse_case(plate_description())
    with pytest.raises(ToleranceError, match=r"0.01 Hz.*plate P1.*far below its first resonances"):
        solve_to_tolerance(case, 0.01, 1e-3)


def test_overridden_ray_counts_are_refined_with_the_resolution():
    """Per-plate overrides are counts at the description's resolution: kept as written there,
    scaled with any other resolution (else the enriched solve would not enrich them)."""
    data = plate_description(resolution=1.0)
    data["discretisation"]["plates"] = {"P1": {"interior": 30, "edge_evanescent": 7}}
    case = parse_case(data)
    problem = plate_problem(case, "P1", 155.0)
    own = plate_ray_counts(case, "P1", problem)
    enriched = plate_ray_counts(case, "P1", problem, 1.5)
    assert own.interior == 30 and own.edge_evanescent == (7,) * 4
    assert enriched.interior == 48 and enriched.edge_evanescent == (11,) * 4


def test_low_frequency_counts_grow_with_the_resolution():
    """Below the first resonance the counts are sized from the plate, so refining refines."""
    case = parse_case(plate_description())
    problem = plate_problem(case, "P1", 1.0)
    coarse, fine = (plate_ray_counts(case, "P1", problem, r).total for r in (1.0, 1.5))
    assert fine > coarse


def test_solve_reports_the_estimate(tmp_path, capsys):
    path = tmp_path / "plate.toml"
    from assembly.generate import description_toml

    path.write_text(description_toml(plate_description(resolution=0.8)))
    out = tmp_path / "out.json"
    assert main(["solve", str(path), "--json", str(out), "--max-rows", "0"]) == 0
    estimate = json.loads(out.read_text())["error_estimate"]
    assert set(estimate["plates"]) == {"P1"} and estimate["total"] == estimate["plates"]["P1"]
    error, _ = plate_error(155.0, 0.8)
    assert EFFECTIVITY[0] <= estimate["total"] / error <= EFFECTIVITY[1]
    assert "estimated error of w" in capsys.readouterr().out
    assert main(["solve", str(path), "--tolerance", "1e-4", "--json", str(out),
                 "--max-rows", "0"]) == 0
    estimate = json.loads(out.read_text())["error_estimate"]
    assert estimate["total"] <= 1e-4 and estimate["resolution"] > 0.8
    assert main(["solve", str(path), "--frequency", "0.01", "--tolerance", "1e-3"]) == 2
    assert "plate P1" in capsys.readouterr().err
    assert np.isfinite(json.loads(out.read_text())["timings"]["estimate"])


def _variant(change, frequency):
    data = plate_description()
    data["frequency"] = frequency
    kind, value = change
    if kind == "eta":
        data["materials"]["steel"]["loss_factor"] = value
    elif kind == "at":
        data["loads"][0]["at"] = list(value)
    elif kind == "width":
        data["plates"]["P1"]["size"] = [value, 0.4]
        data["loads"][0]["at"] = [0.5 * value, 0.2]
    elif kind in ("young_modulus", "density"):
        data["materials"]["steel"][kind] = value
    elif kind == "thickness":
        data["plates"]["P1"]["thickness"] = value
    return data


# The table of inputs that gave silent wrong fields or tracebacks, each with what vtcr
# now does: "accurate" (exit 0, estimate below 1e-2 and no warning), "warned" (exit 0, the
# estimated error printed and flagged, or a named physics warning) or "refused" (exit 2, one
# line naming the field and the fix, nothing written).
GUARD_RAILS = [
    ("1 Hz", ("none", None), 1.0, "accurate", None),
    ("1e-6 Hz", ("none", None), 1e-6, "refused", "below about 0.22 Hz"),
    ("eta 1e-4 at resonance", ("eta", 1e-4), first_resonance(), "accurate", None),
    ("eta 1e-12 at resonance", ("eta", 1e-12), first_resonance(), "warned", "estimated error"),
    ("force 0.1 mm from an edge", ("at", (1e-4, 0.2)), 155.0, "warned", "estimated error"),
    ("force 1 um from an edge", ("at", (1e-6, 0.2)), 155.0, "refused", "edge load"),
    ("force 40 um from an edge", ("at", (4e-5, 0.2)), 155.0, "warned", "estimated error"),
    ("plate 1 um wide", ("width", 1e-6), 155.0, "refused", "not a plate"),
    ("E 1e20", ("young_modulus", 1e20), 155.0, "refused", "far below its first resonance"),
    ("density 1e-20", ("density", 1e-20), 155.0, "refused", "far below its first resonance"),
    ("h 0.3 m", ("thickness", 0.3), 155.0, "warned", "thin-plate"),
    ("h 1e300", ("thickness", 1e300), 155.0, "refused", "SI units"),
    ("h 1e-300", ("thickness", 1e-300), 155.0, "refused", "SI units"),
    ("f 1e-300", ("none", None), 1e-300, "refused", "below about"),
    ("f 1e300", ("none", None), 1e300, "refused", "lower the frequency"),
]


@pytest.mark.parametrize("change, frequency, outcome, says",
                         [row[1:] for row in GUARD_RAILS], ids=[row[0] for row in GUARD_RAILS])
def test_guard_rails(tmp_path, capsys, change, frequency, outcome, says):
    from assembly.generate import description_toml

    path = tmp_path / "plate.toml"
    path.write_text(description_toml(_variant(change, frequency)))
    out = tmp_path / "out.json"
    status = main(["solve", str(path), "--json", str(out), "--max-rows", "0"])
    captured = capsys.readouterr()
    text = captured.out + captured.err
    assert "Traceback" not in text
    if outcome == "refused":
        assert status == 2 and not out.exists()
        assert len(captured.err.strip().splitlines()) == 1 and says in captured.err
        return
    assert status == 0
    estimate = json.loads(out.read_text())["error_estimate"]["total"]
    if outcome == "accurate":
        assert estimate < 1e-2 and "warning" not in text, text
    else:
        assert "warning" in text and says in text, text
        if says == "estimated error":
            assert estimate > 1e-2


def test_grid_estimate_against_a_finer_solve():
    """A 3 x 3 grid (junction corners, two joint directions): the estimate against the
    difference from a solve at twice the resolution (converged to about 1e-6 there)."""
    from assembly.generate import plate_grid

    case = parse_case(plate_grid(3, 3))
    solution = solve_case(case)
    estimate = estimate_error(case, solution)
    reference = solve_case(case, resolution=2.0, residuals=False)
    integrals = relative_l2_errors(solution, reference.plates)
    error = math.sqrt(sum(e for e, _ in integrals.values()) / sum(n for _, n in integrals.values()))
    assert error > 1e-4
    assert EFFECTIVITY[0] <= estimate.total / error <= EFFECTIVITY[1], (error, estimate.total)


def test_unaffordable_estimate_is_skipped_with_its_reason(monkeypatch):
    import solver.estimate

    monkeypatch.setattr(solver.estimate, "ENRICHED_SOLVE_SECONDS", 0.0)
    case = parse_case(chain_description([{"kind": "hinge", "log10_stiffness": 2.5}]))
    estimate = estimate_error(case, solve_case(case))
    assert estimate.total is None and estimate.method == "skipped"
    assert "enriched solve" in estimate.reason
    with pytest.raises(ToleranceError, match="cannot be checked"):
        solve_to_tolerance(case, case.frequencies[0], 1e-3)


def test_localise_update_and_frf_report_the_estimate(tmp_path):
    """localise and update estimate the model's response at its initial parameters (the same
    number solve gives for it), frf at its strongest peak and its top frequency; --no-estimate
    leaves it out."""
    case = str(TWO_PLATES)
    solved, localised, updated, swept = (tmp_path / f"{n}.json" for n in "sluf")
    assert main(["solve", case, "--json", str(solved), "--max-rows", "0"]) == 0
    assert main(["localise", case, "--json", str(localised)]) == 0
    expected = json.loads(solved.read_text())["error_estimate"]
    estimate = json.loads(localised.read_text())["error_estimate"]
    assert estimate["total"] == pytest.approx(expected["total"], rel=1e-6)
    assert estimate["frequencies"]["155"]["plates"] == pytest.approx(expected["plates"], rel=1e-6)
    assert main(["update", case, "--json", str(updated), "--run", str(tmp_path / "r.json"),
                 "--no-estimate"]) in (0, 3)
    assert json.loads(updated.read_text())["error_estimate"] is None
    assert main(["frf", case, "--band", "150", "160", "--start-frequencies", "3", "--json", str(swept)]) == 0
    estimate = json.loads(swept.read_text())["error_estimate"]
    assert "160" in estimate["frequencies"] and 0 < estimate["total"] < 1e-2



def test_tolerance_drives_the_model_and_the_simulated_experiment(tmp_path, monkeypatch):
    """[discretisation] tolerance: localise raises the model's resolution until its response
    meets the tolerance at every frequency, and the simulated experiment is solved to a tighter
    one (0.3 of it) from its own finer start."""
    import updating.data.measurements

    targets = []
    original = updating.data.measurements.solve_to_tolerance

    def recording(case, frequency, tolerance, **kwargs):
        targets.append((tolerance, kwargs["resolution"]))
        return original(case, frequency, tolerance, **kwargs)

    monkeypatch.setattr(updating.data.measurements, "solve_to_tolerance", recording)
    path = tmp_path / "tolerance.toml"
    path.write_text(TWO_PLATES.read_text()
                    + "\n[discretisation]\ntolerance = 1e-4\n")
    out = tmp_path / "out.json"
    assert main(["localise", str(path), "--json", str(out)]) == 0
    estimate = json.loads(out.read_text())["error_estimate"]
    assert estimate["total"] <= 1e-4 and estimate["frequencies"]["155"]["resolution"] > 1.0
    assert targets and all(t == pytest.approx(3e-5) and r > 1.0 for t, r in targets)


def test_a_description_in_millimetres_gives_the_same_field(tmp_path, capsys):
    """mm / t / s (E in MPa, rho in t/mm^3, lengths in mm): no [measurement] table needed (the
    default grid is a fifth of the largest plate side, as 0.1 m is for the SI description),
    a warning that the labels are SI, and the same deflection. Equal to 1e-6 (measured 4e-8 to
    4e-7): the ray amplitudes are ill-conditioned (condition estimates 1e17), so a change of
    units, like a 1e-13 change of E, moves the solution at the level of the Trefftz floor."""
    from assembly.generate import description_toml

    si = plate_description()
    mm = plate_description()
    mm["materials"]["steel"].update(young_modulus=210e3, density=7.8e-9)
    mm["plates"]["P1"].update(thickness=1.0, size=[500.0, 400.0])
    mm["loads"][0]["at"] = [120.0, 310.0]
    path = tmp_path / "mm.toml"
    path.write_text(description_toml(mm))
    assert main(["check", str(path)]) == 0
    assert "millimetres" in capsys.readouterr().out
    a, b = parse_case(si), parse_case(mm)
    assert b.measurement.spacing == pytest.approx(1e3 * a.measurement.spacing)
    assert b.measurement_points() and len(b.measurement_points()) == len(a.measurement_points())
    points = np.array([[0.1, 0.1], [0.31, 0.22], [0.45, 0.35]])
    w_si = solve_case(a).w("P1", points)
    w_mm = solve_case(b).w("P1", 1e3 * points) * 1e-3
    assert np.max(abs(w_mm - w_si)) / np.max(abs(w_si)) < 1e-6


def test_tolerance_refines_only_the_plates_that_need_it():
    """Two separate plates, the second with too few interior rays (an override): the
    tolerance raises the second plate's resolution only, and its estimate falls below it."""
    data = plate_description()
    data["plates"]["P2"] = dict(data["plates"]["P1"], origin=[0.6, 0.0])
    data["boundaries"] += [{"edge": f"P2.{e}", "condition": "simply_supported"}
                           for e in ("left", "right", "bottom", "top")]
    data["loads"].append({"kind": "point_force", "plate": "P2", "at": [0.12, 0.31],
                          "amplitude": 1.0})
    data["discretisation"]["plates"] = {"P2": {"interior": 16}}
    case = parse_case(data)
    before = estimate_error(case, solve_case(case, 155.0))
    assert before.plates["P2"] > 1e-2 > 1e-4 > before.plates["P1"]
    solution, estimate = solve_to_tolerance(case, 155.0, 1e-4)
    assert estimate.total <= 1e-4 and estimate.resolution == {"P1": 1.0, "P2": 1.5}
    assert solution.plates["P1"].basis.n_dof < solution.plates["P2"].basis.n_dof
    exact = navier_point_force(*SIZE, complex_rigidity(E, PLATE_H, PLATE_NU, 0.01),
                               PLATE_RHO * PLATE_H, 2 * math.pi * 155.0, 0.12, 0.31, 1.0,
                               np.array([0.2, 0.3]), np.array([0.1, 0.3]), n_terms=400)
    w = solution.w("P2", np.array([[0.2, 0.1], [0.3, 0.3]]))
    assert np.max(abs(w - exact)) / np.max(abs(exact)) < 1e-3


@pytest.mark.parametrize("n_plates", [3, 30])
def test_the_plates_a_refinement_refines_do_not_depend_on_the_assemblys_size(n_plates):
    """A chain whose plate P2_1 fails the tolerance (2e-3 of its weak field, 1 % of the energy
    of P1_1), between the driven P1_1 (5e-4 of its own field, an error 25 times what P2_1 may
    have) and P3_1 (9e-4), the other plates exact: the refinement takes the failing plate and
    its two neighbours, in a chain of 3 as of 30. The former rule (a plate's share of the
    squared total above tolerance^2 / P) took P3_1 in the chain of 3, not in the chain of 30,
    and left the polluting P1_1 out of both."""
    from assembly.generate import plate_grid
    from solver.estimate import ErrorEstimate
    from solver.tolerance import _to_refine

    case = parse_case(plate_grid(n_plates, 1))
    norms = {pid: 1.0 for pid in case.plates} | {"P1_1": 1.0, "P2_1": 0.01}
    errors = {pid: 0.0 for pid in case.plates} | {"P1_1": 5e-4, "P2_1": 2e-3, "P3_1": 9e-4}
    total = sum(norms.values())
    estimate = ErrorEstimate(
        1e-3, errors, 1.0, 1.5, 0.0,
        shares={pid: errors[pid] ** 2 * norms[pid] / total for pid in case.plates})
    assert _to_refine(case, estimate, 1e-3) == {"P1_1", "P2_1", "P3_1"}
