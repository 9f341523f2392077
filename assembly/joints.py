r"""Validated, immutable models of the joints of an assembly description (``[joints.ID]``).

A joint ties plate edges of equal length: a ``coplanar`` joint two edges in one plane, free
in translation and tied in rotation by a spring (with an optional line mass); a ``hinge``
two edges on a line held in translation; a ``junction`` two or more edges on one line held in
translation, each member tied to the line's rotation by its own spring (a stiffener, an inner
wall). The joint laws are in ``docs/method.md`` section 6.2; the fields in
``docs/description.md``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Annotated, Any, Literal, Union

from pydantic import Field, PlainValidator, Strict, WithJsonSchema

from .types import (
    EdgeId,
    EdgeRef,
    FrozenDict,
    FrozenModel,
    LogStiffness,
    NonNegative,
    check_id,
    is_real,
    parse_edge_ref,
    show_value,
)

__all__ = ["CoplanarJoint", "HingeJoint", "Joint", "JunctionJoint"]


class _JointBase(FrozenModel):
    between: tuple[EdgeRef, EdgeRef]
    log10_stiffness: LogStiffness
    loss_factor: NonNegative = 0.0

    @property
    def stiffness(self) -> float:
        """Rotational stiffness per unit length ``k = 10**log10_stiffness``, N·m/m per rad."""
        return float(10.0**self.log10_stiffness)

    @property
    def complex_stiffness(self) -> complex:
        """Complex rotational stiffness ``k (1 + j zeta)``, N·m/m per rad."""
        return self.stiffness * complex(1.0, self.loss_factor)

    @property
    def sides(self) -> tuple[EdgeId, EdgeId]:
        """The two joined edges, in the order of ``between``."""
        a, b = self.between
        return parse_edge_ref(a), parse_edge_ref(b)

    @property
    def plates(self) -> tuple[str, str]:
        """The two joined plates, in the order of ``between``."""
        a, b = self.sides
        return a.plate, b.plate

    def parameters(self) -> dict[str, float]:
        """Return the updatable parameters, ``{"log10_stiffness": ..., "loss_factor": ...}``.

        Coplanar joints also give ``"mass"``.
        """
        return {"log10_stiffness": self.log10_stiffness, "loss_factor": self.loss_factor}


class CoplanarJoint(_JointBase):
    r"""A coplanar joint: rigid in translation, a rotational spring between the edges.

    On the joint line :math:`w_A = w_B`,
    :math:`M_n^A = M_n^B = k(1 + j\zeta)(\theta_A + \theta_B)` with
    :math:`\theta = \partial w / \partial n` (each plate's outward normal) and
    :math:`K_n^A + K_n^B = \omega^2 \mu w`.

    Parameters
    ----------
    kind : "coplanar"
        Discriminator.
    between : tuple of str, shape (2,)
        The two joined edges, ``["P1.right", "P2.left"]``, of equal length.
    log10_stiffness : float
        :math:`\log_{10} k`, with :math:`k` the rotational stiffness per unit length
        in N·m/m per rad (= N); in [-50, 50].
    loss_factor : float, optional
        Joint loss factor :math:`\zeta` >= 0.  Default 0.
    mass : float, optional
        Line mass :math:`\mu` of the joint in kg/m, >= 0.  Default 0.
    """

    kind: Literal["coplanar"] = "coplanar"
    mass: NonNegative = 0.0

    def parameters(self) -> dict[str, float]:
        """Return ``{"log10_stiffness", "loss_factor", "mass"}`` of the joint."""
        return {**super().parameters(), "mass": self.mass}


class HingeJoint(_JointBase):
    r"""A hinge (fold) joint: two edges on one line, rotations coupled by a spring.

    :math:`M_n^A = M_n^B = k(1 + j\zeta)(\theta_A + \theta_B)`. Held (the paper's fold on
    needles), :math:`w_A = w_B = 0` on the line; moving, the line translates as one body
    with both edges (``docs/method.md`` section 10.4). A hinge has no line mass (:attr:`mass`
    is always 0).

    Parameters
    ----------
    kind : "hinge"
        Discriminator.
    between : tuple of str, shape (2,)
        The two joined edges, of equal length.
    log10_stiffness : float
        :math:`\log_{10} k`, k in N·m/m per rad (= N); in [-50, 50].
    loss_factor : float, optional
        Joint loss factor :math:`\zeta` >= 0.  Default 0.
    held : bool, optional
        ``true``: the fold is held in translation (a support along it, as the paper's
        needles). ``false``: it moves, as a junction line of two members, the first rigid and
        the second on the hinge's spring (``docs/method.md`` section 10.4), which needs frames.
        Default: it moves between framed, non-coplanar plates, as a junction line does, else
        it is held.
    """

    kind: Literal["hinge"] = "hinge"
    held: Annotated[bool, Strict()] | None = None

    # A moving hinge is a junction line of two members: the first rigid, the second tied to the
    # line's rotation by the hinge's spring (M_n = k (theta_A + theta_B), the same law). These
    # give the line's rules (solver.channels.junction_line) what they read of a junction.
    def member_log10_stiffness(self, plate: str) -> float:
        r"""``inf`` (rigid) for the first plate, the hinge's :math:`\log_{10}k` for the second."""
        return math.inf if plate == self.plates[0] else self.log10_stiffness

    def member_loss_factor(self, plate: str) -> float:
        """0 for the first (rigid) plate, the hinge's loss factor for the second."""
        return 0.0 if plate == self.plates[0] else self.loss_factor

    def member_log10_translational_stiffness(self, plate: str) -> float:
        """``inf``: both members move with the line."""
        return math.inf

    def member_translational_loss_factor(self, plate: str) -> float:
        """0: no translational spring."""
        return 0.0

    def translational_springs(self) -> tuple[str, ...]:
        """None: both members move with the line."""
        return ()

    def finite_members(self) -> tuple[str, ...]:
        """The second plate: the hinge's spring ties it to the first."""
        return (self.plates[1],)

    @property
    def mass(self) -> float:
        """Line mass of a hinge: always 0 kg/m."""
        return 0.0


def _member_stiffness(value: object, where: str = "", unit: str = "N") -> float:
    if not is_real(value) and not (isinstance(value, float) and math.isinf(value)):
        raise ValueError(f"{where}must be a number (log10 of k in {unit}) or inf (rigid), "
                         f"got {show_value(value)}")
    value = float(value)  # type: ignore[arg-type]
    if math.isnan(value):
        raise ValueError(f"{where}must be a number in [-50, 50] or inf (rigid), got nan; "
                         "write a number, e.g. 2.0")
    if value == -math.inf:
        raise ValueError(f"{where}must be a number in [-50, 50] or inf (rigid), got -inf;"
                         " a member that carries nothing is not a member: remove its edge")
    if math.isfinite(value) and not -50.0 <= value <= 50.0:
        raise ValueError(f"{where}must be in [-50, 50] or inf (rigid), got {value!r}")
    return value


def _member_loss_factor(value: object, where: str = "") -> float:
    if not is_real(value) or not 0.0 <= float(value) < math.inf:  # type: ignore[arg-type]
        raise ValueError(f"{where}must be a finite number >= 0, got {show_value(value)}")
    return float(value)  # type: ignore[arg-type]


def _per_member(check: Any) -> Any:
    """Validator of a value given for every member or as a table by member plate."""

    def validate(value: object) -> Any:
        if isinstance(value, Mapping):
            return FrozenDict({check_id(str(plate)): check(v, f"member {plate!r}: ")
                               for plate, v in value.items()})
        return check(value)

    return validate


def _member_schema(item: dict[str, Any]) -> Any:
    return WithJsonSchema({"anyOf": [item, {"type": "object", "additionalProperties": item}]})

MemberStiffness = Annotated[
    Any, PlainValidator(_per_member(_member_stiffness)),
    _member_schema({"type": "number", "description": "log10 k in [-50, 50], or inf (rigid)"}),
]
"""log10 of a junction's member stiffness: one number (``inf``: rigid) or a table by plate."""

MemberTranslationalStiffness = Annotated[
    Any, PlainValidator(_per_member(
        lambda value, where="": _member_stiffness(value, where, "N/m^2"))),
    _member_schema({"type": "number",
                    "description": "log10 k_t (N/m^2) in [-50, 50], or inf (rigid)"}),
]
"""log10 of a junction's member translational stiffness: one number (``inf``: rigid) or a
table by plate (members it does not name: rigid)."""

MemberLossFactor = Annotated[
    Any, PlainValidator(_per_member(_member_loss_factor)),
    _member_schema({"type": "number", "minimum": 0}),
]
"""A junction's member loss factor: one number >= 0 or a table by plate."""


class JunctionJoint(FrozenModel):
    r"""A junction line: two or more plate edges on one line, held in translation or moving.

    Held (``held = true``): :math:`w_i = 0` on every member. Moving (``held = false``, the
    default between non-coplanar plates where the model can; ``docs/method.md`` section
    10.4): the line translates as one body, every
    member's edge displacement :math:`(u_n, u_t, w)` mapped through its frame equal to the
    line's, and the forces the members exert on it balance; each member carries in-plane
    (membrane) waves besides its bending. Either way the line has its own rotation
    :math:`\Theta_J` and member :math:`i` is tied to it by a rotational spring,
    :math:`C_i = k_i(1 + j\zeta_i)(\Theta_J - \Theta_i)` (the moment per unit length of the
    line on the member), with :math:`\sum_i C_i = 0` (a massless line).  Rotations are about
    the line, signs from the members' frames (``docs/method.md`` section 6.2b).  A rigid member
    (``inf``) has :math:`\Theta_i = \Theta_J`.  Two members of stiffness :math:`2k` are a
    ``hinge`` of stiffness :math:`k`.

    Parameters
    ----------
    kind : "junction"
        Discriminator.
    between : tuple of str
        The member edges, two or more, of equal length and (with frames) on one line.  Three
        or more members need a ``frame`` on every member plate.
    log10_stiffness : float or mapping of str to float
        One :math:`\log_{10} k` for every member, or a table by member plate, e.g.
        ``{ S1 = inf, S2 = inf, T1 = 2.0 }``; ``inf`` is a rigid member.
    loss_factor : float or mapping of str to float, optional
        :math:`\zeta` >= 0, one for every member or a table by member plate.  Default 0.
    held : bool, optional
        ``true``: the line is held in translation. ``false``: it moves; every member plate
        needs a ``frame`` (:mod:`assembly.lines`). Default: it moves when its members are not
        coplanar and the model can move it, else it is held.
    log10_translational_stiffness : float or mapping of str to float, optional
        On a moving line, :math:`\log_{10}k_{t,i}` (:math:`k_t` in N/m², force per unit length
        per unit displacement) of a translational spring between member :math:`i` and the
        line, :math:`\mathbf f_i = k_{t,i}(1 + j\zeta_{t,i})(\mathbf X_J - \mathbf X_i)`
        (isotropic; :math:`\mathbf f_i` the force per unit length of the line on the member,
        :math:`\mathbf X` the displacements), one for every member or a table by member
        plate (members it does not name: ``inf``, rigid). Default ``inf``: every member moves
        with the line. At least one member stays rigid: the line's translation is the first
        such member's (``docs/method.md`` section 10.4).
    translational_loss_factor : float or mapping of str to float, optional
        :math:`\zeta_{t,i}` >= 0 of those springs.  Default 0.
    """

    kind: Literal["junction"] = "junction"
    between: Annotated[tuple[EdgeRef, ...], Field(min_length=2)]
    log10_stiffness: MemberStiffness
    loss_factor: MemberLossFactor = 0.0
    held: Annotated[bool, Strict()] | None = None
    log10_translational_stiffness: MemberTranslationalStiffness = math.inf
    translational_loss_factor: MemberLossFactor = 0.0

    @property
    def sides(self) -> tuple[EdgeId, ...]:
        """The member edges, in the order of ``between``."""
        return tuple(parse_edge_ref(ref) for ref in self.between)

    @property
    def plates(self) -> tuple[str, ...]:
        """The member plates, in the order of ``between``."""
        return tuple(side.plate for side in self.sides)

    @property
    def mass(self) -> float:
        """Line mass of a junction: always 0 kg/m (a massless line)."""
        return 0.0

    def member_log10_stiffness(self, plate: str) -> float:
        r""":math:`\log_{10} k_i` of the member on ``plate`` (``inf``: rigid)."""
        value = self.log10_stiffness
        return value[plate] if isinstance(value, Mapping) else value

    def member_loss_factor(self, plate: str) -> float:
        r""":math:`\zeta_i` of the member on ``plate``."""
        value = self.loss_factor
        return value.get(plate, 0.0) if isinstance(value, Mapping) else value

    def member_log10_translational_stiffness(self, plate: str) -> float:
        r""":math:`\log_{10} k_{t,i}` of the member on ``plate`` (``inf``: rigid in
        translation)."""
        value = self.log10_translational_stiffness
        return value.get(plate, math.inf) if isinstance(value, Mapping) else value

    def member_translational_loss_factor(self, plate: str) -> float:
        r""":math:`\zeta_{t,i}` of the member on ``plate``."""
        value = self.translational_loss_factor
        return value.get(plate, 0.0) if isinstance(value, Mapping) else value

    def translational_springs(self) -> tuple[str, ...]:
        """The member plates tied to the line's translation by a finite spring."""
        return tuple(p for p in self.plates
                     if math.isfinite(self.member_log10_translational_stiffness(p)))

    def finite_members(self) -> tuple[str, ...]:
        """The member plates whose spring is finite (each one a residual channel)."""
        return tuple(p for p in self.plates if math.isfinite(self.member_log10_stiffness(p)))

    def parameters(self) -> dict[str, Any]:
        """Return ``{"log10_stiffness", "loss_factor"}`` as described (numbers or tables)."""
        return {"log10_stiffness": self.log10_stiffness, "loss_factor": self.loss_factor}

Joint = Annotated[
    Union[CoplanarJoint, HingeJoint, JunctionJoint], Field(discriminator="kind")
]
"""A joint, discriminated on ``kind``: :class:`CoplanarJoint`, :class:`HingeJoint` or
:class:`JunctionJoint`."""
