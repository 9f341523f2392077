"""Assembly descriptions built by program: plate grids and chains, and a TOML writer.

The descriptions are plain dicts in the form of a TOML description, to be read with
:func:`assembly.parse_case` (validated like a file) or written with :func:`description_toml`.

>>> from assembly import parse_case
>>> case = parse_case(plate_grid(3, 2))
>>> len(case.plates), len(case.joints)
(6, 7)
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping

__all__ = ["plate_grid", "grid_joint_ids", "description_toml"]

STEEL = {"young_modulus": 210e9, "poisson_ratio": 0.3, "density": 7800.0}


def grid_joint_ids(n_x: int, n_y: int) -> list[str]:
    """Joint ids of :func:`plate_grid`, in the order of its ``joints`` table.

    ``H{i}_{j}`` joins ``P{i}_{j}.right`` to ``P{i+1}_{j}.left``; ``V{i}_{j}`` joins
    ``P{i}_{j}.top`` to ``P{i}_{j+1}.bottom`` (column i, row j, from 1).
    """
    ids = []
    for j in range(1, n_y + 1):
        for i in range(1, n_x + 1):
            if i < n_x:
                ids.append(f"H{i}_{j}")
            if j < n_y:
                ids.append(f"V{i}_{j}")
    return ids


def _joint_sides(joint_id):
    kind, rest = joint_id[0], joint_id[1:]
    i, j = (int(v) for v in rest.split("_"))
    if kind == "H":
        return [f"P{i}_{j}.right", f"P{i + 1}_{j}.left"]
    return [f"P{i}_{j}.top", f"P{i}_{j + 1}.bottom"]


def plate_grid(n_x: int, n_y: int, *, plate_size=(0.5, 0.4), thickness=0.001, frequency=250.0,
               loss_factor=0.01, log10_stiffness=2.0, truth=None, force_at=(0.17, 0.13),
               spacing=0.1, noise=0.1, seed=1, resolution=None, name=None) -> dict:
    """An ``n_x x n_y`` grid of identical steel plates joined by coplanar joints.

    Plates ``P{i}_{j}`` (column i = 1..n_x along x, row j = 1..n_y along y) of ``plate_size``
    (m) and ``thickness`` (m), origin ``[(i-1) Lx, (j-1) Ly]``; joints as in
    :func:`grid_joint_ids`, each with ``log10_stiffness``, no damping and no line mass; every
    outer edge simply supported; a unit point force in ``P1_1`` at ``force_at`` (plate-local,
    m). ``n_y = 1`` is a chain along x.

    Parameters
    ----------
    truth : mapping of str to float, optional
        ``{joint: log10_stiffness}`` of the simulated experiment's ``[truth]``.
    spacing, noise, seed : float, float, int
        The ``[measurement]`` grid spacing (m), relative noise and seed.
    resolution : float, optional
        ``[discretisation] resolution``; the default rule if None.

    Returns
    -------
    dict
        A description for :func:`assembly.parse_case` or :func:`description_toml`.

    Raises
    ------
    ValueError
        For fewer than two plates, or a ``truth`` joint the grid does not have.
    """
    if n_x < 1 or n_y < 1 or n_x * n_y < 2:
        raise ValueError(f"a plate grid needs n_x, n_y >= 1 and two plates, got {n_x} x {n_y}")
    joints = grid_joint_ids(n_x, n_y)
    unknown = sorted(set(truth or {}) - set(joints))
    if unknown:
        raise ValueError(f"truth names joints the {n_x} x {n_y} grid does not have: "
                         f"{', '.join(unknown)} (joints H{{i}}_{{j}} and V{{i}}_{{j}})")
    lx, ly = plate_size
    plates, boundaries = {}, []
    for j in range(1, n_y + 1):
        for i in range(1, n_x + 1):
            plates[f"P{i}_{j}"] = {"material": "steel", "thickness": thickness,
                                   "size": [lx, ly], "origin": [(i - 1) * lx, (j - 1) * ly]}
            for edge, outer in (("bottom", j == 1), ("right", i == n_x), ("top", j == n_y),
                                ("left", i == 1)):
                if outer:
                    boundaries.append({"edge": f"P{i}_{j}.{edge}",
                                       "condition": "simply_supported"})
    description = {
        "name": name or f"grid-{n_x}x{n_y}",
        "frequency": frequency,
        "materials": {"steel": {**STEEL, "loss_factor": loss_factor}},
        "plates": plates,
        "joints": {jid: {"between": _joint_sides(jid), "kind": "coplanar",
                         "log10_stiffness": log10_stiffness, "loss_factor": 0.0, "mass": 0.0}
                   for jid in joints},
        "boundaries": boundaries,
        "loads": [{"kind": "point_force", "plate": "P1_1", "at": list(force_at),
                   "amplitude": 1.0}],
        "measurement": {"spacing": spacing, "noise": noise, "seed": seed},
        "updating": {"r": 0.8, "bounds": [-1.0, 6.0]},
    }
    if resolution is not None:
        description["discretisation"] = {"resolution": resolution}
    if truth:
        description["truth"] = {"joints": {jid: {"log10_stiffness": value}
                                           for jid, value in truth.items()}}
    return description


def _value(value):
    """A TOML value: strings and booleans as TOML, floats by ``repr`` (they round-trip)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)  # a JSON string is a valid TOML basic string
    if isinstance(value, float) and not math.isfinite(value):
        return "inf" if value > 0 else "-inf" if value < 0 else "nan"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    raise TypeError(f"cannot write {type(value).__name__} {value!r} as a TOML value")


def _key(key):
    return key if key.replace("_", "").replace("-", "").isalnum() else json.dumps(key)


def _is_nested(value):
    """A sub-table or an array of tables (written under their own headers)."""
    return isinstance(value, Mapping) or (
        isinstance(value, list) and bool(value) and all(isinstance(v, Mapping) for v in value))


def _table_lines(table, path):
    """Lines of one table: its plain keys, then its sub-tables and arrays of tables."""
    lines = [f"{_key(k)} = {_value(v)}" for k, v in table.items() if not _is_nested(v)]
    for key, value in table.items():
        if not _is_nested(value):
            continue
        name = ".".join(_key(k) for k in (*path, key))
        if isinstance(value, Mapping):
            inner = _table_lines(value, (*path, key))
            # a table holding only tables needs no header of its own
            header = ["", f"[{name}]"] if any(not _is_nested(v) for v in value.values()) else []
            lines += header + inner
        else:
            for item in value:
                lines += ["", f"[[{name}]]", *_table_lines(item, (*path, key))]
    return lines


def description_toml(data: dict, header: str = "") -> str:
    """TOML text of a description dict, with ``header`` lines as ``#`` comments on top.

    ``tomllib.loads(description_toml(d)) == d`` for the descriptions of this module (and any
    dict of strings, numbers, booleans, lists of them, tables and arrays of tables).
    """
    comments = [f"# {line}".rstrip() for line in header.splitlines()]
    body = _table_lines(data, ())
    return "\n".join(comments + body).lstrip("\n") + "\n"
