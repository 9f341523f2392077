r"""Validated, immutable models of an assembly description.

An assembly is a set of thin rectangular Kirchhoff plates joined along edges.  Each plate
occupies ``[0, Lx] x [0, Ly]`` in its own frame; its edges are ``left`` (x = 0), ``right``
(x = Lx), ``bottom`` (y = 0) and ``top`` (y = Ly), addressed as ``"PLATE.EDGE"``.
All quantities are SI (m, kg, s, N, Pa, Hz); the time convention is :math:`e^{+j\omega t}`.

This module holds the tables of a description (the joints in :mod:`assembly.joints`); the
whole description is
:class:`assembly.case.Case` (``docs/description.md``), and the building blocks of every table
(ids, edge references, constrained numbers, the frozen base model) are in
:mod:`assembly.types`.  Tables, each optional except ``materials`` and ``plates``:

========================  ===================================================================
``name``                  str
``frequency``             Hz, > 0 -- or ``frequencies``: list of distinct values > 0
``[materials.ID]``        :class:`Material`
``[plates.ID]``           :class:`Plate`
``[joints.ID]``           :class:`~assembly.joints.CoplanarJoint` (``kind = "coplanar"``),
                          :class:`~assembly.joints.HingeJoint` (``kind = "hinge"``) or
                          :class:`~assembly.joints.JunctionJoint` (``kind = "junction"``)
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
from typing import Annotated, Any, Literal, Union

import numpy as np
from pydantic import (
    AfterValidator,
    Field,
    Strict,
    model_validator,
)

from .errors import AssemblyError, did_you_mean
from .geometry import edge_geometry
from .types import (
    EDGE_NAMES,
    Complex,
    EdgeRef,
    FrozenModel,
    PoissonRatio,
    Positive,
    Real,
    check_material_loss_factor,
)

__all__ = [
    "Boundary",
    "EdgeMoment",
    "EdgeShear",
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


def cross(a: Any, b: Any) -> tuple[float, float, float]:
    r""":math:`\mathbf a\times\mathbf b` of two 3-vectors, written out: numpy's cross costs
    50 us a call on 3-vectors, and the lines' rules ask for frames' normals thousands of times
    in an update (10 s of the box with a wall's 130 s, profiled, 2026-11-28)."""
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


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
        return np.array(cross(self.x_axis, self.y_axis), dtype=float)

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
        if edge not in EDGE_NAMES:
            self.edge_length(edge)  # raises the AssemblyError
        geometry = edge_geometry(tuple(self.size), edge)
        return geometry.start, geometry.tangent, geometry.normal, geometry.length

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
# Boundary conditions and loads
# --------------------------------------------------------------------------------------
class Boundary(FrozenModel):
    """A boundary condition on one edge; edges neither joined nor listed are free.

    Parameters
    ----------
    edge : str
        Edge reference ``"PLATE.EDGE"``.
    condition : {"clamped", "simply_supported", "free", "symmetric"}
        ``clamped``: w = 0 and dw/dn = 0; ``simply_supported``: w = 0 and M_n = 0 (or a
        prescribed ``edge_moment``); ``free``: K_n = 0 and M_n = 0 (or prescribed loads);
        ``symmetric``: dw/dn = 0 and K_n = 0 (or a prescribed ``edge_shear``), a plane of
        symmetry of the structure.
    in_plane : {"fixed", "free", "diaphragm", "roller"}, optional
        The edge's in-plane condition, for a plate that carries in-plane waves (a member of a
        moving junction line): ``fixed`` u_n = u_t = 0, ``free`` N_nn = N_nt = 0,
        ``diaphragm`` u_t = 0 and N_nn = 0 (the shear diaphragm of folded-plate theory),
        ``roller`` u_n = 0 and N_nt = 0. Default: ``fixed`` for ``clamped`` and
        ``simply_supported``, ``free`` for ``free``, ``roller`` for ``symmetric`` (with it,
        the plane of symmetry).
    """

    edge: EdgeRef
    condition: Literal["clamped", "simply_supported", "free", "symmetric"]
    in_plane: Literal["fixed", "free", "diaphragm", "roller"] | None = None

    @property
    def in_plane_condition(self) -> str:
        """:attr:`in_plane`, or its default for :attr:`condition`."""
        if self.in_plane is not None:
            return self.in_plane
        return {"free": "free", "symmetric": "roller"}.get(self.condition, "fixed")


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

    Only on a free or symmetric edge (clamped, simply supported and joined edges take ``K_n``
    as a reaction).

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


