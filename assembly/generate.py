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

__all__ = ["plate_grid", "grid_joint_ids", "stiffened_panel", "box_with_wall",
           "description_toml"]

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


def _description(name, frequency, loss_factor, plates, joints, boundaries, force,
                 measurement, resolution, truth_joints):
    """A generated description: steel plates of ``loss_factor``, one unit point force
    ``(plate, at)``, the default (scale-free) weights and bounds [-1, 6]; ``frequency`` one
    value or a sequence (``frequencies``); no ``boundaries`` table when ``boundaries`` is None, no
    ``[discretisation]`` when ``resolution`` is None, no ``[truth]`` without ``truth_joints``.
    The keys are in the order the generated case files hold them."""
    description = {
        "name": name,
        **({"frequencies": list(frequency)} if isinstance(frequency, (list, tuple))
           else {"frequency": frequency}),
        "materials": {"steel": {**STEEL, "loss_factor": loss_factor}},
        "plates": plates,
        "joints": joints,
        **({} if boundaries is None else {"boundaries": boundaries}),
        "loads": [{"kind": "point_force", "plate": force[0], "at": list(force[1]),
                   "amplitude": 1.0}],
        "measurement": measurement,
        "updating": {"bounds": [-1.0, 6.0]},
    }
    if resolution is not None:
        description["discretisation"] = {"resolution": resolution}
    if truth_joints:
        description["truth"] = {"joints": truth_joints}
    return description


def _check_truth(truth, names, what, hint):
    """A ValueError naming the ``truth`` entries that are not in ``names`` (``what`` and
    ``hint`` say what the generated description has)."""
    unknown = sorted(set(truth or {}) - set(names))
    if unknown:
        raise ValueError(f"truth names {what} does not have: {', '.join(unknown)} ({hint})")


def _framed_plate(size, origin, x_axis, y_axis, thickness):
    """A steel plate placed in space by its frame."""
    return {"material": "steel", "thickness": thickness, "size": list(size),
            "frame": {"origin": list(origin), "x_axis": list(x_axis), "y_axis": list(y_axis)}}


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
    _check_truth(truth, joints, f"joints the {n_x} x {n_y} grid",
                 "joints H{i}_{j} and V{i}_{j}")
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
    return _description(
        name or f"grid-{n_x}x{n_y}", frequency, loss_factor, plates,
        {jid: {"between": _joint_sides(jid), "kind": "coplanar",
               "log10_stiffness": log10_stiffness, "loss_factor": 0.0, "mass": 0.0}
         for jid in joints},
        boundaries, ("P1_1", force_at), {"spacing": spacing, "noise": noise, "seed": seed},
        resolution, {jid: {"log10_stiffness": value} for jid, value in (truth or {}).items()})



def stiffened_panel(n_bays: int, *, bay_size=(0.5, 0.4), stiffener_height=0.15,
                    thickness=0.001, stiffener_thickness=0.002, frequency=250.0,
                    loss_factor=0.01, log10_stiffness=2.0, truth=None, force_at=(0.17, 0.13),
                    spacing=0.1, noise=0.1, seed=1, resolution=None, name=None) -> dict:
    """A skin of ``n_bays`` bays in the x-y plane with a stiffener welded on every inner bay
    line, standing along +z.

    Bays ``B{i}`` (``bay_size`` and ``thickness``, origin ``[(i-1) Lx, 0, 0]``, axes x, y)
    and stiffeners ``T{i}`` (``stiffener_height x Ly``, ``stiffener_thickness``, origin
    ``[i Lx, 0, 0]``, x_axis +z, y_axis +y: their local ``x`` runs up from the skin and their
    normal is -x), ``i = 1..n_bays - 1``. Weld ``W{i}`` is the junction
    ``B{i}.right | B{i+1}.left | T{i}.left``: the skin continuous (its two members rigid) and
    the stiffener tied by a rotational spring of ``log10_stiffness``. Every skin edge on the
    panel's outline and the stiffeners' ends (``y = 0, Ly``) simply supported, the
    stiffeners' top edges free; a unit point force in ``B1`` at ``force_at``; the
    measurement grid on the skin only (a laser vibrometer sees one face).

    Parameters
    ----------
    frequency : float or sequence of float
        Hz; a sequence gives ``frequencies``.
    truth : mapping of str to float, optional
        ``{weld: log10_stiffness of its stiffener}`` of the simulated experiment.

    Returns
    -------
    dict
        A description for :func:`assembly.parse_case` or :func:`description_toml`.

    Raises
    ------
    ValueError
        For fewer than two bays, or a ``truth`` weld the panel does not have.
    """
    if n_bays < 2:
        raise ValueError(f"a stiffened panel needs at least 2 bays, got {n_bays}")
    welds = [f"W{i}" for i in range(1, n_bays)]
    _check_truth(truth, welds, f"welds the {n_bays}-bay panel", f"welds W1..W{n_bays - 1}")
    lx, ly = bay_size
    along_y = (0.0, 1.0, 0.0)
    plates = {f"B{i}": _framed_plate(bay_size, ((i - 1) * lx, 0.0, 0.0), (1.0, 0.0, 0.0),
                                     along_y, thickness)
              for i in range(1, n_bays + 1)}
    plates.update({f"T{i}": _framed_plate((stiffener_height, ly), (i * lx, 0.0, 0.0),
                                          (0.0, 0.0, 1.0), along_y, stiffener_thickness)
                   for i in range(1, n_bays)})
    supported = ["B1.left", f"B{n_bays}.right"]
    supported += [f"{p}.{e}" for p in plates for e in ("bottom", "top")]
    welds = {f"W{i}": {"kind": "junction",
                       "between": [f"B{i}.right", f"B{i + 1}.left", f"T{i}.left"],
                       "log10_stiffness": {f"B{i}": math.inf, f"B{i + 1}": math.inf,
                                           f"T{i}": log10_stiffness},
                       "loss_factor": 0.0}
             for i in range(1, n_bays)}
    return _description(
        name or f"stiffened-panel-{n_bays}", frequency, loss_factor, plates, welds,
        [{"edge": edge, "condition": "simply_supported"} for edge in supported],
        ("B1", force_at), {"spacing": spacing, "noise": noise, "seed": seed,
                           "plates": [f"B{i}" for i in range(1, n_bays + 1)]},
        resolution, {weld: {"log10_stiffness": {f"T{weld[1:]}": value}}
                     for weld, value in (truth or {}).items()})


def _edge_ends(plate, edge):
    """The 3D ends of a framed plate's edge, counter-clockwise in its local frame, rounded
    to 1e-9 m so that shared edges compare equal."""
    lx, ly = plate["size"]
    corners = {"bottom": ((0, 0), (lx, 0)), "right": ((lx, 0), (lx, ly)),
               "top": ((lx, ly), (0, ly)), "left": ((0, ly), (0, 0))}[edge]
    frame = plate["frame"]
    return tuple(tuple(round(o + x * a + y * b, 9) for o, a, b in
                       zip(frame["origin"], frame["x_axis"], frame["y_axis"]))
                 for x, y in corners)


def _shared_edges(plates):
    """Edges of framed plates that coincide in space, grouped: ``[[\"P.edge\", ...], ...]``
    in plate order."""
    groups = {}
    for name, plate in plates.items():
        for edge in ("bottom", "right", "top", "left"):
            key = frozenset(_edge_ends(plate, edge))
            groups.setdefault(key, []).append(f"{name}.{edge}")
    return [members for members in groups.values() if len(members) > 1]


def box_with_wall(*, size=(0.5, 0.4, 0.3), wall_at=0.3, thickness=0.001,
                  wall_thickness=0.001, frequency=250.0, loss_factor=0.01,
                  fold_log10_stiffness=2.0, weld_log10_stiffness=3.0, truth=None,
                  force_at=(0.17, 0.13), spacing=0.1, noise=0.05, seed=1, resolution=None,
                  held_folds=False, name="box-with-wall") -> dict:
    """A closed box ``[0, a] x [0, b] x [0, c]`` with an inner wall at ``x = wall_at``
    welded to the four faces it meets.

    Every face's frame puts ``w`` along its outward normal (edges counter-clockwise), so that
    each fold's two edges run opposite ways. The wall splits the top, bottom, front and back
    faces in two (``Top1 | Top2`` ...); ``Left``, ``Right`` and the wall ``Wall`` (normal +x)
    are whole. Folds (two edges meeting at 90 degrees) are hinges of
    ``fold_log10_stiffness``, which move as framed hinges do by default (with
    ``held_folds``, ``held = true`` holds them in translation, the model of
    ``closed_box.toml``); the four lines where the wall meets a face are T-junctions
    ``W_top``, ``W_bottom``, ``W_front``, ``W_back``: the face continuous (its two members
    rigid) and the wall tied by a spring of ``weld_log10_stiffness``. A unit point
    force on ``Top1`` at ``force_at``; the measurement grid on every outer face (not the wall,
    which a vibrometer cannot see).

    Parameters
    ----------
    truth : mapping of str to float, optional
        ``{joint: log10 k}``: a fold's stiffness, or a weld's wall member.
    held_folds : bool
        Write ``held = true`` on the folds (lines held in translation, as the case was
        before its folds moved).

    Returns
    -------
    dict
        A description for :func:`assembly.parse_case` or :func:`description_toml`.
    """
    a, b, c = size
    if not 0.0 < wall_at < a:
        raise ValueError(f"wall_at must lie inside (0, {a}), got {wall_at}")
    x, y, z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
    minus = {x: (-1.0, 0.0, 0.0), y: (0.0, -1.0, 0.0)}
    faces = {}  # name: (size, origin, x_axis, y_axis)
    for part, (x0, lx) in (("1", (0.0, wall_at)), ("2", (wall_at, a - wall_at))):
        faces["Top" + part] = ((lx, b), (x0, 0.0, c), x, y)
        faces["Bottom" + part] = ((lx, b), (x0, b, 0.0), x, minus[y])
        faces["Front" + part] = ((lx, c), (x0, 0.0, 0.0), x, z)
        faces["Back" + part] = ((lx, c), (x0 + lx, b, 0.0), minus[x], z)
    faces["Left"] = ((b, c), (0.0, b, 0.0), minus[y], z)
    faces["Right"] = ((b, c), (a, 0.0, 0.0), y, z)
    faces["Wall"] = ((b, c), (wall_at, 0.0, 0.0), y, z)
    plates = {n: _framed_plate(*face, wall_thickness if n == "Wall" else thickness)
              for n, face in faces.items()}
    joints = {}
    for members in _shared_edges(plates):
        owners = [m.split(".")[0] for m in members]
        if "Wall" in owners and len(members) == 3:
            face = next(o for o in owners if o != "Wall").rstrip("12").lower()
            joints[f"W_{face}"] = {
                "kind": "junction", "between": members, "loss_factor": 0.0,
                "log10_stiffness": {o: (weld_log10_stiffness if o == "Wall" else math.inf)
                                    for o in owners}}
        else:
            fold = {"kind": "hinge", "between": members,
                    "log10_stiffness": fold_log10_stiffness, "loss_factor": 0.0}
            joints["_".join(o.lower() for o in owners)] = fold | (
                {"held": True} if held_folds else {})
    _check_truth(truth, joints, "joints the box", f"joints: {', '.join(joints)}")
    return _description(
        name, frequency, loss_factor, plates, joints, None, ("Top1", force_at),
        {"spacing": spacing, "noise": noise, "seed": seed,
         "plates": [n for n in plates if n != "Wall"]},
        resolution, {jid: {"log10_stiffness": {"Wall": value} if jid.startswith("W_") else value}
                     for jid, value in (truth or {}).items()})

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
