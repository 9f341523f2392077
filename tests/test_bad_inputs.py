"""A catalogue of bad inputs outside the description's schema, and the messages they must give.

Where input enters besides the TOML schema (``test_bad_descriptions.py``): probe and
measurement CSV files, command-line options, output paths, and the physical and numerical
sanity of a description (ray resolution, size of the problem, loads, measurement layout).
Every entry runs ``vtcr`` in-process and checks the contract: exit status 2, one line per
problem on stderr, each starting with ``vtcr: `` and naming the file or option and the field,
no traceback, and no output file created. Every entry fails before any solve, so the whole
file runs in a few seconds.
"""

from __future__ import annotations

import json
import math
import os
import stat
import threading
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from support import CASES
from support import TWO_PLATES as TWO

from assembly import load_case, load_case_text
from updating.cli import main

# Two 0.5 x 0.4 m plates joined by G1, a point force on P1; 5 x 4 measurement grid per plate.

# Two separate pairs: P1 | P2 (joint G1) and P3 | P4 (joint G2), each loaded.
PAIRS = TWO.replace("[joints.G1]", """\
[plates.P3]
material = "steel"
thickness = 0.001
size = [0.5, 0.4]

[plates.P4]
material = "steel"
thickness = 0.001
size = [0.5, 0.4]

[joints.G2]
kind = "coplanar"
between = ["P3.right", "P4.left"]
log10_stiffness = 2.0

[joints.G1]""") + """
[[loads]]
kind = "point_force"
plate = "P3"
at = [0.17, 0.13]
amplitude = 1.0
"""

# A chain P1 | P2 | P3 (joints G1, G2).
CHAIN = TWO.replace("[joints.G1]", """\
[plates.P3]
material = "steel"
thickness = 0.001
size = [0.5, 0.4]

[joints.G2]
kind = "coplanar"
between = ["P2.right", "P3.left"]
log10_stiffness = 2.0

[joints.G1]""").replace('edge = "P2.right"', 'edge = "P3.right"')

MULTI = TWO.replace("frequency = 155.0", "frequencies = [150.0, 155.0]")

PROBES = "plate,x,y\nP1,0.1,0.1\nP2,0.2,0.3\n"
MEASUREMENTS = "plate,x,y,re,im\n" + "".join(
    f"P1,{x},{y},1e-6,2e-7\n" for x in (0.05, 0.15, 0.25) for y in (0.05, 0.15))


def _replace(old: str, new: str, text: str = TWO) -> str:
    assert old in text, f"{old!r} not in the description"
    return text.replace(old, new)


@dataclass
class Bad:
    """One bad input: files to write, the command, and what stderr must say."""

    id: str
    args: list[str]  # "{dir}" is replaced by the working directory
    fragments: tuple[str, ...]  # each must appear in the output (file/option, field, fix)
    lines: int = 1  # problems reported, one line each
    files: dict[str, str | bytes] = field(default_factory=dict)
    output: str = "out.json"  # must not be created


def solve_probes(probes: str | bytes, *fragments: str, lines: int = 1, id: str) -> Bad:
    return Bad(id, ["solve", "{dir}/case.toml", "--probes", "{dir}/p.csv", "--json",
                    "{dir}/out.json"], ("p.csv", *fragments), lines, {"p.csv": probes})


def localise_measurements(text: str, *fragments: str, lines: int = 1, id: str,
                          case: str = TWO) -> Bad:
    return Bad(id, ["localise", "{dir}/case.toml", "--measurements", "{dir}/m.csv", "--json",
                    "{dir}/out.json"], ("m.csv", *fragments), lines,
               {"m.csv": text, "case.toml": case})


def described(case: str, *fragments: str, lines: int = 1, id: str,
              command: str = "solve") -> Bad:
    output = [] if command == "check" else ["--json", "{dir}/out.json"]
    return Bad(id, [command, "{dir}/case.toml", *output], ("case.toml", *fragments), lines,
               {"case.toml": case})


def option(args: list[str], *fragments: str, lines: int = 1, id: str,
           output: str = "out.json") -> Bad:
    return Bad(id, args, fragments, lines, output=output)


CATALOGUE: list[Bad] = [
    # ---------------------------------------------------------------- probe CSV
    Bad("probe-missing-file", ["solve", "{dir}/case.toml", "--probes", "{dir}/none.csv",
                               "--json", "{dir}/out.json"], ("none.csv", "not found", "plate,x,y")),
    Bad("probe-is-directory", ["solve", "{dir}/case.toml", "--probes", "{dir}",
                               "--json", "{dir}/out.json"], ("is a directory", "plate,x,y")),
    solve_probes("", "empty", "plate,x,y", id="probe-empty-file"),
    solve_probes("\n\n", "empty", id="probe-blank-file"),
    solve_probes("plate,x,z\nP1,0.1,0.1\n", "row 1", "lacks y", "plate,x,y", id="probe-header"),
    solve_probes("plat,x,y\nP1,0.1,0.1\n", "'plat'", "did you mean 'plate'", "lacks plate",
                 lines=2, id="probe-misspelt-column"),
    solve_probes("plate;x;y\nP1;0,1;0,1\n", "semicolons", "use commas", id="probe-semicolons"),
    solve_probes("plate\tx\ty\nP1\t0.1\t0.1\n", "tabs", "use commas", id="probe-tabs"),
    solve_probes("plate,x,y\nP1,nan,0.1\n", "row 2, column 'x'", "not finite", id="probe-nan"),
    solve_probes("plate,x,y\nP1,0.1,-inf\n", "row 2, column 'y'", "not finite", id="probe-inf"),
    solve_probes("plate,x,y\nP1,abc,0.1\n", "row 2, column 'x'", "'abc' is not a number",
                 id="probe-non-numeric"),
    solve_probes("plate,x,y\nP1,,0.1\n", "row 2, column 'x'", "empty", id="probe-empty-cell"),
    solve_probes("plate,x,y\nP1,0.1,0.1,7\n", "row 2", "more cells", id="probe-extra-cells"),
    solve_probes("plate,x,y\nP9,0.1,0.1\n", "row 2, column 'plate'", "'P9'", "plates: P1, P2",
                 id="probe-unknown-plate"),
    solve_probes("plate,x,y\nP1,0.6,0.1\n", "row 2", "outside plate P1", "plate-local metres",
                 id="probe-outside-plate"),
    solve_probes("plate,x,y\n", "no probe rows", id="probe-no-rows"),
    solve_probes("plate,x,y\nP1,nan,0.1\nP9,0.1,0.1\nP1,0.1,9\n", "row 2", "row 3", "row 4",
                 lines=3, id="probe-all-rows-reported"),
    solve_probes(b"plate,x,y\nP\xe9,0.1,0.1\n", "row 2", "UTF-8", id="probe-not-utf8"),
    # ---------------------------------------------------------------- measurement CSV
    localise_measurements("plate,x,y,re,im\n", "no measurement rows", id="meas-no-rows"),
    localise_measurements("plate,x,y,re,im\nP1,0.1,0.1," + "1" * 200_000 + ",0\n", "row 2",
                          "not readable as CSV", id="meas-200-kB-cell"),
    localise_measurements("plate,x,y,re\nP1,0.1,0.1,1e-6\n", "lacks im", "plate,x,y,re,im",
                          id="meas-header"),
    localise_measurements("plate,x,y,re,im\nP1,0.1,0.1,0,0\nP1,0.2,0.1,0,0\nP2,0.1,0.1,0,0\n",
                          "every displacement at 155 Hz is zero", id="meas-all-zero"),
    localise_measurements(MEASUREMENTS + "P1,0.05,0.05,1e-6,0\n", "row 8",
                          "repeats the point of row 2", "155 Hz", id="meas-duplicate"),
    localise_measurements("plate,x,y,re,im,frequency\nP1,0.1,0.1,1e-6,0,160\n",
                          "row 2, column 'frequency'", "160 Hz", "add it there",
                          id="meas-frequency-not-described"),
    localise_measurements(MEASUREMENTS, "no frequency column", "150.0, 155.0",
                          id="meas-no-frequency-column", case=MULTI),
    localise_measurements("plate,x,y,re,im\nP1,0.1,0.1,nan,0\nP1,0.2,0.1,1e-6,inf\n",
                          "row 2, column 're'", "row 3, column 'im'", lines=2,
                          id="meas-not-finite"),
    localise_measurements(MEASUREMENTS, "joint G2 (P3.right | P4.left)", "measure on P3 or P4",
                          id="meas-joint-unseen", case=PAIRS),
    localise_measurements("plate,x,y,re,im\nP1,0.1,0.1,1e-6,0\nP1,0.2,0.1,1e-6,0\n",
                          "only 2 measurement point(s)", "G1", "at least 3",
                          id="meas-too-few-points"),
    # ---------------------------------------------------------------- command-line options
    option(["simulate", "{dir}/case.toml", "--out", "{dir}/m.csv", "--noise", "1.5"],
           "--noise 1.5", "[0, 1)", id="opt-noise-above-one", output="m.csv"),
    option(["simulate", "{dir}/case.toml", "--out", "{dir}/m.csv", "--noise", "nan"],
           "--noise nan", id="opt-noise-nan", output="m.csv"),
    option(["simulate", "{dir}/case.toml", "--out", "{dir}/m.csv", "--seed", "-1"],
           "--seed -1", ">= 0", id="opt-seed-negative", output="m.csv"),
    option(["simulate", "{dir}/case.toml", "--out", "{dir}/m.csv", "--noise", "abc"],
           "--noise", "invalid float value", "vtcr simulate --help", id="opt-noise-not-a-number",
           output="m.csv"),
    option(["simulate", "{dir}/case.toml", "--out", "{dir}/m.csv", "--noise", "-0.1",
            "--seed", "-2"], "--noise -0.1", "--seed -2", lines=2, id="opt-all-reported",
           output="m.csv"),
    option(["curve", "{dir}/case.toml", "--joint", "G1", "--samples", "1", "--csv",
            "{dir}/c.csv"], "--samples 1", "at least 2", id="opt-samples", output="c.csv"),
    option(["curve", "{dir}/case.toml", "--joint", "G9", "--csv", "{dir}/c.csv"],
           "--joint G9", "joints: G1", id="opt-joint-unknown", output="c.csv"),
    option(["solve", "{dir}/case.toml", "--frequency", "0", "--json", "{dir}/out.json"],
           "--frequency 0", "> 0", id="opt-frequency-zero"),
    option(["solve", "{dir}/case.toml", "--frequency", "nan", "--json", "{dir}/out.json"],
           "--frequency nan", "finite", id="opt-frequency-nan"),
    option(["solve", "{dir}/case.toml", "--max-rows", "-1", "--json", "{dir}/out.json"],
           "--max-rows -1", id="opt-max-rows"),
    option(["solve", "{dir}/case.toml", "--json", "{dir}/no/such/dir/out.json"],
           "--json", "does not exist", "mkdir", id="opt-output-directory-missing",
           output="no"),
    option(["solve", "{dir}/case.toml", "--json", "{dir}"], "--json", "is a directory",
           id="opt-json-is-directory"),
    option(["simulate", "{dir}/case.toml", "--out", "{dir}/case.toml"], "--out",
           "also an input", id="opt-output-overwrites-input", output="none"),
    option(["update", "{dir}/case.toml", "--report", "{dir}/case.toml/r.md"], "--report",
           "not a directory", id="opt-report-under-a-file", output="none"),
    option(["update", "{dir}/case.toml", "--run", "{dir}/x.json", "--json", "{dir}/x.json"],
           "--json and --run name the same file", id="opt-run-is-json", output="x.json"),
    option(["update", "{dir}/case.toml", "--report", "{dir}/x.md", "--json", "{dir}/x.md"],
           "--json and --report name the same file", id="opt-report-is-json", output="x.md"),
    option(["update", "{dir}/case.toml", "--resume", "{dir}/r.json", "--json", "{dir}/r.json"],
           "--json and --resume name the same file", id="opt-resume-is-json", output="r.json"),
    option(["update", "{dir}/case.toml", "--report", "{dir}/r.md", "--json",
            "{dir}/r.run.json"], "--json and the run file name the same file", "r.run.json",
           id="opt-default-run-file-is-json", output="r.run.json"),
    option(["update", "{dir}/case.toml", "--json", "{dir}/../{base}/p.json", "--report",
            "{dir}/p.json"], "--json and --report name the same file",
           id="opt-same-file-two-ways", output="p.json"),
    option(["update", "{dir}/case.toml", "--plot", "{dir}/case.toml/figures"], "--plot",
           "case.toml is a file", id="opt-plot-under-a-file", output="none"),
    option(["update", "{dir}/case.toml", "--plot", "{dir}/case.toml"], "--plot", "is a file",
           id="opt-plot-is-a-file", output="none"),
    # ---------------------------------------------------------------- physical sanity
    described(TWO + "\n[discretisation.plates.P1]\ninterior = 4\n",
              "discretisation.plates.P1.interior", "155 Hz", "asks 24", "interior = 24",
              id="phys-interior-override-coarse", command="check"),
    described(TWO + "\n[discretisation.plates.P2]\nedge_evanescent = 2\n",
              "discretisation.plates.P2.edge_evanescent", "rule asks", id="phys-edge-override"),
    described(TWO + "\n[discretisation]\nresolution = 0.2\n", "discretisation.resolution",
              "at least 0.6", id="phys-resolution-coarse"),
    described(_replace("spacing = 0.1", "spacing = 0.1\nresolution = 0.2"),
              "measurement.resolution", "simulated experiment", id="phys-simulation-coarse",
              command="localise"),
    described(_replace("frequency = 155.0", "frequency = 3e5"), "case.toml: frequency",
              "ray unknowns", "lower the frequency", id="phys-frequency-huge"),
    described(_replace("thickness = 0.001\nsize = [0.5, 0.4]\n\n[plates.P2]",
                       "thickness = nan\nsize = [0.5, 0.4]\n\n[plates.P2]"),
              "plates.P1.thickness", "finite", id="phys-toml-nan"),
    described(_replace("amplitude = 1.0", "amplitude = [1.0, inf]"), "loads[0].amplitude",
              "finite", id="phys-toml-inf"),
    described(TWO + 'points = [{plate = "P2", at = [0.6, 0.1]}]\n',
              "measurement.points[0].at", "outside plate", id="phys-measurement-outside"),
    described(TWO + "plates = []\n", "measurement.plates", "nothing is measured",
              id="phys-measurement-empty", command="localise"),
    described(TWO + 'points = [{plate = "P1", at = [0.05, 0.05]}]\n',
              "measurement.points[0].at", "measurement grid", id="phys-measurement-twice"),
    described(_replace("spacing = 0.1", "spacing = 1e-4"), "measurement.spacing",
              "metres", id="phys-spacing-unit"),
    described(_replace('[[loads]]\nkind = "point_force"\nplate = "P1"\nat = [0.17, 0.13]\n'
                       "amplitude = 1.0\n", ""), "case.toml: loads", "add a load",
              id="phys-no-loads"),
    described(TWO.replace("spacing = 0.1", "plates = []\nspacing = 0.1").replace(
        "[joints.G1]", "[discretisation.plates.P1]\ninterior = 4\n\n[joints.G1]"),
        "measurement.plates", lines=1, id="phys-description-errors-first"),
    described((CASES / "folded_plate.toml").read_text().replace(
        'kind = "hinge"', 'kind = "hinge"\nheld = false'), "joints.G1.held",
        "a moving line needs a frame on every member plate", id="hinge-moving-unframed"),
    # ---------------------------------------------------------------- updating runs
    described((CASES / "single_plate.toml").read_text(), "joints", "no joint",
              id="update-without-joints", command="update"),
    described("a = " + "[" * 5000 + "]" * 5000 + "\n" + TWO, "nests arrays or tables too deeply",
              id="toml-nested-arrays"),
    described("a = " + "{b = " * 3000 + "1" + "}" * 3000 + "\n" + TWO,
              "nests arrays or tables too deeply", id="toml-nested-tables"),
    Bad("update-over-an-unfinished-run", ["update", "{dir}/case.toml", "--run", "{dir}/r.json",
                                          "--json", "{dir}/out.json"],
        ("run file", "r.json", "holds an unfinished run", "--resume", "--force"),
        files={"case.toml": TWO, "r.json": '{"format": "vtcr-run/2", "finished": false}'}),
    Bad("update-over-another-file", ["update", "{dir}/case.toml", "--run", "{dir}/notes.txt",
                                     "--json", "{dir}/out.json"],
        ("notes.txt", "holds a file that is not a vtcr run", "--force"),
        files={"case.toml": TWO, "notes.txt": "my notes"}),
    described(TWO + "".join(f"unknown_key_{i} = 1\n" for i in range(200)),
              "unknown_key_0", "and 150 more problems not shown", lines=51,
              id="toml-200-unknown-keys", command="check"),
    Bad("resume-missing-run", ["update", "{dir}/case.toml", "--resume", "{dir}/none.json",
                               "--json", "{dir}/out.json"],
        ("--resume", "none.json", "cannot read the run file"), files={"case.toml": TWO}),
]


def test_catalogue_is_large_and_unique() -> None:
    ids = [bad.id for bad in CATALOGUE]
    assert len(ids) >= 60
    assert len(set(ids)) == len(ids)


def _run(args: list[str], capsys) -> tuple[int, list[str], str]:
    try:
        status = main(args)
    except SystemExit as exc:  # argparse usage errors
        status = exc.code
    captured = capsys.readouterr()
    return status, captured.err.splitlines(), captured.out


@pytest.mark.parametrize("bad", CATALOGUE, ids=[bad.id for bad in CATALOGUE])
def test_bad_input(bad: Bad, tmp_path: Path, capsys) -> None:
    files = {"case.toml": TWO, **bad.files}
    for name, content in files.items():
        target = tmp_path / name
        if isinstance(content, bytes):
            target.write_bytes(content)
        else:
            target.write_text(content)
    before = set(tmp_path.iterdir())
    args = [a.replace("{dir}", str(tmp_path)).replace("{base}", tmp_path.name)
            for a in bad.args]
    status, lines, out = _run(args, capsys)
    text = "\n".join(lines)
    assert status == 2, (status, text, out)
    assert "Traceback" not in text + out
    assert len(lines) == bad.lines, text
    assert all(line.startswith("vtcr: ") for line in lines), text
    for fragment in bad.fragments:
        assert fragment in text, f"{fragment!r} not in {text!r}"
    assert not (tmp_path / bad.output).exists()
    assert set(tmp_path.iterdir()) == before, "a file was created"


def test_documented_example_is_the_real_message(tmp_path: Path, capsys, monkeypatch) -> None:
    """The bad-input example of ``docs/cli.md`` is what vtcr prints."""
    documented = (CASES.parent / "docs" / "cli.md").read_text()
    command = "$ vtcr update cases/two_plates.toml --measurements meas.csv\n"
    assert command in documented
    shown = documented.split(command, 1)[1].split("```", 1)[0].strip().splitlines()
    (tmp_path / "cases").mkdir()
    (tmp_path / "cases" / "two_plates.toml").write_text((CASES / "two_plates.toml").read_text())
    (tmp_path / "meas.csv").write_text("plate,x,y,re,im\nP1,0.05,0.05,1.2e-6,-3.1e-7\n"
                                       "P1,0.05,0.05,1.1e-6,-3.0e-7\nP3,0.15,0.05,9.8e-7,2.2e-7\n")
    monkeypatch.chdir(tmp_path)
    status, lines, _ = _run(command[2:].split()[1:], capsys)
    assert status == 2
    assert lines == shown
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cases", "meas.csv"]


# ------------------------------------------------------------------------ tolerated input
def test_csv_with_bom_spaces_and_blank_lines_is_read(tmp_path: Path) -> None:
    """Excel writes a UTF-8 byte-order mark; spaces, header case and blank lines are harmless."""
    from updating.data.files import read_probes
    from updating.data.measurements import read_measurements

    case = load_case_text(TWO)
    probes = tmp_path / "p.csv"
    probes.write_bytes("\ufeff Plate , X , y \r\n\r\nP1 , 0.1 , 0.2\r\nP2,0.3,0.1\r\n".encode())
    read = read_probes(probes, case)
    assert read.order == (("P1", 0), ("P2", 0))
    np.testing.assert_allclose(read.by_plate["P1"], [[0.1, 0.2]])
    meas = tmp_path / "m.csv"
    meas.write_bytes(("\ufeffplate, x, y, re, im, comment\n" + "".join(
        line + ",ok\n" for line in MEASUREMENTS.splitlines()[1:])).encode())
    data = read_measurements(meas, case)
    assert data.count() == 6 and data.frequencies == (155.0,)


def test_toml_with_a_byte_order_mark_is_read(tmp_path: Path) -> None:
    """Some Windows editors start UTF-8 files with a BOM; the CSV readers accept one too."""
    path = tmp_path / "case.toml"
    path.write_bytes("\ufeff".encode() + TWO.encode())
    assert load_case(path) == load_case_text(TWO)


def test_row_numbers_are_line_numbers(tmp_path: Path) -> None:
    """Blank lines are skipped but counted, so 'row N' is the line a spreadsheet shows."""
    from updating.data.files import read_probes
    from updating.errors import InputError

    path = tmp_path / "p.csv"
    path.write_text("plate,x,y\n\n\nP1,x,0.1\n")
    with pytest.raises(InputError, match="row 4, column 'x'"):
        read_probes(path, load_case_text(TWO))


# ------------------------------------------------------------------------ joints the data see
def _counts(**plates: int):
    return plates


def test_joint_seen_only_through_other_plates_warns() -> None:
    """Chain P1 | P2 | P3 measured on P1 only: G2 (P2 | P3) is seen indirectly -> warning."""
    from updating.data.measurements import joint_visibility

    errors, warnings = joint_visibility(load_case_text(CHAIN), _counts(P1=20))
    assert errors == []
    assert len(warnings) == 1
    assert "joint G2 (P2.right | P3.left)" in warnings[0]
    assert "measure on P2 or P3" in warnings[0]


def test_joint_visibility_rule() -> None:
    from updating.data.measurements import MIN_POINTS, joint_visibility

    pairs = load_case_text(PAIRS)
    assert joint_visibility(pairs, _counts(P1=5, P4=3)) == ([], [])
    errors, _ = joint_visibility(pairs, _counts(P1=5))
    assert len(errors) == 1 and "joint G2" in errors[0] and "measure on P3 or P4" in errors[0]
    assert joint_visibility(pairs, _counts(P1=5), joints=["G1"]) == ([], [])
    errors, _ = joint_visibility(pairs, _counts(P1=5, P3=MIN_POINTS - 1))
    assert len(errors) == 1 and "too few to see joint(s) G2" in errors[0]


def test_description_layout_is_checked(tmp_path: Path) -> None:
    """Without a measurement file the description's own grid is checked (before simulating)."""
    from updating.data.measurements import check_joints_seen
    from updating.errors import InputError

    case = load_case_text(PAIRS.replace("spacing = 0.1", 'spacing = 0.1\nplates = ["P1"]'))
    with pytest.raises(InputError) as err:
        check_joints_seen(case, None, source="pairs.toml: measurement")
    assert err.value.lines == [line for line in err.value.lines
                               if line.startswith("pairs.toml: measurement: joint G2")]
    assert check_joints_seen(load_case_text(PAIRS), None) == []


# ------------------------------------------------------------------------ resolution rule
@pytest.mark.parametrize("resolution, errors, warnings", [
    (1.0, 0, 0), (0.9, 0, 0), (0.8, 0, 1), (0.6, 0, 1), (0.55, 1, 0), (0.3, 1, 0)])
def test_resolution_thresholds(resolution: float, errors: int, warnings: int) -> None:
    """Error below 0.6 of the rule (wrong field), warning below 0.85 (per-cent errors)."""
    from solver.guards import description_issues

    case = load_case_text(TWO + f"\n[discretisation]\nresolution = {resolution}\n")
    found = description_issues(case)
    assert (len(found[0]), len(found[1])) == (errors, warnings), found


def test_paper_cases_are_sane() -> None:
    from solver.guards import description_issues

    for path in sorted(CASES.glob("*.toml")):
        assert description_issues(load_case(path), need_loads=True) == ([], []), path.name


def test_an_in_plane_condition_that_does_nothing_warns() -> None:
    """Two coplanar plates carry no in-plane waves whatever their joints say: an ``in_plane``
    condition on their edges is named as doing nothing (a member of a held line between
    non-coplanar plates keeps its condition silently: ``tests/test_moving_lines.py``)."""
    from solver.guards import description_issues

    edge = 'edge = "P2.right"\ncondition = "simply_supported"\n'
    case = load_case_text(TWO.replace(edge, edge + 'in_plane = "roller"\n'))
    errors, warnings = description_issues(case)
    assert errors == []
    ((loc, message),) = warnings
    assert loc == ("boundaries", 0, "in_plane") and "P2.right" in message, warnings
    assert description_issues(load_case_text(TWO)) == ([], [])


def test_thin_plate_limit_warns() -> None:
    from solver.guards import description_issues

    case = load_case_text(_replace("thickness = 0.001\nsize = [0.5, 0.4]\n\n[plates.P2]",
                                   "thickness = 0.02\nsize = [0.5, 0.4]\n\n[plates.P2]")
                          .replace("frequency = 155.0", "frequency = 20000.0"))
    errors, warnings = description_issues(case)
    assert errors == []
    assert any(loc == ("frequency",) and "plate P1" in msg and "Kirchhoff" in msg
               for loc, msg in warnings), warnings


@pytest.mark.parametrize("updating, warned", [
    ('misfit = "global"\n', True),  # r = "auto" by default
    ('r = "auto"\nmisfit = "global"\n', True),
    ('misfit = "per_plate"\n', False),
    ('r = 0.8\nmisfit = "global"\n', False),
    ("", False),
])
def test_the_scale_free_weights_with_the_global_misfit_warn(updating: str, warned: bool) -> None:
    """The scale-free weights weigh each plate's data by its own noise; the global misfit does
    not: vtcr check says so, at [updating] misfit, and is silent on every other combination."""
    from solver.guards import description_issues

    errors, warnings = description_issues(load_case_text(TWO + "\n[updating]\n" + updating))
    assert errors == []
    found = [msg for loc, msg in warnings if loc == ("updating", "misfit")]
    assert bool(found) == warned, warnings
    if warned:
        assert "per_plate" in found[0] and "r = \"auto\"" in found[0]


# ------------------------------------------------------------------------ numerical guard rails
def test_condition_warnings_name_plate_and_frequency() -> None:
    from solver.errors import CONDITION_WARNING, condition_warnings

    lines = condition_warnings({"P1": 0.1 / CONDITION_WARNING, "P2": 1e-12, "P3": 0.0}, 155.0)
    assert len(lines) == 2
    assert lines[0].startswith("plate P1 at 155 Hz: condition estimate 1.0e+21")
    assert "plate P3" in lines[1]


def test_modified_problem_collects_condition_warnings() -> None:
    from updating.inverse.cost import ModifiedProblem

    fake = SimpleNamespace(_description_warnings=(), frequencies={
        150.0: SimpleNamespace(system=SimpleNamespace(rcond={"P1": 1e-12, "P2": 1e-25}),
                               no_discretisation=""),
        155.0: SimpleNamespace(system=SimpleNamespace(rcond={"P1": 1e-30, "P2": 1e-12}),
                               no_discretisation="")})
    lines = ModifiedProblem.warnings.fget(fake)
    assert [line.split(":")[0] for line in lines] == ["plate P2 at 150 Hz", "plate P1 at 155 Hz"]


def test_non_finite_solution_raises() -> None:
    from solver.errors import NumericalError, check_finite

    plate = SimpleNamespace(amplitudes=np.array([1.0, math.nan]), condition_estimate=1e30)
    with pytest.raises(NumericalError, match="plate P2 at 155 Hz"):
        check_finite(SimpleNamespace(frequency=155.0, plates={"P1": SimpleNamespace(
            amplitudes=np.ones(2), condition_estimate=1.0), "P2": plate}))
    ok = SimpleNamespace(amplitudes=np.ones(2), condition_estimate=1.0)
    with pytest.raises(NumericalError, match="joint G1 at 155 Hz"):
        check_finite(SimpleNamespace(frequency=155.0, plates={"P1": ok},
                                     residuals={"G1": math.inf}))


def test_solve_case_refuses_nan_frequency_and_unloaded_assembly() -> None:
    from solver import solve_case

    case = load_case_text(TWO)
    with pytest.raises(ValueError, match="finite and > 0"):
        solve_case(case, math.nan)
    unloaded = case.model_copy(update={"loads": ()})
    with pytest.raises(ValueError, match="no loads"):
        solve_case(unloaded)


# ------------------------------------------------------------------------ JSON Schema
def test_schema_command_prints_valid_json(capsys) -> None:
    assert main(["schema"]) == 0

    def not_json(constant: str) -> None:  # Python reads Infinity and NaN; editors do not
        raise ValueError(f"{constant} is not JSON")

    schema = json.loads(capsys.readouterr().out, parse_constant=not_json)
    assert {"name", "frequency", "frequencies", "materials", "plates", "joints", "boundaries",
            "loads", "discretisation", "measurement", "updating", "truth"} <= set(
        schema["properties"])
    defs = schema["$defs"]
    assert defs["Boundary"]["properties"]["condition"]["enum"] == [
        "clamped", "simply_supported", "free", "symmetric"]
    assert defs["EdgeShear"]["properties"]["distribution"]["enum"] == ["uniform", "half_sine"]
    assert defs["HingeJoint"]["properties"]["kind"]["const"] == "hinge"
    assert "kind" in defs["HingeJoint"]["required"]
    for name, sub in defs.items():  # every model and field is documented for the editor
        assert sub.get("description"), name
        for key, prop in sub.get("properties", {}).items():
            assert prop.get("description"), f"{name}.{key}"


def test_schema_out_file(tmp_path: Path, capsys) -> None:
    out = tmp_path / "vtcr.schema.json"
    assert main(["schema", "--out", str(out)]) == 0
    assert "#:schema" in capsys.readouterr().out
    assert json.loads(out.read_text())["title"] == "vtcr assembly description"


def test_cases_validate_against_schema() -> None:
    jsonschema = pytest.importorskip("jsonschema")
    from assembly.schema import case_json_schema

    schema = case_json_schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    validator = jsonschema.Draft202012Validator(schema)
    paths = sorted(CASES.glob("*.toml"))
    assert paths
    for path in paths:
        errors = [e.message for e in validator.iter_errors(tomllib.loads(path.read_text()))]
        assert errors == [], path.name
    for text in (TWO, PAIRS, MULTI):
        assert validator.is_valid(tomllib.loads(text))


@pytest.mark.parametrize("old, new", [
    ('kind = "coplanar"', 'kind = "welded"'),
    ('between = ["P1.right", "P2.left"]', 'between = ["P1.east", "P2.left"]'),
    ("loss_factor = 0.01", "loss_factor = 0.0"),
    ('condition = "simply_supported"', 'condition = "pinned"'),
    ("frequency = 155.0", "frequencies = [155.0, 155.0]"),
    ('[plates.P1]', '[plates."P 1"]'),
    ("log10_stiffness = 2.0", "log10_stiffness = 2.0\nstiffness = 100.0"),
])
def test_schema_rejects_bad_descriptions(old: str, new: str) -> None:
    jsonschema = pytest.importorskip("jsonschema")
    from assembly.schema import case_json_schema

    validator = jsonschema.Draft202012Validator(case_json_schema())
    assert not validator.is_valid(tomllib.loads(_replace(old, new)))


def _solve_json(tmp_path: Path, target: str, capsys) -> tuple[int, list[str]]:
    (tmp_path / "case.toml").write_text(TWO)
    status, lines, _ = _run(["solve", str(tmp_path / "case.toml"), "--quiet", "--json", target],
                            capsys)
    return status, lines


def test_output_through_a_symlink_keeps_the_link(tmp_path: Path, capsys) -> None:
    (tmp_path / "real.json").write_text("old")
    (tmp_path / "link.json").symlink_to("real.json")
    status, lines = _solve_json(tmp_path, str(tmp_path / "link.json"), capsys)
    assert status == 0, lines
    assert (tmp_path / "link.json").is_symlink()
    assert json.loads((tmp_path / "real.json").read_text())["frequency"] == 155.0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["case.toml", "link.json", "real.json"]


@pytest.mark.skipif(not Path("/dev/null").is_char_device(), reason="needs /dev/null")
def test_output_to_a_device_is_written_through(tmp_path: Path, capsys) -> None:
    status, lines = _solve_json(tmp_path, "/dev/null", capsys)
    assert status == 0, lines
    assert Path("/dev/null").is_char_device()


def test_a_temporary_file_left_by_a_killed_writer_is_removed(tmp_path: Path, capsys) -> None:
    """kill -9 between writing the temporary file and renaming it leaves ``.NAME.PID.HEX.tmp``;
    the next write of that output removes it, and leaves a live writer's alone."""
    import subprocess
    import sys

    ended = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                           capture_output=True, text=True, check=True)
    stale = tmp_path / f".out.json.{int(ended.stdout)}.0badc0de.tmp"
    live = tmp_path / f".out.json.{os.getpid()}.0123abcd.tmp"
    stale.write_text("{half")
    live.write_text("{half")
    status, lines = _solve_json(tmp_path, str(tmp_path / "out.json"), capsys)
    assert status == 0, lines
    assert not stale.exists() and live.exists()
    assert json.loads((tmp_path / "out.json").read_text())["frequency"]


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_write_error_is_one_line_with_status_2(tmp_path: Path, capsys) -> None:
    status, lines = _solve_json(tmp_path, "/dev/full", capsys)
    assert status == 2
    assert lines == ["vtcr: /dev/full: No space left on device; free space or give another "
                     "path"]


def test_repeated_frequency_solves_each(tmp_path: Path, capsys) -> None:
    """``--frequency 150 --frequency 160`` solves both (it used to keep only the last)."""
    (tmp_path / "case.toml").write_text(TWO)
    out = tmp_path / "out.json"
    status, lines, _ = _run(["solve", str(tmp_path / "case.toml"), "--quiet", "--frequency",
                             "150", "--frequency", "160", "--json", str(out)], capsys)
    assert status == 0, lines
    solved = json.loads(out.read_text())["frequencies"]
    assert [f["frequency"] for f in solved] == [150.0, 160.0]
    assert solved[0]["probes"] != solved[1]["probes"]
    status, lines, _ = _run(["solve", str(tmp_path / "case.toml"), "--frequency", "150",
                             "--frequency", "-1"], capsys)
    assert status == 2 and lines == ["vtcr: --frequency -1.0: must be a finite frequency > 0 "
                                     "in Hz; give e.g. --frequency 155"]


def test_version(capsys) -> None:
    from importlib.metadata import version

    status, _, out = _run(["--version"], capsys)
    assert status == 0
    assert out.strip() == f"vtcr {version('vtcr')}"


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs named pipes")
def test_output_to_a_named_pipe_is_written_through(tmp_path: Path, capsys) -> None:
    pipe = tmp_path / "pipe"
    os.mkfifo(pipe)
    received = []
    reader = threading.Thread(target=lambda: received.append(pipe.read_text()))
    reader.start()
    status, lines = _solve_json(tmp_path, str(pipe), capsys)
    reader.join(timeout=30)
    assert status == 0, lines
    assert json.loads(received[0])["frequency"] == 155.0
    assert stat.S_ISFIFO(pipe.stat().st_mode)


def test_repeated_probe_points_are_output_twice(tmp_path: Path) -> None:
    """Probes are outputs: a point given twice is solved once per row, not refused."""
    (tmp_path / "case.toml").write_text(TWO)
    (tmp_path / "p.csv").write_text("plate,x,y\nP1,0.1,0.1\nP2,0.2,0.1\nP1,0.1,0.1\n")
    out = tmp_path / "out.json"
    assert main(["solve", str(tmp_path / "case.toml"), "--probes", str(tmp_path / "p.csv"),
                 "--json", str(out), "--no-estimate", "--max-rows", "0"]) == 0
    rows = json.loads(out.read_text())["probes"]
    assert [r["plate"] for r in rows] == ["P1", "P2", "P1"] and rows[0] == rows[2]


def test_every_option_has_help_with_its_default() -> None:
    """Each argument of each command has a help text; one with a default states it."""
    import argparse

    from updating.cli import build_parser

    parser = build_parser()
    commands = parser._subparsers._group_actions[0].choices
    for name, command in commands.items():
        formatter = command._get_formatter()
        for action in command._actions:
            if isinstance(action, argparse._HelpAction):
                continue
            assert action.help, (name, action.dest)
            text = formatter._get_help_string(action)
            if action.option_strings and action.default not in (None, False):
                assert "default" in text, (name, action.dest, text)


def test_measurement_rows_are_capped(tmp_path: Path, capsys, monkeypatch) -> None:
    """A measurement file beyond the row cap stops at the first row over it (the file is not
    read further), one line with exit 2; the cap is lowered here to keep the test small."""
    import updating.data.measurements

    monkeypatch.setattr(updating.data.measurements, "MAX_MEASUREMENT_ROWS", 3)
    (tmp_path / "case.toml").write_text(TWO)
    rows = "".join(f"P1,0.{i},0.1,1e-6,0\n" for i in range(1, 5))
    (tmp_path / "m.csv").write_text("plate,x,y,re,im\n" + rows)
    status, lines, _ = _run(["localise", str(tmp_path / "case.toml"), "--measurements",
                             str(tmp_path / "m.csv")], capsys)
    assert status == 2 and len(lines) == 1
    assert "row 5: more than 3 measured values" in lines[0] and "down-sample" in lines[0]


def test_a_full_filesystem_is_one_line_and_leaves_nothing(tmp_path: Path) -> None:
    """Outputs on a full filesystem: a 64 kB tmpfs, filled, mounted in a private mount
    namespace (``unshare``; skipped where user namespaces are not allowed). The JSON cannot be
    written: exit 2, one line naming the file and the fix, no traceback, no temporary left."""
    import shutil
    import subprocess
    import sys

    if shutil.which("unshare") is None:
        pytest.skip("no unshare(1) to mount a private tmpfs; a full device is still covered "
                    "by the /dev/full test above, a full regular-file filesystem is not")
    full = tmp_path / "full"
    full.mkdir()
    script = (f"mount -t tmpfs -o size=64k tmpfs {full} && "
              f"dd if=/dev/zero of={full}/fill bs=1k count=64 2>/dev/null; "
              f"{sys.executable} -m updating solve {CASES / 'two_plates.toml'} --no-estimate "
              f"--json {full}/out.json --max-rows 0 >/dev/null; status=$?; "
              f"ls -a {full}; exit $status")
    probe = subprocess.run(["unshare", "-rm", "true"], capture_output=True)
    if probe.returncode != 0:
        pytest.skip("user namespaces are disabled on this machine, so no private tmpfs can be "
                    "mounted; /dev/full above still covers a full output device")
    done = subprocess.run(["unshare", "-rm", "sh", "-c", script], capture_output=True,
                          text=True, env=dict(os.environ, OPENBLAS_NUM_THREADS="1"), timeout=120)
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 2, done.stderr
    assert len(lines) == 1 and "Traceback" not in done.stderr, lines
    assert "out.json" in lines[0] and "free space or give another path" in lines[0], lines
    assert sorted(done.stdout.split()) == [".", "..", "fill"], done.stdout


def test_millimetres_against_si_materials_are_named_first() -> None:
    """Sizes in millimetres with E in pascals: the first line suspects the units, before the
    ray-count line their consequences raise (whose fix, lowering the frequency, would be
    wrong); the same description with E in MPa (a consistent N, mm, t, s system) only warns."""
    from solver.guards import description_issues

    mm = (TWO.replace("size = [0.5, 0.4]", "size = [500.0, 400.0]")
          .replace("thickness = 0.001", "thickness = 1.0"))
    errors, _ = description_issues(load_case_text(mm))
    assert errors[0][0] == ("plates",) and "look like millimetres" in errors[0][1]
    consistent = mm.replace("young_modulus = 210e9", "young_modulus = 210e3")
    errors, warnings = description_issues(load_case_text(consistent))
    assert not any("look like millimetres" in message for _, message in errors)
    assert any("millimetres" in message for _, message in warnings)
