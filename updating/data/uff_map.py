"""The node map of measured UFF data: the correspondence table, CSV ``node,plate,x,y``
(plate-local metres), that places each response node of a UFF file on a plate
(:func:`read_uff_map`; :func:`updating.data.uff.read_uff` reads it with the file, see
:mod:`updating.data.uff` for how the nodes of the file are matched).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from updating.data.files import plate_point, point_key, read_csv_table
from updating.errors import InputError

if TYPE_CHECKING:
    from assembly import Case

__all__ = ["MapEntry", "map_rows", "node_key", "read_uff_map"]


def node_key(text: str) -> str:
    """A node as text: integers normalised (``"012"`` -> ``"12"``), names stripped."""
    text = str(text).strip()
    try:
        return str(int(text))
    except ValueError:
        return text


@dataclass(frozen=True)
class MapEntry:
    """One row of the correspondence table."""

    node: str
    plate: str
    x: float
    y: float
    row: int


def map_rows(path: str | Path, case: Case) -> tuple[dict[str, MapEntry], list[str]]:
    """``({node: MapEntry}, problems)``: every problem of the table, none raised."""
    columns = ("node", "plate", "x", "y")
    try:  # the shared CSV checks: UTF-8 (BOM allowed), commas, header, misspelt columns
        _, rows = read_csv_table(path, "UFF node map", columns)
    except InputError as err:
        return {}, err.lines
    entries, problems, points = {}, [], {}
    for number, row in rows:
        if row is None:
            problems.append(f"{path}: row {number}: more cells than the header's columns; "
                            "one node per row node,plate,x,y")
            continue
        node = node_key(row["node"])
        if not node:
            problems.append(f"{path}: row {number}, column 'node': empty; give the UFF "
                            "response node number")
            continue
        try:
            x, y = plate_point(path, number, case, row["plate"], row)
        except InputError as err:
            problems.extend(err.lines)
            continue
        if node in entries:
            problems.append(f"{path}: row {number}, column 'node': node {node} is already "
                            f"placed on row {entries[node].row}; give each node once")
            continue
        key = point_key(row["plate"], x, y)
        if key in points:
            other = entries[points[key]]
            problems.append(f"{path}: row {number}: node {node} is placed at the point of node "
                            f"{other.node} (row {other.row}: {row['plate']}, {x:g}, {y:g}); a "
                            "point is measured once: remove one node, or average their "
                            "measurements into one")
            continue
        points[key] = node
        entries[node] = MapEntry(node, row["plate"], x, y, number)
    if not entries and not problems:
        problems.append(f"{path}: no rows; add lines node,plate,x,y")
    return entries, problems


def read_uff_map(path: str | Path, case: Case) -> dict[str, MapEntry]:
    """Read the UFF node correspondence table ``node,plate,x,y`` (plate-local metres).

    Parameters
    ----------
    path : str or Path
    case : assembly.Case
        Plates and their sizes, to check every point.

    Returns
    -------
    dict of str to MapEntry
        Keyed by the node as text (integers normalised: ``"012"`` is ``"12"``).

    Raises
    ------
    InputError
        Every problem at once: missing file or columns, empty or duplicate node, non-numeric
        coordinate, unknown plate, point outside its plate, no rows.
    """
    entries, problems = map_rows(path, case)
    if problems:
        raise InputError(problems)
    return entries
