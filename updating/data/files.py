"""Files exchanged with the user: probe and measurement CSV, JSON results (written atomically).

Every problem in a file is reported as :class:`InputError` with one line naming the file, the
row and column, and what would fix it; all the bad rows of a file are reported at once.

CSV files are read leniently where spreadsheets differ and strictly where a mistake would
change the numbers: a UTF-8 byte-order mark, spaces around cells and the case of the header
are ignored, blank lines are skipped, and unknown extra columns are ignored (unless one looks
like a misspelt column); a file separated by ``;`` or tabs, a non-numeric or non-finite cell,
a repeated point and a row with more cells than the header are errors. Row numbers are the
file's line numbers (the header is row 1), as a spreadsheet shows them.
"""

from __future__ import annotations

import csv
import difflib
import glob
import json
import math
import os
import secrets
import stat
import sys
from collections.abc import Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from io import BufferedReader
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

import numpy as np

from updating.errors import InputError

if TYPE_CHECKING:
    import _csv

    from assembly import Case

__all__ = ["Probes", "atomic_output", "output_collisions", "output_path_problem",
           "parse_finite", "plate_point", "plot_directory_problem", "point_key", "point_problem",
           "read_csv_table", "read_probes", "too_many_cells", "write_json_atomic",
           "write_text_atomic"]


STDOUT = "-"
"""An output path that means standard output."""


@dataclass(frozen=True)
class Probes:
    """Points grouped by plate: ``{plate_id: ndarray (n, 2)}``, and the original row order."""

    by_plate: dict
    order: tuple  # ((plate_id, index_in_plate), ...)
    nodes: tuple | None = None  # the optional ``node`` column, in row order (UFF node numbers)


def parse_finite(path: str | Path, row_number: int, column: str, text: str | None,
                 what: str) -> float:
    """A finite float from one CSV cell, or :class:`InputError` naming the row, column and fix."""
    where = f"{path}: row {row_number}, column {column!r}"
    if text is None or not str(text).strip():
        raise InputError(f"{where}: the cell is empty; give {what}")
    try:
        value = float(text)
    except (TypeError, ValueError):
        hint = " (write a decimal point, not a comma)" if "," in str(text) else ""
        raise InputError(f"{where}: {text!r} is not a number{hint}; give {what}") from None
    if not math.isfinite(value):
        raise InputError(f"{where}: {text} is not finite; give {what}")
    return value


def point_problem(path: str | Path, row_number: int, case: Case, plate_id: str, x: float,
                  y: float) -> str | None:
    """Message when a CSV row's point is not on its plate (None when it is)."""
    if plate_id not in case.plates:
        close = difflib.get_close_matches(plate_id, list(case.plates), n=1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        return (f"{path}: row {row_number}, column 'plate': plate {plate_id!r} is not in the "
                f"assembly (plates: {', '.join(case.plates)}){hint}; fix the plate id")
    lx, ly = case.plates[plate_id].size
    if not (0.0 <= x <= lx and 0.0 <= y <= ly):
        return (f"{path}: row {row_number}: point ({x}, {y}) is outside plate {plate_id} "
                f"[0, {lx}] x [0, {ly}]; give plate-local metres")
    return None


def plate_point(path: str | Path, row_number: int, case: Case, plate_id: str,
                row: Mapping[str, str]) -> tuple[float, float]:
    """``(x, y)`` of a CSV row's point on its plate, or :class:`InputError` naming the fix."""
    x, y = (parse_finite(path, row_number, c, row[c], "plate-local metres") for c in ("x", "y"))
    problem = point_problem(path, row_number, case, plate_id, x, y)
    if problem:
        raise InputError(problem)
    return x, y


def _open_text(path: str | Path, what: str, header: str) -> BufferedReader:
    """The CSV file opened in binary for streaming (:func:`_decoded_lines`), or
    :class:`InputError`."""
    hint = f"give an existing CSV file with the header {header}"
    try:
        return open(path, "rb")  # noqa: SIM115 - closed by _closing
    except IsADirectoryError:
        raise InputError(f"{path}: is a directory, not a {what} file; {hint}") from None
    except FileNotFoundError:
        raise InputError(f"{path}: {what} file not found; check the path, or {hint}") from None
    except OSError as err:
        raise InputError(f"{path}: cannot read the {what} file ({err.strerror}); {hint}") from None


def _decoded_lines(handle: Iterable[bytes], path: str | Path) -> Iterator[str]:
    """The file's lines as text, one at a time (a UTF-8 byte-order mark removed); a line that
    is not UTF-8 is an :class:`InputError` naming its line number."""
    for number, raw in enumerate(handle, start=1):
        if number == 1 and raw.startswith(b"\xef\xbb\xbf"):
            raw = raw[3:]
        try:
            yield raw.decode("utf-8")
        except UnicodeDecodeError:
            raise InputError(f"{path}: row {number}: not UTF-8 text; save the file as CSV "
                             "UTF-8 (comma delimited)") from None


def _records(reader: _csv.Reader, path: str | Path, header_text: str) -> Iterator[list[str]]:
    """The reader's rows, read as they are used (memory bounded by what the caller keeps); a
    row the csv module cannot read (a cell beyond its field limit of 131072 characters, a
    quote left open to the end of the file) is an :class:`InputError`."""
    while True:
        try:
            cells = next(reader)
        except StopIteration:
            return
        except csv.Error as err:
            raise InputError(f"{path}: row {reader.line_num}: not readable as CSV ({err}); "
                             f"one point per row {header_text}, numbers of a few characters")
        yield cells


def _closing(rows: Iterable[list[str]], handle: BufferedReader) -> Iterator[list[str]]:
    """``rows``, then the file closed (also when the caller stops early or raises)."""
    with handle:
        yield from rows


def read_csv_table(path: str | Path, what: str, columns: Sequence[str], optional: Sequence[str] = ()
                   ) -> tuple[tuple[str, ...], Iterator[tuple[int, dict[str, str] | None]]]:
    """Check a CSV file and its header; return its columns and its rows.

    Parameters
    ----------
    path : str or path-like
    what : str
        What the file holds, for messages (``"probe"``, ``"measurement"``).
    columns : sequence of str
        Required columns (lower case).
    optional : sequence of str, optional
        Optional columns; absent ones are not in the row dicts.

    Returns
    -------
    present : tuple of str
        The known columns the header has.
    rows : iterator of (int, dict of str to str)
        The file's line number (header = 1) and the stripped cells of the present columns;
        blank rows are skipped.

    Raises
    ------
    InputError
        Missing, unreadable or empty file, not UTF-8, a file separated by ``;`` or tabs, a
        header lacking a column or naming one twice, a column that looks like a misspelt
        known column. Rows with more cells than the header are reported together with the
        caller's row problems (yielded as ``(row, None)``).
    """
    header_text = ",".join(columns)
    handle = _open_text(path, what, header_text)
    reader = csv.reader(_decoded_lines(handle, path))
    records = _closing(_records(reader, path, header_text), handle)
    first = next((cells for cells in records if any(cell.strip() for cell in cells)), None)
    if first is None:
        raise InputError(f"{path}: the {what} file is empty; write the header {header_text} "
                         "and one row per point")
    header = [cell.strip().lower() for cell in first]
    joined = ",".join(first)
    for separator, name in ((";", "semicolons"), ("\t", "tabs")):
        if len(header) == 1 and separator in joined:
            raise InputError(
                f"{path}: row {reader.line_num}: the columns are separated by {name}; use "
                f"commas, with a decimal point in numbers ({header_text}); in a spreadsheet "
                "save as 'CSV UTF-8 (comma delimited)'")
    known = set(columns) | set(optional)
    problems = []
    repeated = sorted({h for h in header if h and header.count(h) > 1})
    if repeated:
        problems.append(f"{path}: row {reader.line_num}: column(s) {', '.join(repeated)} "
                        "appear twice in the header; keep one of each")
    for h in header:
        if h and h not in known:
            close = difflib.get_close_matches(h, sorted(known - set(header)), n=1, cutoff=0.75)
            if close:
                problems.append(f"{path}: row {reader.line_num}: unknown column {h!r} (did you "
                                f"mean {close[0]!r}?); rename it")
    missing = [c for c in columns if c not in header]
    if missing:
        found = ",".join(h for h in header) or "nothing"
        problems.append(f"{path}: row {reader.line_num}: the header lacks {', '.join(missing)} "
                        f"(found {found}); the {what} file needs the columns {header_text}"
                        + (f" (and optionally {','.join(optional)})" if optional else ""))
    if problems:
        raise InputError(problems)
    index = {h: i for i, h in enumerate(header) if h in known}

    def rows() -> Iterator[tuple[int, dict[str, str] | None]]:
        for cells in records:
            if not any(cell.strip() for cell in cells):
                continue
            number = reader.line_num
            if len(cells) > len(header):
                yield number, None
                continue
            yield number, {c: (cells[i].strip() if i < len(cells) else "")
                           for c, i in index.items()}

    return tuple(index), rows()


def too_many_cells(path: str | Path, number: int, columns: Iterable[str]) -> str:
    return (f"{path}: row {number}: more cells than the header's columns; remove the extra "
            f"cells (or the thousands separators), one point per row {','.join(columns)}")


def point_key(plate_id: str, x: float, y: float, *rest: float) -> tuple[str | float, ...]:
    """A key that identifies a point up to 1e-9 m (the precision of written CSV values)."""
    return (plate_id, round(x, 9), round(y, 9), *rest)


def read_probes(path: str | Path, case: Case) -> Probes:
    """Read a probe CSV (header ``plate,x,y``, plate-local metres) and check it against ``case``.

    An optional ``node`` column numbers the points (whole numbers >= 1, each once): the UFF
    node numbers of ``vtcr frf --uff``, so that a UFF node map ``node,plate,x,y`` is also a
    probe file.

    Raises
    ------
    InputError
        Missing, empty or non-UTF-8 file, wrong header or separator, unknown plate,
        non-numeric or non-finite coordinate, a point outside its plate, a node given twice,
        a node that is not a whole number >= 1, or no rows; every bad row is reported. A point
        given twice is not a problem: probes are outputs, and the row is output twice.
    """
    columns = ("plate", "x", "y")
    problems, rows, seen_nodes = [], [], {}
    present, table = read_csv_table(path, "probe", columns, optional=("node",))
    numbered = "node" in present
    for number, row in table:
        if row is None:
            problems.append(too_many_cells(path, number, columns + (("node",) if numbered
                                                                    else ())))
            continue
        plate_id = row["plate"]
        try:
            x, y = plate_point(path, number, case, plate_id, row)
        except InputError as err:
            problems.extend(err.lines)
            continue
        node = None
        if numbered:
            text = row["node"]
            if not (text.isascii() and text.isdigit()) or int(text) < 1 or int(text) >= 2**31:
                problems.append(f"{path}: row {number}, column 'node': {text!r} is not a node "
                                "number; give a whole number from 1 to 2147483647")
                continue
            node = int(text)
            if node in seen_nodes:
                problems.append(f"{path}: row {number}, column 'node': node {node} is already "
                                f"on row {seen_nodes[node]}; give each point its own node")
                continue
            seen_nodes[node] = number
        rows.append((plate_id, x, y, node))
    if not rows and not problems:
        problems.append(f"{path}: no probe rows; add at least one line plate,x,y")
    if problems:
        raise InputError(problems)
    by_plate, order = {}, []
    for plate_id, x, y, _ in rows:
        by_plate.setdefault(plate_id, []).append((x, y))
        order.append((plate_id, len(by_plate[plate_id]) - 1))
    nodes = tuple(node for *_, node in rows) if numbered else None
    return Probes({k: np.array(v) for k, v in by_plate.items()}, tuple(order), nodes)


def output_path_problem(path: str | Path, option: str,
                        inputs: Iterable[str | Path | None] = ()) -> str | None:
    """Why an output file cannot be written (one line naming the option), or None.

    Checked before any work is done, so that a long run does not fail at its end: the path
    must not be a directory nor one of the ``inputs``, and its directory must exist and be
    writable (the directory is not created: a misspelt directory is more often a mistake).

    Parameters
    ----------
    path : str or path-like
    option : str
        The command-line option that gave it, e.g. ``"--json"``.
    inputs : iterable of str or path-like, optional
        Files the command reads; writing over one of them is refused.
    """
    if str(path) == STDOUT:
        return None
    target = Path(path)
    where = f"{option} {path}"
    if str(path).strip() == "":
        return f"{option}: the file name is empty; give a file name"
    if target.is_dir():
        return f"{where}: is a directory; give a file name inside it, e.g. {target / 'out'}"
    for source in inputs:
        if source and target.exists() and Path(source).exists() and \
                os.path.samefile(target, source):
            return f"{where}: is also an input of this command; write to another file"
    parent = target.parent
    if not parent.exists():
        return (f"{where}: directory {parent} does not exist; create it first "
                f"(mkdir -p {parent}) or give another path")
    if not parent.is_dir():
        return f"{where}: {parent} is not a directory; give a path in an existing directory"
    if not os.access(parent, os.W_OK | os.X_OK):
        return f"{where}: directory {parent} is not writable; give a path in a writable one"
    if target.exists() and not os.access(target, os.W_OK):
        return f"{where}: the file exists and is not writable; give another path"
    return None


def output_collisions(outputs: Iterable[tuple[str, str | Path | None]]) -> list[str]:
    """One line per pair of outputs that name the same file (through symlinks too), or none.

    Parameters
    ----------
    outputs : iterable of (str, str or path-like or None)
        ``(option, path)``; ``None`` paths are skipped.
    """
    seen, problems = {}, []
    for option, path in outputs:
        if path is None:
            continue
        key = STDOUT if str(path) == STDOUT else os.path.realpath(path)
        if key in seen:
            problems.append(f"{seen[key]} and {option} both write to standard output; give "
                            "one of them a file" if key == STDOUT else
                            f"{seen[key]} and {option} name the same file {path}; give each "
                            "output its own file")
        else:
            seen[key] = option
    return problems


def plot_directory_problem(path: str | Path, option: str = "--plot") -> str | None:
    """Why figures cannot be written into directory ``path``, or None.

    The directory and its missing parents are created by the run; the nearest existing
    ancestor must be a writable directory.
    """
    target = Path(path)
    where = f"{option} {path}"
    if target.exists() and not target.is_dir():
        return f"{where}: is a file, not a directory; give a directory for the figures"
    existing = target
    while not existing.exists():
        existing = existing.parent
    if not existing.is_dir():
        return f"{where}: {existing} is a file, not a directory; give a directory for the figures"
    if not os.access(existing, os.W_OK | os.X_OK):
        return f"{where}: directory {existing} is not writable; give a writable directory"
    return None


@contextmanager
def atomic_output(path: str | Path, binary: bool = False) -> Iterator[IO[Any]]:
    """Yield a handle on a temporary file beside ``path``, renamed onto it on success.

    A reader never sees a half-written file, and an interruption (Ctrl-C, crash) leaves the
    previous file, if any, intact. The temporary file is created with mode "x", so it gets the
    usual permissions (umask), unlike :func:`tempfile.mkstemp`'s 0600. A symbolic link is
    followed (the file it points to is replaced, the link kept); a target that exists and is
    not a regular file (a device such as ``/dev/null``, a named pipe) is written through.

    ``-`` (:data:`STDOUT`) is standard output.

    Raises
    ------
    OSError
        With ``filename`` the output ``path`` (not the temporary file), e.g. on a full disk.
    """
    if str(path) == STDOUT:
        stream = sys.stdout.buffer if binary else sys.stdout
        yield stream
        stream.flush()
        return
    try:
        if os.path.exists(path) and not stat.S_ISREG(os.stat(path).st_mode):
            with open(path, "wb" if binary else "w") as handle:
                yield handle
        else:
            with _replaced_atomically(Path(os.path.realpath(path)), binary) as handle:
                yield handle
    except OSError as err:
        raise OSError(err.errno, err.strerror, str(path)) from err


def _process_ended(pid: int) -> bool:
    """Whether no process ``pid`` runs any more (a live or foreign process counts as running)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except (PermissionError, OverflowError, ValueError):
        pass
    return False


def _remove_stale_temporaries(path: Path) -> None:
    """Remove the temporary files of ``path`` left by writers that were killed between
    writing and renaming (``.NAME.PID.HEX.tmp`` whose PID no longer runs)."""
    for tmp in path.parent.glob(f".{glob.escape(path.name)}.*.tmp"):
        pid = tmp.name[len(path.name) + 2:].split(".")[0]
        if pid.isdigit() and _process_ended(int(pid)):
            tmp.unlink(missing_ok=True)


@contextmanager
def _replaced_atomically(path: Path, binary: bool) -> Iterator[IO[Any]]:
    path.parent.mkdir(parents=True, exist_ok=True)
    _remove_stale_temporaries(path)
    tmp = path.parent / f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp"
    try:
        with open(tmp, "xb" if binary else "x") as handle:
            yield handle
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_text_atomic(path: str | Path, text: str) -> None:
    """Write ``text`` to ``path`` atomically (:func:`atomic_output`)."""
    with atomic_output(path) as handle:
        handle.write(text)


def write_json_atomic(path: str | Path, data: Any) -> None:
    """Write JSON atomically (see :func:`write_text_atomic`)."""
    write_text_atomic(path, json.dumps(data, indent=2) + "\n")
