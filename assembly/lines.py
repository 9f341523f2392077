"""Which junction lines move (``docs/method.md`` section 10.4): the rule shared by the
description's checks and the solver.

A junction line moves when its description says ``held = false``; by default it is held. A
moving line needs its ends held: each member edge must meet a simply supported or clamped
edge, a hinge or a held line, whose corners then hold the line's ends, as the shear diaphragm of
folded-plate theory does. Lines that meet other moving lines at their ends (the corners of a
box), end on free edges, or share a plate with a coplanar joint (which carries no in-plane
continuity) are not modelled yet.

Why not moving by default between non-coplanar plates (the aim): with in-plane ``roller``
ends (:math:`u_n = 0`, :math:`N_{nt} = 0`) refinement does not converge (2e-2 to 3e-1 between
resolutions 1.5 and 2.25 on a three-bay panel, one line or two), for a reason not found yet.
``fixed`` ends, the default of a supported edge, once failed too with two or more lines (order
1 at 2.5 kHz): the lines' functions went beyond what the stiffeners' rays answer, a near-null
direction of the interface problem per function; they now stop there
(:func:`solver.joint_rules.interface_function_count`, ``docs/method.md`` section 10.4) and
converge (2e-6 to 8e-5 from 1 to 2.5 kHz). Until ``roller`` is understood a held line stays the
default; ``vtcr solve --tolerance`` reports the non-convergence of a moving one.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import Any

from .geometry import EDGE_NAMES
from .joints import JunctionJoint
from .types import EdgeId

__all__ = ["unheld_ends", "moving_lines"]


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


def moving_lines(joints: Mapping[str, Any]) -> tuple[str, ...]:
    """The junction lines that move (``held = false``), in the description's order."""
    return tuple(jid for jid, joint in joints.items()
                 if isinstance(joint, JunctionJoint) and joint.held is False)
