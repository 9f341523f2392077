r"""A summary of an assembly for ``vtcr check``: plates, edges, joints, loads and graph.

:func:`summarise` returns a renderable and prints nothing; the CLI prints it.  With rich
installed it is a :class:`rich.console.Group` of tables, otherwise (or with
``style="text"``) a plain string.  The bending wavelength of each plate is

.. math:: \lambda = 2\pi / \kappa_0, \qquad \kappa_0^4 = \rho h \omega^2 / D, \qquad
          D = E h^3 / (12 (1 - \nu^2)),

and "wavelengths across" is ``Lx / lambda x Ly / lambda``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

from .case import Case
from .graph import build_graph, components, plate_degrees
from .joints import CoplanarJoint, Joint
from .lines import free_ends, given_supports, meeting_ends
from .models import PointForce
from .types import EDGE_NAMES, EdgeId

__all__ = ["summarise", "summary_text"]

_MAX_FREQUENCY_COLUMNS = 3


@dataclass(frozen=True)
class _Section:
    title: str
    columns: tuple[str, ...]
    rows: list[tuple[str, ...]] = field(default_factory=list)


def _complex(z: complex) -> str:
    if z.imag == 0.0:
        return f"{z.real:g}"
    sign = "+" if z.imag >= 0 else "-"
    return f"{z.real:g} {sign} {abs(z.imag):g}j"


def _shown_frequencies(case: Case) -> list[float]:
    freqs = list(case.frequencies or ())
    if len(freqs) <= _MAX_FREQUENCY_COLUMNS:
        return freqs
    return [min(freqs), max(freqs)]


def _header(case: Case) -> list[str]:
    freqs = case.frequencies or ()
    shown = ", ".join(f"{f:g}" for f in freqs[:8]) + (", ..." if len(freqs) > 8 else "")
    noun = "frequency" if len(freqs) == 1 else f"{len(freqs)} frequencies"
    return [
        f"Assembly {case.name!r}: {len(case.plates)} plate(s), {len(case.joints)} joint(s), "
        f"{len(case.loads)} load(s); {noun}: {shown} Hz"
    ]


def _per_member(value: float | Mapping[str, float]) -> str:
    """A joint parameter: one number, or a junction's ``plate value`` table."""
    if isinstance(value, Mapping):
        return ", ".join(f"{plate} {v:g}" for plate, v in value.items())
    return f"{value:g}"


def _sections(case: Case) -> list[_Section]:
    degrees = plate_degrees(build_graph(case))
    freqs = _shown_frequencies(case)

    plates = _Section(
        "Plates",
        ("plate", "material", "Lx x Ly (m)", "h (mm)", "joints")
        + tuple(f"lambda @ {f:g} Hz (m, across)" for f in freqs),
    )
    for pid, plate in case.plates.items():
        material = case.materials[plate.material]
        cells = []
        for f in freqs:
            lam = material.bending_wavelength(plate.thickness, f)
            cells.append(f"{lam:.3g} ({plate.lx / lam:.1f} x {plate.ly / lam:.1f})")
        plates.rows.append(
            (
                pid,
                plate.material,
                f"{plate.lx:g} x {plate.ly:g}",
                f"{plate.thickness * 1e3:g}",
                str(degrees.get(pid, 0)),
                *cells,
            )
        )

    conditions = case.edge_conditions()
    joined = case.edge_joints()
    moving = set(case.moving_lines())
    in_plane = {key: bc.in_plane_condition for bc in case.boundaries
                for key in [case.edge(bc.edge)]}
    members = {p for jid in moving for p in case.joints[jid].plates}
    title = "Edges (joint id or condition" + ("; in-plane condition of the plates with "
                                              "in-plane waves)" if members else ")")
    edges = _Section(title, ("plate", *EDGE_NAMES))
    for pid in case.plates:
        keys = [EdgeId(pid, name) for name in EDGE_NAMES]
        edges.rows.append((pid, *(_edge_cell(key, joined, conditions, in_plane, pid in members)
                                  for key in keys)))

    supports = given_supports(case.boundaries)
    joints = _Section(
        "Joints", ("joint", "kind", "between", "log10 k", "zeta", "mu (kg/m)", "length (m)")
    )
    for jid, joint in case.joints.items():
        joints.rows.append(
            (
                jid,
                _joint_kind(joint, jid in moving,
                            _line_ends(case, jid, conditions, supports, joined, moving)
                            if jid in moving else ""),
                " - ".join(joint.between),
                _per_member(joint.log10_stiffness),
                _per_member(joint.loss_factor),
                f"{joint.mass:g}" if isinstance(joint, CoplanarJoint) else "-",
                f"{case.edge_length(joint.between[0]):g}",
            )
        )

    loads = _Section("Loads", ("#", "kind", "where", "amplitude", "distribution"))
    for i, load in enumerate(case.loads):
        if isinstance(load, PointForce):
            where = f"{load.plate} at ({load.at[0]:g}, {load.at[1]:g}) m"
            loads.rows.append((str(i), load.kind, where, f"{_complex(load.amplitude)} N", "-"))
        else:
            unit = "N/m" if load.kind == "edge_shear" else "N·m/m"
            loads.rows.append(
                (str(i), load.kind, load.edge, f"{_complex(load.amplitude)} {unit}",
                 load.distribution)
            )
    return [s for s in (plates, edges, joints, loads) if s.rows]


def _joint_kind(joint: Joint, moving: bool, ends: str = "") -> str:
    """A joint's kind cell: a line's (junction or hinge) moving or held, what its ends are
    where that sets how its loads converge (``ends``: :func:`_line_ends`), and a junction's
    members' translational springs (log10 k_t, N/m^2) where it has any."""
    if joint.kind == "coplanar":
        return joint.kind
    springs = ", ".join(f"{p} {joint.member_log10_translational_stiffness(p):g}"
                        for p in joint.translational_springs())
    return (f"{joint.kind} ({'moving' if moving else 'held'}" + (f"; {ends}" if ends else "")
            + (f"; log10 k_t {springs}" if springs else "") + ")")


def _line_ends(case: Case, joint_id: str, conditions: Mapping[EdgeId, str],
               supports: Mapping[EdgeId, tuple[str, str]], joined: Mapping[EdgeId, str],
               moving: set[str]) -> str:
    """What a moving line's ends are where they slow its loads' convergence and raise its
    cost (``docs/method.md`` section 10.4): ``"ends free to slide, pinned; T1 hangs"``, say,
    or empty. Free to slide: on a free edge or one free in its plane; pinned: a member's
    corner held across the line by another member's support; meeting other moving lines;
    mixed: a plane of symmetry for part of the motion only. At pinned or mixed ends the members
    that hang on the line (held across it in their plane by nothing else) are named: they set
    the line's rule there. ``conditions``, ``supports``, ``joined`` and ``moving``: the
    assembly's edge conditions, given supports, joined edges and moving lines, found once for
    all its lines."""
    joint = case.joints[joint_id]
    kinds = [name for name, present in (
        ("free to slide", free_ends(joint, conditions, supports)),
        ("pinned", case.pinned_ends(joint_id)),
        ("meeting other lines", meeting_ends(joint, joined, moving)),
        ("mixed", case.singular_ends(joint_id))) if present]
    hanging = (case.hanging_members(joint_id) if {"pinned", "mixed"} & set(kinds) else [])
    return (f"ends {', '.join(kinds)}" if kinds else "") + (
        f"; {', '.join(hanging)} {'hangs' if len(hanging) == 1 else 'hang'}" if hanging else "")


def _edge_cell(key: EdgeId, joined: dict[EdgeId, str], conditions: dict[EdgeId, str],
               in_plane: dict[EdgeId, str], with_in_plane: bool) -> str:
    """An edge's joint, or its condition, with its in-plane condition on a plate that carries
    in-plane waves (a member of a moving line)."""
    if key in joined:
        return joined[key]
    cell = conditions[key].replace("_", " ")
    if with_in_plane:  # an edge without a boundary is free, in-plane too
        cell += f", in-plane {in_plane.get(key, 'free')}"
    return cell


def _notes(case: Case) -> list[str]:
    graph = build_graph(case)
    groups = components(graph)
    notes = []
    if len(groups) == 1:
        notes.append(
            f"Graph: connected ({graph.number_of_nodes()} plate(s), "
            f"{len(case.joints)} joint(s))."
        )
    else:
        listed = "; ".join("{" + ", ".join(g) + "}" for g in groups)
        notes.append(
            f"Graph: NOT connected, {len(groups)} sub-assemblies: {listed} "
            "(allowed; each sub-assembly responds independently)."
        )
    if not case.loads:
        notes.append("No loads: the forced response is zero.")
    if case.truth.joints:
        true = "; ".join(
            f"{jid}: " + ", ".join(f"{k}={_per_member(v)}" for k, v in t.changes().items())
            for jid, t in case.truth.joints.items()
        )
        notes.append(f"Truth (simulated experiment): {true}.")
    unused = sorted(set(case.materials) - {p.material for p in case.plates.values()})
    if unused:
        notes.append(f"Unused materials: {', '.join(unused)}.")
    return notes


def _text_table(section: _Section) -> list[str]:
    rows = [section.columns, *section.rows]
    widths = [max(len(r[i]) for r in rows) for i in range(len(section.columns))]
    lines = [section.title]
    for k, row in enumerate(rows):
        lines.append("  " + "  ".join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip())
        if k == 0:
            lines.append("  " + "  ".join("-" * w for w in widths))
    return lines


def summary_text(case: Case) -> str:
    """Return the summary of an assembly as plain text.

    Parameters
    ----------
    case : Case
        A validated assembly.

    Returns
    -------
    str
        Header line, tables (plates with bending wavelengths, edges, joints, loads) and
        notes on the graph (connected components), one item per line.

    Examples
    --------
    >>> from assembly import load_case
    >>> print(summary_text(load_case("cases/single_plate.toml")).splitlines()[0])
    Assembly 'single-plate': 1 plate(s), 0 joint(s), 1 load(s); frequency: 155 Hz
    """
    lines = _header(case)
    for section in _sections(case):
        lines += ["", *_text_table(section)]
    lines += ["", *_notes(case)]
    return "\n".join(lines)


def summarise(case: Case, *, style: Literal["auto", "rich", "text"] = "auto") -> Any:
    """Summarise an assembly for ``vtcr check``; prints nothing.

    Parameters
    ----------
    case : Case
        A validated assembly.
    style : {"auto", "rich", "text"}, optional
        ``"rich"``: a :class:`rich.console.Group` of :class:`rich.table.Table`;
        ``"text"``: the plain string of :func:`summary_text`; ``"auto"`` (default): rich if
        it is installed, else text.

    Returns
    -------
    rich.console.Group or str
        Print it with ``rich.console.Console().print(...)`` or ``print(...)``.

    Raises
    ------
    ModuleNotFoundError
        If ``style="rich"`` and rich is not installed.

    Examples
    --------
    >>> from assembly import load_case
    >>> text = summarise(load_case("cases/single_plate.toml"), style="text")
    >>> "lambda @ 155 Hz" in text
    True
    """
    if style == "text":
        return summary_text(case)
    try:
        from rich.console import Group
        from rich.table import Table
        from rich.text import Text
    except ModuleNotFoundError:
        if style == "rich":
            raise
        return summary_text(case)
    parts: list[Any] = [Text(line, style="bold") for line in _header(case)]
    for section in _sections(case):
        table = Table(title=section.title, title_justify="left")
        for column in section.columns:
            table.add_column(column, overflow="fold")
        for row in section.rows:
            table.add_row(*(Text(cell) for cell in row))  # Text: no markup parsing of ids
        parts.append(table)
    parts += [Text(line) for line in _notes(case)]
    return Group(*parts)
