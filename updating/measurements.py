"""Field measurements: reading, writing, and simulated experiments.

A measurement set holds, per frequency, complex displacements ``w`` (m) at plate-local points.
A simulated experiment solves the description's *true* assembly (``[truth.joints.*]``) with a
finer discretisation than the one being updated (``[measurement] resolution`` times the rule),
samples it on the measurement grid, and multiplies each value by ``1 + e`` with ``e`` uniform
in ``[-noise, noise]`` (seeded): the paper's noise acts on the magnitudes (section 2.2).
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from solver import solve_case
from updating.files import InputError, csv_rows, parse_finite, point_problem, write_text_atomic

__all__ = ["Measurements", "simulate_measurements", "read_measurements", "write_measurements",
           "add_noise"]


@dataclass(frozen=True)
class Measurements:
    """Measured displacements: ``data[frequency][plate] = (points (n, 2), w (n,))``."""

    data: dict

    @property
    def frequencies(self):
        return tuple(sorted(self.data))

    def count(self, frequency=None):
        freqs = self.frequencies if frequency is None else (frequency,)
        return sum(len(w) for f in freqs for _, w in self.data[f].values())


def measurement_layout(case):
    """``{plate: points (n, 2)}`` of the description's grid and point measurements."""
    layout = {}
    for plate_id, x, y in case.measurement_points():
        layout.setdefault(plate_id, []).append((x, y))
    return {pid: np.array(points, dtype=float) for pid, points in layout.items()}


def add_noise(values, noise, rng):
    """``w (1 + e)``, ``e ~ U[-noise, noise]`` independently for every value."""
    return values * (1.0 + rng.uniform(-noise, noise, size=values.shape))


def simulate_measurements(case, noise=None, seed=None, resolution=None):
    """Simulated experiment on the description's measurement layout.

    Parameters
    ----------
    case : assembly.Case
        The description; its ``true_case()`` is solved.
    noise, seed, resolution : optional
        Override ``[measurement] noise``, ``seed`` and ``resolution``.
    """
    settings = case.measurement
    noise = settings.noise if noise is None else noise
    seed = settings.seed if seed is None else seed
    resolution = settings.resolution if resolution is None else resolution
    truth = case.true_case()
    scale = truth.discretisation.resolution * resolution
    layout = measurement_layout(case)
    rng = np.random.default_rng(seed)
    data = {}
    for frequency in case.frequencies:
        solution = solve_case(truth, frequency, resolution=scale)
        data[frequency] = {pid: (points, add_noise(solution.w(pid, points), noise, rng))
                           for pid, points in layout.items()}
    return Measurements(data)


def write_measurements(path, measurements):
    """CSV ``plate,x,y,re,im[,frequency]`` (the frequency column when several), atomically."""
    several = len(measurements.frequencies) > 1
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(["plate", "x", "y", "re", "im"] + (["frequency"] if several else []))
    for frequency in measurements.frequencies:
        for pid, (points, values) in measurements.data[frequency].items():
            for (x, y), w in zip(points, values):
                writer.writerow([pid, repr(float(x)), repr(float(y)), repr(float(w.real)),
                                 repr(float(w.imag))] + ([repr(frequency)] if several else []))
    write_text_atomic(path, buffer.getvalue())


def read_measurements(path, case):
    """Read a measurement CSV (contract: ``plate,x,y,re,im`` and optional ``frequency``).

    Rows without a frequency column belong to the description's single frequency. Every bad
    row is reported (unknown plate, point outside its plate, non-finite values, a frequency
    the description does not solve at, no rows).
    """
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as err:
        raise InputError(f"{path}: cannot read the measurement file ({err.strerror}); give an "
                         "existing CSV with header plate,x,y,re,im") from None
    reader = csv.DictReader(io.StringIO(text))
    header = [h.strip() for h in (reader.fieldnames or [])]
    missing = [c for c in ("plate", "x", "y", "re", "im") if c not in header]
    if missing:
        raise InputError(f"{path}: header lacks {', '.join(missing)}; the measurement file needs "
                         "the columns plate,x,y,re,im (and frequency when several)")
    has_frequency = "frequency" in header
    if not has_frequency and len(case.frequencies) > 1:
        raise InputError(f"{path}: no frequency column but the description has frequencies "
                         f"{list(case.frequencies)}; add a frequency column")
    problems, rows = [], {}
    for number, row in csv_rows(reader):
        pid = row["plate"]
        try:
            x, y = (parse_finite(path, number, c, row[c], "plate-local metres")
                    for c in ("x", "y"))
            re, im = (parse_finite(path, number, c, row[c], "the displacement in metres")
                      for c in ("re", "im"))
            frequency = (parse_finite(path, number, "frequency", row["frequency"],
                                      "a frequency in Hz")
                         if has_frequency else case.frequencies[0])
        except InputError as err:
            problems.extend(err.lines)
            continue
        problem = point_problem(path, number, case, pid, x, y)
        if problem:
            problems.append(problem)
            continue
        match = [f for f in case.frequencies if abs(f - frequency) <= 1e-9 * f]
        if not match:
            problems.append(f"{path}: row {number}, column 'frequency': {frequency} Hz is not a "
                            f"frequency of the description {list(case.frequencies)}; add it there")
            continue
        rows.setdefault(match[0], {}).setdefault(pid, []).append((x, y, complex(re, im)))
    if not rows and not problems:
        problems.append(f"{path}: no measurement rows; add lines plate,x,y,re,im")
    if problems:
        raise InputError(problems)
    data = {}
    for frequency, plates in rows.items():
        data[frequency] = {pid: (np.array([(x, y) for x, y, _ in r]), np.array([w for *_, w in r]))
                           for pid, r in plates.items()}
        if not any(np.abs(w).max() > 0 for _, w in data[frequency].values()):
            raise InputError(f"{path}: every displacement at {frequency} Hz is zero; the "
                             "measurement term needs a non-zero field")
    return Measurements(data)
