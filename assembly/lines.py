"""Which junction lines move (``docs/method.md`` section 10.4): the rule shared by the
description's checks, its summary and the solver.

A junction line moves when ``held = false``, or by default (``held`` not given) when its member
plates are not coplanar. Its ends may meet a simply supported or clamped edge, a hinge or a
held line (their kinematic corners hold the line's ends, as the shear diaphragm of
folded-plate theory does), another moving line (the junction point where they meet translates
as one body: :func:`solver.layout.junction_point_axes`, ``docs/method.md`` section 6.4; the
wall's corners in ``cases/box_with_wall.toml``), a coplanar joint (a stiffener crossing a skin
joint: the point is the same) or a free edge (a junction point that nothing holds: it
translates freely in 3D). The members of a line that meets others or ends on a free edge reach
further with their edge waves (:data:`solver.problems.MEETING_END_REACH`,
:data:`solver.problems.FREE_END_REACH`).

By default a line stays held only where moving costs much more: where an end edge is in-plane
``roller`` (:math:`u_n = 0`, :math:`N_{nt} = 0`). There only the members' bending supports hold
the line's ends, under line loads that are log-singular at them (``docs/method.md`` section
10.4); with the usual rays refinement did not converge (2e-2 to 3e-1 between resolutions 1.5
and 2.25 on a three-bay panel), and the members' edge waves now reach
:data:`solver.problems.ROLLER_END_REACH` times further, at 10 to 100 times the cost: an L fold
then converges (5e-5, then 3e-7 to 2e-5), the panel's resolutions 1.5 and 2.25 agree to 6e-4
to 1.9e-3 at 1 kHz but only to 2.5e-3 to 1.5e-2 at 2.5 kHz. ``held = false`` moves such a line;
``vtcr check`` warns either way, of the cost or of what the held line leaves out, unless
``held = true`` is given (:func:`solver.guards.description_issues`).

``fixed`` ends, the default of a supported edge, converge since a moving line's functions stop
at what every member's rays answer (:func:`solver.joint_rules.interface_function_count`).
"""

from __future__ import annotations

from collections.abc import Collection, Iterable, Iterator, Mapping
from typing import Any

import numpy as np

from .geometry import EDGE_NAMES
from .joints import JunctionJoint
from .models import FRAME_TOLERANCE
from .types import EdgeId, parse_edge_ref

__all__ = ["members_coplanar", "given_in_plane", "free_ends", "roller_ends", "meeting_ends",
           "moving_lines"]


def members_coplanar(joint: JunctionJoint, plates: Mapping[str, Any]) -> bool:
    """Whether a junction's member plates lie in one plane (or have no frames: a flat layout):
    their normals parallel to the frames' own tolerance,
    :data:`assembly.models.FRAME_TOLERANCE`."""
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


def given_in_plane(boundaries: Iterable[Any]) -> dict[EdgeId, str]:
    """The in-plane conditions ``boundaries`` give (their ``in_plane``, where set), by edge."""
    return {parse_edge_ref(bc.edge): bc.in_plane for bc in boundaries if bc.in_plane is not None}


def free_ends(joint: JunctionJoint, conditions: Mapping[EdgeId, str]) -> list[EdgeId]:
    """The edges at the line's ends that are free (``conditions``: every edge's, as
    :meth:`assembly.Case.edge_conditions` gives them): where nothing holds the line's end
    (module notes)."""
    return [edge for edge in _end_edges(joint) if conditions[edge] == "free"]


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
                 in_plane: Mapping[EdgeId, str]) -> tuple[str, ...]:
    """The junction lines that move, in the description's order: ``held = false``, or by
    default non-coplanar members and no in-plane ``roller`` end (module notes); ``in_plane``
    holds the boundaries' given in-plane conditions by edge."""
    return tuple(jid for jid, joint in joints.items() if isinstance(joint, JunctionJoint) and (
        joint.held is False
        or (joint.held is None and not members_coplanar(joint, plates)
            and not roller_ends(joint, in_plane))))
