"""Numerical failures and doubts of a solve: the error raised on non-finite results and the
warnings of ill-conditioned plate matrices (a leaf of :mod:`solver`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, TypeVar

import numpy as np

if TYPE_CHECKING:  # for annotations only: at run time this module stays a leaf
    from solver.plate import PlateSolution
    from solver.solution import CaseSolution

__all__ = ["ToleranceError", "GroupPivotError", "CONDITION_WARNING", "NumericalError",
           "condition_warnings", "plate_condition_warnings", "check_finite"]


CONDITION_WARNING = 1e20
"""Condition estimate above which a solve is reported as numerically doubtful.

Trefftz matrices reach 1e17–1e19 while the field is accurate to 1e-9
(``docs/method.md`` section 9.1); past 1e20 the field itself starts to lose digits in double
precision.
"""


class NumericalError(ArithmeticError):
    """A solve produced a non-finite result; the message names the frequency and the plate."""


_Solution = TypeVar("_Solution", bound="CaseSolution")


def condition_warnings(rcond: Mapping[str, float], frequency: float) -> tuple[str, ...]:
    """One warning per plate whose condition estimate exceeds :data:`CONDITION_WARNING`.

    Parameters
    ----------
    rcond : mapping of str to float
        Reciprocal condition estimate of each plate's VTCR matrix.
    frequency : float
        Hz, named in the messages.

    Returns
    -------
    tuple of str
    """
    out = []
    for pid, value in rcond.items():
        estimate = 1.0 / value if value > 0 else float("inf")
        if not estimate <= CONDITION_WARNING:
            out.append(f"plate {pid} at {frequency:g} Hz: condition estimate {estimate:.1e} "
                       f"exceeds {CONDITION_WARNING:.0e}, the field may have lost digits; lower "
                       "[discretisation] resolution or the frequency")
    return tuple(out)


def plate_condition_warnings(solutions: Mapping[str, PlateSolution]) -> tuple[str, ...]:
    """:func:`condition_warnings` of plate solutions ``{plate: PlateSolution}``, each at its
    own frequency."""
    frequencies = {pid: s.problem.omega / (2.0 * np.pi) for pid, s in solutions.items()}
    return tuple(w for pid, s in solutions.items()
                 for w in condition_warnings({pid: s.rcond}, frequencies[pid]))


def check_finite(solution: _Solution) -> _Solution:
    """Raise :class:`NumericalError` if a solution holds a non-finite amplitude or residual.

    Nothing downstream should receive NaN silently: a non-finite ray amplitude (a singular
    or overflowing solve) or joint residual is reported with its frequency and plate (joint).

    Parameters
    ----------
    solution : CaseSolution or solver.substructure.AssemblySolution

    Returns
    -------
    The same solution.
    """
    f = solution.frequency
    for pid, plate in solution.plates.items():
        if not np.all(np.isfinite(plate.amplitudes)):
            raise NumericalError(
                f"the VTCR solve of plate {pid} at {f:g} Hz gave non-finite ray amplitudes "
                f"(condition estimate {plate.condition_estimate:.1e}); check the plate's "
                "material, thickness and loads for extreme values, or lower [discretisation] "
                "resolution")
    for jid, value in (getattr(solution, "residuals", None) or {}).items():
        if not np.isfinite(value):
            raise NumericalError(
                f"the residual of joint {jid} at {f:g} Hz is not finite ({value}); check the "
                "joint's parameters and the loads (a zero response has no residual)")
    return solution


class ToleranceError(ValueError):
    """The requested tolerance cannot be reached; the message names the plate and the cause."""


class GroupPivotError(np.linalg.LinAlgError):
    """A group's pivot block is singular: restricted pivoting cannot factorise the matrix."""
