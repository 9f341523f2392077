"""Files exchanged with the user: probe and measurement CSV, JSON results (written atomically).

Every problem in a file is reported as :class:`InputError` with one line naming the file, the
row and column, and what would fix it.
"""

from __future__ import annotations

import csv
import json
import math
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["InputError", "Probes", "csv_rows", "parse_finite", "point_problem", "read_probes",
           "write_json_atomic", "write_text_atomic"]


class InputError(ValueError):
    """Bad user input (file, option): one line per problem, shown without a traceback."""

    def __init__(self, lines):
        self.lines = [lines] if isinstance(lines, str) else list(lines)
        super().__init__("\n".join(self.lines))


@dataclass(frozen=True)
class Probes:
    """Points grouped by plate: ``{plate_id: ndarray (n, 2)}``, and the original row order."""

    by_plate: dict
    order: tuple  # ((plate_id, index_in_plate), ...)


def parse_finite(path, row_number, column, text, what):
    """A finite float from one CSV cell, or :class:`InputError` naming the row, column and fix."""
    try:
        value = float(text)
    except (TypeError, ValueError):
        raise InputError(f"{path}: row {row_number}, column {column!r}: {text!r} is not a "
                         f"number; give {what}") from None
    if not math.isfinite(value):
        raise InputError(f"{path}: row {row_number}, column {column!r}: {text} is not finite; "
                         f"give {what}")
    return value


def point_problem(path, row_number, case, plate_id, x, y):
    """Message when a CSV row's point is not on its plate (None when it is)."""
    if plate_id not in case.plates:
        return (f"{path}: row {row_number}, column 'plate': plate {plate_id!r} is not in the "
                f"assembly (plates: {', '.join(case.plates)})")
    lx, ly = case.plates[plate_id].size
    if not (0.0 <= x <= lx and 0.0 <= y <= ly):
        return (f"{path}: row {row_number}: point ({x}, {y}) is outside plate {plate_id} "
                f"[0, {lx}] x [0, {ly}]; give plate-local metres")
    return None


def csv_rows(reader):
    """``(row number, {column: stripped text})`` of a csv.DictReader, header being row 1."""
    for number, raw in enumerate(reader, start=2):
        yield number, {k.strip(): (v or "").strip() for k, v in raw.items() if k}


def read_probes(path, case):
    """Read a probe CSV (header ``plate,x,y``, plate-local metres) and check it against ``case``.

    Raises
    ------
    InputError
        Missing file, wrong header, unknown plate, non-numeric or non-finite coordinate, a
        point outside its plate, or no rows; every bad row is reported.
    """
    path = Path(path)
    try:
        handle = path.open(newline="")
    except OSError as err:
        raise InputError(f"{path}: cannot read the probe file ({err.strerror}); "
                         "give an existing CSV with header plate,x,y") from None
    problems, rows = [], []
    with handle:
        reader = csv.DictReader(handle)
        header = [h.strip() for h in (reader.fieldnames or [])]
        if not {"plate", "x", "y"} <= set(header):
            raise InputError(f"{path}: header is {','.join(header) or 'empty'}; the probe file "
                             "needs the columns plate,x,y")
        for number, row in csv_rows(reader):
            plate_id = row["plate"]
            try:
                x, y = (parse_finite(path, number, c, row[c], "plate-local metres")
                        for c in ("x", "y"))
            except InputError as err:
                problems.extend(err.lines)
                continue
            problem = point_problem(path, number, case, plate_id, x, y)
            if problem:
                problems.append(problem)
                continue
            rows.append((plate_id, x, y))
    if not rows and not problems:
        problems.append(f"{path}: no probe rows; add at least one line plate,x,y")
    if problems:
        raise InputError(problems)
    by_plate, order = {}, []
    for plate_id, x, y in rows:
        by_plate.setdefault(plate_id, []).append((x, y))
        order.append((plate_id, len(by_plate[plate_id]) - 1))
    return Probes({k: np.array(v) for k, v in by_plate.items()}, tuple(order))


def write_text_atomic(path, text):
    """Write ``text`` to ``path`` through a temporary file and a rename (never half-written)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w") as handle:
            handle.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def write_json_atomic(path, data):
    """Write JSON atomically (see :func:`write_text_atomic`)."""
    write_text_atomic(path, json.dumps(data, indent=2) + "\n")
