r"""Which junction lines move (``docs/method.md`` section 10.4): the rule shared by the
description's checks, its summary and the solver.

A junction line moves when ``held = false``, or by default (``held`` not given) when its member
plates are not coplanar. Its ends may meet a simply supported or clamped edge, a hinge or a
held line (their kinematic corners hold the line's ends, as the shear diaphragm of
folded-plate theory does), another moving line (the junction point where they meet translates
as one body: :func:`solver.layout.junction_point_axes`, ``docs/method.md`` section 6.4; the
wall's corners in ``cases/box_with_wall.toml``), a coplanar joint (a stiffener crossing a skin
joint: the point is the same) or a free edge (a junction point that nothing holds: it
translates freely in 3D). The members of a line that meets others or ends on an edge free in
its plane (a free edge, or a supported one with ``in_plane = "free"``: the end slides along the
line) reach further with their edge waves (:data:`solver.line_ends.MEETING_END_REACH`,
:data:`solver.line_ends.FREE_END_REACH`).

By default a line stays held only where its ends are a plane of symmetry for part of the
motion and not for the rest (:func:`singular_ends`). A ``roller`` edge (:math:`u_n = 0`,
:math:`N_{nt} = 0`) is the in-plane half of a plane of symmetry, a ``symmetric`` edge
(:math:`\partial_n w = 0`, :math:`K_n = 0`) its bending half; ``diaphragm`` with
``simply_supported`` is a plane of antisymmetry. Where every member's end edge is both halves
(the structure's own plane of symmetry) or neither, the fields continue smoothly across the
plane and the line converges as elsewhere. Where the halves are mixed (a ``roller`` edge
simply supported in bending, say), the line's translation along one member's in-plane normal,
even across the plane, is another member's deflection, odd across it: the line's data have a
kink at the end and its loads are log-singular there (``docs/method.md`` section 10.4). With
the usual rays refinement did not converge (2e-2 to 3e-1 between resolutions 1.5 and 2.25 on a
three-bay panel with roller ends); the members of a moving line with such an end carry
logarithmic corner functions there and reach further with their edge waves
(:func:`solver.line_ends.singular_end_corners`, :data:`solver.line_ends.SINGULAR_END_REACH`), and
the line's load functions gain the loads' logarithmic terms at that end
(:func:`singular_line_ends`, :func:`solver.joint_rules.load_function_values`), at 30 to 50
times the cost of the held line. ``held = false`` moves such a line; ``vtcr check``
warns either way, of the cost or of what the held line leaves out, unless ``held = true`` is
given (:func:`solver.guards.description_issues`). Its warning names the members that *hang* on
the line (:func:`hanging_members`): held across the line in their plane by no boundary edge of
their own, as a stiffener with a free top and ``roller`` ends is. With mixed ends the line's
end holds such a member only at a point, through another member's bending support, and
refinement converges more slowly (an L fold at 1.2 kHz, ``bench/bench_roller_ends.py
--hanging``: 1.1e-3 between resolutions 2.25 and 3.4; the same fold held across the line,
4.5e-7).

``fixed`` ends, the default of a supported edge, converge since a moving line's functions stop
at what every member's rays answer (:func:`solver.joint_rules.interface_function_count`).

An end *pins* a member at its corner (:func:`pinned_ends`) where the member's end edge leaves
its in-plane displacement across the line free (a free edge, ``free`` or ``roller`` in plane)
and another member's end edge, not coplanar with it, holds that member's deflection
(``simply_supported`` or ``clamped``): the line ties the two, so the first member is held
across the line at one point, its corner, and the line's load is concentrated there (a
stiffener free at its ends on a supported skin; each member of a fold whose ends slide). The
members of such a line, if it meets no other and not every member hangs on it
(:func:`hanging_members`), carry the mixed ends' logarithmic families at those corners and
reach as at a free end, up to :data:`solver.line_ends.PINNED_END_REACH` (``docs/method.md``
section 10.4, *Pinned ends*).
"""

from __future__ import annotations

import math
from collections.abc import Collection, Iterable, Iterator, Mapping
from typing import Any

from .geometry import EDGE_NAMES
from .joints import HingeJoint, JunctionJoint
from .models import FRAME_TOLERANCE, cross
from .types import EdgeId, parse_edge_ref

__all__ = ["LINE_JOINTS", "members_coplanar", "continuing_members", "member_directions",
           "given_supports",
           "free_ends", "held_ends", "pinned_ends", "line_ends", "symmetry_halves",
           "singular_ends", "singular_line_ends", "hanging_members", "meeting_ends",
           "line_moves", "moving_lines"]

SYMMETRY_PLANE = ("symmetric", "roller")
"""The bending and in-plane conditions of an edge on a plane of symmetry of the structure."""


def members_coplanar(joint: JunctionJoint, plates: Mapping[str, Any]) -> bool:
    """Whether a junction's member plates lie in one plane (or have no frames: a flat layout):
    their normals parallel to the frames' own tolerance,
    :data:`assembly.models.FRAME_TOLERANCE`."""
    frames = [getattr(plates.get(p), "frame", None) for p in joint.plates]
    if any(frame is None for frame in frames):
        return True
    return all(_parallel(frames[0], frame) for frame in frames[1:])


def continuing_members(joint: JunctionJoint, plates: Mapping[str, Any]
                       ) -> tuple[int | None, ...]:
    """For each member of a line, the index of the member that continues it in its plane across
    the line (their edges' in-plane normals opposite: a skin's two bays), or None."""
    normals = [plates[side.plate].edge_in_space(side.edge)[2] for side in joint.sides]
    return tuple(next((j for j in range(len(normals))
                       if j != i and float(normals[i] @ normals[j]) < -1.0 + 1e-9), None)
                 for i in range(len(normals)))


def _parallel(first: Any, second: Any) -> bool:
    """Whether two plate frames' normals are parallel, to
    :data:`assembly.models.FRAME_TOLERANCE`."""
    return bool(math.hypot(*cross(first.normal, second.normal)) < FRAME_TOLERANCE)


def _neighbours(side: EdgeId) -> tuple[EdgeId, EdgeId]:
    """The edges of ``side``'s plate that meet its start and its end (edge ``i`` runs from
    corner ``i`` to corner ``i + 1``, so edge ``i - 1`` meets its start)."""
    index = EDGE_NAMES.index(side.edge)
    return (EdgeId(side.plate, EDGE_NAMES[index - 1]),
            EdgeId(side.plate, EDGE_NAMES[(index + 1) % 4]))


def _end_edges(joint: JunctionJoint) -> Iterator[EdgeId]:
    """The edges that meet the line's ends: each member edge's two neighbours."""
    for side in joint.sides:
        yield from _neighbours(side)


def free_ends(joint: JunctionJoint, conditions: Mapping[EdgeId, str],
              supports: Mapping[EdgeId, tuple[str, str]]) -> list[EdgeId]:
    """The edges at the line's ends that leave it free to slide: free edges (``conditions``:
    every edge's, as :meth:`assembly.Case.edge_conditions` gives them) and supported edges
    free in their plane (``supports`` as for :func:`singular_ends`: ``in_plane = "free"``),
    module notes."""
    return [edge for edge in _end_edges(joint)
            if conditions[edge] == "free" or supports.get(edge, ("", ""))[1] == "free"]


def held_ends(joint: JunctionJoint, supports: Mapping[EdgeId, tuple[str, str]]) -> list[EdgeId]:
    """The edges at the line's ends that hold it in their plane without being a mirror of it:
    supported edges with ``in_plane = "fixed"`` (``supports`` as for :func:`singular_ends`).
    The line's in-plane loads converge slowly there (``docs/method.md`` section 10.4, *Ends
    held in their plane*)."""
    return [edge for edge in _end_edges(joint) if supports.get(edge, ("", ""))[1] == "fixed"]


def member_directions(joint: Any, plates: Mapping[str, Any]) -> tuple[int, ...]:
    r"""For each edge of a joint, +1 if it runs (counter-clockwise) along the joint line's
    direction, -1 if against it.

    The line runs along its first edge.  A junction between framed plates takes the other
    directions from the frames, :math:`s_i = \mathbf t_i\cdot\mathbf e_\Gamma` with
    :math:`\mathbf t_i = \mathbf e_{z,i}\times\mathbf n_i` the member's edge tangent
    (``docs/method.md`` section 6.2b); every other joint is ``(1, -1)``: the second edge runs the
    other way, as in an assembly unrolled in a plane (checked for framed plates).
    """
    sides = joint.sides
    if not isinstance(joint, JunctionJoint) or plates[sides[0].plate].frame is None:
        return (1, -1)
    start, end, _ = plates[sides[0].plate].edge_in_space(sides[0].edge)
    line = end - start
    directions = []
    for side in sides:
        a, b, _ = plates[side.plate].edge_in_space(side.edge)
        directions.append(1 if float((b - a) @ line) > 0.0 else -1)
    return tuple(directions)


def line_ends(joint: JunctionJoint,
              plates: Mapping[str, Any]) -> tuple[list[EdgeId], list[EdgeId]]:
    """The edges at the line's start and at its end: each member edge's neighbour there
    (:func:`_neighbours`, swapped for a member that runs against the line)."""
    ends: tuple[list[EdgeId], list[EdgeId]] = ([], [])
    for side, direction in zip(joint.sides, member_directions(joint, plates)):
        before, after = _neighbours(side)
        first, last = (before, after) if direction > 0 else (after, before)
        ends[0].append(first)
        ends[1].append(last)
    return ends


def symmetry_halves(support: tuple[str, str]) -> int:
    """How many of an edge's ``(bending, in-plane)`` conditions are those of a plane of
    symmetry (:data:`SYMMETRY_PLANE`): 2 on one, 0 on none, 1 on a mix (module notes)."""
    return sum(given == plane for given, plane in zip(support, SYMMETRY_PLANE))


def _mixed_end(edges: list[EdgeId], supports: Mapping[EdgeId, tuple[str, str]]) -> list[EdgeId]:
    """The end edges ``edges`` at one end of a line if that end is a plane of symmetry for part
    of the motion only (:func:`singular_ends`), else none."""
    given = [edge for edge in edges if edge in supports]
    halves = [symmetry_halves(supports[edge]) for edge in given]
    return given if any(halves) and any(count < 2 for count in halves) else []


def singular_ends(joint: JunctionJoint, plates: Mapping[str, Any],
                  supports: Mapping[EdgeId, tuple[str, str]]) -> list[EdgeId]:
    """The end edges of a line whose end is a plane of symmetry for part of the motion only
    (module notes): at one end of the line, some member's edge is ``roller`` in-plane or
    ``symmetric`` in bending, and not every member's edge there is both. ``supports`` holds
    the ``(bending, in-plane)`` conditions of the edges with a boundary condition; edges
    without one (joined, or free by default) take no part."""
    return [edge for edges in line_ends(joint, plates) for edge in _mixed_end(edges, supports)]


def _kinked(edges: list[EdgeId], supports: Mapping[EdgeId, tuple[str, str]]) -> bool:
    r"""Whether, at one end of a line, an end edge is ``roller`` in-plane (a member's in-plane
    displacement across the line even about the end plane) and one is ``simply_supported``
    (another's deflection odd, its slope free): the line ties the two, so its data have a kink
    at the end and its loads go like :math:`a\ln t + b + c\,t\ln t` (module notes)."""
    given = [supports[edge] for edge in edges if edge in supports]
    return (any(in_plane == "roller" for _, in_plane in given)
            and any(bending == "simply_supported" for bending, _ in given))


def singular_line_ends(joint: JunctionJoint, plates: Mapping[str, Any],
                       supports: Mapping[EdgeId, tuple[str, str]]) -> tuple[bool, bool]:
    """Whether the line's loads are log-singular at its start and at its end (along the line,
    :func:`line_ends`): a mixed end (:func:`singular_ends`) with a kink (:func:`_kinked`).
    The other mixes (``symmetric`` with ``diaphragm`` or ``fixed``, ``clamped`` with
    ``roller``) converge under the rule without the logarithmic load functions, which there
    slowed refinement three to forty times, and against finite elements of a fold with
    ``symmetric`` + ``diaphragm`` ends were no better (``docs/method.md`` section 10.4).
    ``supports`` as for :func:`singular_ends`."""
    return tuple(bool(_mixed_end(edges, supports)) and _kinked(edges, supports)
                 for edges in line_ends(joint, plates))


HOLDS_DEFLECTION = ("simply_supported", "clamped")
"""The bending conditions of an end edge that hold a member's deflection at the line's end."""

SLIDES_ACROSS = ("free", "roller")
"""The in-plane conditions of an end edge that leave a member's displacement across its line
free (:math:`N_{nt} = 0` on the end edge, whose tangent is the line's in-plane normal)."""


def pinned_ends(joint: JunctionJoint, plates: Mapping[str, Any],
                conditions: Mapping[EdgeId, str],
                supports: Mapping[EdgeId, tuple[str, str]]) -> list[EdgeId]:
    """The end edges at each end of a line where a member is *pinned* at its corner (module
    notes): its end edge leaves its in-plane displacement across the line free (a free edge,
    or one with ``in_plane`` in :data:`SLIDES_ACROSS`), and the end edge of a member not
    coplanar with it holds that member's deflection (:data:`HOLDS_DEFLECTION`), which at the
    line is the first member's displacement across it. ``conditions`` as for
    :func:`free_ends`, ``supports`` as for :func:`singular_ends`."""
    frames = [getattr(plates.get(side.plate), "frame", None) for side in joint.sides]
    pinned = []
    for edges in line_ends(joint, plates):
        slides = [conditions.get(edge) == "free"
                  or supports.get(edge, ("", ""))[1] in SLIDES_ACROSS for edge in edges]
        holds = [supports.get(edge, ("", ""))[0] in HOLDS_DEFLECTION for edge in edges]
        if any(slides[i] and holds[j] and frames[i] is not None and frames[j] is not None
               and not _parallel(frames[i], frames[j])
               for i in range(len(edges)) for j in range(len(edges))):
            pinned.extend(edges)
    return pinned


HOLDS_ACROSS = {"end": ("fixed", "diaphragm"), "far": ("fixed", "roller")}
"""The in-plane conditions that hold a member's displacement across its line (along its in-plane
normal there): on an end edge, whose tangent that normal is (``diaphragm``: :math:`u_t = 0`),
and on the far edge, whose normal it is (``roller``: :math:`u_n = 0`)."""


def _held_across(side: EdgeId, supports: Mapping[EdgeId, tuple[str, str]]) -> bool:
    """Whether one of ``side``'s plate's own boundary edges holds its in-plane displacement
    across ``side`` (:data:`HOLDS_ACROSS`); joined and free edges do not."""
    index = EDGE_NAMES.index(side.edge)
    far = EdgeId(side.plate, EDGE_NAMES[(index + 2) % 4])
    ends = _neighbours(side)
    return (any(supports[e][1] in HOLDS_ACROSS["end"] for e in ends if e in supports)
            or (far in supports and supports[far][1] in HOLDS_ACROSS["far"]))


def hanging_members(joint: JunctionJoint, plates: Mapping[str, Any],
                    supports: Mapping[EdgeId, tuple[str, str]]) -> list[str]:
    """The members of a line that hang on it (module notes): held across the line in their
    plane by no boundary edge of their own (:func:`_held_across`), nor of a member coplanar
    with them (the line ties their translations, and their in-plane normals are one). A
    stiffener with a free top and ``roller`` ends hangs; the skin bays beside it, their far
    edges fixed in-plane, do not. ``supports`` as for :func:`singular_ends`."""
    held = [_held_across(side, supports) for side in joint.sides]
    frames = [getattr(plates.get(side.plate), "frame", None) for side in joint.sides]
    hanging = []
    for i, side in enumerate(joint.sides):
        if held[i] or frames[i] is None:
            continue
        if not any(held[j] and frames[j] is not None and _parallel(frames[i], frames[j])
                   for j in range(len(held)) if j != i):
            hanging.append(side.plate)
    return hanging


def meeting_ends(joint: JunctionJoint, line_of: Mapping[EdgeId, str],
                 moving: Collection[str]) -> list[EdgeId]:
    """The edges at the line's ends that lie on other ``moving`` lines (``line_of``: the joint
    of each joined edge): the junction points where moving lines meet (module notes)."""
    return [edge for edge in _end_edges(joint) if line_of.get(edge) in moving]


def given_supports(boundaries: Iterable[Any]) -> dict[EdgeId, tuple[str, str]]:
    """The ``(bending, in-plane)`` conditions of the edges ``boundaries`` give, the in-plane
    one by default where not set (:attr:`assembly.models.Boundary.in_plane_condition`)."""
    return {parse_edge_ref(bc.edge): (bc.condition, bc.in_plane_condition) for bc in boundaries}


LINE_JOINTS = (JunctionJoint, HingeJoint)
"""The joints that are lines which may move: junctions and hinges (a moving hinge is a junction
line of two members, the first rigid: :class:`assembly.joints.HingeJoint`)."""


def line_moves(joint: Any, plates: Mapping[str, Any],
               supports: Mapping[EdgeId, tuple[str, str]]) -> bool:
    """Whether a joint is a line that moves: a junction or a hinge with ``held = false``, or
    by default non-coplanar members and no end that is a plane of symmetry for part of the
    motion only (:func:`singular_ends`). It reads this joint alone."""
    return isinstance(joint, LINE_JOINTS) and (
        joint.held is False
        or (joint.held is None and not members_coplanar(joint, plates)
            and not singular_ends(joint, plates, supports)))


def moving_lines(joints: Mapping[str, Any], plates: Mapping[str, Any],
                 boundaries: Iterable[Any]) -> tuple[str, ...]:
    """The junction lines and hinges that move (:func:`line_moves`), in the description's
    order."""
    supports = given_supports(boundaries)
    return tuple(jid for jid, joint in joints.items() if line_moves(joint, plates, supports))
