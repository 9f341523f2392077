r"""Validated, immutable models of an assembly description.

An assembly is a set of thin rectangular Kirchhoff plates joined along edges.  Each plate
occupies ``[0, Lx] x [0, Ly]`` in its own frame; its edges are ``left`` (x = 0), ``right``
(x = Lx), ``bottom`` (y = 0) and ``top`` (y = Ly), addressed as ``"PLATE.EDGE"``.
All quantities are SI (m, kg, s, N, Pa, Hz); the time convention is :math:`e^{+j\omega t}`.

The top-level model is :class:`Case`, one TOML description (see
``docs/description.md``).  Tables, each optional except ``materials`` and
``plates``:

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
:meth:`Case.with_joint_parameters`.  Cross-references (materials, plates, edges, joints) are
checked once by a ``model_validator(mode="after")`` on :class:`Case`, which reports every
problem at once.
"""

from __future__ import annotations

import difflib
import functools
import math
import numbers
from collections.abc import Iterable, Mapping, Sequence
from typing import Annotated, Any, Literal, NamedTuple, Union

import numpy as np
from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    PlainSerializer,
    PlainValidator,
    Strict,
    ValidationError,
    WithJsonSchema,
    model_serializer,
    model_validator,
)

from .errors import AssemblyError, format_path

__all__ = [
    "EDGE_NAMES",
    "Boundary",
    "Case",
    "Compute",
    "CoplanarJoint",
    "Discretisation",
    "EdgeId",
    "EdgeMoment",
    "EdgeShear",
    "FrozenDict",
    "HingeJoint",
    "Joint",
    "JointTruth",
    "JunctionJoint",
    "Load",
    "Material",
    "Measurement",
    "Plate",
    "PlateDiscretisation",
    "PlateFrame",
    "PointForce",
    "PointMeasurement",
    "Truth",
    "Updating",
    "parse_edge_ref",
]

EDGE_NAMES: tuple[str, ...] = ("left", "right", "bottom", "top")
"""Edge names of a rectangular plate, in the plate-local frame."""

JOINT_PARAMETERS: tuple[str, ...] = ("log10_stiffness", "loss_factor", "mass")
"""Joint parameters that updating may change (``mass`` only for coplanar joints)."""

_ID_CHARS = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-")


# --------------------------------------------------------------------------------------
# Read-only mapping
# --------------------------------------------------------------------------------------
class FrozenDict(dict):  # type: ignore[type-arg]
    """A read-only ``dict``: the tables of a :class:`Case` (plates, joints, ...).

    It compares, iterates and serialises like a ``dict``; every mutating method raises
    :class:`TypeError`.  Build a modified assembly by copy instead, e.g. with
    :meth:`Case.with_joint_parameters`.
    """

    def _read_only(self, *args: object, **kwargs: object) -> None:
        raise TypeError(
            "assembly tables are read-only; build a modified copy instead "
            "(e.g. Case.with_joint_parameters or Case.model_copy(update=...))"
        )

    __setitem__ = __delitem__ = _read_only  # type: ignore[assignment]
    clear = pop = popitem = setdefault = update = _read_only  # type: ignore[assignment]
    __ior__ = _read_only  # type: ignore[assignment]

    def __reduce__(self) -> tuple[type, tuple[dict[Any, Any]]]:
        """Support copy, deepcopy and pickle (rebuilt from a plain dict)."""
        return (type(self), (dict(self),))

    def __hash__(self) -> int:  # type: ignore[override]
        """Hash the items, so that frozen models holding a FrozenDict are hashable."""
        return hash(frozenset(self.items()))

    def __repr__(self) -> str:
        """Return ``FrozenDict({...})``."""
        return f"FrozenDict({dict.__repr__(self)})"


def _freeze(value: dict[Any, Any]) -> FrozenDict:
    return FrozenDict(value)


# --------------------------------------------------------------------------------------
# Small helpers for messages
# --------------------------------------------------------------------------------------
def _show(value: object, limit: int = 60) -> str:
    """Return a short one-line repr of a user value."""
    text = repr(value).replace("\n", " ")
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _listing(names: Iterable[str]) -> str:
    names = list(names)
    return ", ".join(names) if names else "none"


def _did_you_mean(word: str, choices: Iterable[str]) -> str:
    close = difflib.get_close_matches(word, list(choices), n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _is_real(value: object) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


# --------------------------------------------------------------------------------------
# Edge references
# --------------------------------------------------------------------------------------
class EdgeId(NamedTuple):
    """A plate edge: ``EdgeId("P1", "right")`` is the description's ``"P1.right"``."""

    plate: str
    edge: str

    @property
    def ref(self) -> str:
        """The edge reference as written in a description, ``"PLATE.EDGE"``."""
        return f"{self.plate}.{self.edge}"


def _edge_ref_problem(ref: str) -> str | None:
    """Return what is wrong with an edge reference (with a fix), or None if well formed."""
    parts = ref.split(".")
    if len(parts) != 2 or not parts[0] or not parts[1]:
        return (
            f"malformed edge reference {ref!r}; write 'PLATE.EDGE', e.g. 'P1.right', "
            f"with EDGE one of {', '.join(EDGE_NAMES)}"
        )
    if parts[1] not in EDGE_NAMES:
        return (
            f"{parts[1]!r} in {ref!r} is not an edge name ({', '.join(EDGE_NAMES)})"
            f"{_did_you_mean(parts[1], EDGE_NAMES)}; fix the edge reference"
        )
    return None


def parse_edge_ref(ref: str) -> EdgeId:
    """Split an edge reference ``"PLATE.EDGE"`` into plate id and edge name.

    Parameters
    ----------
    ref : str
        Edge reference, e.g. ``"P1.right"``.  Edge names are ``left`` (x = 0), ``right``
        (x = Lx), ``bottom`` (y = 0) and ``top`` (y = Ly) of the plate-local frame.

    Returns
    -------
    EdgeId
        ``(plate, edge)``.

    Raises
    ------
    AssemblyError
        If `ref` is not a string of the form ``"PLATE.EDGE"`` with a known edge name.
        Whether the plate exists is not checked (see :meth:`Case.edge`).

    Examples
    --------
    >>> parse_edge_ref("P1.right")
    EdgeId(plate='P1', edge='right')
    """
    if not isinstance(ref, str):
        raise AssemblyError(f"an edge reference must be a string 'PLATE.EDGE', got {_show(ref)}")
    return _split_edge_ref(ref)


@functools.lru_cache(maxsize=65536)
def _split_edge_ref(ref: str) -> EdgeId:
    """:func:`parse_edge_ref` of a string, remembered: a joint's ``sides`` are read every time
    a plate's subproblem is set up, for every plate (tens of thousands of times on a grid of
    a hundred plates)."""
    problem = _edge_ref_problem(ref)
    if problem is not None:
        raise AssemblyError(problem)
    plate, edge = ref.split(".")
    return EdgeId(plate, edge)


# --------------------------------------------------------------------------------------
# Reusable constrained types
# --------------------------------------------------------------------------------------
def _check_id(value: str) -> str:
    if not value or not set(value) <= _ID_CHARS:
        raise ValueError(
            f"id {value!r} may only contain letters, digits, '_' and '-' (it is used in edge "
            "references 'PLATE.EDGE', CSV files and on the command line); rename it"
        )
    return value


def _check_edge_ref(value: str) -> str:
    problem = _edge_ref_problem(value)
    if problem is not None:
        raise ValueError(problem)
    return value


def _to_complex(value: object) -> complex:
    """Read a complex number written as a number or as ``[re, im]``."""
    if _is_real(value):
        z = complex(float(value))  # type: ignore[arg-type]
    elif isinstance(value, numbers.Complex) and not isinstance(value, bool):
        z = complex(value)
    elif (
        isinstance(value, (list, tuple))
        and len(value) == 2
        and _is_real(value[0])
        and _is_real(value[1])
    ):
        z = complex(float(value[0]), float(value[1]))
    else:
        raise ValueError(
            f"must be a number or [re, im], got {_show(value)}; write e.g. 1.0 or [1.0, 0.5]"
        )
    if not (math.isfinite(z.real) and math.isfinite(z.imag)):
        raise ValueError(f"must be finite, got {_show(value)}; give a finite amplitude")
    return z


def _complex_pair(z: complex) -> list[float]:
    return [z.real, z.imag]


def _check_material_loss_factor(value: float) -> float:
    if not value > 0:
        raise ValueError(
            f"must be > 0, got {value!r}: the VTCR needs eta > 0 (structural damping makes "
            "every plate problem uniquely solvable); give the material's loss factor, e.g. 0.01"
        )
    return value


def _check_frequencies(values: tuple[float, ...]) -> tuple[float, ...]:
    if not values:
        raise ValueError("is empty; list at least one frequency in Hz, e.g. [150.0, 155.0]")
    seen: set[float] = set()
    for f in values:
        if f in seen:
            raise ValueError(f"{f:g} Hz is listed twice; list each frequency once")
        seen.add(f)
    return values


def _check_bounds(values: tuple[float, float]) -> tuple[float, float]:
    lo, hi = values
    if not lo < hi:
        raise ValueError(
            f"lower bound {lo:g} is not below upper bound {hi:g}; write bounds = [lo, hi] "
            "with lo < hi (log10 of the stiffness), e.g. [-3.0, 7.0]"
        )
    return values


def _check_identify(values: tuple[str, ...]) -> tuple[str, ...]:
    if not values:
        raise ValueError('is empty; list what to identify, e.g. identify = ["stiffness"]')
    if len(set(values)) != len(values):
        raise ValueError(f"lists a parameter twice ({', '.join(values)}); list each once")
    return values


Real = Annotated[float, Strict()]
"""A finite real number (ints accepted, booleans and strings rejected)."""
Positive = Annotated[float, Strict(), Field(gt=0)]
"""A finite real number > 0."""
NonNegative = Annotated[float, Strict(), Field(ge=0)]
"""A finite real number >= 0."""
Count = Annotated[int, Strict(), Field(ge=0)]
"""A whole number >= 0 (no floats, no booleans)."""
Frequency = Positive
"""A frequency in Hz, > 0."""
PoissonRatio = Annotated[float, Strict(), Field(gt=-1, lt=0.5)]
"""Poisson's ratio, in (-1, 0.5)."""
LogStiffness = Annotated[float, Strict(), Field(ge=-50, le=50)]
"""log10 of a joint's rotational stiffness per unit length (k in N·m/m per rad = N)."""
Id = Annotated[str, AfterValidator(_check_id)]
"""An identifier of a material, plate or joint: letters, digits, ``_`` and ``-``."""
EdgeRef = Annotated[str, AfterValidator(_check_edge_ref)]
"""An edge reference ``"PLATE.EDGE"``."""
Complex = Annotated[
    complex,
    PlainValidator(_to_complex),
    PlainSerializer(_complex_pair, return_type=list[float]),
    WithJsonSchema(
        {
            "anyOf": [
                {"type": "number"},
                {"type": "array", "items": {"type": "number"}, "minItems": 2, "maxItems": 2},
            ],
            "description": "a complex number written as a real number or as [re, im]",
        }
    ),
]
"""A complex number, written as a number or as ``[re, im]``; stored as :class:`complex`."""


class _Model(BaseModel):
    """Base of every description model: frozen, no unknown keys, finite floats."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


# --------------------------------------------------------------------------------------
# Materials and plates
# --------------------------------------------------------------------------------------
class Material(_Model):
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
    loss_factor: Annotated[float, Strict(), AfterValidator(_check_material_loss_factor)]

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


class PlateFrame(_Model):
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


class Plate(_Model):
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
            f"{_did_you_mean(str(edge), EDGE_NAMES)}"
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
class _JointBase(_Model):
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
    if not _is_real(value) and not (isinstance(value, float) and math.isinf(value)):
        raise ValueError(f"{where}must be a number (log10 of k in N) or inf (rigid), "
                         f"got {_show(value)}")
    value = float(value)  # type: ignore[arg-type]
    if math.isnan(value) or value == -math.inf:
        raise ValueError(f"{where}must be a number in [-50, 50] or inf (rigid), got {value!r};"
                         " a member that carries nothing is not a member: remove its edge")
    if math.isfinite(value) and not -50.0 <= value <= 50.0:
        raise ValueError(f"{where}must be in [-50, 50] or inf (rigid), got {value!r}")
    return value


def _member_loss_factor(value: object, where: str = "") -> float:
    if not _is_real(value) or not 0.0 <= float(value) < math.inf:  # type: ignore[arg-type]
        raise ValueError(f"{where}must be a finite number >= 0, got {_show(value)}")
    return float(value)  # type: ignore[arg-type]


def _per_member(check: Any) -> Any:
    """Validator of a value given for every member or as a table by member plate."""

    def validate(value: object) -> Any:
        if isinstance(value, Mapping):
            return FrozenDict({_check_id(str(plate)): check(v, f"member {plate!r}: ")
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


class JunctionJoint(_Model):
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
class Boundary(_Model):
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


class _EdgeLoad(_Model):
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


class PointForce(_Model):
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
# Discretisation, measurement, updating, truth
# --------------------------------------------------------------------------------------
class PlateDiscretisation(_Model):
    """Per-plate ray counts overriding the automatic rule; omitted counts stay automatic.

    Parameters
    ----------
    interior : int, optional
        Number of interior (propagating) ray sectors, >= 4.
    edge_propagating : int, optional
        Propagating edge-ray sectors per edge (both signs of beta together), >= 0.
    edge_evanescent : int, optional
        Evanescent (boundary-layer) edge-ray sectors per edge, >= 0.
    corner : int, optional
        Corner-ray sectors per corner, >= 0.
    """

    interior: Annotated[int, Strict(), Field(ge=4)] | None = None
    edge_propagating: Count | None = None
    edge_evanescent: Count | None = None
    corner: Count | None = None


class Discretisation(_Model):
    """Ray discretisation settings (``[discretisation]``).

    Parameters
    ----------
    resolution : float, optional
        Multiplier (> 0) on the automatic ray-count rule.  Default 1.0.
    quadrature_per_sector : int, optional
        Gauss-Legendre points per ray sector, >= 2.  Default 8.
    edge_wavenumber_ratio : float, optional
        :math:`\\tau_{max} > 1`: edge rays span ``|beta| <= tau_max * kappa0``.  Default 2.5.
    interface_functions : int, optional
        Number of functions per interface unknown (>= 1); None (default) = automatic.
    tolerance : float, optional
        Largest accepted estimated relative L2 error of ``w`` (0 < tolerance < 1): ``solve``,
        the updating commands and the simulated experiment (to 0.3 of it) raise the resolution
        until the a-posteriori estimate is below it, or stop naming the plate that cannot
        reach it.  None (default): solve at ``resolution`` and report the estimate.
    plates : mapping of str to PlateDiscretisation, optional
        Per-plate overrides, ``[discretisation.plates.P1]``.
    """

    resolution: Positive = 1.0
    quadrature_per_sector: Annotated[int, Strict(), Field(ge=2)] = 8
    edge_wavenumber_ratio: Annotated[float, Strict(), Field(gt=1)] = 2.5
    interface_functions: Annotated[int, Strict(), Field(ge=1)] | None = None
    tolerance: Annotated[float, Strict(), Field(gt=0, lt=1)] | None = None
    plates: Annotated[dict[str, PlateDiscretisation], AfterValidator(_freeze)] = Field(
        default_factory=FrozenDict
    )

    def for_plate(self, plate_id: str) -> PlateDiscretisation:
        """Return the overrides of one plate (all None when it has none)."""
        return self.plates.get(plate_id, PlateDiscretisation())


class PointMeasurement(_Model):
    """One measurement point.

    Parameters
    ----------
    plate : str
        Plate id.
    at : tuple of float, shape (2,)
        ``[x, y]`` in plate-local m, on the plate (edges allowed).
    """

    plate: str
    at: tuple[Real, Real]


DEFAULT_GRID_FRACTION = 0.2
"""Default measurement spacing, as a fraction of the largest plate side of the assembly."""


def default_spacing(plates) -> float | None:
    """:data:`DEFAULT_GRID_FRACTION` times the largest side of ``plates`` (None without any)."""
    sides = [max(plate.size) for plate in plates.values() if plate is not None]
    return DEFAULT_GRID_FRACTION * max(sides) if sides else None


class Measurement(_Model):
    """Measurement grid of a (simulated) experiment (``[measurement]``).

    The grid of a measured plate of size ``Lx x Ly`` consists of the centres of a uniform
    mesh of about `spacing`: ``nx = max(1, round(Lx / spacing))`` cells, points
    ``x_i = (i + 1/2) Lx / nx`` for ``i = 0 .. nx - 1`` (likewise in y).  See
    :meth:`Case.measurement_points`.

    Parameters
    ----------
    spacing : float, optional
        Grid spacing in m, > 0.  Default: a fifth of the largest plate side of the assembly
        (0.1 m for 0.5 m plates, the paper's grid), so that a description in other consistent
        units (mm) gets the same grid.
    plates : tuple of str, optional
        Plates carrying the grid; None (default) = every plate; ``[]`` = no grid (only
        `points`).
    noise : float, optional
        Relative noise amplitude (fraction, >= 0) of a simulated experiment.  Default 0.
    seed : int, optional
        Seed (>= 0) of the noise generator.  Default 1.
    resolution : float, optional
        Discretisation multiplier (> 0) used to simulate the experiment, finer than the
        model's so that the simulation is not the model itself.  Default 1.6.
    points : tuple of PointMeasurement, optional
        Extra measurement points ``{plate, at = [x, y]}``.  Default none.
    """

    spacing: Positive | None = None
    plates: tuple[str, ...] | None = None
    noise: NonNegative = 0.0
    seed: Count = 1
    resolution: Positive = 1.6
    points: tuple[PointMeasurement, ...] = ()


def _check_r(value: float | str) -> float | str:
    if value != "auto" and not 0.0 < value <= 1.0:
        raise ValueError(f"must be > 0 and <= 1, or \"auto\", got {value:g}; e.g. r = 0.8, "
                         "or r = \"auto\" (the scale-free weights)")
    return value


class Updating(_Model):
    """Localisation--correction settings (``[updating]``).

    Parameters
    ----------
    r : float or "auto", optional
        Weight of the measurement term in ``E_mod^2 = (1 - r) E_int^2 + r E_mes^2``,
        in (0, 1], or ``"auto"`` (default): weights that do not depend on the size of the
        structure (``updating.weights``: each joint's law weighed by the energy of its own
        plates, each plate's data by its own stated noise, at the fixed `balance`).
    alpha : mapping of str to float, optional
        Joint weights ``alpha_i >= 0`` of the interface error.  Joints not listed weigh 1;
        the weights are normalised to sum 1.  In a validated :class:`Case` this holds every
        joint, normalised; None (default) = equal weights ``1 / N_joints``.  With
        ``r = "auto"`` they multiply the scale-free weights (equal: those alone).
    balance : float, optional
        With ``r = "auto"``: the weight of a joint's law relative to the data around it,
        ``beta`` in ``beta e_j^2 / E_j`` against the noise-whitened misfit of its plates
        (``E_j`` the energy of the joint's plates), > 0.  Default 2000.
    bounds : tuple of float, shape (2,), optional
        ``[lo, hi]`` on ``log10_stiffness``, lo < hi.  Default [-3, 7].
    identify : tuple of {"stiffness", "damping", "mass"}, optional
        Joint parameters to identify: ``log10_stiffness``, ``loss_factor`` and/or ``mass``.
        Default ("stiffness",).
    max_steps : int, optional
        Maximum number of correction steps, >= 1.  Default 8.
    stop_ratio : float, optional
        A joint is selected for correction only if its residual exceeds `stop_ratio` times
        its floor (the residual a right model shows on average); > 1.  Default 3.0.
    significance : float, optional
        ... and the residual a right model exceeds at any of the joints with probability
        `significance` (familywise: among hundreds of joints, some stand several times above
        their floors by noise alone), in (0, 0.5).  Default 0.05.
    min_decrease : float, optional
        Smallest relative decrease of ``E_mod`` for a correction to count, in [0, 1).
        Default 0.01.
    confidence : float, optional
        Level of the confidence interval reported for every corrected joint, in (0, 1).
        Default 0.9.
    misfit : {"global", "per_plate"}, optional
        Normalisation of ``E_mes^2``: the whole data's squared norm (``"global"``, the
        paper's), or the mean over the measured points of each plate's misfit relative to its
        own data (``"per_plate"``: under relative noise, plates far from the load count as
        much as the loaded ones).  Default: ``"per_plate"`` with ``r = "auto"``, ``"global"``
        with a number.
    """

    r: Annotated[Union[Annotated[float, Strict()], Literal["auto"]],
                 AfterValidator(_check_r)] = "auto"
    alpha: Annotated[dict[str, NonNegative], AfterValidator(_freeze)] | None = None
    bounds: Annotated[tuple[Real, Real], AfterValidator(_check_bounds)] = (-3.0, 7.0)
    identify: Annotated[
        tuple[Literal["stiffness", "damping", "mass"], ...], AfterValidator(_check_identify)
    ] = ("stiffness",)
    max_steps: Annotated[int, Strict(), Field(ge=1)] = 8
    stop_ratio: Annotated[float, Strict(), Field(gt=1)] = 3.0
    significance: Annotated[float, Strict(), Field(gt=0, lt=0.5)] = 0.05
    min_decrease: Annotated[float, Strict(), Field(ge=0, lt=1)] = 0.01
    confidence: Annotated[float, Strict(), Field(gt=0, lt=1)] = 0.9
    misfit: Literal["global", "per_plate"] | None = None
    balance: Annotated[float, Strict(), Field(gt=0)] = 2000.0

    @property
    def automatic(self) -> bool:
        """Whether the weights are the scale-free ones (``r = "auto"``)."""
        return self.r == "auto"

    @property
    def misfit_kind(self) -> str:
        """``misfit`` as given, else the default of the weights (``per_plate`` with
        ``r = "auto"``, ``global`` with a number)."""
        return self.misfit or ("per_plate" if self.automatic else "global")


class Compute(_Model):
    """Where independent tasks (frequencies, noise realisations) run (``[compute]``).

    The command-line options ``--workers`` and ``--scheduler`` override these.

    Parameters
    ----------
    workers : int, optional
        Local worker processes (>= 1), one BLAS thread each.  Default 1: this process.
    scheduler : str, optional
        Address of a running Dask distributed scheduler, e.g. ``"tcp://node1:8786"`` (the
        ``distributed`` extra); its workers run the tasks and ``workers`` is ignored.
    """

    workers: Annotated[int, Strict(), Field(ge=1)] = 1
    scheduler: Annotated[str, Field(min_length=1)] | None = None


class JointTruth(_Model):
    """The "true" parameters of one joint, used to simulate an experiment.

    Parameters
    ----------
    log10_stiffness : float or mapping of str to float, optional
        True :math:`\\log_{10} k`; None keeps the model value.  For a junction, one value for
        every member or a table by member plate (``inf``: rigid), like the joint itself.
    loss_factor : float or mapping of str to float, optional
        True :math:`\\zeta \\ge 0`; None keeps the model value (a table for a junction).
    mass : float, optional
        True line mass in kg/m (coplanar joints only); None keeps the model value.
    """

    log10_stiffness: MemberStiffness | None = None
    loss_factor: MemberLossFactor | None = None
    mass: NonNegative | None = None

    def changes(self) -> dict[str, Any]:
        """Return the parameters that are given, ``{name: value}``."""
        return {k: getattr(self, k) for k in ("log10_stiffness", "loss_factor", "mass")
                if getattr(self, k) is not None}


class Truth(_Model):
    """True joint parameters of a simulated experiment (``[truth.joints.ID]``).

    Parameters
    ----------
    joints : mapping of str to JointTruth, optional
        Per joint; joints not listed keep their model values.
    """

    joints: Annotated[dict[str, JointTruth], AfterValidator(_freeze)] = Field(
        default_factory=FrozenDict
    )


# --------------------------------------------------------------------------------------
# Cross-reference checks
# --------------------------------------------------------------------------------------
Loc = tuple[Union[str, int], ...]


class CrossReferenceError(ValueError):
    """Raised by :class:`Case` validation with every cross-reference problem.

    Attributes
    ----------
    issues : list of (loc, message)
        ``loc`` is a tuple path such as ``("joints", "G2", "between", 1)``.
    """

    def __init__(self, issues: Sequence[tuple[Loc, str]]) -> None:
        self.issues = list(issues)
        super().__init__("\n".join(f"{format_path(loc)}: {msg}" for loc, msg in self.issues))


def _grid_shape(size: tuple[float, float], spacing: float) -> tuple[int, int]:
    """``(nx, ny)`` cells of the measurement grid of a plate."""
    return max(1, round(size[0] / spacing)), max(1, round(size[1] / spacing))


def _grid_points(size: tuple[float, float], spacing: float) -> list[tuple[float, float]]:
    """Cell centres of the measurement grid of a plate, ordered by x, then y (m)."""
    (lx, ly), (nx, ny) = size, _grid_shape(size, spacing)
    return [((i + 0.5) * lx / nx, (j + 0.5) * ly / ny) for i in range(nx) for j in range(ny)]


def _on_grid(size: tuple[float, float], spacing: float, x: float, y: float) -> bool:
    """Tell whether a point is a cell centre of the plate's measurement grid (to 1e-9 m)."""
    (lx, ly), (nx, ny) = size, _grid_shape(size, spacing)
    i, j = round(x * nx / lx - 0.5), round(y * ny / ly - 0.5)
    return (0 <= i < nx and 0 <= j < ny and abs((i + 0.5) * lx / nx - x) <= 1e-9
            and abs((j + 0.5) * ly / ny - y) <= 1e-9)


def _junction_with(joint: JunctionJoint, changes: Mapping[str, Any],
                   member: str | None) -> JunctionJoint:
    """A junction with new member values: ``changes`` ``{name: number or table by plate}``
    for every member, or for ``member`` only."""
    data = joint.model_dump()
    for name, value in changes.items():
        if name == "mass":
            if value != 0.0:
                raise AssemblyError(f"junction {' - '.join(joint.between)} has no line mass; "
                                    f"got mass = {value!r}")
            continue
        if name not in ("log10_stiffness", "loss_factor"):
            raise AssemblyError(f"{name!r} is not a parameter of a junction's members "
                                "(parameters: log10_stiffness, loss_factor)")
        current = data[name]
        table = dict(current) if isinstance(current, Mapping) else dict.fromkeys(
            joint.plates, current)
        if member is not None:
            table[member] = value
        elif isinstance(value, Mapping):
            table.update(value)
        else:
            table = dict.fromkeys(joint.plates, value)
        data[name] = {p: float(v) for p, v in table.items()}
    try:
        return JunctionJoint.model_validate(data)
    except ValidationError as exc:
        problems = "; ".join(e["msg"].removeprefix("Value error, ") for e in exc.errors())
        raise AssemblyError(f"invalid member parameters of junction "
                            f"{' - '.join(joint.between)}: {problems}") from None


# --------------------------------------------------------------------------------------
# The assembly
# --------------------------------------------------------------------------------------
class Case(_Model):
    r"""An assembly description: plates, joints, boundary conditions, loads and settings.

    Build it with :func:`assembly.load_case` (TOML file), :func:`assembly.load_case_text`
    or :func:`assembly.parse_case` (dict), which report every problem at once as a
    :class:`~assembly.errors.DescriptionError`.  ``Case.model_validate(data)`` works too but
    raises pydantic's ``ValidationError``.

    Parameters
    ----------
    name : str
        Name of the assembly.
    frequency : float, optional
        Single excitation frequency in Hz, > 0.  Give exactly one of `frequency` and
        `frequencies`.
    frequencies : tuple of float, optional
        Distinct frequencies in Hz, > 0.  After validation always set: ``(frequency,)``
        when `frequency` was given.
    materials : mapping of str to Material
        ``[materials.ID]`` tables; ids use letters, digits, ``_`` and ``-``.
    plates : mapping of str to Plate
        ``[plates.ID]`` tables, at least one.
    joints : mapping of str to CoplanarJoint or HingeJoint, optional
        ``[joints.ID]`` tables.
    boundaries : tuple of Boundary, optional
        ``[[boundaries]]``; edges neither joined nor listed are free.
    loads : tuple of EdgeShear, EdgeMoment or PointForce, optional
        ``[[loads]]``.
    discretisation : Discretisation, optional
    measurement : Measurement, optional
    updating : Updating, optional
        After validation ``updating.alpha`` holds every joint's weight, normalised to sum 1.
    compute : Compute, optional
        Where independent tasks run (local processes or a Dask scheduler).
    truth : Truth, optional
        True joint parameters of a simulated experiment.

    Notes
    -----
    The model is frozen and its tables are :class:`FrozenDict`; derived assemblies are built
    by copy (:meth:`with_joint_parameters`, :meth:`true_case`), so an updating history stays
    reproducible.

    Examples
    --------
    >>> from assembly import load_case
    >>> case = load_case("cases/single_plate.toml")
    >>> case.frequencies, case.plates["P1"].size
    ((155.0,), (0.5, 0.4))
    """

    name: Annotated[str, Field(min_length=1)]
    frequency: Frequency | None = None
    frequencies: Annotated[tuple[Frequency, ...], AfterValidator(_check_frequencies)] | None = (
        None
    )
    materials: Annotated[dict[Id, Material], AfterValidator(_freeze)]
    plates: Annotated[dict[Id, Plate], Field(min_length=1), AfterValidator(_freeze)]
    joints: Annotated[dict[Id, Joint], AfterValidator(_freeze)] = Field(
        default_factory=FrozenDict
    )
    boundaries: tuple[Boundary, ...] = ()
    loads: tuple[Load, ...] = ()
    discretisation: Discretisation = Field(default_factory=Discretisation)
    measurement: Measurement = Field(default_factory=Measurement)
    updating: Updating = Field(default_factory=Updating)
    compute: Compute = Field(default_factory=Compute)
    truth: Truth = Field(default_factory=Truth)

    # ---------------------------------------------------------------- validation
    @model_validator(mode="after")
    def _check_references(self) -> Case:
        if self.measurement.spacing is None:  # relative to the structure, not to the metre
            object.__setattr__(self, "measurement", self.measurement.model_copy(
                update={"spacing": default_spacing(self.plates)}))
        from assembly.checks import View, cross_check

        issues = cross_check(
            View(
                materials=self.materials,
                plates=self.plates,
                joints=self.joints,
                boundaries=self.boundaries,
                loads=self.loads,
                discretisation=self.discretisation,
                measurement=self.measurement,
                updating=self.updating,
                truth=self.truth,
                has_frequency=self.frequency is not None,
                has_frequencies=self.frequencies is not None,
            )
        )
        if issues:
            raise CrossReferenceError(issues)
        # Normalisations on a frozen model, done once here (before anyone sees the object).
        if self.frequency is not None:
            object.__setattr__(self, "frequencies", (self.frequency,))
        weights = {jid: (self.updating.alpha or {}).get(jid, 1.0) for jid in self.joints}
        total = sum(weights.values())
        if weights and abs(total - 1.0) > 1e-12:
            weights = {jid: w / total for jid, w in weights.items()}
        object.__setattr__(
            self, "updating", self.updating.model_copy(update={"alpha": FrozenDict(weights)})
        )
        return self

    @model_serializer(mode="wrap")
    def _serialise(self, handler: Any) -> Any:
        # Dump the frequency the way it was given, so that a dump validates again.
        data = handler(self)
        if isinstance(data, dict):
            data.pop("frequencies" if self.frequency is not None else "frequency", None)
        return data

    # ---------------------------------------------------------------- look-ups
    def edge(self, ref: str | EdgeId) -> EdgeId:
        """Resolve an edge reference of this assembly.

        Parameters
        ----------
        ref : str or EdgeId
            ``"PLATE.EDGE"`` or an :class:`EdgeId`.

        Returns
        -------
        EdgeId

        Raises
        ------
        AssemblyError
            If the reference is malformed or the plate is not in the assembly.
        """
        edge = EdgeId(*ref) if isinstance(ref, tuple) else parse_edge_ref(ref)
        if edge.plate not in self.plates:
            raise AssemblyError(
                f"plate {edge.plate!r} is not in the assembly (plates: {_listing(self.plates)})"
            )
        if edge.edge not in EDGE_NAMES:
            raise AssemblyError(f"{edge.edge!r} is not an edge name ({', '.join(EDGE_NAMES)})")
        return edge

    def edge_length(self, ref: str | EdgeId) -> float:
        """Return the length in m of an edge ``"PLATE.EDGE"``."""
        edge = self.edge(ref)
        return self.plates[edge.plate].edge_length(edge.edge)

    def material_of(self, plate_id: str) -> Material:
        """Return the material of a plate."""
        return self.materials[self.plates[plate_id].material]

    def edge_conditions(self) -> dict[EdgeId, str]:
        """Return the condition of every plate edge.

        Returns
        -------
        dict of EdgeId to str
            For each plate (description order) and edge (left, right, bottom, top):
            ``"joined"``, ``"clamped"``, ``"simply_supported"`` or ``"free"``.
        """
        joined = self.edge_joints()
        given = {parse_edge_ref(bc.edge): bc.condition for bc in self.boundaries}
        return {
            EdgeId(pid, e): "joined"
            if EdgeId(pid, e) in joined
            else given.get(EdgeId(pid, e), "free")
            for pid in self.plates
            for e in EDGE_NAMES
        }

    def edge_joints(self) -> dict[EdgeId, str]:
        """Return ``{edge: joint id}`` for every joined edge."""
        return {side: jid for jid, joint in self.joints.items() for side in joint.sides}

    def member_directions(self, joint_id: str) -> tuple[int, ...]:
        r"""For each edge of a joint, +1 if it runs (counter-clockwise) along the joint line's
        direction, -1 if against it.

        The line runs along its first edge.  A junction between framed plates takes the
        other directions from the frames, :math:`s_i = \mathbf t_i\cdot\mathbf e_\Gamma` with
        :math:`\mathbf t_i = \mathbf e_{z,i}\times\mathbf n_i` the member's edge tangent
        (``docs/method.md`` section 6.2b); every other joint is ``(1, -1)``: the second edge
        runs the other way, as in an assembly unrolled in a plane (checked for framed plates).
        """
        joint = self.joints[joint_id]
        sides = joint.sides
        if not isinstance(joint, JunctionJoint) or self.plates[sides[0].plate].frame is None:
            return (1, -1)
        start, end, _ = self.plates[sides[0].plate].edge_in_space(sides[0].edge)
        line = end - start
        directions = []
        for side in sides:
            a, b, _ = self.plates[side.plate].edge_in_space(side.edge)
            directions.append(1 if float((b - a) @ line) > 0.0 else -1)
        return tuple(directions)

    def joint_parameters(self) -> dict[str, dict[str, float]]:
        """Return the current joint parameters, ``{joint id: {name: value}}``.

        Every joint has ``log10_stiffness`` and ``loss_factor``; coplanar joints also
        ``mass`` (kg/m).
        """
        return {jid: joint.parameters() for jid, joint in self.joints.items()}

    def measured_plates(self) -> tuple[str, ...]:
        """Return the plates carrying the measurement grid (all plates by default)."""
        chosen = self.measurement.plates
        return tuple(self.plates) if chosen is None else chosen

    def measurement_points(self) -> tuple[tuple[str, float, float], ...]:
        """Return the measurement points ``(plate, x, y)`` in plate-local m.

        The grid of each measured plate (:meth:`measured_plates`) consists of the cell
        centres of a uniform mesh: ``nx = max(1, round(Lx / spacing))`` cells and points
        ``x_i = (i + 1/2) Lx / nx``, ``i = 0 .. nx - 1`` (likewise in y), ordered by plate,
        then x, then y -- the rule of ``solver.field_grid``.  The explicit
        ``measurement.points`` follow.

        Returns
        -------
        tuple of (str, float, float)

        Examples
        --------
        >>> from assembly import load_case
        >>> case = load_case("cases/single_plate.toml")
        >>> len(case.measurement_points())  # 5 x 4 cell centres of a 0.1 m mesh
        20
        """
        spacing = self.measurement.spacing
        points: list[tuple[str, float, float]] = []
        for pid in self.measured_plates():
            points.extend((pid, x, y) for x, y in _grid_points(self.plates[pid].size, spacing))
        points.extend((p.plate, p.at[0], p.at[1]) for p in self.measurement.points)
        return tuple(points)

    # ---------------------------------------------------------------- derived cases
    def with_joint_parameters(self, parameters: Mapping[str, Mapping[str, float]]) -> Case:
        """Return a copy of the assembly with some joint parameters replaced.

        The assembly itself is not changed.

        Parameters
        ----------
        parameters : mapping of str to mapping of str to float
            ``{joint id: {name: value}}`` with names ``log10_stiffness``, ``loss_factor``
            and (coplanar joints) ``mass``.  Parameters not given keep their value.

        Returns
        -------
        Case
            The new assembly.

        Raises
        ------
        AssemblyError
            For an unknown joint or parameter, a value that is not a real number or is out
            of range, or a non-zero mass on a hinge.

        Examples
        --------
        >>> from assembly import load_case_text
        >>> case = load_case_text('''
        ... name = "two"
        ... frequency = 155.0
        ... [materials.steel]
        ... young_modulus = 210e9
        ... poisson_ratio = 0.3
        ... density = 7800.0
        ... loss_factor = 0.01
        ... [plates.P1]
        ... material = "steel"
        ... thickness = 0.001
        ... size = [0.5, 0.4]
        ... [plates.P2]
        ... material = "steel"
        ... thickness = 0.001
        ... size = [0.4, 0.4]
        ... [joints.G1]
        ... kind = "coplanar"
        ... between = ["P1.right", "P2.left"]
        ... log10_stiffness = 2.0
        ... ''')
        >>> new = case.with_joint_parameters({"G1": {"log10_stiffness": 1.5}})
        >>> new.joints["G1"].log10_stiffness, case.joints["G1"].log10_stiffness
        (1.5, 2.0)
        """
        if not isinstance(parameters, Mapping):
            raise AssemblyError(
                f"joint parameters must be a mapping {{joint id: {{name: value}}}}, got "
                f"{_show(parameters)}"
            )
        joints = dict(self.joints)
        for key, changes in parameters.items():
            jid, _, member = str(key).partition(".")
            if jid not in self.joints or (member and member not in self.joints[jid].plates):
                raise AssemblyError(
                    f"joint {key!r} is not in the assembly (joints: {_listing(self.joints)}; "
                    "a junction's member as JOINT.PLATE)"
                )
            if not isinstance(changes, Mapping):
                raise AssemblyError(
                    f"parameters of joint {key!r} must be a mapping {{name: value}}, got "
                    f"{_show(changes)}"
                )
            if isinstance(joints[jid], JunctionJoint):
                joints[jid] = _junction_with(joints[jid], changes, member or None)
                continue
            joint = self.joints[jid]
            data = joint.model_dump()
            for name, value in changes.items():
                if name not in JOINT_PARAMETERS:
                    raise AssemblyError(
                        f"{name!r} is not a joint parameter of joint {jid!r} (parameters: "
                        f"{', '.join(JOINT_PARAMETERS)})"
                    )
                scalar_array = isinstance(value, np.ndarray) and (
                    value.shape == () and value.dtype.kind in "iuf"
                )
                if not (_is_real(value) or scalar_array):
                    raise AssemblyError(
                        f"{name} of joint {jid!r} must be a real number, got {_show(value)}"
                    )
                value = float(value)
                if name == "mass" and isinstance(joint, HingeJoint):
                    if value != 0.0:
                        raise AssemblyError(
                            f"joint {jid!r} is a hinge, which has no line mass; got mass = "
                            f"{value:g}"
                        )
                    continue
                data[name] = value
            try:
                joints[jid] = type(joint).model_validate(data)
            except ValidationError as exc:
                problems = "; ".join(
                    f"{'.'.join(map(str, e['loc']))} {e['msg'].lower()}, got {_show(e['input'])}"
                    for e in exc.errors()
                )
                raise AssemblyError(f"invalid parameters for joint {jid!r}: {problems}") from None
        return self.model_copy(update={"joints": FrozenDict(joints)})

    def updatable_joints(self) -> dict[str, tuple[str, str | None]]:
        """The joints the updating localises and corrects, by name.

        Every two-edge joint by its id; every finite member of a junction as ``JOINT.PLATE``
        (each member's spring is a channel of its own; rigid members are not updatable).

        Returns
        -------
        dict of str to (str, str or None)
            ``{name: (joint id, member plate or None)}``, in description order.
        """
        out: dict[str, tuple[str, str | None]] = {}
        for jid, joint in self.joints.items():
            if isinstance(joint, JunctionJoint):
                out.update({f"{jid}.{p}": (jid, p) for p in joint.finite_members()})
            else:
                out[jid] = (jid, None)
        return out

    def updatable_parameters(self) -> dict[str, dict[str, float]]:
        """``{name: {log10_stiffness, loss_factor, mass}}`` of :meth:`updatable_joints`."""
        out = {}
        for name, (jid, member) in self.updatable_joints().items():
            joint = self.joints[jid]
            if member is None:
                out[name] = {"log10_stiffness": joint.log10_stiffness,
                             "loss_factor": joint.loss_factor, "mass": joint.mass}
            else:
                out[name] = {"log10_stiffness": joint.member_log10_stiffness(member),
                             "loss_factor": joint.member_loss_factor(member), "mass": 0.0}
        return out

    def updatable_alpha(self) -> dict[str, float]:
        """The weight of each updatable joint's residual in :math:`E_{int}^2`: its joint's
        ``[updating] alpha`` (a junction's members share it)."""
        return {name: self.updating.alpha[jid]
                for name, (jid, _) in self.updatable_joints().items()}

    def true_log10_stiffness(self) -> dict[str, float]:
        """``{updatable joint: true log10 k}`` of the joints whose ``[truth]`` gives a
        stiffness (every finite member of such a junction; members it does not name keep
        their model values)."""
        true = self.true_case().updatable_parameters()
        return {name: true[name]["log10_stiffness"]
                for name, (jid, _) in self.updatable_joints().items()
                if jid in self.truth.joints and self.truth.joints[jid].log10_stiffness is not None}

    def true_parameters(self) -> dict[str, dict[str, float]]:
        """``{updatable joint: {parameter: true value}}`` of the parameters (``log10_stiffness``,
        ``loss_factor``, ``mass``) that ``[truth]`` gives, for the joints it names."""
        true = self.true_case().updatable_parameters()
        out: dict[str, dict[str, float]] = {}
        for name, (jid, _) in self.updatable_joints().items():
            given = self.truth.joints[jid].changes() if jid in self.truth.joints else {}
            if given:
                out[name] = {key: true[name][key] for key in given}
        return out

    def true_case(self) -> Case:
        """Return the assembly with its joints replaced by the ``[truth]`` parameters.

        Joints not listed in ``[truth.joints]`` keep their model values; the truth table
        itself is kept, so ``case.true_case().true_case() == case.true_case()``.

        Returns
        -------
        Case
        """
        changes = {jid: true.changes() for jid, true in self.truth.joints.items()}
        return self.with_joint_parameters({j: c for j, c in changes.items() if c})
