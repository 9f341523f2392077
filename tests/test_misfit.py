"""``[updating] misfit``: E_mes^2 normalised by the whole data (the paper's) or per measured
plate (each plate's misfit relative to its own data, averaged over the plates)."""


import numpy as np
import pytest
from support import CASES

from updating.cli import main
from updating.data.measurements import simulate_measurements
from updating.inverse.cost import ModifiedProblem


def _with_misfit(case, misfit):
    return case.model_copy(update={"updating": case.updating.model_copy(
        update={"misfit": misfit})})


@pytest.fixture(scope="module")
def problems(four_plates_case):
    case = four_plates_case
    measurements = simulate_measurements(case)
    return {misfit: ModifiedProblem(_with_misfit(case, misfit), measurements)
            for misfit in ("global", "per_plate")}


def test_per_plate_misfit_is_the_mean_of_the_plates_relative_misfits(problems):
    """At the same interface unknowns, each plate's part of E_mes^2 is its squared misfit over
    P times its own data's squared norm (per plate) or over the whole data's (global): the two
    differ by the factor ``P |d_p|^2 / |d|^2`` exactly (to round-off)."""
    parameters = problems["global"].initial_parameters()
    interfaces = problems["global"].evaluate(parameters).interface
    parts = {m: p.evaluation_at(parameters, interfaces).misfits for m, p in problems.items()}
    total = dict.fromkeys(parts["global"], 0.0)
    for frequency, freq in problems["global"].frequencies.items():
        whole = sum(float(np.vdot(v, v).real) for v in freq.data)
        p = len(freq.data)
        s = interfaces[frequency]
        for pid, op, values in zip(freq.plates, freq.operators, freq.data):
            squared = float(np.vdot(op.residual(s) - values, op.residual(s) - values).real)
            own = float(np.vdot(values, values).real)
            total[pid] += squared / (p * own)
            # the global part of the same plate, from the same squared misfit
            assert squared / whole == pytest.approx(
                problems["global"].frequencies[frequency].misfits(s, freq.data)[pid],
                rel=1e-12)
    for pid, value in total.items():
        assert parts["per_plate"][pid] == pytest.approx(value, rel=1e-12)
    assert parts["per_plate"] != pytest.approx(parts["global"], rel=1e-3)


def test_each_normalisation_is_minimised_by_its_own_solve(problems):
    """The minimiser of each cost gives that cost a lower value than the other's minimiser
    does (the measurement rows are weighted as the cost says), by more than round-off."""
    parameters = problems["global"].initial_parameters()
    minimisers = {m: p.evaluate(parameters).interface for m, p in problems.items()}
    for own, other in (("global", "per_plate"), ("per_plate", "global")):
        problem = problems[own]
        at_own = problem.evaluation_at(parameters, minimisers[own]).e_mod
        at_other = problem.evaluation_at(parameters, minimisers[other]).e_mod
        assert at_own < at_other * (1.0 - 1e-6)


def test_per_plate_misfit_keeps_the_four_plate_decisions(tmp_path):
    """``misfit = "per_plate"`` on the main job: the same steps as the paper's normalisation
    (G2, G1, G4, then G2 re-corrected), every truth in its interval."""
    text = (CASES / "four_plates.toml").read_text()
    assert "[updating]\n" in text
    path = tmp_path / "four.toml"
    path.write_text(text.replace("[updating]\n", '[updating]\nmisfit = "per_plate"\n'))
    out = tmp_path / "run.json"
    assert main(["update", str(path), "--json", str(out), "--quiet"]) == 0
    import json

    result = json.loads(out.read_text())
    assert [s["selected"] for s in result["steps"]] == [None, "G2", "G1", "G4", "G2"]
    truth = {"G1": 0.5, "G2": 4.5, "G4": 1.5}
    for joint, value in truth.items():
        low, high = result["identified"][joint]["interval"]
        assert (low is None or low <= value) and (high is None or value <= high)


def test_an_unknown_misfit_is_one_line_and_exit_2(tmp_path, capsys):
    text = (CASES / "two_plates.toml").read_text()
    path = tmp_path / "bad.toml"
    path.write_text(text.replace("[updating]\n", '[updating]\nmisfit = "plate"\n'))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "updating.misfit" in err[0] and "'per_plate'" in err[0]
