"""Field measurements: reading, writing, and simulated experiments.

A measurement set holds, per frequency, complex displacements ``w`` (m) at plate-local points.
A simulated experiment solves the description's *true* assembly (``[truth.joints.*]``) with a
finer discretisation than the one being updated (``[measurement] resolution`` times the rule),
samples it on the measurement grid, and multiplies each value by ``1 + e`` with ``e`` uniform
in ``[-noise, noise]`` (seeded): the paper's noise acts on the magnitudes (section 2.2).
"""

from __future__ import annotations

import csv
import functools
import io
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from assembly.graph import build_graph, components
from solver import solve_case
from solver.errors import ToleranceError
from solver.tolerance import solve_to_tolerance
from updating.data.files import (
    parse_finite,
    point_key,
    point_problem,
    read_csv_table,
    too_many_cells,
    write_text_atomic,
)
from updating.errors import InputError

if TYPE_CHECKING:
    from assembly import Case
    from updating.executor import Executor

__all__ = ["Measurements", "simulate_measurements", "read_measurements", "write_measurements",
           "add_noise"]


@dataclass(frozen=True)
class Measurements:
    """Measured displacements: ``data[frequency][plate] = (points (n, 2), w (n,))``."""

    data: dict

    @property
    def frequencies(self) -> tuple[float, ...]:
        return tuple(sorted(self.data))

    def count(self, frequency: float | None = None) -> int:
        freqs = self.frequencies if frequency is None else (frequency,)
        return sum(len(w) for f in freqs for _, w in self.data[f].values())


def measurement_layout(case: Case) -> dict[str, np.ndarray]:
    """``{plate: points (n, 2)}`` of the description's grid and point measurements."""
    layout = {}
    for plate_id, x, y in case.measurement_points():
        layout.setdefault(plate_id, []).append((x, y))
    return {pid: np.array(points, dtype=float) for pid, points in layout.items()}


def add_noise(values: np.ndarray, noise: float, rng: np.random.Generator) -> np.ndarray:
    """``w (1 + e)``, ``e ~ U[-noise, noise]`` independently for every value."""
    return values * (1.0 + rng.uniform(-noise, noise, size=values.shape))


# With [discretisation] tolerance, the simulated experiment is solved to this fraction of it,
# so that the "measured" field is tighter than the model it is compared with.
SIMULATION_TIGHTENING = 0.3


def _true_response(truth: Case, scale: float, layout: Mapping[str, np.ndarray],
                   frequency: float) -> dict[str, np.ndarray]:
    """``{plate: w at its layout points}`` of the true structure (an executor task): at
    ``scale``, or from there to :data:`SIMULATION_TIGHTENING` times the description's
    tolerance; when the Trefftz round-off floor does not allow that, to the tolerance itself
    (from the finer start, so still tighter than the model), else the error names the plate."""
    tolerance = truth.discretisation.tolerance
    if tolerance is None:
        solution = solve_case(truth, frequency, resolution=scale, residuals=False, check=False)
    else:
        try:
            solution, _ = solve_to_tolerance(truth, frequency,
                                             SIMULATION_TIGHTENING * tolerance, resolution=scale)
        except ToleranceError:
            solution, _ = solve_to_tolerance(truth, frequency, tolerance, resolution=scale)
    return {pid: solution.w(pid, points) for pid, points in layout.items()}


def simulate_measurements(case: Case, noise: float | None = None, seed: int | None = None,
                          resolution: float | None = None,
                          executor: Executor | None = None) -> Measurements:
    """Simulated experiment on the description's measurement layout.

    Parameters
    ----------
    case : assembly.Case
        The description; its ``true_case()`` is solved.
    noise, seed, resolution : optional
        Override ``[measurement] noise``, ``seed`` and ``resolution``.
    executor : updating.executor.Executor, optional
        Solves the frequencies in parallel; the noise is drawn here afterwards, in frequency
        order, so the data do not depend on the executor.
    """
    settings = case.measurement
    noise = settings.noise if noise is None else noise
    seed = settings.seed if seed is None else seed
    resolution = settings.resolution if resolution is None else resolution
    truth = case.true_case()
    scale = truth.discretisation.resolution * resolution
    layout = measurement_layout(case)
    task = functools.partial(_true_response, truth, scale, layout)
    frequencies = list(case.frequencies)
    responses = executor.map(task, frequencies) if executor else [task(f) for f in frequencies]
    rng = np.random.default_rng(seed)
    data = {frequency: {pid: (layout[pid], add_noise(values[pid], noise, rng))
                        for pid in layout}
            for frequency, values in zip(frequencies, responses)}
    return Measurements(data)


def write_measurements(path: str | Path, measurements: Measurements, sweep: bool = False) -> None:
    """CSV ``plate,x,y,re,im[,frequency]`` (the frequency column when several), atomically.

    ``sweep=True`` writes the columns of a frequency sweep (``vtcr frf``),
    ``plate,x,y,frequency,re,im``, with the frequency column always; the readers take the
    columns by name, so both read back the same.
    """
    if sweep:
        columns = ["plate", "x", "y", "frequency", "re", "im"]
    else:
        several = len(measurements.frequencies) > 1
        columns = ["plate", "x", "y", "re", "im"] + (["frequency"] if several else [])
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, columns, lineterminator="\n", extrasaction="ignore")
    writer.writeheader()
    for frequency in measurements.frequencies:
        for pid, (points, values) in measurements.data[frequency].items():
            for (x, y), w in zip(points, values):
                writer.writerow({"plate": pid, "x": repr(float(x)), "y": repr(float(y)),
                                 "frequency": repr(frequency), "re": repr(float(w.real)),
                                 "im": repr(float(w.imag))})
    write_text_atomic(path, buffer.getvalue())


MAX_MEASUREMENT_ROWS = 100_000
"""Most rows of a measurement file (all frequencies): a laser-vibrometer scan has hundreds to a
few thousand points per frequency; 1e5 values already take about 1 GB in the updating."""


def read_measurements(path: str | Path, case: Case) -> Measurements:
    """Read a measurement CSV (contract: ``plate,x,y,re,im`` and optional ``frequency``).

    Rows without a frequency column belong to the description's single frequency. Every bad
    row is reported at once: unknown plate, point outside its plate, non-numeric or
    non-finite values, a frequency the description does not solve at, a point measured twice
    at the same frequency (average repeated measurements first), and, per frequency, a field
    that is zero everywhere; also an empty file or one without rows, a wrong header or
    separator (see :func:`updating.data.files.read_csv_table`).
    """
    columns = ("plate", "x", "y", "re", "im")
    present, table = read_csv_table(path, "measurement", columns, optional=("frequency",))
    has_frequency = "frequency" in present
    if not has_frequency and len(case.frequencies) > 1:
        raise InputError(f"{path}: row 1: no frequency column but the description has "
                         f"frequencies {list(case.frequencies)}; add a frequency column (Hz)")
    problems, rows, seen = [], {}, {}
    for count, (number, row) in enumerate(table, start=1):
        if count > MAX_MEASUREMENT_ROWS:  # stop reading: the rest would not be used anyway
            raise InputError(problems + [
                f"{path}: row {number}: more than {MAX_MEASUREMENT_ROWS} measured values; each "
                "value is a row of the interface problem (1e5 values take about 1 GB and 10 s "
                "per frequency): down-sample the scan (every k-th point) or average it onto a "
                "coarser grid"])
        if row is None:
            problems.append(too_many_cells(path, number, columns))
            continue
        pid = row["plate"]
        try:
            values = [parse_finite(path, number, c, row[c], what) for c, what in (
                ("x", "plate-local metres"), ("y", "plate-local metres"),
                ("re", "the displacement in metres"), ("im", "the displacement in metres"))]
            frequency = (parse_finite(path, number, "frequency", row["frequency"],
                                      "a frequency in Hz")
                         if has_frequency else case.frequencies[0])
        except InputError as err:
            problems.extend(err.lines)
            continue
        x, y, re, im = values
        problem = point_problem(path, number, case, pid, x, y)
        if problem:
            problems.append(problem)
            continue
        match = [f for f in case.frequencies if abs(f - frequency) <= 1e-9 * f]
        if not match:
            problems.append(f"{path}: row {number}, column 'frequency': {frequency:g} Hz is not "
                            f"a frequency of the description {list(case.frequencies)}; add it "
                            "there or remove the row")
            continue
        key = point_key(pid, x, y, match[0])
        if key in seen:
            problems.append(f"{path}: row {number}: repeats the point of row {seen[key]} "
                            f"({pid}, {x:g}, {y:g} at {match[0]:g} Hz); keep one row per "
                            "point and frequency (average repeated measurements first)")
            continue
        seen[key] = number
        rows.setdefault(match[0], {}).setdefault(pid, []).append((x, y, complex(re, im)))
    if not rows and not problems:
        problems.append(f"{path}: no measurement rows; add lines plate,x,y,re,im")
    data = {}
    for frequency in sorted(rows):
        data[frequency] = {pid: (np.array([(x, y) for x, y, _ in r]),
                                 np.array([w for *_, w in r]))
                           for pid, r in rows[frequency].items()}
        if not any(np.abs(w).max() > 0 for _, w in data[frequency].values()):
            problems.append(f"{path}: every displacement at {frequency:g} Hz is zero; the "
                            "measurement term needs a non-zero field (check the re and im "
                            "columns and their units, metres)")
    if problems:
        raise InputError(problems)
    return Measurements(data)


MIN_POINTS = 3
"""Fewest measurement points (summed over frequencies) on a sub-assembly whose joints are updated.

Study on ``cases/four_plates.toml`` (truth: G3 at log10 k = 3.5, noise-free, points on P3):
over log10 k in [-1, 6] the cost curve of G3 rises to 1e-4 above its minimum with 1 point,
7e-4 with 2, and 2.2e-2 with 3 -- already the 2.3e-2 of the full 80-point grid. With fewer
than 3 points the measurement term barely depends on the joints, so any noise decides.
"""


def _layout_counts(case: Case) -> dict[str, int]:
    counts = {}
    for pid, _, _ in case.measurement_points():
        counts[pid] = counts.get(pid, 0) + 1
    return counts


def _joint_label(case: Case, name: str) -> str:
    jid, member = case.updatable_joints()[name]
    if member is None:
        a, b = case.joints[jid].between
        return f"joint {jid} ({a} | {b})"
    return f"member {name} of junction {jid} ({' | '.join(case.joints[jid].between)})"


def joint_visibility(case: Case, counts: Mapping[str, int], joints: Iterable[str] | None = None
                     ) -> tuple[list[str], list[str]]:
    """Which joints the measurements cannot see: ``(errors, warnings)``, one message each.

    The rule (per connected sub-assembly of the joint graph, points summed over frequencies):

    * **error** -- no measurement point on the sub-assembly of a joint: the measurements do not
      depend on that joint at all, so its residual stays at the discretisation floor whatever
      its parameters and updating it is meaningless;
    * **error** -- fewer than :data:`MIN_POINTS` points on such a sub-assembly: the
      measurement term hardly depends on its joints (see :data:`MIN_POINTS`);
    * **warning** -- neither plate of a joint carries a point but other plates of its
      sub-assembly do: the joint still shapes the measured field, but only through the other
      plates. In ``cases/four_plates.toml`` with G3 = P3 | P4 wrong and only P1 measured, the
      noise-free cost curve of G3 has its minimum at the truth, yet with 10 % noise it varies
      by a factor 1.9 over log10 k in [-1, 6] against 21 with P3 measured: poorly
      identifiable. The paper measures both sides of its joints.

    Parameters
    ----------
    case : assembly.Case
    counts : mapping of str to int
        Number of measurement points per plate (all frequencies together).
    joints : iterable of str, optional
        The joints to be updated or examined; default every joint.

    Returns
    -------
    errors, warnings : list of str
    """
    units = case.updatable_joints()
    joints = list(units if joints is None else joints)
    plates_of = {name: case.joints[units[name][0]].plates for name in joints}
    errors, warnings = [], []
    for group in components(build_graph(case)):
        members = [j for j in joints if plates_of[j][0] in group]
        if not members:
            continue
        n = sum(counts.get(pid, 0) for pid in group)
        plates = ", ".join(group)
        if n == 0:
            for jid in members:
                errors.append(
                    f"{_joint_label(case, jid)}: no measurement point on its plates "
                    f"{{{plates}}}, so the measurements do not depend on it and its residual "
                    f"stays at the discretisation floor; measure on "
                    f"{' or '.join(plates_of[jid])}")
        elif n < MIN_POINTS:
            errors.append(
                f"only {n} measurement point(s) on plates {{{plates}}}: too few to see joint(s) "
                f"{', '.join(members)} (with fewer than {MIN_POINTS} points the measurements "
                f"hardly depend on a joint); measure at least {MIN_POINTS} points, best a grid "
                "on both sides of each joint")
        else:
            for jid in members:
                own = plates_of[jid]
                if not any(counts.get(p, 0) for p in own):
                    which = (f"neither {own[0]} nor {own[1]}" if len(own) == 2
                             else f"none of {', '.join(own)}")
                    warnings.append(
                        f"{_joint_label(case, jid)}: {which} carries a measurement point, so "
                        "the joint is seen only through the other plates and its parameters "
                        f"are poorly identifiable; measure on {' or '.join(own)}")
    return errors, warnings


def check_joints_seen(case: Case, measurements: Measurements | None = None,
                      joints: Iterable[str] | None = None,
                      source: str = "<measurements>") -> list[str]:
    """Check, before an updating run, that the measurements can see the joints to update.

    Parameters
    ----------
    case : assembly.Case
    measurements : Measurements, optional
        A measurement set; None checks the description's own layout (``[measurement]``
        grid and points, what a simulated experiment measures).
    joints : iterable of str, optional
        The joints to be updated or examined (default every joint).
    source : str
        Names the measurements in messages: the file, or ``"CASE.toml: measurement"``.

    Returns
    -------
    list of str
        Warnings, one line each (see :func:`joint_visibility`), and a warning per frequency
        of the description that the measurements lack.

    Raises
    ------
    InputError
        Every error of :func:`joint_visibility`, one line each, prefixed by `source`.
    """
    if measurements is None:
        counts, frequencies = _layout_counts(case), case.frequencies
    else:
        counts = {}
        for plates in measurements.data.values():
            for pid, (_, values) in plates.items():
                counts[pid] = counts.get(pid, 0) + len(values)
        frequencies = measurements.frequencies
    errors, warnings = joint_visibility(case, counts, joints)
    if errors:
        raise InputError([f"{source}: {line}" for line in errors])
    lacking = [f for f in case.frequencies if f not in frequencies]
    if lacking and measurements is not None:
        warnings.append(f"no measurement at {', '.join(f'{f:g}' for f in lacking)} Hz, a "
                        "frequency of the description; those frequencies are not used")
    return [f"{source}: {line}" for line in warnings]
