r"""How the ends of a moving line set its members' bases: the rules by situation at an end.

A moving line's loads converge slowly where its ends are corners of the assembled field, and
how far its members' edge waves must reach (in units of the description's
``edge_wavenumber_ratio`` :math:`\tau`) depends on what holds the end: a free edge or one
sliding in its plane (:data:`FREE_END_REACH`), a junction point where lines meet
(:data:`MEETING_END_REACH`), an end held in its plane (:data:`HELD_END_REACH`, with the
exponents of the singular in-plane loads, :func:`held_end_exponents`), a mixed or pinned end
(:data:`SINGULAR_END_REACH`, :data:`PINNED_END_REACH`, with logarithmic families at the
members' corners, :func:`singular_end_corners`). This module classifies the lines and members
of a case by those situations (:func:`free_end_lines`, :func:`pinned_lines`, ...) and gives each
member its reach (:func:`edge_reach`, :func:`reach_growth`); :mod:`solver.problems` builds the
bases from them and :mod:`solver.layout` the lines' counts. ``docs/method.md`` section 10.4
derives and measures each rule.

The reaches are read here when a basis is built, so a study may patch them on this module
(``bench/bench_free_ends.py``, the tests' ``monkeypatch``); :data:`HELD_END_FROM` is also read
by :mod:`solver.layout` as imported, and the functions are imported by name where they are
called, so a study patches a function there (``bench/bench_roller_ends.py`` patches
:func:`singular_end_corners` in :mod:`solver.problems` and :mod:`solver.in_plane`).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Mapping

from assembly.case import Case
from assembly.geometry import EDGE_NAMES
from assembly.lines import (
    HOLDS_DEFLECTION,
    continuing_members,
    free_ends,
    given_supports,
    held_ends,
    line_ends,
    meeting_ends,
    symmetry_halves,
)
from assembly.types import EdgeId
from solver.junction_exponents import EndMember, line_loading_exponents
from solver.resolution import joint_resolution, plate_resolution

__all__ = [
    "FREE_END_REACH",
    "HELD_END_FROM",
    "HELD_END_REACH",
    "MEETING_END_REACH",
    "PINNED_END_REACH",
    "REACH_GROWTH_FROM",
    "SINGULAR_END_REACH",
    "UNLOADED_HELD_END_REACH",
    "edge_reach",
    "end_layer_lines",
    "free_end_lines",
    "free_end_plates",
    "held_end_corners",
    "held_end_exponents",
    "held_end_lines",
    "held_end_plates",
    "held_free_ends",
    "meeting_end_lines",
    "meeting_end_plates",
    "mixed_end_plates",
    "pinned_lines",
    "reach_growth",
    "singular_end_corners",
    "singular_end_edges",
    "singular_end_lines",
    "singular_end_plates",
    "unloaded_held_end_plates",
]


SINGULAR_END_REACH = 3.0
r"""How much further than elsewhere the edge waves of a member of a moving line reach where an
end of the line is mixed (:func:`mixed_end_plates`), bending (:math:`\tau\kappa_0`) and
in-plane (:math:`\beta_{max}`) alike. The members of a line with a singular end, mixed or
pinned (:func:`singular_end_lines`), carry logarithmic families at those ends
(:func:`singular_end_corners`).

* Where the end is a plane of symmetry for part of the motion only (an in-plane ``roller`` end
  simply supported in bending, say: :func:`assembly.lines.singular_ends`), the line's loads
  are log-singular, and the line gains logarithmic load functions too
  (:func:`solver.joint_rules.load_function_values`; ``docs/method.md`` section 10.4).
  Neither families nor reach alone converges where a member hangs on the line
  (:func:`assembly.lines.hanging_members`): an L fold so at 1 kHz changed by 6.8e-2 between
  resolutions 2.25 and 3.4 with the families and the usual reach, by 3.8e-3 between 3.4 and 5
  with six times the reach and no families, by 7.9e-5 with both at three times; with the
  logarithmic load functions as well, the usual reach leaves 1.9e-2 in ``(u, v)``, three
  times 9.6e-4 (and 2.9e-5 in ``w``).
* Where a member is pinned at its corner (:func:`assembly.lines.pinned_ends`: its end slides
  across the line, and another member's support holds the deflection that is its
  displacement there), the line's loads are concentrated at the end: a point force on the
  corner, spread over a layer far thinner than the rays resolve. There the members reach as
  at a free end, up to :data:`PINNED_END_REACH`."""


PINNED_END_REACH = 6.0
r"""The furthest the members of a moving line with a pinned end (and no mixed end) reach, in
units of :math:`\tau`: as at a free end (:data:`FREE_END_REACH`, growing with the resolution
from :data:`REACH_GROWTH_FROM`), but not past this, unless the line meets others.

* With the logarithmic families at its corners, growing further made the interface problem
  of the rigid fold with sliding ends of ``bench/bench_free_ends.py`` nearly singular at
  300 Hz and resolution 5 (reach 10: interface loads 2e4 times larger, ``w`` 1e3 off its
  finite elements; 1.6e-6 at this cap).
* Fixed at :data:`SINGULAR_END_REACH`, as a mixed end's, the same fold stalled at 1 kHz where
  the line's count outgrew the reach (1.8e-6 at resolution 3.375, 1.4e-3 at 5.06; 6.2e-7 at
  this cap).
* Where every member hangs on the line (held across it in plane by no edge of its own, nor
  of a member coplanar with it: :func:`assembly.lines.hanging_members`), the pins are all that
  holds the line across, and the members keep the free end's rule, without families: on the
  L fold with every supported edge free in plane at 300 Hz the families left ``w`` 7.5e-4 and
  2.4e-4 from resolution 5 at 2.25 and 3.375, where without them it is 1.7e-4 and 1.2e-4 (the
  two fields at 5 agree within 1.2e-4).
* Where the line meets others, neither the families nor this cap (:func:`singular_end_edges`):
  on the trihedral corner of ``bench/bench_corner.py --floating``, whose far ends slide and
  pin its members, the families left ``w`` 1.1 to 1.6 times further off its finite elements
  from resolution 2.25 to 5 at 300 Hz, and 3 to 11 times at 100 and 150 Hz (finite elements
  of ``bench/fem_corner.py`` at those frequencies, levels 4 and 6 within 2.1e-7, measured
  once on 2026-11-29: at resolution 2.25, 1.9e-2 and 7.5e-3 against 6.9e-3 and 7.1e-4); and
  with the families the cap left it 1.3e-3 off at resolution 5 and 300 Hz, 5.7e-4 without.

``docs/accuracy.md`` section 8."""


def singular_end_edges(case: Case, joint_id: str,
                       meeting: frozenset[str] | None = None) -> set[EdgeId]:
    """The end edges of a line at its singular ends: an end that is a plane of symmetry for
    part of the motion only (:meth:`assembly.Case.singular_ends`), or one where a member is
    pinned at its corner (:meth:`assembly.Case.pinned_ends`) on a line that meets no other
    (``meeting``: :func:`meeting_end_lines`, found if not given) and holds some member across
    it (not every member hangs on it: :meth:`assembly.Case.hanging_members`);
    :data:`PINNED_END_REACH` says why not elsewhere."""
    meeting = meeting_end_lines(case) if meeting is None else meeting
    floating = set(case.hanging_members(joint_id)) == set(case.joints[joint_id].plates)
    pinned = case.pinned_ends(joint_id) if joint_id not in meeting and not floating else []
    return set(case.singular_ends(joint_id)) | set(pinned)


def singular_end_lines(case: Case) -> frozenset[str]:
    """The moving lines with a singular end (:func:`singular_end_edges`)."""
    supports = given_supports(case.boundaries).values()
    if not any(symmetry_halves(support) or support[0] in HOLDS_DEFLECTION
               for support in supports):
        return frozenset()  # the common case, without finding the moving lines
    meeting = meeting_end_lines(case)
    return frozenset(jid for jid in case.moving_lines()
                     if singular_end_edges(case, jid, meeting))


def pinned_lines(case: Case) -> dict[str, bool]:
    """The moving lines with a pinned end (:func:`singular_end_edges`) and no mixed end, each
    with whether a member hangs on it alone: held across it in its plane by no edge of its own
    (:meth:`assembly.Case.hanging_members`) and a member of no other moving line (a stiffener
    free at its ends and top; the web of a channel whose ends slide hangs on both its lines).
    Their count is :func:`solver.joint_rules.pinned_line_count`."""
    lines = Counter(plate for jid in case.moving_lines() for plate in case.joints[jid].plates)
    return {jid: any(lines[plate] == 1 for plate in case.hanging_members(jid))
            for jid in singular_end_lines(case) if not case.singular_ends(jid)}


def singular_end_plates(case: Case) -> frozenset[str]:
    """The members of the moving lines with a singular end (:func:`singular_end_lines`)."""
    return _members(case, singular_end_lines(case))


def mixed_end_plates(case: Case) -> frozenset[str]:
    """The members of the moving lines with an end that is a plane of symmetry for part of the
    motion only (:meth:`assembly.Case.singular_ends`)."""
    if not any(map(symmetry_halves, given_supports(case.boundaries).values())):
        return frozenset()  # the common case, without finding the moving lines
    return frozenset(plate for jid in case.moving_lines() if case.singular_ends(jid)
                     for plate in case.joints[jid].plates)


MEETING_END_REACH = 3.0
r"""How much further than elsewhere the edge waves of a member of a moving line reach where the
line's ends meet other moving lines (a junction point, ``docs/method.md`` section 10.4), bending
and in-plane alike, up to resolution :data:`REACH_GROWTH_FROM`, growing with it beyond.
``cases/box_with_wall.toml`` with its four welds moving, at 600 Hz: the
worst plate's w changed by 3.8e-3, 2.6e-3, 2.9e-3 from resolution 1.5 to 2.25, 3.375 and 5
with the usual reach (no convergence), by 1.1e-4, 8.5e-5 with twice the reach, by 6.0e-5,
8.9e-6 with three times; three times on the wall alone, the plate whose corners are the
points, still left 3.2e-4, 3.7e-4. Those changes refined the rays alone (the lines' Legendre
count stopped at resolution 5/3); with the count following the members' reach
(:func:`solver.layout.answered_wavenumber`) the box with its folds moving too, whose corners
join three moving lines, changes by 6.2e-3, 2.4e-3 and 9.4e-4 from resolution 1.5 to 2.25,
3.375 and 5 at 189.6 Hz: the lines' loads converge slowly at such corners (and with the reach
growing, on to 7.5: :data:`REACH_GROWTH_FROM`). Most of that was their count at the points:
with the floor of :func:`solver.joint_rules.end_layer_count` there (:func:`end_layer_lines`)
the change from 1.5 to 2.25 is 4.7e-4."""


def meeting_end_lines(case: Case) -> frozenset[str]:
    """The moving lines whose ends meet other moving lines (:func:`assembly.lines.meeting_ends`):
    junction points."""
    moving = case.moving_lines()
    if len(moving) < 2:  # the common case: no two lines to meet
        return frozenset()
    line_of = case.edge_joints()
    return frozenset(jid for jid in moving if meeting_ends(case.joints[jid], line_of, moving))


def meeting_end_plates(case: Case) -> frozenset[str]:
    """The members of the moving lines whose ends meet other moving lines
    (:func:`meeting_end_lines`)."""
    return _members(case, meeting_end_lines(case))


FREE_END_REACH = 3.0
r"""How much further than elsewhere the edge waves of a member of a moving line reach where an
end of the line meets a free edge (a junction point that nothing holds, ``docs/method.md``
section 10.4), bending and in-plane alike, up to resolution :data:`REACH_GROWTH_FROM`; beyond
it the reach grows with the resolution (:func:`edge_reach`). The bracket of
``tests/test_free_ends.py`` (``bench/bench_free_ends.py``), worst plate, change between
resolutions 2.25 and 3.375 at 300 Hz, 1 kHz and 3 kHz (with the line's count stopped at
resolution 5/3, as then): w 2.4e-4, 4.9e-4, 1.8e-4 and (u, v) 1.7e-3, 9.9e-3, 1.3e-3 with the
usual reach; 2.7e-6, 4.7e-6, 1.3e-5 and 8.6e-5, 3.1e-4, 8.9e-5 with three times. The solve
costs 4.8 to 12.8 times more.

The same where the end's edges are supported but free in plane (``in_plane = "free"``: the
end slides along the line; :func:`free_end_plates`). The rigid L fold with such ends against
independent finite elements (``bench/bench_free_ends.py --sliding-ends``), worst plate's
``w`` at resolutions 1.5, 2.25, 3.375: 2.4e-4, 2.3e-4, 3.0e-4 with the usual reach (1 kHz:
9.4e-3, 1.1e-2, 1.2e-2), 1.2e-4, 4.9e-5, 8.4e-6 with this one (1 kHz: 1.8e-4, 7.4e-5,
3.1e-5)."""

REACH_GROWTH_FROM = 1.5
r"""The resolution from which the reach of the members of a line with a free end, or meeting
other lines, grows in proportion to it (:func:`edge_reach`): :data:`FREE_END_REACH` or
:data:`MEETING_END_REACH` times :math:`\max(1, s/1.5)`.

Why: the line's loads converge slowly in their Legendre functions at a free end (its ends are
corners of the assembled field), and the more of them the line has, the further the members'
edge waves must reach to answer them. Against independent finite elements (the rigid bracket,
``bench/bench_free_ends.py --finite-elements``), with the count fixed and the rays at
resolution 2.25, the error of ``w`` falls with the count to a floor set by the reach, then
rises: at 300 Hz 2.4e-3, 4.9e-4, 1.3e-4 with 16, 24, 28 functions, then 5.3e-4 and 1.5e-3
with 36 and 52 at three times the reach; 6.2e-5 with 32 at 4.5 times; 2.8e-5 with 36 to 40
at six times, and no rise to 52. At 1 kHz three times the reach is best at 40 functions
(4.9e-5), six times at 52 (5.4e-6). A fixed reach therefore stalled: the bracket was 3.4e-4
off at resolution 3.375 and 8.5e-4 at 5. Growing with the resolution, as the count does,
the reach keeps the loads answered: 5.6e-3, 2.4e-3, 5.3e-4, 4.4e-5, 7.3e-6 at resolutions 1
to 5 (300 Hz), 2.8e-3, 5.9e-4, 3.8e-5, 7.1e-6 at 1 to 3.375 (1 kHz), the estimate 0.6 to 1.6
times the error (with the line's count floor since, :func:`solver.joint_rules.end_layer_count`,
2.5e-4, 1.0e-4, 2.1e-5 at 1.5, 2.25, 3.375 at 300 Hz). The edge waves' sectors widen with the
reach rather than multiply (:func:`reach_growth`), so the cost grows about as with a fixed
reach (300 Hz: 0.4, 1.2, 2.5 and 7.2 s at resolutions 1.5, 2.25, 3.375 and 5); up to 1.5
nothing changes.

Where three lines meet the same holds against independent finite elements: the trihedral
corner of ``tests/test_meeting_corner.py`` (``bench/bench_corner.py``), worst plate's ``w`` at
300 Hz and resolutions 1.5, 2.25, 3.375 and 5, is 4.7e-5, 8.2e-6, 1.6e-6 and 1.5e-7 off with the
reach growing, 4.7e-5, 8.2e-6, 5.4e-6 and 4.4e-5 with it fixed at three times (the estimate 6
to 42 times the error at 3.375), and 4.1e-4, 5.9e-4, 2.1e-4 and 2.4e-4 with the usual reach.
``cases/box_with_wall.toml`` at 189.6 Hz (its finite elements: ``bench/fem_box.py``) changed by
6.2e-3, 2.3e-3, 9.4e-4 and 3.9e-6 from resolution 1.5 to 2.25, 3.375, 5 and 7.5 with the reach
fixed (the last step frozen: the count at its stop, the estimate blind), growing by 6.1e-3,
2.3e-3, 7.5e-4 and 1.4e-4; the two fields at 7.5 differ by 1.7e-4."""


def free_end_lines(case: Case) -> frozenset[str]:
    """The moving lines with an end on an edge free in its plane, where the end slides: a free
    edge, or a supported one with ``in_plane = "free"`` (:func:`assembly.lines.free_ends`)."""
    moving = case.moving_lines()
    if not moving:
        return frozenset()
    conditions, supports = case.edge_conditions(), given_supports(case.boundaries)
    return frozenset(jid for jid in moving if free_ends(case.joints[jid], conditions, supports))


def end_layer_lines(case: Case) -> frozenset[str]:
    """The moving lines with an end that translates along the line, where the loads form a
    layer (:func:`solver.joint_rules.end_layer_count`): an end free to slide
    (:func:`free_end_lines`) or a junction point where lines meet
    (:func:`meeting_end_lines`)."""
    return free_end_lines(case) | meeting_end_lines(case)


def free_end_plates(case: Case) -> frozenset[str]:
    """The members of the moving lines with an end free to slide (:func:`free_end_lines`)."""
    return _members(case, free_end_lines(case))


HELD_END_REACH = 2.0
r"""How much further than elsewhere the edge waves of a member of a moving line reach where an
end of the line is held in its plane (``in_plane = "fixed"``, the default of supported edges),
bending and in-plane alike (bending :data:`UNLOADED_HELD_END_REACH` times where no exponent
loads the line), from resolution :data:`HELD_END_FROM` on (:func:`held_end_lines`;
``docs/method.md`` section 10.4, *Ends held in their plane*).

Why: there the members' in-plane fields meet at a corner that is not a mirror, the line's
in-plane loads converge slowly at the end (as singular loads would), and their Legendre
functions, stopped at the usual reach (:func:`solver.joint_rules.interface_function_count`),
leave the members' traces apart beyond them: on ``cases/stiffened_panel.toml`` at 230 Hz and
resolution 2.25 the skin's translation along a weld differs from its neighbour's by 3e-4 of
the line's (root mean square), nearly all of it in Legendre degrees above the line's 13
functions, and by 100 times less with the same ends made shear diaphragms (mirrors). With
twice the reach the count followed it where the members' wavenumbers differ
(:func:`solver.layout.answered_wavenumber`) until 0.3.8, when the loads came to carry their
singular terms there (:func:`held_end_exponents`; the figures below are from before).
Against independent finite elements
(``bench/bench_panel.py``, ``bench/fem_junction.py --ends fixed``), worst plate's ``(u, v)``:

* the panel at 184.8 / 230 / 257 Hz stalled at 4.4e-4 / 3.4e-4 / 6.4e-4 from resolution 1.5 on,
  its estimate falling to 0.04 to 0.5 of that; with twice the reach 1.1e-4 / 7.6e-5 / 2.5e-4 at
  2.25 and 6.4e-5 / 9.9e-5 / 3.4e-4 at 3.4, the estimate 0.5 to 2.5 times the error on the
  skin;
* the T junction of ``tests/test_moving_lines.py`` with fixed ends (its stiffener's top fixed)
  at 1 kHz, resolutions 1.5 and 2.25: 3.1e-4 and 3.4e-4 before, 9.3e-5 and 1.2e-4 after; at
  300 Hz 1.3e-2 and 8.5e-4 before, 3.2e-4 and 8.0e-4 after (a stall the reach does not lift).

1.5 times (the panel at 230 Hz, resolution 3.4: 2.6e-3), or twice growing with the resolution
as at a free end (184.8 Hz, 3.4: 3.5e-4), were erratic; three times, growing, 3e-5 at 2.25 but
5.4 times the solve. The solve costs 1.4 to 3.9 times more at 230 Hz, 300 Hz and 1 kHz, 4 to 6
times on a two-stiffener panel at 2.5 kHz (where resolutions 1.5 and 2.25 then agree to 1e-5
instead of 3e-4). Not better everywhere: the T junction at 300 Hz is 8.0e-4 and 2.9e-3 off at
resolutions 2.25 and 3.4, an ill-conditioned interface problem that the error estimate reports
(``docs/method.md`` section 10.4)."""

UNLOADED_HELD_END_REACH = 3.0
r""":data:`HELD_END_REACH` of a member's bending waves where no exponent loads the held line
(:func:`unloaded_held_end_plates`: an L fold, whose members are each a fixed-free corner at the
end, like or unlike). No singular load term carries the end there, and the members' bending
rays must: with twice the reach an L fold of 2 mm plates (``tests/test_held_ends.py``) at 1 kHz
stalled 2.5e-4, 3.0e-4 and 6.4e-5 off its finite elements in ``(u, v)`` at resolutions 1.5,
2.25 and 3.4 (``w`` 1.1e-5, 1.8e-5, 4.2e-6), its error along the line (85 % of it in the two
columns of the comparison grid nearest it, spread along its length); three times, 2.3e-5 and
1.9e-5 at 1.5 and 2.25 (``w`` 1.1e-6, 8.3e-7), about the finite elements' own accuracy (their
last refinement changed ``(u, v)`` by 1.2e-5), four times no better. The members' in-plane
reach, or the line's count, changed nothing, or made it worse (the count 1.5 times: 6.6e-4). At
300 Hz the fold is at the finite elements' accuracy either way. The solve at 1 kHz and 1.5:
0.51 s against 0.33 s, a warm solve, the fastest of six processes alternating between the two
reaches (2044 unknowns against 1684). A T junction, whose loads carry their
singular terms, gains nothing from it (the same errors to two digits at 300 Hz and 1 kHz, for
1.5 times the solve, one run each) and keeps :data:`HELD_END_REACH`."""

HELD_END_FROM = 1.5
"""The resolution from which :data:`HELD_END_REACH` applies. Below it the solve keeps its cost
(the descriptions' resolutions 1 and 1.25); the error estimate's enriched solve, at 1.5 times
the resolution, has the wider reach from resolution 1 on, and so sees what the narrower one
leaves along the lines."""


def held_end_lines(case: Case) -> frozenset[str]:
    """The moving lines with an end held in its plane (:func:`assembly.lines.held_ends`)."""
    supports = given_supports(case.boundaries)
    return frozenset(jid for jid in case.moving_lines()
                     if held_ends(case.joints[jid], supports))


def held_end_plates(case: Case) -> frozenset[str]:
    """The members of the moving lines with an end held in its plane (:func:`held_end_lines`)."""
    return _members(case, held_end_lines(case))


def unloaded_held_end_plates(case: Case) -> frozenset[str]:
    """The members of the moving lines with an end held in its plane whose held ends no
    exponent loads (:func:`held_end_exponents` none at either end: an L fold), whose bending
    waves reach :data:`UNLOADED_HELD_END_REACH` times as far as elsewhere."""
    return _far_reaching_plates(case)[4]


def held_end_exponents(case: Case, joint_id: str,
                       resolution: float | Mapping[str, float] | None = None
                       ) -> tuple[tuple[float, ...], ...]:
    r"""Per end of a moving line (start, end, along the line), the exponents :math:`\lambda` of
    the in-plane field whose modes load the line there (:mod:`solver.junction_exponents`), at
    an end where every member's end edge is fixed in its plane, from the joint's resolution
    :data:`HELD_END_FROM` on (its members' reach doubles there: below, the rays do not answer
    the loads' layer at the end); none elsewhere. The line's loads go like
    :math:`t^{\lambda - 1}` at that end (``resolution`` as for
    :func:`solver.resolution.plate_resolution`, the joint's the finest of its members')."""
    exponents = _held_line_exponents(case).get(joint_id)
    if exponents is None or joint_resolution(case, joint_id, resolution) < HELD_END_FROM - 1e-9:
        return ((), ())
    return exponents


def held_end_corners(case: Case, plate_id: str,
                     resolution: float | Mapping[str, float] | None = None
                     ) -> tuple[tuple[int, bool, tuple[float, ...]], ...]:
    """The corners of a plate where its edge on a moving line meets an end of the line with
    :func:`held_end_exponents` (``resolution`` as there): ``(corner, incoming_fixed,
    exponents)``, corner ``c`` joining
    edges ``c - 1`` and ``c``, ``incoming_fixed`` if edge ``c - 1`` is the end edge."""
    if plate_id not in _far_reaching_plates(case)[3]:  # the common case
        return ()
    corners = []
    for jid in _held_line_exponents(case):
        joint = case.joints[jid]
        if plate_id not in joint.plates:
            continue
        start, end = held_end_exponents(case, jid, resolution)
        for side, direction in zip(joint.sides, case.member_directions(jid)):
            if side.plate != plate_id:
                continue
            i = EDGE_NAMES.index(side.edge)
            first, last = (start, end) if direction > 0 else (end, start)
            if first:
                corners.append((i, True, first))
            if last:
                corners.append(((i + 1) % 4, False, last))
    # in the corners' order, whatever the joints': plates alike (a panel's inner bays) then
    # have equal corners and share one basis (solver.in_plane.membrane_bases)
    return tuple(sorted(corners))


def _line_exponents(case: Case) -> dict[str, tuple[tuple[float, ...], ...]]:
    """Per held line of ``case`` (:func:`held_end_lines`), per end, the exponents of
    :func:`held_end_exponents` at any resolution from :data:`HELD_END_FROM` on."""
    supports, held = given_supports(case.boundaries), held_end_lines(case)
    return {jid: tuple(line_loading_exponents(_end_members(case, jid))
                       if all(supports.get(edge, ("", ""))[1] == "fixed" for edge in edges)
                       else () for edges in line_ends(case.joints[jid], case.plates))
            for jid in case.joints if jid in held}  # the case's order, not the set's


def _end_members(case: Case, joint_id: str) -> tuple[EndMember, ...]:
    """The :class:`~solver.junction_exponents.EndMember` of each member of a line: two
    members whose in-plane normals on the line are opposite continue each other
    (:func:`assembly.lines.continuing_members`)."""
    joint = case.joints[joint_id]
    members = []
    for side, partner in zip(joint.sides, continuing_members(joint, case.plates)):
        material = case.material_of(side.plate)
        shear = material.young_modulus / (2.0 * (1.0 + material.poisson_ratio))
        members.append(EndMember(case.plates[side.plate].thickness, shear,
                                 material.poisson_ratio, partner))
    return tuple(members)


def _members(case: Case, joint_ids: Iterable[str]) -> frozenset[str]:
    """The plates of the joints ``joint_ids``."""
    return frozenset(plate for jid in joint_ids for plate in case.joints[jid].plates)


def edge_reach(case: Case, plate_id: str,
               resolution: float | Mapping[str, float] | None = None,
               held_ends: bool = True, in_plane: bool = False) -> float:
    r"""The largest edge-wave wavenumber of a plate in units of its bending wavenumber: the
    description's ``edge_wavenumber_ratio`` :math:`\tau` (the plate's own where
    ``[discretisation.plates.ID]`` gives one), times :data:`SINGULAR_END_REACH` on a
    member of a moving line with a mixed end (:func:`mixed_end_plates`), times
    :data:`MEETING_END_REACH` on a member of a moving line that meets others at its ends
    (:func:`meeting_end_plates`) or :data:`FREE_END_REACH` on one with an end on a free edge
    (:func:`free_end_plates`), those two times :math:`\max(1, s/s_g)`, :math:`s` the plate's
    resolution (``resolution`` as for :func:`solver.resolution.plate_resolution`) and :math:`s_g` =
    :data:`REACH_GROWTH_FROM` (at most :data:`PINNED_END_REACH` where the line has a pinned
    end, :func:`singular_end_plates`, and meets no other); times :data:`HELD_END_REACH` on a
    member of a line held at an end (:func:`held_end_plates`) from resolution
    :data:`HELD_END_FROM` on, unless
    ``held_ends`` is false (the reach the line's count may follow instead:
    :func:`solver.layout.answered_wavenumber`), its bending waves
    :data:`UNLOADED_HELD_END_REACH` times where no exponent loads such a line
    (:func:`unloaded_held_end_plates`; ``in_plane``: the reach of its in-plane waves); times
    :math:`\max(1, s/s_g)` on a member of a held line with an end on a free edge
    (:func:`held_free_ends`), whose count follows it (:func:`solver.layout.interface_layout`)."""
    return case.discretisation.edge_ratio(plate_id) * _reach_factors(
        case, plate_id, resolution, held_ends, in_plane)[0]


def reach_growth(case: Case, plate_id: str,
                 resolution: float | Mapping[str, float] | None = None) -> float:
    r"""How many times a plate's :func:`edge_reach` exceeds what it would be without growing
    with the resolution (1 but on the members of a line with a free end or meeting others, and
    of a held line with an end on a free edge, above :data:`REACH_GROWTH_FROM`). The edge
    waves' counts are those of the resolution divided by it, so that their sectors widen with
    the reach instead of multiplying: the count of a
    fixed reach at that resolution. Against the finite elements of the free-ended fold the
    error is the same (300 Hz: 5.3e-4, 4.4e-5 and 7.3e-6 at resolutions 2.25, 3.375 and 5, with
    2006, 2998 and 4418 unknowns instead of 2882, 6312 and 13598; 1 kHz: 3.8e-5 and 7.1e-6 at
    2.25 and 3.375 instead of 4.1e-5 and 5.5e-6), at a fraction of the cost (2.5 s instead of
    14 s at 3.375 and 300 Hz, 7 s instead of 148 s at 5)."""
    multiplier, fixed = _reach_factors(case, plate_id, resolution)
    return multiplier / fixed


def _reach_factors(case: Case, plate_id: str,
                   resolution: float | Mapping[str, float] | None,
                   held_ends: bool = True, in_plane: bool = False) -> tuple[float, float]:
    r"""A plate's edge reach in units of :math:`\tau`, and the same without its growth
    (``held_ends``, ``in_plane`` as in :func:`edge_reach`)."""
    singular, meeting, free, held, unloaded, mixed, held_free = _far_reaching_plates(case)
    if plate_id in mixed:
        return SINGULAR_END_REACH, SINGULAR_END_REACH
    scale = plate_resolution(case, plate_id, resolution)
    if plate_id in meeting or plate_id in free:
        fixed = max(MEETING_END_REACH if plate_id in meeting else 1.0,
                    FREE_END_REACH if plate_id in free else 1.0)
        reach = fixed * max(1.0, scale / REACH_GROWTH_FROM)
        capped = plate_id in singular and plate_id not in meeting
        return (min(reach, PINNED_END_REACH) if capped else reach), fixed
    if held_ends and plate_id in held and scale >= HELD_END_FROM - 1e-9:
        reach = (UNLOADED_HELD_END_REACH if plate_id in unloaded and not in_plane
                 else HELD_END_REACH)
        return reach, reach
    if plate_id in held_free:
        return max(1.0, scale / REACH_GROWTH_FROM), 1.0
    return 1.0, 1.0


_FAR_REACHING: dict[int, tuple[Case, tuple[frozenset[str], ...], dict, dict]] = {}


def _case_lines(case: Case) -> tuple[Case, tuple[frozenset[str], ...], dict, dict]:
    """The memo of ``case`` (a frozen model), for the few cases in use: its
    :func:`_far_reaching_plates`, :func:`_held_line_exponents` and :func:`_held_free_ends`,
    which find the moving lines (5 ms on a 50-bay panel) and are asked for every plate and
    joint by several builders (0.5 s a pass over its 99 plates without the memo; the lines'
    exponents, asked per joint, grew the 50-bay panel's layout from 0.09 s to 2.4 s)."""
    entry = _FAR_REACHING.get(id(case))  # the memo holds its cases: their ids stay theirs
    if entry is None:
        if len(_FAR_REACHING) >= 8:
            _FAR_REACHING.clear()
        exponents = _line_exponents(case)
        unloaded = [jid for jid, ends in exponents.items() if not any(ends)]
        held_free = _held_free_ends(case)
        entry = _FAR_REACHING[id(case)] = (case, (singular_end_plates(case),
                                                  meeting_end_plates(case),
                                                  free_end_plates(case),
                                                  held_end_plates(case),
                                                  _members(case, unloaded),
                                                  mixed_end_plates(case),
                                                  _members(case, held_free)),
                                           exponents, held_free)
    return entry


def _far_reaching_plates(case: Case) -> tuple[frozenset[str], ...]:
    """:func:`singular_end_plates`, :func:`meeting_end_plates`, :func:`free_end_plates`,
    :func:`held_end_plates`, :func:`unloaded_held_end_plates`, :func:`mixed_end_plates` and
    the members of the held lines of :func:`held_free_ends` of ``case``, found once per case
    (:func:`_case_lines`)."""
    return _case_lines(case)[1]


def _held_line_exponents(case: Case) -> dict[str, tuple[tuple[float, ...], ...]]:
    """:func:`_line_exponents` of ``case``, found once per case (:func:`_case_lines`)."""
    return _case_lines(case)[2]


def held_free_ends(case: Case, joint_id: str) -> tuple[bool, bool]:
    r"""Per end of a held line (start, end along it), whether a member's edge ends there on a
    free edge of its plate: a hinge or a junction line that neither continues its plates (a
    coplanar joint) nor moves, whose members hold :math:`w = 0` and tie their rotations by a
    spring. There a member has a corner between :math:`w = 0` and a free edge; its plate
    carries the clamped-free corner functions (:func:`solver.problems.plate_wedges`) and the
    line's moment goes like their :math:`t^{\mu - 2}`
    (:func:`solver.joint_rules.singular_load_ends`; ``docs/method.md`` section 5.5, *A held
    line's end on a free edge*). A member edge of a moving line counts as free, as in the
    plates' bending problems. ``(False, False)`` for any other joint."""
    return _case_lines(case)[3].get(joint_id, (False, False))


def _held_free_ends(case: Case) -> dict[str, tuple[bool, bool]]:
    """:func:`held_free_ends` of every held line of ``case`` that has such an end."""
    moving = set(case.moving_lines())
    conditions, joints = case.edge_conditions(), case.edge_joints()

    def free(edge: EdgeId) -> bool:
        return conditions[edge] == "free" or joints.get(edge) in moving

    out = {}
    for jid, joint in case.joints.items():
        if joint.kind == "coplanar" or jid in moving:
            continue
        ends = tuple(any(map(free, edges)) for edges in line_ends(joint, case.plates))
        if any(ends):
            out[jid] = ends
    return out


def singular_end_corners(case: Case, plate_id: str) -> tuple[int, ...]:
    """The corners of a plate where its edge on a moving line meets the edge of a singular end
    of that line (:func:`singular_end_edges`), where the line's loads are log-singular or
    concentrated: corner ``c`` joins edges ``c - 1`` and ``c``."""
    if plate_id not in _far_reaching_plates(case)[0]:  # the common case
        return ()
    corners, meeting = set(), meeting_end_lines(case)
    for jid in case.moving_lines():
        # its own lines only: each other line's ends would cost a pass over the description
        if plate_id not in case.joints[jid].plates:
            continue
        ends = {edge.edge for edge in singular_end_edges(case, jid, meeting)
                if edge.plate == plate_id}
        for side in case.joints[jid].sides:
            if side.plate == plate_id:
                i = EDGE_NAMES.index(side.edge)
                corners.update(c for c, other in ((i, i - 1), ((i + 1) % 4, (i + 1) % 4))
                               if EDGE_NAMES[other] in ends)
    return tuple(sorted(corners))


