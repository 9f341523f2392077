r"""Validated, immutable models of an assembly description.

An assembly is a set of thin rectangular Kirchhoff plates joined along edges.  Each plate
occupies ``[0, Lx] x [0, Ly]`` in its own frame; its edges are ``left`` (x = 0), ``right``
(x = Lx), ``bottom`` (y = 0) and ``top`` (y = Ly), addressed as ``"PLATE.EDGE"``.
All quantities are SI (m, kg, s, N, Pa, Hz); the time convention is :math:`e^{+j\omega t}`.

This module holds the tables of a description; the whole description is
:class:`assembly.case.Case` (``docs/description.md``), and the building blocks of every table
(ids, edge references, constrained numbers, the frozen base model) are in
:mod:`assembly.types`.  Tables, each optional except ``materials`` and ``plates``:

========================  ===================================================================
``name``                  str
``frequency``             Hz, > 0 -- or ``frequencies``: list of distinct values > 0
``[materials.ID]``        :class:`Material`
``[plates.ID]``           :class:`Plate`
``[joints.ID]``           :class:`CoplanarJoint` (``kind = "coplanar"``),
                          :class:`HingeJoint` (``kind = "hinge"``) or
                          :class:`JunctionJoint` (``kind = "junction"``)
``[[boundaries]]``        :class:`Boundary`; edges neither joined nor listed are free
``[[loads]]``             :class:`EdgeShear`, :class:`EdgeMoment` or :class:`PointForce`
``[discretisation]``      :class:`Discretisation` (ray counts)
``[measurement]``         :class:`Measurement` (simulated or real measurement grid)
``[updating]``            :class:`Updating` (localisation--correction settings)
``[compute]``             :class:`Compute` (where independent tasks run)
``[truth.joints.ID]``     :class:`JointTruth` ("true" joint parameters of a simulated test)
========================  ===================================================================

Every model is frozen (``ConfigDict(extra="forbid", frozen=True)``) and its tables are
read-only mappings; derived assemblies are built by copy, e.g.
:meth:`assembly.case.Case.with_joint_parameters`.  Cross-references (materials, plates, edges,
joints) are checked once by the validator of :class:`~assembly.case.Case`, which reports every
problem at once.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Annotated, Any, Literal, Union

import numpy as np
from pydantic import (
    AfterValidator,
    Field,
    PlainValidator,
    Strict,
    WithJsonSchema,
    model_validator,
)

from .errors import AssemblyError, did_you_mean, format_path
from .types import (
    EDGE_NAMES,
    Complex,
    EdgeId,
    EdgeRef,
    FrozenDict,
    FrozenModel,
    LogStiffness,
    NonNegative,
    PoissonRatio,
    Positive,
    Real,
    check_id,
    check_material_loss_factor,
    is_real,
    parse_edge_ref,
    show_value,
)

__all__ = [
    "Boundary",
    "CoplanarJoint",
    "EdgeMoment",
    "EdgeShear",
    "HingeJoint",
    "Joint",
    "JunctionJoint",
    "Load",
    "Material",
    "Plate",
    "PlateFrame",
    "PointForce",
]

# --------------------------------------------------------------------------------------
# Materials and plates
# --------------------------------------------------------------------------------------
class Material(FrozenModel):
    r"""An isotropic, hysteretically damped plate material.

    Parameters
    ----------
    young_modulus : float
        Young's modulus :math:`E` in Pa, > 0.
    poisson_ratio : float
        Poisson's ratio :math:`\nu`, in (-1, 0.5).
    density : float
        Mass density :math:`\rho` in kg/m^3, > 0.
    loss_factor : float
        Structural loss factor :math:`\eta` (dimensionless), > 0: the complex rigidity is
        :math:`D^* = D(1 + j\eta)`.  The VTCR needs :math:`\eta > 0`, which makes every plate
        problem uniquely solvable.
    """

    young_modulus: Positive
    poisson_ratio: PoissonRatio
    density: Positive
    loss_factor: Annotated[float, Strict(), AfterValidator(check_material_loss_factor)]

    def flexural_rigidity(self, thickness: float) -> float:
        r"""Return the bending stiffness :math:`D = E h^3 / (12 (1 - \nu^2))` in N·m.

        Parameters
        ----------
        thickness : float
            Plate thickness :math:`h` in m.

        Returns
        -------
        float
            :math:`D` in N·m (without damping).

        Examples
        --------
        >>> steel = Material(young_modulus=210e9, poisson_ratio=0.3, density=7800.0,
        ...                  loss_factor=0.01)
        >>> round(steel.flexural_rigidity(0.002), 2)
        153.85
        """
        return self.young_modulus * thickness**3 / (12.0 * (1.0 - self.poisson_ratio**2))

    def bending_wavenumber(self, thickness: float, frequency: Any) -> Any:
        r"""Return the undamped bending wavenumber :math:`\kappa_0` in rad/m.

        .. math:: \kappa_0^4 = \rho h \omega^2 / D, \qquad \omega = 2 \pi f

        Parameters
        ----------
        thickness : float
            Plate thickness :math:`h` in m.
        frequency : float or array_like of float, shape (n,)
            Frequency :math:`f` in Hz.

        Returns
        -------
        float or ndarray of float, shape (n,)
            :math:`\kappa_0` in rad/m.

        Examples
        --------
        >>> steel = Material(young_modulus=210e9, poisson_ratio=0.3, density=7800.0,
        ...                  loss_factor=0.01)
        >>> round(float(steel.bending_wavenumber(0.002, 500.0)), 2)
        31.63
        """
        omega = 2.0 * np.pi * np.asarray(frequency, dtype=float)
        kappa = (self.density * thickness * omega**2 / self.flexural_rigidity(thickness)) ** 0.25
        return float(kappa) if kappa.ndim == 0 else kappa

    def bending_wavelength(self, thickness: float, frequency: Any) -> Any:
        r"""Return the bending wavelength :math:`\lambda = 2\pi/\kappa_0` in m.

        Parameters
        ----------
        thickness : float
            Plate thickness :math:`h` in m.
        frequency : float or array_like of float, shape (n,)
            Frequency in Hz.

        Returns
        -------
        float or ndarray of float, shape (n,)
            Wavelength in m.

        Examples
        --------
        >>> steel = Material(young_modulus=210e9, poisson_ratio=0.3, density=7800.0,
        ...                  loss_factor=0.01)
        >>> round(float(steel.bending_wavelength(0.002, 500.0)), 3)
        0.199
        """
        return 2.0 * np.pi / self.bending_wavenumber(thickness, frequency)


FRAME_TOLERANCE = 1e-6
"""Tolerance of the frames' orthonormality and of the coincidence of joined edges, relative
to 1 (axes) or to the edge length (positions)."""


def _unit(vector: tuple[float, float, float]) -> np.ndarray:
    return np.asarray(vector, dtype=float)


class PlateFrame(FrozenModel):
    r"""Placement of a plate in 3D: its local ``x``, ``y`` along ``x_axis``, ``y_axis``.

    A plate-local point :math:`(x, y)` is at :math:`\mathbf o + x\,\mathbf e_x + y\,\mathbf e_y`
    and its deflection :math:`w` is along :math:`\mathbf e_z = \mathbf e_x\times\mathbf e_y`.

    Parameters
    ----------
    origin : tuple of float, shape (3,)
        Position of the plate's local origin, m.
    x_axis : tuple of float, shape (3,)
        Direction of the local x axis, a unit vector (to 1e-6).
    y_axis : tuple of float, shape (3,)
        Direction of the local y axis, a unit vector normal to ``x_axis`` (to 1e-6).
    """

    origin: tuple[Real, Real, Real]
    x_axis: tuple[Real, Real, Real]
    y_axis: tuple[Real, Real, Real]

    @model_validator(mode="after")
    def _check_orthonormal(self) -> PlateFrame:
        ex, ey = _unit(self.x_axis), _unit(self.y_axis)
        for name, axis in (("x_axis", ex), ("y_axis", ey)):
            if abs(float(np.linalg.norm(axis)) - 1.0) > FRAME_TOLERANCE:
                raise ValueError(
                    f"{name} {axis.tolist()} has length {np.linalg.norm(axis):.6g}, not 1; "
                    "give unit vectors, e.g. x_axis = [1, 0, 0], y_axis = [0, 0, 1]"
                )
        if abs(float(ex @ ey)) > FRAME_TOLERANCE:
            raise ValueError(
                f"x_axis and y_axis are not orthogonal (dot product {float(ex @ ey):.3g}); "
                "give perpendicular unit vectors, e.g. x_axis = [1, 0, 0], y_axis = [0, 0, 1]"
            )
        return self

    @property
    def normal(self) -> np.ndarray:
        r""":math:`\mathbf e_z = \mathbf e_x\times\mathbf e_y`, the direction of ``w``."""
        return np.cross(_unit(self.x_axis), _unit(self.y_axis))

    def to_space(self, x: Any, y: Any) -> np.ndarray:
        """3D positions (m) of plate-local points, shape ``(..., 3)``."""
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        return (_unit(self.origin) + x[..., None] * _unit(self.x_axis)
                + y[..., None] * _unit(self.y_axis))

    def to_space_vector(self, vector: Any) -> np.ndarray:
        """A plate-local in-plane vector ``(vx, vy)`` as a 3D vector."""
        return vector[0] * _unit(self.x_axis) + vector[1] * _unit(self.y_axis)


class Plate(FrozenModel):
    """A rectangular Kirchhoff plate occupying ``[0, Lx] x [0, Ly]`` in its local frame.

    Parameters
    ----------
    material : str
        Id of a ``[materials.ID]`` table.
    thickness : float
        Thickness :math:`h` in m, > 0.
    size : tuple of float, shape (2,)
        ``[Lx, Ly]`` in m, both > 0.
    origin : tuple of float, shape (2,), optional
        Position of the local origin in the assembly plane, m (plots only).  Default (0, 0).
    rotation : float, optional
        Rotation of the local frame in the assembly plane, degrees counter-clockwise
        (plots only).  Default 0.
    frame : PlateFrame, optional
        Placement in 3D (:class:`PlateFrame`).  Joined edges of framed plates must coincide
        in space, and the members of a junction line take their orientations from their
        frames.  Without it the assembly is described unrolled in a plane.
    """

    material: str
    thickness: Positive
    size: tuple[Positive, Positive]
    origin: tuple[Real, Real] = (0.0, 0.0)
    rotation: Real = 0.0
    frame: PlateFrame | None = None

    @property
    def lx(self) -> float:
        """Length along the local x axis, m."""
        return self.size[0]

    @property
    def ly(self) -> float:
        """Length along the local y axis, m."""
        return self.size[1]

    @property
    def area(self) -> float:
        """Area ``Lx * Ly`` in m^2."""
        return self.size[0] * self.size[1]

    def edge_length(self, edge: str) -> float:
        """Return the length of an edge in m (``Ly`` for left/right, ``Lx`` for bottom/top).

        Parameters
        ----------
        edge : {"left", "right", "bottom", "top"}
            Edge name.

        Returns
        -------
        float
            Edge length in m.

        Raises
        ------
        AssemblyError
            If `edge` is not an edge name.
        """
        if edge in ("left", "right"):
            return self.size[1]
        if edge in ("bottom", "top"):
            return self.size[0]
        raise AssemblyError(
            f"{edge!r} is not an edge name ({', '.join(EDGE_NAMES)})"
            f"{did_you_mean(str(edge), EDGE_NAMES)}"
        )

    def edge_frame(self, edge: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
        r"""Return the geometry of an edge, traversed counter-clockwise.

        The boundary runs counter-clockwise, so the tangent is
        :math:`\mathbf t = \mathbf e_z \times \mathbf n = (-n_y, n_x)`:
        bottom from (0, 0), right from (Lx, 0), top from (Lx, Ly), left from (0, Ly).

        Parameters
        ----------
        edge : {"left", "right", "bottom", "top"}
            Edge name.

        Returns
        -------
        start : ndarray of float, shape (2,)
            First point of the edge (arc length s = 0), plate-local m.
        tangent : ndarray of float, shape (2,)
            Unit tangent (direction of increasing s).
        normal : ndarray of float, shape (2,)
            Outward unit normal.
        length : float
            Edge length in m.

        Examples
        --------
        >>> plate = Plate(material="steel", thickness=0.001, size=(0.5, 0.4))
        >>> start, t, n, length = plate.edge_frame("right")
        >>> start.tolist(), t.tolist(), n.tolist(), length
        ([0.5, 0.0], [0.0, 1.0], [1.0, 0.0], 0.4)
        """
        lx, ly = self.size
        frames = {
            "bottom": ((0.0, 0.0), (0.0, -1.0)),
            "right": ((lx, 0.0), (1.0, 0.0)),
            "top": ((lx, ly), (0.0, 1.0)),
            "left": ((0.0, ly), (-1.0, 0.0)),
        }
        if edge not in frames:
            self.edge_length(edge)  # raises the AssemblyError
        start, normal = frames[edge]
        n = np.array(normal)
        return np.array(start), np.array([-n[1], n[0]]) + 0.0, n, self.edge_length(edge)

    def edge_in_space(self, edge: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The 3D start and end of an edge (counter-clockwise) and its outward normal.

        Needs a :attr:`frame`.
        """
        assert self.frame is not None
        start, tangent, normal, length = self.edge_frame(edge)
        end = start + length * tangent
        return (self.frame.to_space(*start), self.frame.to_space(*end),
                self.frame.to_space_vector(normal))

    def contains(self, x: float, y: float, *, strict: bool = True) -> bool:
        """Tell whether a plate-local point lies in the plate.

        Parameters
        ----------
        x, y : float
            Plate-local coordinates in m.
        strict : bool, optional
            If True (default) the point must be strictly inside (``0 < x < Lx``,
            ``0 < y < Ly``); otherwise the edges count as inside.

        Returns
        -------
        bool
        """
        lx, ly = self.size
        if strict:
            return 0.0 < x < lx and 0.0 < y < ly
        return 0.0 <= x <= lx and 0.0 <= y <= ly

    def to_global(self, x: Any, y: Any) -> tuple[np.ndarray, np.ndarray]:
        """Map plate-local points to the assembly plane (plot layout).

        Parameters
        ----------
        x, y : array_like of float, shape (n,)
            Plate-local coordinates in m.

        Returns
        -------
        X, Y : ndarray of float, shape (n,)
            ``origin + R(rotation) @ (x, y)`` in m.
        """
        angle = math.radians(self.rotation)
        c, s = math.cos(angle), math.sin(angle)
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        return self.origin[0] + c * x - s * y, self.origin[1] + s * x + c * y


# --------------------------------------------------------------------------------------
# Joints
# --------------------------------------------------------------------------------------
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
    r"""A hinge (fold) joint: the joint line is fixed, rotations coupled by a spring.

    On the joint line :math:`w_A = w_B = 0` and
    :math:`M_n^A = M_n^B = k(1 + j\zeta)(\theta_A + \theta_B)`.  The line does not move, so a
    hinge has no line mass (:attr:`mass` is always 0).

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
    """

    kind: Literal["hinge"] = "hinge"

    @property
    def mass(self) -> float:
        """Line mass of a hinge: always 0 kg/m (its line is fixed)."""
        return 0.0


def _member_stiffness(value: object, where: str = "") -> float:
    if not is_real(value) and not (isinstance(value, float) and math.isinf(value)):
        raise ValueError(f"{where}must be a number (log10 of k in N) or inf (rigid), "
                         f"got {show_value(value)}")
    value = float(value)  # type: ignore[arg-type]
    if math.isnan(value) or value == -math.inf:
        raise ValueError(f"{where}must be a number in [-50, 50] or inf (rigid), got {value!r};"
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
MemberLossFactor = Annotated[
    Any, PlainValidator(_per_member(_member_loss_factor)),
    _member_schema({"type": "number", "minimum": 0}),
]
"""A junction's member loss factor: one number >= 0 or a table by plate."""


class JunctionJoint(FrozenModel):
    r"""A junction line: two or more plate edges on one line held in translation.

    On the line :math:`w_i = 0` on every member; the line has its own rotation
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
    """

    kind: Literal["junction"] = "junction"
    between: Annotated[tuple[EdgeRef, ...], Field(min_length=2)]
    log10_stiffness: MemberStiffness
    loss_factor: MemberLossFactor = 0.0

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
        """Line mass of a junction: always 0 kg/m (its line is fixed)."""
        return 0.0

    def member_log10_stiffness(self, plate: str) -> float:
        r""":math:`\log_{10} k_i` of the member on ``plate`` (``inf``: rigid)."""
        value = self.log10_stiffness
        return value[plate] if isinstance(value, Mapping) else value

    def member_loss_factor(self, plate: str) -> float:
        r""":math:`\zeta_i` of the member on ``plate``."""
        value = self.loss_factor
        return value.get(plate, 0.0) if isinstance(value, Mapping) else value

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


# --------------------------------------------------------------------------------------
# Boundary conditions and loads
# --------------------------------------------------------------------------------------
class Boundary(FrozenModel):
    """A boundary condition on one edge; edges neither joined nor listed are free.

    Parameters
    ----------
    edge : str
        Edge reference ``"PLATE.EDGE"``.
    condition : {"clamped", "simply_supported", "free"}
        ``clamped``: w = 0 and dw/dn = 0; ``simply_supported``: w = 0 and M_n = 0 (or a
        prescribed ``edge_moment``); ``free``: K_n = 0 and M_n = 0 (or prescribed loads).
    """

    edge: EdgeRef
    condition: Literal["clamped", "simply_supported", "free"]


class _EdgeLoad(FrozenModel):
    edge: EdgeRef
    amplitude: Complex
    distribution: Literal["uniform", "half_sine"] = "uniform"

    def profile(self, s: Any, length: float) -> np.ndarray:
        r"""Return the load along the edge.

        ``uniform``: the amplitude everywhere; ``half_sine``: ``amplitude * sin(pi s / L)``.

        Parameters
        ----------
        s : array_like of float, shape (n,)
            Arc length along the edge in m, in [0, L] (either direction: both profiles
            are symmetric).
        length : float
            Edge length :math:`L` in m.

        Returns
        -------
        ndarray of complex, shape (n,)
            The load (N/m for a shear, N·m/m for a moment).
        """
        s = np.asarray(s, dtype=float)
        if self.distribution == "uniform":
            return np.full(s.shape, self.amplitude, dtype=complex)
        return self.amplitude * np.sin(np.pi * s / length).astype(complex)


class EdgeShear(_EdgeLoad):
    """A prescribed Kirchhoff shear on an edge: ``K_n = p`` (N/m, along +w).

    Only on a free edge (clamped, simply supported and joined edges take ``K_n`` as a
    reaction).

    Parameters
    ----------
    kind : "edge_shear"
        Discriminator.
    edge : str
        Edge reference ``"PLATE.EDGE"``.
    amplitude : complex
        :math:`p` in N/m; a number or ``[re, im]``.
    distribution : {"uniform", "half_sine"}, optional
        ``half_sine`` means ``amplitude * sin(pi s / L)`` along the edge.  Default uniform.
    """

    kind: Literal["edge_shear"] = "edge_shear"


class EdgeMoment(_EdgeLoad):
    """A prescribed bending moment on an edge: ``M_n = m`` (N·m/m).

    Only on a free or simply supported edge.

    Parameters
    ----------
    kind : "edge_moment"
        Discriminator.
    edge : str
        Edge reference ``"PLATE.EDGE"``.
    amplitude : complex
        :math:`m` in N·m/m; a number or ``[re, im]``.
    distribution : {"uniform", "half_sine"}, optional
        ``half_sine`` means ``amplitude * sin(pi s / L)`` along the edge.  Default uniform.
    """

    kind: Literal["edge_moment"] = "edge_moment"


class PointForce(FrozenModel):
    """A transverse point force (N, along +w) strictly inside a plate.

    Parameters
    ----------
    kind : "point_force"
        Discriminator.
    plate : str
        Plate id.
    at : tuple of float, shape (2,)
        ``[x, y]`` in plate-local m, with ``0 < x < Lx`` and ``0 < y < Ly``.
    amplitude : complex
        Force in N; a number or ``[re, im]``.
    """

    kind: Literal["point_force"] = "point_force"
    plate: str
    at: tuple[Real, Real]
    amplitude: Complex


Load = Annotated[Union[EdgeShear, EdgeMoment, PointForce], Field(discriminator="kind")]
"""A load, discriminated on ``kind``."""


# --------------------------------------------------------------------------------------
# Cross-reference checks
# --------------------------------------------------------------------------------------
Loc = tuple[Union[str, int], ...]


class CrossReferenceError(ValueError):
    """Raised by :class:`~assembly.case.Case` validation with every cross-reference problem.

    Attributes
    ----------
    issues : list of (loc, message)
        ``loc`` is a tuple path such as ``("joints", "G2", "between", 1)``.
    """

    def __init__(self, issues: Sequence[tuple[Loc, str]]) -> None:
        self.issues = list(issues)
        super().__init__("\n".join(f"{format_path(loc)}: {msg}" for loc, msg in self.issues))


# --------------------------------------------------------------------------------------
# The assembly
# --------------------------------------------------------------------------------------
