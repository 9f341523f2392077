"""The forced response of a description at one frequency, as the solver returns it: every
plate's field (:class:`CaseSolution`); a jointed assembly's adds its joint residuals
(:class:`solver.substructure.AssemblySolution`, a subclass).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from solver.membrane import MembraneSolution

__all__ = ["CaseSolution"]


@dataclass(frozen=True)
class CaseSolution:
    """Field of every plate of an assembly at one frequency.

    Attributes
    ----------
    frequency : float
        Hz.
    plates : dict of str to PlateSolution
    timings : dict of str to float
        Seconds spent in ``"assembly"`` (basis, boundary traces, matrices) and ``"solve"``.
    warnings : tuple of str
    """

    frequency: float
    plates: dict
    timings: dict
    warnings: tuple = ()

    @property
    def n_unknowns(self) -> int:
        """Ray unknowns of all plates."""
        return sum(p.basis.n_dof for p in self.plates.values())

    @property
    def condition_estimate(self) -> float:
        """Largest condition estimate of the solves."""
        return max(p.condition_estimate for p in self.plates.values())

    def w(self, plate_id: str, points: ArrayLike) -> np.ndarray:
        """Complex displacement (m) at plate-local points of one plate, shape (n,)."""
        return self.plates[plate_id].field(points)["w"]

    def in_plane(self, plate_id: str, points: ArrayLike) -> np.ndarray:
        """Complex in-plane displacement ``(u, v)`` (m) along the plate's local x and y at its
        points, shape (n, 2): zero for a plate without in-plane waves (every plate here)."""
        return np.zeros((len(np.atleast_2d(points)), 2), dtype=complex)

    @property
    def membranes(self) -> dict[str, MembraneSolution]:
        """The in-plane field of every plate that carries one (none here): see
        :attr:`solver.substructure.AssemblySolution.membranes`."""
        return {}
