"""Interrupted updating runs lose nothing: run files, --resume, Ctrl-C.

The run is the four-plate study at one frequency (309.4 Hz), which takes four correction steps:
enough to interrupt after the first and still have work left to resume.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest
from support import ROOT

from updating.cli import main
from updating.data import runfile


@pytest.fixture(scope="module")
def one_frequency_case(tmp_path_factory):
    text = (ROOT / "cases" / "four_plates.toml").read_text()
    text = text.replace("frequencies = [218.0, 248.0, 309.4]", "frequency = 309.4")
    assert "frequency = 309.4" in text
    path = tmp_path_factory.mktemp("case") / "four.toml"
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def uninterrupted(one_frequency_case, tmp_path_factory):
    out = tmp_path_factory.mktemp("full") / "full.json"
    assert main(["update", str(one_frequency_case), "--json", str(out), "--quiet"]) == 0
    return json.loads(out.read_text())


def _steps(run_json):
    return [(s["step"], s["selected"], s["e_mod_percent"],
             {j: v["log10_stiffness"] for j, v in s["joints"].items()}) for s in run_json["steps"]]


def _interrupted_after_step_1(case, tmp_path, monkeypatch):
    """Run ``update`` with a Ctrl-C right after step 1 is saved; returns the run file."""
    run = tmp_path / "run.json"
    save_step = runfile.RunFile.save_step

    def save_then_interrupt(self, step):
        save_step(self, step)
        if step.step == 1:
            raise KeyboardInterrupt

    with monkeypatch.context() as patch:
        patch.setattr(runfile.RunFile, "save_step", save_then_interrupt)
        assert main(["update", str(case), "--run", str(run), "--quiet"]) == 130
    return run


def test_resume_after_an_interruption_ends_like_an_uninterrupted_run(
        one_frequency_case, uninterrupted, tmp_path, monkeypatch, capsys):
    assert len(uninterrupted["steps"]) >= 3  # something is left to resume after step 1
    run = _interrupted_after_step_1(one_frequency_case, tmp_path, monkeypatch)
    assert "--resume" in capsys.readouterr().err
    saved = json.loads(run.read_text())
    assert saved["finished"] is False and [s["step"] for s in saved["steps"]] == [0, 1]
    resumed = tmp_path / "resumed.json"
    assert main(["update", str(one_frequency_case), "--resume", str(run), "--json",
                 str(resumed), "--quiet"]) == 0
    # the loop's state is its finished steps: the resumed run repeats the same arithmetic
    assert _steps(json.loads(resumed.read_text())) == _steps(uninterrupted)
    assert json.loads(run.read_text())["finished"] is True


def test_resume_of_a_run_file_without_plate_misfits(one_frequency_case, uninterrupted,
                                                   tmp_path, monkeypatch):
    """Run files written before steps carried per-plate misfits (needed by the neighbourhood
    rule) resume to the same end: the last finished step's misfits are recomputed."""
    run = _interrupted_after_step_1(one_frequency_case, tmp_path, monkeypatch)
    saved = json.loads(run.read_text())
    for step in saved["steps"]:
        del step["misfits"]
    run.write_text(json.dumps(saved))
    resumed = tmp_path / "resumed.json"
    assert main(["update", str(one_frequency_case), "--resume", str(run), "--json",
                 str(resumed), "--quiet"]) == 0
    assert _steps(json.loads(resumed.read_text())) == _steps(uninterrupted)


def test_ctrl_c_leaves_a_valid_run_file(one_frequency_case, tmp_path, uninterrupted):
    run = tmp_path / "run.json"
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    process = subprocess.Popen(
        [sys.executable, "-m", "updating", "update", str(one_frequency_case), "--run", str(run),
         "--quiet"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
        # a user's shell starts vtcr with Ctrl-C at its default; pytest itself may have SIGINT
        # ignored (a shell starts background jobs so), and an ignored SIGINT is inherited
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and process.poll() is None:
        if run.exists() and len(json.loads(run.read_text())["steps"]) >= 2:
            break
        time.sleep(0.05)
    assert process.poll() is None, "the run ended before it could be interrupted"
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 130
    assert "Traceback" not in err and "finished steps are saved" in err
    saved = json.loads(run.read_text())  # valid JSON: written atomically
    assert saved["finished"] is False and len(saved["steps"]) >= 2
    assert _steps({"steps": [s for s in uninterrupted["steps"][:len(saved["steps"])]]}) == \
        [(r["step"], r["selected"], 100 * r["e_mod"],
          {j: p["log10_stiffness"] for j, p in r["parameters"].items()}) for r in saved["steps"]]


def test_resume_refuses_a_run_of_another_description(one_frequency_case, tmp_path, capsys):
    run = tmp_path / "run.json"
    assert main(["update", str(one_frequency_case), "--run", str(run), "--quiet"]) == 0
    other = tmp_path / "other.toml"
    other.write_text(one_frequency_case.read_text().replace("r = 0.8", "r = 0.7"))
    assert main(["update", str(other), "--resume", str(run), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "another description" in err[0] and str(run) in err[0]


@pytest.mark.parametrize("content, message", [
    (None, "cannot read the run file"),
    ("{not json", "not valid JSON"),
    ('{"format": "something-else"}', "not a vtcr-run/2 run file"),
    ('{"format": "vtcr-run/1", "finished": true}', "a run of an earlier vtcr (vtcr-run/1)"),
])
def test_resume_rejects_bad_run_files(one_frequency_case, tmp_path, capsys, content, message):
    run = tmp_path / "run.json"
    if content is not None:
        run.write_text(content)
    assert main(["update", str(one_frequency_case), "--resume", str(run), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0] and "--resume" in err[0]


@pytest.fixture(scope="module")
def finished_run(one_frequency_case, tmp_path_factory):
    run = tmp_path_factory.mktemp("finished") / "run.json"
    assert main(["update", str(one_frequency_case), "--run", str(run), "--quiet"]) == 0
    return json.loads(run.read_text())


def _set(path, value):
    """A mutation of a run record: ``path`` of keys and indices, set to ``value``."""
    def mutate(record):
        for key in path[:-1]:
            record = record[key]
        record[path[-1]] = value
    return mutate


@pytest.mark.parametrize("mutate, message", [
    (_set(["steps"], {}), "steps: Input should be a valid array"),
    (_set(["steps", 1], "step"), "steps[1]: Input should be an object"),
    (_set(["steps", 1, "residuals"], None), "steps[1].residuals: Input should be an object"),
    (_set(["steps", 1, "e_mod"], "abc"), "steps[1].e_mod: Input should be a valid number"),
    (_set(["steps", 1, "e_mod"], float("nan")), "steps[1].e_mod: must be a finite number"),
    (_set(["steps", 1, "floors", "G1"], -1.0), "steps[1].floors.G1: Input should be greater"),
    (_set(["steps", 1, "parameters"], {}), "steps[1].parameters: has joints []"),
    (_set(["steps", 1, "parameters", "G2", "log10_stiffness"], 40.0),
     "steps[1].parameters.G2.log10_stiffness: 40 is outside the bounds [-1, 6]"),
    (_set(["steps", 0, "parameters", "G1", "log10_stiffness"], 3.0),
     "steps[0].parameters: differ from the description's joints"),
    (_set(["steps", 1, "step"], 5), "steps[1].step: is 5, the 1-th step must be step 1"),
    (_set(["steps", 1, "selected"], "G9"), "corrects 'G9', which is not a joint"),
    (_set(["steps", 1, "surprise"], 1), "steps[1].surprise: Extra inputs are not permitted"),
    (_set(["status"], 7), "status: Input should be 0, 1 or 2"),
    (_set(["status"], None), "the file: a finished run has a status (0, 1 or 2)"),
])
def test_a_hand_edited_run_file_is_refused_with_the_field_named(
        one_frequency_case, finished_run, tmp_path, capsys, mutate, message):
    """Each edit gives one line naming the field, exit 2, and nothing written."""
    record = json.loads(json.dumps(finished_run))
    assert record["steps"][1]["selected"] == "G2"  # the edits above aim at a correction step
    mutate(record)
    run = tmp_path / "run.json"
    run.write_text(json.dumps(record))
    before = run.read_text()
    out = tmp_path / "out.json"
    assert main(["update", str(one_frequency_case), "--resume", str(run), "--json", str(out),
                 "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0] and str(run) in err[0], err
    assert run.read_text() == before and not out.exists()


def test_an_existing_run_file_is_replaced_only_with_force(one_frequency_case, finished_run,
                                                         tmp_path, capsys):
    run = tmp_path / "run.json"
    unfinished = dict(finished_run, finished=False, status=None, message=None)
    run.write_text(json.dumps(unfinished))
    assert main(["update", str(one_frequency_case), "--run", str(run), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert "holds an unfinished run" in err and "--resume" in err and "--force" in err
    assert json.loads(run.read_text()) == unfinished
    assert main(["update", str(one_frequency_case), "--run", str(run), "--quiet", "--force"]) == 0
    assert json.loads(run.read_text())["steps"] == finished_run["steps"]


def test_the_same_command_again_replaces_its_own_finished_run(one_frequency_case,
                                                               finished_run, tmp_path, capsys):
    """Running a finished run's command again reproduces it, so it may replace it; a finished
    run of another description, or of other measurements, is kept."""
    run = tmp_path / "run.json"
    run.write_text(json.dumps(finished_run))
    assert main(["update", str(one_frequency_case), "--run", str(run), "--quiet",
                 "--no-estimate"]) == 0
    assert json.loads(run.read_text())["steps"] == finished_run["steps"]
    other = dict(finished_run, description_sha256="0" * 64)
    run.write_text(json.dumps(other))
    assert main(["update", str(one_frequency_case), "--run", str(run), "--quiet"]) == 2
    assert "holds a finished run of another description" in capsys.readouterr().err
    other = dict(finished_run, measurements_sha256="0" * 64)
    run.write_text(json.dumps(other))
    assert main(["update", str(one_frequency_case), "--run", str(run), "--quiet"]) == 2
    assert "holds a finished run with other measurements" in capsys.readouterr().err
    assert json.loads(run.read_text()) == other


def test_resuming_a_finished_run_reports_it_without_running_the_loop(
        one_frequency_case, finished_run, tmp_path, capsys, monkeypatch, uninterrupted):
    from updating.cli import identification  # the loop as the command calls it

    run = tmp_path / "run.json"
    run.write_text(json.dumps(finished_run))

    def no_loop(*args, **kwargs):
        raise AssertionError("the loop ran again")

    monkeypatch.setattr(identification, "update_joints", no_loop)
    out = tmp_path / "out.json"
    assert main(["update", str(one_frequency_case), "--resume", str(run), "--json",
                 str(out)]) == 0
    shown = " ".join(capsys.readouterr().out.split())  # the console wraps long lines
    assert "finished: its result is reported without running the loop again" in shown
    result = json.loads(out.read_text())
    assert _steps(result) == _steps(uninterrupted)
    assert result["identified"] == uninterrupted["identified"]


def test_a_run_file_in_use_by_another_run_is_refused(one_frequency_case, tmp_path, capsys):
    """A second update on the same run file while the first holds it: one line, exit 2, and
    the lock is gone once its holder ends."""
    run = tmp_path / "run.json"
    with runfile.RunLock(run):
        assert main(["update", str(one_frequency_case), "--run", str(run), "--quiet"]) == 2
        assert "another vtcr update is writing it" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())  # nothing written, the lock file removed
    assert main(["update", str(one_frequency_case), "--run", str(run), "--quiet"]) == 0


def test_a_lock_dies_with_its_process(tmp_path):
    """kill -9 of the holder: the system releases the lock, so a lock is never stale."""
    run = tmp_path / "run.json"
    code = (f"from updating.data.runfile import RunLock; import time\n"
            f"with RunLock({str(run)!r}):\n    print('locked', flush=True); time.sleep(60)")
    holder = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "locked"
        with pytest.raises(runfile.InputError):
            runfile.RunLock(run).__enter__()
        holder.kill()
        holder.wait()
        with runfile.RunLock(run):
            pass
    finally:
        holder.kill()
        holder.wait()
        holder.stdout.close()


@pytest.mark.parametrize("terminal, quiet, shown", [
    (True, False, True), (False, False, False), (True, True, False)])
def test_progress_shows_only_on_a_terminal_and_not_when_quiet(terminal, quiet, shown):
    import io

    from rich.console import Console

    from updating.cli.progress import progress_bar

    buffer = io.StringIO()
    console = Console(file=buffer, force_terminal=terminal, quiet=quiet, width=80)
    with progress_bar(console, "correcting G7", 3) as advance:
        for _ in range(3):
            advance()
    assert ("correcting G7" in buffer.getvalue()) is shown


@pytest.mark.parametrize("quiet, lines", [(False, 2), (True, 0)])
def test_off_a_terminal_each_stage_is_one_line_on_standard_error(capsys, quiet, lines):
    import io

    from rich.console import Console

    from updating.cli.progress import progress_bar

    buffer = io.StringIO()
    console = Console(file=buffer, force_terminal=False, quiet=quiet, width=80)
    with progress_bar(console, "localising", 3) as advance:
        advance("step 1: correcting G7", amount=0)
        advance()  # an unlabelled unit of work is not a stage
        advance("step 1 finished")
    err = capsys.readouterr().err.splitlines()
    assert len(err) == lines and buffer.getvalue() == ""
    if lines:
        assert err[0].startswith("vtcr: step 1: correcting G7 (") and err[0].endswith(" s)")


def test_outputs_get_the_usual_permissions_and_no_temporary_is_left(tmp_path):
    from updating.data.files import write_json_atomic

    out = tmp_path / "out.json"
    write_json_atomic(out, {"a": 1})
    umask = os.umask(0)
    os.umask(umask)
    assert out.stat().st_mode & 0o777 == 0o666 & ~umask
    assert [p.name for p in tmp_path.iterdir()] == ["out.json"]


def test_the_resume_hint_keeps_the_outputs_and_counts_its_steps():
    """After Ctrl-C, the command that continues the run asks for the same outputs (a resumed
    run that forgot --json would write none), and one step is 'one finished step'."""
    from argparse import Namespace

    from updating.cli.identification import _finished_steps, _resume_command

    args = Namespace(case="c.toml", measurements="m.csv", json="out.json", report=None,
                     plot="figs", confidence=None)
    assert _resume_command(args, "c.run.json") == (
        "vtcr update c.toml --measurements m.csv --json out.json --plot figs "
        "--resume c.run.json")
    assert (_finished_steps(1), _finished_steps(3)) == ("1 finished step is",
                                                         "3 finished steps are")
