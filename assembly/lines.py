"""Which junction lines move (``docs/method.md`` section 10.4): the rule shared by the
description's checks, its summary and the solver.

A junction line moves when ``held = false``, or by default (``held`` not given) when its member
plates are not coplanar and its ends are held. An end is held where each member edge meets a
simply supported or clamped edge, a hinge, a held line, or another moving line: the corners
then hold the line's ends, as the shear diaphragm of folded-plate theory does, or the junction
point where moving lines meet translates as one body (:func:`solver.layout.junction_point_axes`,
``docs/method.md`` section 6.4; the wall's corners in ``cases/box_with_wall.toml``). The
members of lines that meet reach further with their edge waves
(:data:`solver.problems.MEETING_END_REACH`). By default a line stays held:

* where an end meets a free edge or a coplanar joint: refused with ``held = false``;
* where moving costs much more: an end edge is in-plane ``roller`` (:math:`u_n = 0`,
  :math:`N_{nt} = 0`). There only the members' bending supports hold the line's ends, under
  line loads that are log-singular at them (``docs/method.md`` section 10.4); with the usual
  rays refinement did not converge (2e-2 to 3e-1 between resolutions 1.5 and 2.25 on a
  three-bay panel), and the members' edge waves now reach
  :data:`solver.problems.ROLLER_END_REACH` times further, at 10 to 100 times the cost: an L
  fold then converges (5e-5, then 3e-7 to 2e-5), the panel's resolutions 1.5 and 2.25 agree
  to 6e-4 to 1.9e-3 at 1 kHz but only to 2.5e-3 to 1.5e-2 at 2.5 kHz. By default such a line
  therefore stays held; ``held = false`` moves it, and ``vtcr check`` warns
  (:func:`solver.guards.description_issues`).

``fixed`` ends, the default of a supported edge, converge since a moving line's functions stop
at what every member's rays answer (:func:`solver.joint_rules.interface_function_count`).
"""

from __future__ import annotations

from collections.abc import Collection, Iterator, Mapping
from typing import Any

import numpy as np

from .geometry import EDGE_NAMES
from .joints import JunctionJoint
from .models import FRAME_TOLERANCE
from .types import EdgeId

__all__ = ["members_coplanar", "unheld_ends", "roller_ends", "meeting_ends", "moving_lines"]


def members_coplanar(joint: JunctionJoint, plates: Mapping[str, Any]) -> bool:
    """Whether a junction's member plates lie in one plane (or have no frames: a flat layout):
    their normals parallel to the frames' own tolerance, :data:`assembly.models.FRAME_TOLERANCE`."""
    frames = [getattr(plates.get(p), "frame", None) for p in joint.plates]
    if any(frame is None for frame in frames):
        return True
    first = frames[0].normal
    return all(np.linalg.norm(np.cross(first, f.normal)) < FRAME_TOLERANCE
               for f in frames[1:])


def _end_edges(joint: JunctionJoint) -> Iterator[EdgeId]:
    """The edges that meet the line's ends: each member edge's two neighbours."""
    for side in joint.sides:
        index = EDGE_NAMES.index(side.edge)
        for neighbour in (EDGE_NAMES[index - 1], EDGE_NAMES[(index + 1) % 4]):
            yield EdgeId(side.plate, neighbour)


def unheld_ends(joint: JunctionJoint, conditions: Mapping[EdgeId, str],
                holding: Mapping[EdgeId, bool]) -> list[EdgeId]:
    """The edges at the line's ends that do not hold it: neither simply supported nor clamped
    (``conditions``, the boundaries' conditions by edge) nor on a joint that holds its line
    (``holding``: by joined edge, whether its joint is a hinge or a held junction)."""
    return [edge for edge in _end_edges(joint)
            if conditions.get(edge) not in ("simply_supported", "clamped")
            and not holding.get(edge, False)]


def roller_ends(joint: JunctionJoint, in_plane: Mapping[EdgeId, str]) -> list[EdgeId]:
    """The edges at the line's ends whose given in-plane condition (``in_plane``, by edge) is
    ``roller``: where the members' bending supports alone hold the line's ends (module
    notes)."""
    return [edge for edge in _end_edges(joint) if in_plane.get(edge) == "roller"]


def meeting_ends(joint: JunctionJoint, line_of: Mapping[EdgeId, str],
                 moving: Collection[str]) -> list[EdgeId]:
    """The edges at the line's ends that lie on other ``moving`` lines (``line_of``: the joint
    of each joined edge): the junction points where moving lines meet (module notes)."""
    return [edge for edge in _end_edges(joint) if line_of.get(edge) in moving]


def moving_lines(joints: Mapping[str, Any], plates: Mapping[str, Any],
                 conditions: Mapping[EdgeId, str],
                 in_plane: Mapping[EdgeId, str]) -> tuple[str, ...]:
    """The junction lines that move, in the description's order: ``held = false``, or by
    default non-coplanar members and held ends (module notes); ``conditions`` and ``in_plane``
    are the boundaries' bending and given in-plane conditions by edge.

    The default is found by elimination: a line with an end that nothing can hold (a free
    edge) is held, which may hold the ends of others; what remains moves, lines whose ends
    meet other moving lines included (junction points, module notes)."""
    joints = {jid: j for jid, j in joints.items() if j is not None}  # the valid ones
    junctions = {jid: j for jid, j in joints.items() if isinstance(j, JunctionJoint)}
    moving = {jid for jid, j in junctions.items() if j.held is False}
    line_of = {side: jid for jid, joint in joints.items() for side in joint.sides}
    undecided = {jid for jid, j in junctions.items()
                 if j.held is None and not members_coplanar(j, plates)
                 and not roller_ends(j, in_plane)}

    def holding(lines: set[str]) -> dict[EdgeId, bool]:
        return {side: jid not in lines and getattr(joints[jid], "kind", "") != "coplanar"
                for side, jid in line_of.items()}

    while True:
        held_by = holding(undecided | moving)
        free_ends = {jid for jid in undecided
                     if any(line_of.get(edge) not in undecided
                            for edge in unheld_ends(junctions[jid], conditions, held_by))}
        if not free_ends:
            break
        undecided -= free_ends
    moving |= undecided
    return tuple(jid for jid in joints if jid in moving)
