"""VTCR numerics: Kirchhoff plate operators, complex rays, plate and assembly solves.

Import direction: ``assembly`` <- ``solver`` <- ``updating``; this package never imports
``updating``.
"""

from solver.plate import PlateProblem, PlateSolution, solve_plate
from solver.rays import RayCounts, automatic_ray_counts, build_ray_basis
from solver.solution import CaseSolution
from solver.vtcr import field_grid, solve_case

__all__ = [
    "CaseSolution",
    "PlateProblem",
    "PlateSolution",
    "RayCounts",
    "automatic_ray_counts",
    "build_ray_basis",
    "field_grid",
    "solve_case",
    "solve_plate",
]
