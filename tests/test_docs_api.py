"""``docs/api.md``: its Python blocks run, in order, in one namespace, from the repository's
root, as a reader would paste them (the blocks assert what they promise)."""

from __future__ import annotations

import re
import subprocess
import sys

from support import ROOT, TWO_PLATES


def test_the_api_page_runs():
    text = (ROOT / "docs" / "api.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) >= 3
    done = subprocess.run([sys.executable, "-c", "\n".join(blocks)], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    out = done.stdout
    assert "G1: log10 k = " in out and "G4: log10 k = " in out
    assert "below its first resonance" in out


LOW = TWO_PLATES.replace("frequency = 155.0", "frequency = 0.1")


def test_library_calls_run_the_guard_rails():
    """A two-plate description at 0.1 Hz (far below the plates' first resonance, where the
    rays do not converge) is refused by solve_case, ModifiedProblem and frequency_sweep, each
    naming the field; check=False solves it all the same."""
    import numpy as np
    import pytest

    import assembly
    import solver
    import updating

    case = assembly.load_case_text(LOW)
    points = {"P1": np.array([[0.25, 0.2]])}
    measured = updating.Measurements({0.1: {"P1": (points["P1"], np.ones(1, dtype=complex))}})
    for call in (lambda: solver.solve_case(case),
                 lambda: updating.ModifiedProblem(case, measured),
                 lambda: updating.frequency_sweep(case, (0.1, 0.2), points, count=3)):
        with pytest.raises(assembly.DescriptionError, match="first resonance"):
            call()
    assert np.isfinite(solver.solve_case(case, check=False).w("P1", points["P1"])).all()


def test_importing_the_command_line_loads_no_numpy():
    """The vtcr entry point sets the BLAS threads before numpy loads: importing updating.cli
    must not load numpy, nor change the environment."""
    code = ("import os, sys; before = dict(os.environ); import updating.cli; "
            "assert 'numpy' not in sys.modules, 'numpy'; "
            "assert dict(os.environ) == before, 'environment'")
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                          text=True, timeout=60)
    assert done.returncode == 0, done.stderr[-2000:]
