"""Run files: every finished localisation–correction step, saved as it finishes.

A run file is JSON, rewritten atomically (:func:`updating.data.files.write_json_atomic`) after each
finished step, so an interrupted run — Ctrl-C, a killed job, a crash — leaves a valid file
holding every step that was finished. ``vtcr update CASE --resume RUN`` continues from its last
step; since the loop's state is a function of its finished steps only
(:func:`updating.inverse.strategy.update_joints`), the resumed run ends where an uninterrupted one
would have.

A run belongs to one description and one measurement set: both are fingerprinted (SHA-256 of
the validated description and of the measured values) and a resume against anything else is
refused, since its steps would not be steps of the new problem. A run file is an input like
any other when resumed: its records are validated (types, finite values, the description's
joints, steps in order, corrected values within the updating bounds) before any work.

A run file belongs to one run at a time (:class:`RunLock`, an advisory lock on a hidden file
beside it, released by the system if the process dies), and an existing run file is only
replaced when the user says so (``--force``); ``--resume`` continues it.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import IO, TYPE_CHECKING, Annotated, Any, Literal, Self

import numpy as np
import pydantic

from updating.data.files import write_json_atomic
from updating.errors import InputError
from updating.inverse.strategy import Step

if TYPE_CHECKING:
    from assembly import Case
    from updating.data.measurements import Measurements
    from updating.inverse.strategy import UpdateResult

try:  # advisory locks where the system has them (POSIX); elsewhere runs are not locked
    import fcntl
except ImportError:  # pragma: no cover - not POSIX
    fcntl = None

__all__ = ["RUN_FORMAT", "fingerprint", "RunFile", "read_run", "load_run", "RunLock",
           "refuse_replacing"]

RUN_FORMAT = "vtcr-run/2"
"""``vtcr-run/1`` runs measured the joint residual at the Gauss points, with floors of the
noise alone: their steps are not steps of this version's problem, and are not resumed."""


def fingerprint(case: Case, measurements: Measurements) -> tuple[str, str]:
    """``(description digest, measurement digest)``: SHA-256 hex strings."""
    return description_digest(case), measurement_digest(measurements)


def description_digest(case: Case) -> str:
    """SHA-256 of the validated description (its meaning, not its text: comments, key order
    and number spelling do not change it)."""
    return hashlib.sha256(case.model_dump_json().encode()).hexdigest()


def measurement_digest(measurements: Measurements) -> str:
    """SHA-256 of the measured points and values, frequency by frequency."""
    digest = hashlib.sha256()
    for frequency in measurements.frequencies:
        digest.update(np.float64(frequency).tobytes())
        for pid in sorted(measurements.data[frequency]):
            points, values = measurements.data[frequency][pid]
            digest.update(pid.encode())
            digest.update(np.ascontiguousarray(points, dtype=float).tobytes())
            digest.update(np.ascontiguousarray(values, dtype=complex).tobytes())
    return digest.hexdigest()


class RunFile:
    """The run file of one updating run; :meth:`save_step` is the loop's ``on_step`` hook."""

    def __init__(self, path: str | Path, case_name: str, digests: tuple[str, str],
                 steps: Iterable[Step] = (),
                 finished: tuple[int, str | None] | None = None) -> None:
        self.path = Path(path)
        self.case_name = case_name
        self.digests = digests
        self.steps = list(steps)
        self.finished = finished  # (status, message) of a finished run read back

    def _write(self, status: int | None = None, message: str | None = None) -> None:
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

    def save_step(self, step: Step) -> None:
        """Append a finished step and rewrite the file."""
        self.steps.append(step)
        self._write()

    def finish(self, result: UpdateResult) -> None:
        """Mark the run finished with the loop's status."""
        self.steps = list(result.steps)
        self._write(result.status, result.message)


def _finite(value: float) -> float:
    if not math.isfinite(value):
        raise ValueError("must be a finite number")
    return value


Finite = Annotated[float, pydantic.AfterValidator(_finite)]
NonNegative = Annotated[Finite, pydantic.Field(ge=0.0)]
Interval = tuple[Finite, Finite]


class _Parameters(pydantic.BaseModel, extra="forbid", strict=True):
    log10_stiffness: Finite
    loss_factor: NonNegative
    mass: NonNegative


class _StepRecord(pydantic.BaseModel, extra="forbid"):
    """One :meth:`Step.to_record`, as a run file holds it."""

    model_config = pydantic.ConfigDict(strict=True)

    step: Annotated[int, pydantic.Field(ge=0)]
    selected: str | None
    parameters: dict[str, _Parameters]
    residuals: dict[str, NonNegative]
    floors: dict[str, NonNegative]
    e_mod: NonNegative
    e_int: NonNegative
    e_mes: NonNegative
    interval: Interval | None = None
    recorrection: bool = False
    e_mod_floor: NonNegative = 0.0
    misfits: dict[str, NonNegative] = {}
    also: dict[str, Interval] = {}
    thresholds: dict[str, NonNegative] = {}


class _RunRecord(pydantic.BaseModel):
    format: str
    case: str
    description_sha256: str
    measurements_sha256: str
    finished: bool
    status: Literal[0, 1, 2] | None
    message: str | None
    steps: list[_StepRecord]

    @pydantic.model_validator(mode="after")
    def _status_when_finished(self) -> _RunRecord:
        if self.finished != (self.status is not None):
            raise ValueError("a finished run has a status (0, 1 or 2) and an unfinished one "
                             "none")
        return self


def _first_problem(err: pydantic.ValidationError) -> str:
    """``steps[2].e_mod: must be a finite number (and 3 more problems)``."""
    problems = err.errors()
    first = problems[0]
    where = "".join(f"[{part}]" if isinstance(part, int) else f".{part}" for part in first["loc"])
    message = first["msg"].removeprefix("Value error, ")
    more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
    return f"{where.lstrip('.') or 'the file'}: {message}{more}"


def _step_problems(steps: Sequence[_StepRecord], case: Case) -> str | None:
    """What makes ``steps`` (validated records) impossible for ``case``, or None."""
    joints = set(case.updatable_joints())
    lo, hi = case.updating.bounds
    initial = case.updatable_parameters()
    previous = initial  # each step after the first is checked against the one before it
    for n, step in enumerate(steps):
        where = f"steps[{n}]"
        if step.step != n:
            return f"{where}.step: is {step.step}, the {n}-th step must be step {n}"
        for name in ("parameters", "residuals", "floors", "thresholds"):
            keys = set(getattr(step, name))
            if keys != joints and (name != "thresholds" or keys):
                return (f"{where}.{name}: has joints {sorted(keys)}, the description has "
                        f"{sorted(joints)}")
        for joint in (*step.also, *([step.selected] if step.selected is not None else [])):
            if joint not in joints:
                return f"{where}: corrects {joint!r}, which is not a joint of the description"
        values = {j: p.model_dump() for j, p in step.parameters.items()}
        if n == 0 and values != initial:
            return f"{where}.parameters: differ from the description's joints (step 0 is the model)"
        if n > 0:
            for joint, p in values.items():
                moved = p != previous[joint]
                if moved and not lo <= p["log10_stiffness"] <= hi:
                    return (f"{where}.parameters.{joint}.log10_stiffness: "
                            f"{p['log10_stiffness']:g} is outside the bounds [{lo:g}, {hi:g}]")
        previous = values
    return None


_FIX = "give a run file written by vtcr update (or start a new run without --resume)"


def read_run(path: str | Path) -> tuple[str, dict[str, Any]]:
    """``(text, parsed JSON)`` of a run file to resume: readable, JSON, of this format (checked
    before any work, see :func:`load_run` for the rest)."""
    try:
        text = Path(path).read_text()
        data = json.loads(text)
    except OSError as err:
        raise InputError(f"--resume {path}: cannot read the run file ({err.strerror}); {_FIX}") \
            from None
    except ValueError as err:
        raise InputError(f"--resume {path}: not valid JSON ({err}); {_FIX}") from None
    if isinstance(data, dict) and data.get("format") == "vtcr-run/1":
        raise InputError(f"--resume {path}: a run of an earlier vtcr (vtcr-run/1), whose joint "
                         "residual and floors differ from this version's; start a new run (with "
                         "--force over it, or another --run)")
    if not isinstance(data, dict) or data.get("format") != RUN_FORMAT:
        raise InputError(f"--resume {path}: not a {RUN_FORMAT} run file; {_FIX}")
    return text, data


def load_run(path: str | Path, case: Case, digests: tuple[str, str]) -> RunFile:
    """Read a run file to resume; returns a :class:`RunFile` holding its finished steps.

    Raises
    ------
    InputError
        The file is missing, not a run file, damaged (any field of the wrong type, a value not
        finite, joints that are not the description's, steps out of order, a corrected value
        outside the bounds), or made for another description or another measurement set.
    """
    path = Path(path)
    text, data = read_run(path)
    if data.get("description_sha256") != digests[0]:
        raise InputError(f"--resume {path}: the run was made with another description than "
                         f"{case.name!r} (its content changed); resume with the description "
                         "it was made with, or start a new run")
    if data.get("measurements_sha256") != digests[1]:
        raise InputError(f"--resume {path}: the run was made with other measurements; resume "
                         "with the same measurement file (or simulation settings), or start a "
                         "new run")
    try:
        record = _RunRecord.model_validate_json(text)
    except pydantic.ValidationError as err:
        raise InputError(f"--resume {path}: damaged run file, {_first_problem(err)}; {_FIX}") \
            from None
    if not record.steps:
        raise InputError(f"--resume {path}: the run holds no finished step; start a new run")
    problem = _step_problems(record.steps, case)
    if problem:
        raise InputError(f"--resume {path}: damaged run file, {problem}; {_FIX}")
    steps = [Step.from_record(step.model_dump()) for step in record.steps]
    return RunFile(path, case.name, digests, steps,
                   (record.status, record.message) if record.finished else None)


def refuse_replacing(path: str | Path, description_sha256: str | None = None) -> str | None:
    """Refuse to start a new run over an existing run file (``--force`` replaces it).

    A finished run of the same description may be replaced: running the same command again
    reproduces it. Returns the measurement digest that run was made with (the caller refuses
    after all with :func:`refuse_other_measurements` if this run's differs), or None when
    there is no file.
    """
    path = Path(path)
    if not path.exists():
        return None
    try:
        data = json.loads(path.read_text())
        finished = data.get("finished")
    except (OSError, ValueError, AttributeError):
        data, finished = {}, None
    if (finished is True and description_sha256 is not None
            and data.get("description_sha256") == description_sha256):
        return data.get("measurements_sha256")
    what = ("a finished run" if finished is True else "an unfinished run" if finished is False
            else "a file that is not a vtcr run")
    raise InputError(f"run file {path}: holds {what}{_OF_ANOTHER if finished is True else ''}; "
                     f"continue or report it with --resume {path}, start over with --force, or "
                     "give another --run")


_OF_ANOTHER = " of another description"


def refuse_other_measurements(path: str | Path, expected: str | None,
                              measurements_sha256: str) -> None:
    """The second half of :func:`refuse_replacing`, once the measurements are known: a
    finished run of the same description but other measurements is kept."""
    if expected is not None and expected != measurements_sha256:
        raise InputError(f"run file {path}: holds a finished run with other measurements; "
                         f"report it with --resume {path}, start over with --force, or give "
                         "another --run")


class RunLock:
    """An advisory lock saying that one run writes the run file ``path``.

    The lock is on a hidden file beside it (the run file itself is replaced atomically at
    every step, so its inode changes); the system releases it when the process ends, even
    on ``kill -9``, so a lock is never stale. The lock file is removed on release.
    """

    def __init__(self, path: str | Path) -> None:
        path = Path(os.path.realpath(path))
        self.path = path.parent / f".{path.name}.lock"
        self._handle: IO[str] | None = None

    def __enter__(self) -> Self:
        if fcntl is None:  # pragma: no cover - not POSIX
            return self
        while True:
            try:
                self.path.parent.mkdir(parents=True, exist_ok=True)
                handle = open(self.path, "a")
            except OSError as err:
                raise OSError(err.errno, err.strerror, str(self.path)) from err
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                handle.close()
                raise InputError(f"run file {self.path.parent / self.path.name[1:-5]}: "
                                 "another vtcr update is writing it; wait for it to finish "
                                 "or give this run another --run") from None
            # the holder before us may have removed the file between our open and our lock
            if self.path.exists() and os.stat(self.path).st_ino == os.fstat(handle.fileno()).st_ino:
                self._handle = handle
                return self
            handle.close()

    def __exit__(self, *exc: object) -> Literal[False]:
        if self._handle is not None:
            self.path.unlink(missing_ok=True)
            self._handle.close()
            self._handle = None
        return False
