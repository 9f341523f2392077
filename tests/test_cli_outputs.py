"""What the commands print and write, beyond the numbers (issue 13)."""

import json
import os
import subprocess
import sys

from support import CASES

from updating.cli import main


def test_solve_follows_the_measurement_layout(tmp_path):
    """Without probes, solve reports w where [measurement] measures: the folded plate's
    vertical face only (plates = ["P2"]), on its 18 x 18 grid."""
    out = tmp_path / "out.json"
    assert main(["solve", str(CASES / "folded_plate.toml"), "--json", str(out),
                 "--no-estimate", "--max-rows", "0"]) == 0
    rows = json.loads(out.read_text())["probes"]
    assert {row["plate"] for row in rows} == {"P2"} and len(rows) == 18 * 18


def test_simulating_without_truth_warns(tmp_path, capsys):
    text = (CASES / "two_plates.toml").read_text()
    start = text.index("[truth.joints.G1]")
    end = text.index("\n\n", start) if "\n\n" in text[start:] else len(text)
    path = tmp_path / "model.toml"
    path.write_text(text[:start] + text[end:])
    assert main(["simulate", str(path), "--out", str(tmp_path / "m.csv")]) == 0
    assert "has no [truth.joints] table" in capsys.readouterr().out
    assert main(["simulate", str(CASES / "two_plates.toml"), "--out",
                 str(tmp_path / "m2.csv")]) == 0
    assert "no [truth.joints]" not in capsys.readouterr().out


def test_corrected_joints_are_marked_without_styles(tmp_path, capsys):
    """Off a terminal (no bold), the Table-4 table still shows which joint each step
    corrected: a '>' before its log10 k."""
    text = (CASES / "two_plates.toml").read_text()
    start = text.index("[truth.joints.G1]")
    path = tmp_path / "wrong.toml"
    path.write_text(text[:start] + "[truth.joints.G1]\nlog10_stiffness = 3.0\n"
                    "loss_factor = 0.1\n")
    assert main(["update", str(path), "--no-estimate", "--run", str(tmp_path / "r.json")]) \
        in (0, 3)
    out = capsys.readouterr().out
    assert ">" in out.split("E_mod² %")[0] and ">, bold: corrected joint(s)" in out


def test_curve_prints_percent_and_writes_fractions(tmp_path, capsys):
    import csv

    path = tmp_path / "curve.csv"
    assert main(["curve", str(CASES / "two_plates.toml"), "--joint", "G1", "--samples", "3",
                 "--csv", str(path)]) == 0
    out = capsys.readouterr().out
    rows = list(csv.DictReader(path.read_text().splitlines()))
    assert "E_mod² %" in out and "<" in out
    for row in rows:
        assert f"{100 * float(row['e_mod']):.4g}" in out


def test_json_has_one_shape_with_tool_units_and_inputs(tmp_path):
    """solve's JSON has the same keys for one frequency and several (the contract's
    frequency/probes of the first, then every frequency), and every JSON names the tool
    version, the units and fingerprints of its inputs."""
    case = str(CASES / "two_plates.toml")
    one, two, loc = (tmp_path / f"{n}.json" for n in ("one", "two", "loc"))
    assert main(["solve", case, "--json", str(one), "--no-estimate", "--max-rows", "0"]) == 0
    assert main(["solve", case, "--json", str(two), "--no-estimate", "--max-rows", "0",
                 "--frequency", "150", "--frequency", "160"]) == 0
    single, double = json.loads(one.read_text()), json.loads(two.read_text())
    assert set(single) == set(double)
    assert len(single["frequencies"]) == 1 and len(double["frequencies"]) == 2
    assert double["frequency"] == 150 and double["probes"] == double["frequencies"][0]["probes"]
    assert main(["localise", case, "--json", str(loc), "--no-estimate"]) == 0
    for result in (single, json.loads(loc.read_text())):
        assert result["vtcr"]["version"] and result["units"]["w"] == "m"
        assert len(result["inputs"]["description"]["sha256"]) == 64
    assert json.loads(loc.read_text())["inputs"]["measurements"]["path"] == "simulated"


def test_json_keeps_the_description_warnings(tmp_path, capsys):
    """A warning of the description's checks (here a resolution below the rule, which
    qualifies the field and its error estimate) is in every JSON output, under
    inputs.description.warnings, and in update's report, as the command printed it; a
    description without one writes []."""
    text = (CASES / "two_plates.toml").read_text() + "\n[discretisation]\nresolution = 0.8\n"
    warned, quiet = tmp_path / "warned.toml", tmp_path / "quiet.json"
    warned.write_text(text)
    report = tmp_path / "run.md"
    extra = {"solve": ["--max-rows", "0"], "localise": [], "plan": [],
             "frf": ["--band", "150", "160", "--start-frequencies", "3", "--max-points", "3"],
             "update": ["--report", str(report), "--run", str(tmp_path / "r.json")]}
    for command, options in extra.items():
        out = tmp_path / f"{command}.json"
        assert main([command, str(warned), "--json", str(out), "--no-estimate", *options]) \
            in ((0, 3) if command == "update" else (0,)), command
        printed = [line.removeprefix("warning: ")
                   for line in capsys.readouterr().out.splitlines()
                   if line.startswith("warning: ") and "resolution 0.8" in line]
        kept = json.loads(out.read_text())["inputs"]["description"]["warnings"]
        assert printed and set(printed) <= set(kept), (command, printed, kept)
    assert all(f"- {line}" in report.read_text() for line in printed)
    assert main(["solve", str(CASES / "two_plates.toml"), "--json", str(quiet),
                 "--no-estimate", "--max-rows", "0"]) == 0
    assert json.loads(quiet.read_text())["inputs"]["description"]["warnings"] == []


def _without_timings(value):
    if isinstance(value, dict):
        return {k: _without_timings(v) for k, v in value.items() if k != "timings"}
    if isinstance(value, list):
        return [_without_timings(v) for v in value]
    return value


def test_a_solve_is_the_same_to_the_bit_whatever_the_string_hashing(tmp_path):
    """The same description gives the same numbers in every run: Python's string hashing,
    which orders a set of names differently from one process to the next, orders nothing the
    solver builds. The stiffened panel at resolution 1.5 (its welds' held ends add their
    loaded corners) solved under two seeds: every number of the JSON but the timings equal
    (0.3.8 ordered its plates' loaded corners by the welds' set: 966 of them differed)."""
    text = (CASES / "stiffened_panel.toml").read_text()
    assert text.count("\nresolution = 1.25\n") == 1
    case = tmp_path / "panel.toml"
    case.write_text(text.replace("\nresolution = 1.25\n", "\nresolution = 1.5\n"))
    outputs = []
    for seed in ("1", "2"):
        out = tmp_path / f"seed{seed}.json"
        subprocess.run([sys.executable, "-m", "updating", "solve", str(case), "--frequency",
                        "257", "--no-estimate", "--json", str(out), "--quiet"], check=True,
                       timeout=300, env=dict(os.environ, PYTHONHASHSEED=seed,
                                             OPENBLAS_NUM_THREADS="1"))
        outputs.append(_without_timings(json.loads(out.read_text())))
    assert outputs[0] == outputs[1]
