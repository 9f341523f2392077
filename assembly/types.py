r"""The building blocks of an assembly description: read-only mappings, ids and edge
references, constrained numbers and complex values, and the frozen base model of every table
(:mod:`assembly.models` builds the tables on them, :mod:`assembly.case` the whole description).
"""

from __future__ import annotations

import functools
import math
import numbers
from collections.abc import Mapping
from typing import Annotated, Any, NamedTuple

from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    PlainSerializer,
    PlainValidator,
    Strict,
    WithJsonSchema,
)

from .errors import AssemblyError, did_you_mean
from .geometry import EDGE_NAMES

__all__ = [
    "EDGE_NAMES",
    "JOINT_PARAMETERS",
    "FrozenDict",
    "JointParameters",
    "freeze",
    "show_value",
    "is_real",
    "EdgeId",
    "parse_edge_ref",
    "check_id",
    "check_material_loss_factor",
    "check_frequencies",
    "check_bounds",
    "check_identify",
    "Real",
    "Positive",
    "NonNegative",
    "Count",
    "Frequency",
    "PoissonRatio",
    "LogStiffness",
    "Id",
    "EdgeRef",
    "Complex",
    "FrozenModel",
]


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


class JointParameters(FrozenDict):
    """Joint parameters ``{joint: {name: value}}``, read-only at both levels.

    The names are those of :data:`JOINT_PARAMETERS`; a joint is an updatable joint of
    :meth:`assembly.case.Case.updatable_joints` (a junction member is ``JOINT.PLATE``). They
    are what the updating passes from step to step, and what its results and run files hold:
    being read-only, a set can be shared, kept and compared without defensive copies, and a
    change makes a new set (:meth:`with_joint`).

    >>> p = JointParameters.of({"G1": {"log10_stiffness": 3.0, "loss_factor": 0.0}})
    >>> q = p.with_joint("G1", log10_stiffness=2.5)
    >>> q["G1"]["log10_stiffness"], p["G1"]["log10_stiffness"]
    (2.5, 3.0)
    """

    @classmethod
    def of(cls, parameters: Mapping[str, Mapping[str, float]]) -> JointParameters:
        """``parameters`` as a :class:`JointParameters` (itself when it already is one)."""
        if isinstance(parameters, cls):
            return parameters
        return cls({joint: FrozenDict(values) for joint, values in parameters.items()})

    def with_joint(self, joint: str, **values: float) -> JointParameters:
        """A copy with ``values`` set on ``joint``, the others shared."""
        return JointParameters({**self, joint: FrozenDict({**self[joint], **values})})

    def __repr__(self) -> str:
        """Return ``JointParameters({...})``."""
        return f"JointParameters({dict.__repr__(self)})"


def freeze(value: dict[Any, Any]) -> FrozenDict:
    return FrozenDict(value)


# --------------------------------------------------------------------------------------
# Small helpers for messages
# --------------------------------------------------------------------------------------
def show_value(value: object, limit: int = 60) -> str:
    """Return a short one-line repr of a user value."""
    text = repr(value).replace("\n", " ")
    return text if len(text) <= limit else text[: limit - 3] + "..."


def is_real(value: object) -> bool:
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
            f"{did_you_mean(parts[1], EDGE_NAMES)}; fix the edge reference"
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
        raise AssemblyError(
            f"an edge reference must be a string 'PLATE.EDGE', got {show_value(ref)}")
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
def check_id(value: str) -> str:
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
    if is_real(value):
        z = complex(float(value))  # type: ignore[arg-type]
    elif isinstance(value, numbers.Complex) and not isinstance(value, bool):
        z = complex(value)
    elif (
        isinstance(value, (list, tuple))
        and len(value) == 2
        and is_real(value[0])
        and is_real(value[1])
    ):
        z = complex(float(value[0]), float(value[1]))
    else:
        raise ValueError(
            f"must be a number or [re, im], got {show_value(value)}; write e.g. 1.0 or [1.0, 0.5]"
        )
    if not (math.isfinite(z.real) and math.isfinite(z.imag)):
        raise ValueError(f"must be finite, got {show_value(value)}; give a finite amplitude")
    return z


def _complex_pair(z: complex) -> list[float]:
    return [z.real, z.imag]


def check_material_loss_factor(value: float) -> float:
    if not value > 0:
        raise ValueError(
            f"must be > 0, got {value!r}: the VTCR needs eta > 0 (structural damping makes "
            "every plate problem uniquely solvable); give the material's loss factor, e.g. 0.01"
        )
    return value


def check_frequencies(values: tuple[float, ...]) -> tuple[float, ...]:
    if not values:
        raise ValueError("is empty; list at least one frequency in Hz, e.g. [150.0, 155.0]")
    seen: set[float] = set()
    for f in values:
        if f in seen:
            raise ValueError(f"{f:g} Hz is listed twice; list each frequency once")
        seen.add(f)
    return values


def check_bounds(values: tuple[float, float]) -> tuple[float, float]:
    lo, hi = values
    if not lo < hi:
        raise ValueError(
            f"lower bound {lo:g} is not below upper bound {hi:g}; write bounds = [lo, hi] "
            "with lo < hi (log10 of the stiffness), e.g. [-3.0, 7.0]"
        )
    return values


def check_identify(values: tuple[str, ...]) -> tuple[str, ...]:
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
Id = Annotated[str, AfterValidator(check_id)]
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


class FrozenModel(BaseModel):
    """Base of every description model: frozen, no unknown keys, finite floats."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


