"""Run files: every finished localisation–correction step, saved as it finishes.

A run file is JSON, rewritten atomically (:func:`updating.files.write_json_atomic`) after each
finished step, so an interrupted run — Ctrl-C, a killed job, a crash — leaves a valid file
holding every step that was finished. ``vtcr update CASE --resume RUN`` continues from its last
step; since the loop's state is a function of its finished steps only
(:func:`updating.strategy.update_joints`), the resumed run ends where an uninterrupted one
would have.

A run belongs to one description and one measurement set: both are fingerprinted (SHA-256 of
the validated description and of the measured values) and a resume against anything else is
refused, since its steps would not be steps of the new problem.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np

from updating.files import InputError, write_json_atomic
from updating.strategy import Step

__all__ = ["RUN_FORMAT", "fingerprint", "RunFile", "load_run"]

RUN_FORMAT = "vtcr-run/1"


def fingerprint(case, measurements):
    """``(description digest, measurement digest)``: SHA-256 hex strings."""
    description = hashlib.sha256(case.model_dump_json().encode()).hexdigest()
    digest = hashlib.sha256()
    for frequency in measurements.frequencies:
        digest.update(np.float64(frequency).tobytes())
        for pid in sorted(measurements.data[frequency]):
            points, values = measurements.data[frequency][pid]
            digest.update(pid.encode())
            digest.update(np.ascontiguousarray(points, dtype=float).tobytes())
            digest.update(np.ascontiguousarray(values, dtype=complex).tobytes())
    return description, digest.hexdigest()


class RunFile:
    """The run file of one updating run; :meth:`save_step` is the loop's ``on_step`` hook."""

    def __init__(self, path, case_name, digests, steps=()):
        self.path = Path(path)
        self.case_name = case_name
        self.digests = digests
        self.steps = list(steps)

    def _write(self, status=None, message=None):
        write_json_atomic(self.path, {
            "format": RUN_FORMAT,
            "case": self.case_name,
            "description_sha256": self.digests[0],
            "measurements_sha256": self.digests[1],
            "finished": status is not None,
            "status": status,
            "message": message,
            "steps": [step.to_record() for step in self.steps],
        })

    def save_step(self, step):
        """Append a finished step and rewrite the file."""
        self.steps.append(step)
        self._write()

    def finish(self, result):
        """Mark the run finished with the loop's status."""
        self.steps = list(result.steps)
        self._write(result.status, result.message)


def load_run(path, case_name, digests):
    """Read a run file to resume; returns a :class:`RunFile` holding its finished steps.

    Raises
    ------
    InputError
        The file is missing, not a run file, damaged, or made for another description or
        another measurement set.
    """
    path = Path(path)
    fix = "give a run file written by vtcr update (or start a new run without --resume)"
    try:
        data = json.loads(path.read_text())
    except OSError as err:
        raise InputError(f"--resume {path}: cannot read the run file ({err.strerror}); {fix}") \
            from None
    except ValueError as err:
        raise InputError(f"--resume {path}: not valid JSON ({err}); {fix}") from None
    if not isinstance(data, dict) or data.get("format") != RUN_FORMAT:
        raise InputError(f"--resume {path}: not a {RUN_FORMAT} run file; {fix}")
    if data.get("description_sha256") != digests[0]:
        raise InputError(f"--resume {path}: the run was made with another description than "
                         f"{case_name!r} (its content changed); resume with the description "
                         "it was made with, or start a new run")
    if data.get("measurements_sha256") != digests[1]:
        raise InputError(f"--resume {path}: the run was made with other measurements; resume "
                         "with the same measurement file (or simulation settings), or start a "
                         "new run")
    try:
        steps = [Step.from_record(record) for record in data["steps"]]
    except (KeyError, TypeError) as err:
        raise InputError(f"--resume {path}: damaged step record ({err}); {fix}") from None
    if not steps:
        raise InputError(f"--resume {path}: the run holds no finished step; start a new run")
    return RunFile(path, case_name, digests, steps)
