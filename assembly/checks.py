"""Cross-reference checks of a description: what a single table cannot check alone.

:class:`assembly.case.Case` validation calls :func:`cross_check` on a view of its tables and
raises :class:`assembly.errors.CrossReferenceError` with every problem found, each as
``(loc, message)``: the joints' edges and members, the frames of plates placed in 3D, the
boundaries and loads, the measurement points and the truth tables, each message naming the
fix.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from assembly.errors import Loc, did_you_mean, listing
from assembly.grid import on_grid
from assembly.joints import CoplanarJoint, HingeJoint, JunctionJoint
from assembly.lines import moving_lines as lines_that_move
from assembly.models import (
    FRAME_TOLERANCE,
    Boundary,
    EdgeMoment,
    EdgeShear,
    Material,
    Plate,
    PointForce,
)
from assembly.settings import (
    Discretisation,
    JointTruth,
    Measurement,
    Truth,
    Updating,
    default_spacing,
)
from assembly.types import EdgeId, parse_edge_ref

__all__ = ["View", "cross_check"]

@dataclass
class View:
    """What the cross-reference checks look at; None marks an invalid or absent part.

    Mappings and sequences may hold None for items that failed their own validation:
    their ids are known but their content is not checked further.
    """

    materials: Mapping[str, Material | None] | None
    plates: Mapping[str, Plate | None] | None
    joints: Mapping[str, CoplanarJoint | HingeJoint | JunctionJoint | None] | None
    boundaries: Sequence[Boundary | None] | None
    loads: Sequence[EdgeShear | EdgeMoment | PointForce | None] | None
    discretisation: Discretisation | None
    measurement: Measurement | None
    updating: Updating | None
    truth: Truth | None
    has_frequency: bool
    has_frequencies: bool


_HELD_SPRINGS = ("junction {jid!r} is held in translation, so its members' translational springs "
                 "would do nothing; set held = false (framed, non-coplanar members) or remove "
                 "them")
"""The line of a held junction given translational springs."""


def _member_issues(
    jid: str, joint: Any, ids: list[EdgeId], ends: list[Any], loc: Loc
) -> list[tuple[Loc, str]]:
    """Problems of a joint's edges taken together: repeated edges or plates, lengths,
    a junction's stiffness tables and its need of frames."""
    issues: list[tuple[Loc, str]] = []
    refs = joint.between
    for i, edge in enumerate(ids):
        for j in range(i):
            if edge == ids[j]:
                issues.append((loc, f"joins edge {refs[i]!r} to itself; a joint connects edges "
                               "of different plates, fix the edge references"))
            elif edge.plate == ids[j].plate:
                issues.append((loc, f"joins two edges of the same plate {edge.plate!r} "
                               f"({refs[j]!r} and {refs[i]!r}); a joint connects different "
                               "plates, fix the edge references"))
    if issues or any(end is None for end in ends):
        return issues
    lengths = [plate.edge_length(edge.edge) for edge, plate in ends]
    for i in range(1, len(ids)):
        la, lb = lengths[0], lengths[i]
        if abs(la - lb) > 1e-9 * max(la, lb):
            issues.append((loc, f"the joined edges differ in length: {refs[0]!r} is {la:g} m "
                           f"and {refs[i]!r} is {lb:g} m; join edges of equal length (check "
                           "the plates' size or the edge references)"))
    if not isinstance(joint, JunctionJoint):
        return issues
    members = [edge.plate for edge in ids]
    for name in ("log10_stiffness", "loss_factor", "log10_translational_stiffness",
                 "translational_loss_factor"):
        table = getattr(joint, name)
        if not isinstance(table, Mapping):
            continue
        for plate in table:
            if plate not in members:
                issues.append((("joints", jid, name, plate), f"plate {plate!r} is not a "
                               f"member of junction {jid!r} (members: {', '.join(members)}); "
                               "name member plates only"))
        missing = [p for p in members if p not in table]
        if name == "log10_stiffness" and missing:
            issues.append((("joints", jid, name), f"gives no stiffness for member "
                           f"{', '.join(missing)}; give every member a value (inf: rigid)"))
    without = [pid for (_, plate), pid in zip(ends, members) if plate.frame is None]
    if len(ids) > 2 and without:
        issues.append((loc, f"a junction of {len(ids)} members needs a frame on every member "
                       f"plate; add [plates.{without[0]}] frame = {{ origin = [x, y, z], "
                       "x_axis = [...], y_axis = [...] }"))
    return issues


def _frame_issues(
    joints: Mapping[str, Any], plates: Mapping[str, Plate | None]
) -> list[tuple[Loc, str]]:
    """Problems of plates placed in 3D: all plates framed or none, joined edges coinciding in
    space, coplanar joints between parallel plates, two-edge joints along opposite edges."""
    known = {pid: p for pid, p in plates.items() if p is not None}
    framed = [pid for pid, p in known.items() if p.frame is not None]
    if not framed:
        return []
    issues: list[tuple[Loc, str]] = []
    unframed = [pid for pid in known if known[pid].frame is None]
    if unframed:
        return [(("plates", unframed[0], "frame"), f"plate {unframed[0]!r} has no frame while "
                 f"plate {framed[0]!r} has one; give every plate a frame, or none")]
    for jid, joint in joints.items():
        if joint is None or any(side.plate not in known for side in joint.sides):
            continue
        loc = ("joints", jid, "between")
        sides = joint.sides
        first = known[sides[0].plate].edge_in_space(sides[0].edge)
        length = float(np.linalg.norm(first[1] - first[0]))
        directions = []
        for i, side in enumerate(sides[1:], start=1):
            start, end, _ = known[side.plate].edge_in_space(side.edge)
            same = max(np.linalg.norm(start - first[0]), np.linalg.norm(end - first[1]))
            reversed_ = max(np.linalg.norm(start - first[1]), np.linalg.norm(end - first[0]))
            gap = float(min(same, reversed_))
            if gap > FRAME_TOLERANCE * length:
                issues.append(((*loc, i), f"edges {joint.between[0]!r} and {joint.between[i]!r} "
                               f"do not meet in space (ends {gap:.3g} m apart); fix the plates' "
                               "frame or size, or the edge references"))
            directions.append(same <= reversed_)
        if isinstance(joint, JunctionJoint) or len(directions) != 1 or issues:
            continue
        a, b = (known[side.plate].frame for side in sides)
        if directions[0]:
            issues.append((loc, f"edges {joint.between[0]!r} and {joint.between[1]!r} run the "
                           "same way along the line, so the plates' normals do not match a "
                           f"{joint.kind} joint; reverse one plate's frame (y_axis -> -y_axis) "
                           'or describe the line as kind = "junction"'))
        elif joint.kind == "coplanar" and float(a.normal @ b.normal) < 1.0 - FRAME_TOLERANCE:
            angle = math.degrees(math.acos(max(-1.0, min(1.0, float(a.normal @ b.normal)))))
            issues.append((loc, f"joins plates whose normals are {angle:.3g} degrees apart; a "
                           'coplanar joint needs coplanar plates, use kind = "hinge" or '
                           '"junction" for a fold'))
    return issues


def _truth_form_issues(jid: str, joint: Any, true: JointTruth) -> list[tuple[Loc, str]]:
    """A joint's truth takes the joint's form: finite numbers for a two-edge joint, numbers or
    tables by member plate for a junction."""
    issues: list[tuple[Loc, str]] = []
    if joint is None:
        return issues
    for name in ("log10_stiffness", "loss_factor"):
        value = getattr(true, name)
        loc = ("truth", "joints", jid, name)
        if value is None:
            continue
        if isinstance(joint, JunctionJoint):
            if isinstance(value, Mapping):
                issues += [(loc, f"plate {p!r} is not a member of junction {jid!r} (members: "
                            f"{', '.join(joint.plates)}); name member plates only")
                           for p in value if p not in joint.plates]
        elif isinstance(value, Mapping):
            issues.append((loc, f"joint {jid!r} is a {joint.kind} joint: give one number, not "
                           "a table by plate (tables are for junctions)"))
        elif not math.isfinite(value):
            issues.append((loc, f"joint {jid!r} is a {joint.kind} joint, whose stiffness must "
                           f"be finite (got {value!r}); give a number in [-50, 50]"))
    return issues


def cross_check(view: View) -> list[tuple[Loc, str]]:
    """Return every cross-reference problem of an assembly, as ``(loc, message)``."""
    return _CrossCheck(view).run()


class _CrossCheck:
    """The cross-reference checks of one :class:`View`, one method per table, in the order the
    tables depend on each other (joints before the boundaries and loads on their edges); each
    appends ``(loc, message)`` to :attr:`issues`."""

    def __init__(self, view: View) -> None:
        self.view = view
        self.issues: list[tuple[Loc, str]] = []
        self.plates = view.plates
        self.plate_list = listing(self.plates) if self.plates is not None else ""
        self.joints = view.joints
        self.joint_list = listing(self.joints) if self.joints is not None else ""
        self.joined: dict[EdgeId, str] = {}
        self.conditions: dict[EdgeId, tuple[str, int]] = {}

    def run(self) -> list[tuple[Loc, str]]:
        self.frequencies()
        self.materials()
        self.joints_()
        self.boundaries()
        self.moving_lines()
        self.loads()
        self.discretisation()
        self.measurement()
        self.updating()
        self.truth()
        return self.issues

    def edge_of(self, ref: str, loc: Loc) -> tuple[EdgeId, Plate] | None:
        """Resolve an (already well-formed) edge reference; report an unknown plate."""
        if self.plates is None:
            return None
        edge = parse_edge_ref(ref)
        if edge.plate not in self.plates:
            self.issues.append(
                (
                    loc,
                    f"plate {edge.plate!r} is not in the assembly (plates: {self.plate_list})"
                    f"{did_you_mean(edge.plate, self.plates)}; fix the edge reference",
                )
            )
            return None
        plate = self.plates[edge.plate]
        return None if plate is None else (edge, plate)

    def known_plate(self, plate_id: str, loc: Loc, fix: str) -> Plate | None:
        if self.plates is None:
            return None
        if plate_id not in self.plates:
            self.issues.append(
                (
                    loc,
                    f"plate {plate_id!r} is not in the assembly (plates: {self.plate_list})"
                    f"{did_you_mean(plate_id, self.plates)}; {fix}",
                )
            )
            return None
        return self.plates[plate_id]

    def known_joint(self, jid: str, loc: Loc, fix: str) -> bool:
        if self.joints is None:
            return False
        if jid not in self.joints:
            where = f"joints: {self.joint_list}" if self.joints else "the assembly has no joints"
            self.issues.append(
                (
                    loc,
                    f"joint {jid!r} is not in the assembly ({where})"
                    f"{did_you_mean(jid, self.joints)}; {fix}",
                )
            )
            return False
        return True

    def frequencies(self) -> None:
        """``frequency`` or ``frequencies``, one of them."""
        if self.view.has_frequency and self.view.has_frequencies:
            self.issues.append(
                (("frequencies",), "both `frequency` and `frequencies` are given; keep only one")
            )
        elif not (self.view.has_frequency or self.view.has_frequencies):
            self.issues.append(
                (
                    ("frequency",),
                    "no frequency given; add frequency = 155.0 (Hz) or "
                    "frequencies = [150.0, 155.0]",
                )
            )

    def materials(self) -> None:
        """Each plate's material is defined."""
        if self.plates is not None and self.view.materials is not None:
            for pid, plate in self.plates.items():
                if (
                    plate is not None
                    and isinstance(plate.material, str)
                    and plate.material not in self.view.materials
                ):
                    m = plate.material
                    self.issues.append(
                        (
                            ("plates", pid, "material"),
                            f"material {m!r} is not defined "
                            f"(materials: {listing(self.view.materials)})"
                            f"{did_you_mean(m, self.view.materials)}; add a [materials.{m}] table "
                            "or use a defined material",
                        )
                    )

    def joints_(self) -> None:
        """Each joint's edges exist, carry no other joint, and fit its members and frames."""
        if self.view.joints is not None:
            for jid, joint in self.view.joints.items():
                if joint is None:
                    continue
                loc = ("joints", jid, "between")
                ids = [parse_edge_ref(ref) for ref in joint.between]
                ends = [self.edge_of(ref, (*loc, i)) for i, ref in enumerate(joint.between)]
                self.issues += _member_issues(jid, joint, ids, ends, loc)
                for i, edge in enumerate(ids):
                    if edge in ids[:i]:
                        continue
                    if edge in self.joined:
                        self.issues.append(
                            (
                                (*loc, i),
                                f"edge {edge.ref!r} is already joined by joint "
                                f"{self.joined[edge]!r}; "
                                "an edge carries at most one joint, fix the edge reference or "
                                "remove one of the joints",
                            )
                        )
                    else:
                        self.joined[edge] = jid
            if self.plates is not None:
                self.issues += _frame_issues(self.view.joints, self.plates)

    def boundaries(self) -> None:
        """Each boundary condition's edge exists, is not joined and has one condition."""
        if self.view.boundaries is not None:
            for i, bc in enumerate(self.view.boundaries):
                if bc is None:
                    continue
                loc = ("boundaries", i, "edge")
                self.edge_of(bc.edge, loc)
                edge = parse_edge_ref(bc.edge)
                if edge in self.joined:
                    self.issues.append(
                        (
                            loc,
                            f"edge {bc.edge!r} is joined by joint {self.joined[edge]!r}, so "
                            "it cannot "
                            "also have a boundary condition; remove this [[boundaries]] entry "
                            "(or the joint)",
                        )
                    )
                if edge in self.conditions:
                    cond, j = self.conditions[edge]
                    self.issues.append(
                        (
                            loc,
                            f"edge {bc.edge!r} already has a boundary condition ({cond} in "
                            f"boundaries[{j}]); give each edge one condition, remove one entry",
                        )
                    )
                else:
                    self.conditions[edge] = (bc.condition, i)

    def moving_lines(self) -> None:
        """A line that must move (``held = false``) has framed members, and translational
        springs sit on moving lines with at least one member rigid in translation
        (:mod:`assembly.lines`). What one joint decides alone is checked on every valid joint
        whatever else is wrong; whether a line moves by default needs every joint, plate and
        boundary valid, and is checked then."""
        joints, plates = self.view.joints or {}, self.plates or {}
        known = {jid: joint for jid, joint in joints.items()
                 if isinstance(joint, (HingeJoint, JunctionJoint))}
        for jid, joint in known.items():
            springs, loc = joint.translational_springs(), ("joints", jid,
                                                           "log10_translational_stiffness")
            if springs and len(springs) == len(joint.plates):
                self.issues.append((loc, "every member has a translational spring; leave at "
                                    "least one member rigid in translation (inf): the line "
                                    "translates with it"))
            if joint.held is True and springs:
                self.issues.append((loc, _HELD_SPRINGS.format(jid=jid)))
            damped = [p for p in joint.plates if joint.member_translational_loss_factor(p) > 0
                      and p not in springs]
            if damped and (isinstance(joint.translational_loss_factor, Mapping) or not springs):
                self.issues.append((("joints", jid, "translational_loss_factor"),
                                    f"member(s) {', '.join(damped)} have a translational "
                                    "loss factor but no translational spring (rigid), so it "
                                    "would do nothing; give the spring "
                                    "(log10_translational_stiffness) or remove the loss "
                                    "factor"))
            if joint.held is not False or any(plates.get(p) is None for p in joint.plates):
                continue
            unframed = [p for p in joint.plates if plates[p].frame is None]
            if unframed:
                self.issues.append((("joints", jid, "held"),
                                    f"a moving line needs a frame on every member plate; "
                                    f"add [plates.{unframed[0]}.frame], or set held = true"))
        if (self.issues or not joints or not plates or None in joints.values()
                or None in plates.values()):
            return
        boundaries = [bc for bc in self.view.boundaries or () if bc is not None]
        moving = set(lines_that_move(joints, plates, boundaries))
        for jid, joint in known.items():
            if joint.held is None and joint.translational_springs() and jid not in moving:
                self.issues.append((("joints", jid, "log10_translational_stiffness"),
                                    _HELD_SPRINGS.format(jid=jid)))

    def loads(self) -> None:
        """Each load's plate or edge exists, and an edge load acts where the edge lets it."""
        edge_loads: dict[tuple[EdgeId, str], int] = {}
        if self.view.loads is not None:
            for i, load in enumerate(self.view.loads):
                if load is None:
                    continue
                if isinstance(load, PointForce):
                    plate = self.known_plate(load.plate, ("loads", i, "plate"), "fix the plate id")
                    if plate is not None and not plate.contains(*load.at):
                        x, y = load.at
                        self.issues.append(
                            (
                                ("loads", i, "at"),
                                f"point ({x:g}, {y:g}) is not strictly inside plate "
                                f"{load.plate!r} (0 < x < {plate.lx:g}, 0 < y < {plate.ly:g}, "
                                "plate-local m); move the force inside the plate",
                            )
                        )
                    continue
                loc = ("loads", i, "edge")
                self.edge_of(load.edge, loc)
                edge = parse_edge_ref(load.edge)
                if (edge, load.kind) in edge_loads:
                    self.issues.append(
                        (
                            loc,
                            f"edge {load.edge!r} already carries an {load.kind} load "
                            f"(loads[{edge_loads[edge, load.kind]}]); give one {load.kind} per "
                            "edge, e.g. with the amplitudes summed",
                        )
                    )
                edge_loads.setdefault((edge, load.kind), i)
                cond = self.conditions.get(edge, ("free", -1))[0]
                if isinstance(load, EdgeShear):
                    if edge in self.joined:
                        why = (f"joined by joint {self.joined[edge]!r}, which sets its "
                               "Kirchhoff shear K_n")
                    elif cond in ("clamped", "simply_supported"):
                        state = cond.replace("_", " ")
                        why = f"{state}: w = 0 there, so its Kirchhoff shear K_n is a reaction"
                    else:
                        why = None
                    if why:
                        self.issues.append(
                            (
                                loc,
                                f"an edge_shear load cannot act on edge {load.edge!r}: the edge "
                                f"is {why}; load a free edge or use a point_force",
                            )
                        )
                else:
                    if edge in self.joined:
                        why = (f"joined by joint {self.joined[edge]!r}, which sets its "
                               "bending moment M_n")
                    elif cond in ("clamped", "symmetric"):
                        why = (f"{cond}: its rotation is fixed, so its bending moment M_n is "
                               "a reaction")
                    else:
                        why = None
                    if why:
                        self.issues.append(
                            (
                                loc,
                                f"an edge_moment load cannot act on edge {load.edge!r}: the edge "
                                f"is {why}; load a free or simply supported edge",
                            )
                        )

    def discretisation(self) -> None:
        """Each plate-specific discretisation names a plate."""
        if self.view.discretisation is not None:
            for pid in self.view.discretisation.plates:
                self.known_plate(
                    pid, ("discretisation", "plates", pid), "fix the plate id or remove the table"
                )

    def measurement(self) -> None:
        """Measured plates and points exist, are distinct and off the grid's points."""
        if self.view.measurement is not None:
            seen: set[str] = set()
            for i, pid in enumerate(self.view.measurement.plates or ()):
                self.known_plate(pid, ("measurement", "plates", i), "fix the plate id")
                if pid in seen:
                    self.issues.append(
                        (("measurement", "plates", i),
                         f"plate {pid!r} is listed twice; list it once")
                    )
                seen.add(pid)
            gridded = set(self.plates or ()) if self.view.measurement.plates is None else seen
            spacing = self.view.measurement.spacing or default_spacing(self.plates or {})
            earlier: dict[tuple[str, float, float], str] = {}
            for i, point in enumerate(self.view.measurement.points):
                plate = self.known_plate(
                    point.plate, ("measurement", "points", i, "plate"), "fix the plate id"
                )
                x, y = point.at
                if plate is not None and not plate.contains(x, y, strict=False):
                    self.issues.append(
                        (
                            ("measurement", "points", i, "at"),
                            f"point ({x:g}, {y:g}) is outside plate {point.plate!r} "
                            f"(0 <= x <= {plate.lx:g}, 0 <= y <= {plate.ly:g}, plate-local m); "
                            "move the point onto the plate",
                        )
                    )
                    continue
                key = (point.plate, round(x, 9), round(y, 9))
                twin = earlier.get(key)
                if twin is None and plate is not None and point.plate in gridded:
                    if on_grid(plate.size, spacing, x, y):
                        twin = "a point of the measurement grid"
                if twin is not None:
                    self.issues.append(
                        (
                            ("measurement", "points", i, "at"),
                            f"point ({x:g}, {y:g}) of plate {point.plate!r} is already "
                            f"{twin}; a point is measured once, remove this one",
                        )
                    )
                earlier.setdefault(key, f"measurement.points[{i}]")
            measured = self.view.measurement
            if measured.plates is not None and not measured.plates and not (
                measured.points
            ):
                self.issues.append(
                    (
                        ("measurement", "plates"),
                        "is empty and no `points` are given, so nothing is measured; list the "
                        'measured plates, e.g. plates = ["P1"], or add points = [{plate = "P1", '
                        "at = [0.1, 0.2]}]",
                    )
                )

    def updating(self) -> None:
        """Each joint weight names a joint, and the weights do not all vanish."""
        if self.view.updating is not None and self.view.updating.alpha is not None:
            alpha = self.view.updating.alpha
            all_known = True
            for jid in alpha:
                all_known &= self.known_joint(
                    jid, ("updating", "alpha", jid), "fix the joint id or remove its weight"
                )
            if all_known and self.joints and sum(alpha.get(j, 1.0) for j in self.joints) <= 0.0:
                self.issues.append(
                    (
                        ("updating", "alpha"),
                        "the joint weights sum to 0; give at least one joint a positive weight "
                        "(joints not listed weigh 1)",
                    )
                )

    def truth(self) -> None:
        """Each ``[truth]`` table names a joint and gives what that joint can have."""
        if self.view.truth is not None:
            for jid, true in self.view.truth.joints.items():
                loc = ("truth", "joints", jid)
                if not self.known_joint(jid, loc, "fix the joint id or remove its table"):
                    continue
                joint = self.joints[jid] if self.joints is not None else None
                self.issues += _truth_form_issues(jid, joint, true)
                if isinstance(joint, (HingeJoint, JunctionJoint)) and true.mass is not None:
                    self.issues.append(
                        (
                            (*loc, "mass"),
                            f"joint {jid!r} is a {joint.kind}, which has no line mass (its joint "
                            "line is fixed); remove `mass`",
                        )
                    )
        return self.issues
