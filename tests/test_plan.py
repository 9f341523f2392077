"""``vtcr plan``: identifiability before the test (``updating.inverse.plan``).

The sensitivities and the damping share go through the joint's condensation of the model
response; they are checked against independent direct solves (``solver.solve_case``) and the
power balance of ``solver.power``.
"""

import json

import numpy as np
import pytest
from support import CASES

from assembly import load_case
from solver import solve_case
from solver.power import power_flow
from updating.cli import main
from updating.data.measurements import measurement_layout, simulate_measurements
from updating.inverse.plan import identifiability_plan


def _stiff_two_plates(tmp_path, log10_k):
    text = (CASES / "two_plates.toml").read_text()
    old = "log10_stiffness = 1.5             # log k"
    assert old in text
    path = tmp_path / "two.toml"
    path.write_text(text.replace(old, f"log10_stiffness = {log10_k}             # log k"))
    return path


def _values(case, layout, frequency):
    solution = solve_case(case, frequency)
    return np.concatenate([solution.w(pid, points) for pid, points in sorted(layout.items())])


def test_sensitivities_and_damping_share_match_direct_solves():
    """The field change per +0.1 decade and per +0.1 of the loss factor at the planned points,
    and the share of the injected power the joint dissipates, against solves of the changed
    descriptions (same discretisation: they agree to the solves' round-off, 1e-6 here)."""
    case = load_case(CASES / "two_plates.toml")
    plans, _, estimates = identifiability_plan(case, simulate_measurements(case))
    assert estimates == {}  # not asked for
    plan = plans["G1"]
    frequency = case.frequencies[0]
    layout = measurement_layout(case)
    base = _values(case, layout, frequency)
    joint = case.joints["G1"]
    for change, expected in ((dict(log10_stiffness=joint.log10_stiffness + 0.1),
                              plan.stiffness_sensitivity[frequency]),
                             (dict(loss_factor=joint.loss_factor + 0.1),
                              plan.damping_sensitivity[frequency])):
        moved = _values(case.with_joint_parameters({"G1": change}), layout, frequency)
        direct = np.linalg.norm(moved - base) / np.linalg.norm(base)
        assert expected == pytest.approx(direct, rel=1e-6), change
    flow = power_flow(case, solve_case(case, frequency))
    share = flow.joint_dissipated["G1"] / flow.total_injected
    assert plan.damping_share[frequency] == pytest.approx(share, rel=1e-6)
    assert 0.0 < share < 1.0


def test_plan_command_on_the_four_plates(tmp_path, capsys):
    """Every joint of the four-plate model is identifiable at its 80 planned values per
    frequency with ±10 % noise; the expected interval holds the model value (the data are its
    prediction), the JSON carries per joint its sensitivities, interval and verdict, and the
    information shares sum to one; beside them, the model's estimated discretisation error at
    each frequency (the sensitivities are read against it)."""
    out = tmp_path / "plan.json"
    assert main(["plan", str(CASES / "four_plates.toml"), "--json", str(out)]) == 0
    result = json.loads(out.read_text())
    assert result["confidence"] == 0.9 and "±10 %" in result["noise"]
    estimate = result["error_estimate"]
    assert set(estimate["frequencies"]) == {"218", "248", "309.4"}
    assert 0.0 < estimate["total"] < 1e-2
    assert set(result["joints"]) == {"G1", "G2", "G3", "G4"}
    for joint in result["joints"].values():
        assert joint["verdict"] == "identifiable"
        low, high = joint["expected"]["interval"]
        assert low < joint["log10_stiffness"] < high and high - low < 0.3
        assert set(joint["sensitivity_percent_per_0.1_decade"]) == {"218", "248", "309.4"}
        assert sum(item["share"] for item in joint["information"]) == pytest.approx(1.0)
    assert "identifiable" in capsys.readouterr().out
    # a plan of some joints only (a large structure planned region by region) gives those
    # joints exactly what the whole plan gives them: each joint's plan is its own
    part = tmp_path / "part.json"
    assert main(["plan", str(CASES / "four_plates.toml"), "--joints", "G4", "G2", "--json",
                 str(part), "--no-estimate"]) == 0
    planned = json.loads(part.read_text())["joints"]
    assert list(planned) == ["G2", "G4"]
    for joint in planned:
        assert planned[joint] == result["joints"][joint]
    assert "planned G4" in capsys.readouterr().err  # progress, one line per joint in a log
    assert main(["plan", str(CASES / "four_plates.toml"), "--joints", "G2", "G9"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--joints G9: not an updatable joint" in err[0]


def test_a_near_rigid_joint_is_only_bounded(tmp_path, capsys):
    """Model log10 k = 4.8 on the two plates (0.66 % field change per 0.1 decade, ±20 % noise):
    only a lower bound, and the suggestion names where the information comes from."""
    out = tmp_path / "plan.json"
    assert main(["plan", str(_stiff_two_plates(tmp_path, 4.8)), "--json", str(out)]) == 0
    joint = json.loads(out.read_text())["joints"]["G1"]
    assert joint["verdict"] == "bounded"
    assert joint["expected"]["only"] == "lower bound"
    assert joint["expected"]["interval"][1] is None
    printed = " ".join(capsys.readouterr().out.split())
    assert "most of what the data say about it comes from plate" in printed


def test_plan_without_stated_noise_assumes_one_percent(tmp_path, capsys):
    path = tmp_path / "quiet.toml"
    text = (CASES / "two_plates.toml").read_text()
    assert "noise = 0.2" in text
    path.write_text(text.replace("noise = 0.2", "noise = 0.0"))
    out = tmp_path / "plan.json"
    assert main(["plan", str(path), "--json", str(out)]) == 0
    assert "assumes ±1 % uniform noise" in " ".join(capsys.readouterr().out.split())
    assert "assumed" in json.loads(out.read_text())["noise"]


def test_plan_bad_level_is_one_line_and_exit_2(capsys):
    assert main(["plan", str(CASES / "two_plates.toml"), "--confidence", "1.5"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--confidence 1.5" in err[0]


def test_plan_on_the_points_of_a_measurement_file(tmp_path):
    """``--measurements`` gives the planned points (here every other one of the simulated
    grid): their values are not used, and fewer points give a wider expected interval."""
    meas, half = tmp_path / "m.csv", tmp_path / "half.csv"
    case = str(CASES / "two_plates.toml")
    assert main(["simulate", case, "--out", str(meas), "--quiet"]) == 0
    lines = meas.read_text().splitlines()
    half.write_text("\n".join([lines[0]] + lines[1::2]) + "\n")
    widths = []
    for path in (meas, half):
        out = tmp_path / f"{path.stem}.json"
        assert main(["plan", case, "--measurements", str(path), "--json", str(out),
                     "--quiet"]) == 0
        low, high = json.loads(out.read_text())["joints"]["G1"]["expected"]["interval"]
        widths.append(high - low)
    assert widths[1] > widths[0] > 0.0


def test_expected_interval_is_that_of_typical_noisy_data(tmp_path):
    """The plan's expected interval is that of the model's prediction plus typical noise: on
    the two plates at ±50 % noise its ends lie within the interquartile ranges of the ends of
    the intervals that 20 noisy data sets give (each joint corrected first, as ``update`` does;
    measured: low 1.21 in [1.17, 1.31], high 1.64 in [1.61, 1.67]). Noise-free data compared
    with noisy redraws would give [1.05, 1.56], outside both ranges: the statistic is quadratic
    in the data, and noise moves it on average."""
    from updating.data.measurements import Measurements
    from updating.inverse.confidence import confidence_interval, noise_model
    from updating.inverse.cost import ModifiedProblem
    from updating.inverse.strategy import correct_joint

    path = tmp_path / "noisy.toml"
    text = (CASES / "two_plates.toml").read_text()
    path.write_text(text.replace("noise = 0.2", "noise = 0.5"))
    case = load_case(path)
    layout = measurement_layout(case)
    points = Measurements({f: {pid: (p, np.ones(len(p), dtype=complex))
                               for pid, p in layout.items()} for f in case.frequencies})
    plans, noise, _ = identifiability_plan(case, points)
    expected = plans["G1"].interval
    problem = ModifiedProblem(case, points)
    model = problem.initial_parameters()
    prediction = problem.synthetic_data(model, 0.0, realisations=1)[0]
    assert noise == noise_model(0.5, 0.0)
    rng = np.random.default_rng(5)
    ends = []
    for _ in range(20):
        data = {f: [w * (1 + rng.uniform(-0.5, 0.5, w.shape)) for w in values]
                for f, values in prediction.items()}
        noisy = problem.with_data(data)
        identified, _, _ = correct_joint(noisy, model, "G1", case.updating.bounds)
        interval = confidence_interval(noisy, identified, ("G1", "log10_stiffness"),
                                       [("G1", "log10_stiffness")], noise, 0.9,
                                       case.updating.bounds)
        ends.append((interval.low, interval.high))
    lows, highs = np.percentile(np.array(ends, dtype=float), [25, 75], axis=0).T
    assert expected.kind == "two-sided"
    assert lows[0] <= expected.low <= lows[1]
    assert highs[0] <= expected.high <= highs[1]


def test_a_long_plan_says_so_before_it_starts(monkeypatch, capsys):
    """Above ``LONG_PLAN_SECONDS`` of estimated work the plan warns first, with the estimate
    and the way to plan fewer joints (here the threshold is lowered to the four plates')."""
    monkeypatch.setattr("updating.cli.identification.LONG_PLAN_SECONDS", 0.0)
    assert main(["plan", str(CASES / "four_plates.toml"), "--joints", "G1", "--no-estimate"]) == 0
    printed = " ".join(capsys.readouterr().out.split())
    assert "planning 1 joint takes about" in printed and "--joints J1 J2" in printed
