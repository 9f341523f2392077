"""Finite-element reference solver for the benchmark: Argyris triangles (scikit-fem).

Solves the forced harmonic response of a simply supported rectangular Kirchhoff
plate ``[0, Lx] x [0, Ly]`` under a point force, with the conventions of the
project: time dependence ``exp(+j omega t)`` and hysteretic damping, so that

    D (1 + j eta) lap^2 w - rho h omega^2 w = F delta(x - x0),
    D = E h^3 / (12 (1 - nu^2)).

The discretisation uses scikit-fem's ``ElementTriArgyris`` (quintic, C1, 21
dofs per triangle) on a structured ``MeshTri.init_tensor`` mesh of
``n_x x n_y`` rectangles, each split into two triangles.  This module is a
bench-only tool (dependency: ``scikit-fem``); it is not part of the ``vtcr``
package.

Run ``python bench/fem_argyris.py`` for the self-check: convergence of the FEM
solution to the Navier double-sine series (:func:`navier_reference`) at 155 Hz
and 400 Hz, then the coarsest mesh reaching 1 % from 100 Hz to 1.6 kHz.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.sparse.linalg import splu
from skfem import Basis, BilinearForm, ElementTriArgyris, MeshTri, asm
from skfem.helpers import dd, ddot, trace

#: Argyris nodal dofs that vanish at a vertex of an edge ``y = const`` when
#: ``w = 0`` along that edge (value and tangential derivatives up to order 2).
_TANGENTIAL_DOFS_X_EDGE = ["u", "u_x", "u_xx"]
#: Same for an edge ``x = const``.
_TANGENTIAL_DOFS_Y_EDGE = ["u", "u_y", "u_yy"]


@dataclass(frozen=True)
class FemResult:
    """Outcome of one Argyris FEM solve.

    Attributes
    ----------
    w : numpy.ndarray
        Complex transverse displacement (m) at the requested points, shape ``(n,)``.
    n_dofs : int
        Number of free unknowns (after eliminating the simply supported dofs).
    t_assembly : float
        Seconds spent building the mesh, the basis, the real stiffness and
        mass matrices and the load vector, and eliminating the constrained
        dofs.  Evaluating ``w`` at the points (building the point-evaluation
        operator) is not timed.
    t_solve : float
        Seconds spent forming the complex dynamic stiffness matrix and
        factorising/solving it with SuperLU.
    n_x, n_y : int
        Number of mesh intervals along ``x`` and ``y``.
    """

    w: np.ndarray
    n_dofs: int
    t_assembly: float
    t_solve: float
    n_x: int
    n_y: int


@dataclass(frozen=True)
class MeshTrial:
    """One row of the mesh-refinement table of :func:`fem_until_accurate`.

    Attributes
    ----------
    n_x, n_y : int
        Number of mesh intervals along ``x`` and ``y``.
    n_dofs : int
        Number of free unknowns.
    error : float
        Relative L2 error of ``w`` at the points against the reference.
    t_assembly, t_solve : float
        Timings of the solve, see :class:`FemResult`.
    """

    n_x: int
    n_y: int
    n_dofs: int
    error: float
    t_assembly: float
    t_solve: float


@BilinearForm
def bending_form(u, v, w):
    """Bending form with unit rigidity: (1-nu) u_,ab v_,ab + nu lap u lap v."""
    nu = w.nu
    return (1.0 - nu) * ddot(dd(u), dd(v)) + nu * trace(dd(u)) * trace(dd(v))


@BilinearForm
def mass_form(u, v, _):
    """Unit mass form: u v."""
    return u * v


def bending_stiffness(E: float, nu: float, h: float) -> float:
    """Return the (real) bending stiffness ``D = E h^3 / (12 (1 - nu^2))``.

    Parameters
    ----------
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio.
    h : float
        Thickness (m).

    Returns
    -------
    float
        Bending stiffness (N m).
    """
    return E * h**3 / (12.0 * (1.0 - nu**2))


def bending_wavelength(E: float, nu: float, rho: float, h: float, frequency: float) -> float:
    """Return the free bending wavelength ``2 pi / k`` of the undamped plate.

    Parameters
    ----------
    E, nu, rho, h : float
        Young's modulus (Pa), Poisson's ratio, density (kg/m^3), thickness (m).
    frequency : float
        Frequency (Hz).

    Returns
    -------
    float
        Wavelength (m), with ``k^4 = rho h omega^2 / D``.
    """
    omega = 2.0 * math.pi * frequency
    k = (rho * h * omega**2 / bending_stiffness(E, nu, h)) ** 0.25
    return 2.0 * math.pi / k


def solve_fem(
    Lx: float,
    Ly: float,
    E: float,
    nu: float,
    rho: float,
    h: float,
    eta: float,
    frequency: float,
    force_at: tuple[float, float],
    force: complex,
    points: np.ndarray,
    n_x: int,
    n_y: int,
) -> FemResult:
    """Solve the simply supported plate under a point force with Argyris elements.

    Parameters
    ----------
    Lx, Ly : float
        Plate dimensions (m); the plate is ``[0, Lx] x [0, Ly]``.
    E, nu, rho, h : float
        Young's modulus (Pa), Poisson's ratio, density (kg/m^3), thickness (m).
    eta : float
        Hysteretic loss factor: the stiffness is multiplied by ``1 + j eta``.
    frequency : float
        Excitation frequency (Hz).
    force_at : tuple of float
        Position ``(x0, y0)`` of the point force (m), inside the plate.  It
        need not be a mesh node: the load vector is the Argyris basis
        evaluated at that point (exact Dirac load for a C1 element).
    force : complex
        Force amplitude (N).
    points : numpy.ndarray
        Evaluation points, shape ``(n, 2)``, inside the plate.
    n_x, n_y : int
        Number of mesh intervals along ``x`` and ``y`` (``2 n_x n_y`` triangles).

    Returns
    -------
    FemResult
        Displacements at ``points``, number of free dofs and timings.

    Notes
    -----
    Simply supported edges impose ``w = 0`` along each edge: at every boundary
    vertex the value and the first and second tangential derivatives are
    constrained (``u, u_x, u_xx`` on ``y = 0, Ly``; ``u, u_y, u_yy`` on
    ``x = 0, Lx``; all five at corners), which makes the quintic trace vanish
    identically; ``u_xy`` and the edge normal-derivative dofs stay free, so the
    zero normal moment is natural.

    scikit-fem builds each Argyris basis from global monomials ``x^i y^j``
    through a per-triangle inverse Vandermonde matrix whose conditioning grows
    like ``(L / element size)^5``.  On very fine meshes (tens of thousands of
    dofs) this sets a round-off floor of about 1e-5 on the relative error,
    far below the accuracies a benchmark needs.  Centring the plate on the
    origin would lower that floor but makes scikit-fem's ``x**i`` on negative
    coordinates about five times slower, so it is not done.
    """
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    t0 = time.perf_counter()
    mesh = MeshTri.init_tensor(np.linspace(0.0, Lx, n_x + 1), np.linspace(0.0, Ly, n_y + 1))
    # A fresh element per mesh: ElementGlobal caches its inverse Vandermonde
    # matrices (one per triangle) on the instance.
    basis = Basis(mesh, ElementTriArgyris())
    K = bending_stiffness(E, nu, h) * asm(bending_form, basis, nu=nu)
    M = rho * h * asm(mass_form, basis)
    load = force * basis.point_source(np.asarray(force_at, dtype=float))

    x_edges = basis.get_dofs(lambda x: np.isclose(x[1], 0.0) | np.isclose(x[1], Ly))
    y_edges = basis.get_dofs(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], Lx))
    fixed = np.union1d(x_edges.all(_TANGENTIAL_DOFS_X_EDGE), y_edges.all(_TANGENTIAL_DOFS_Y_EDGE))
    free = basis.complement_dofs(fixed)
    K_ff = K[free][:, free]
    M_ff = M[free][:, free]
    load_f = load[free]
    t1 = time.perf_counter()

    omega = 2.0 * math.pi * frequency
    A = ((1.0 + 1j * eta) * K_ff - omega**2 * M_ff).tocsc()
    u_f = splu(A).solve(load_f.astype(complex))
    t2 = time.perf_counter()

    probes = basis.probes(points.T).tocsr()
    return FemResult(
        w=probes[:, free] @ u_f,
        n_dofs=free.size,
        t_assembly=t1 - t0,
        t_solve=t2 - t1,
        n_x=n_x,
        n_y=n_y,
    )


def mesh_intervals(
    Lx: float, Ly: float, wavelength: float, per_wavelength: float
) -> tuple[int, int]:
    """Return the mesh size ``(n_x, n_y)`` giving a target element density.

    Parameters
    ----------
    Lx, Ly : float
        Plate dimensions (m).
    wavelength : float
        Bending wavelength (m), see :func:`bending_wavelength`.
    per_wavelength : float
        Requested number of mesh intervals (element edges) per wavelength.

    Returns
    -------
    tuple of int
        ``(n_x, n_y)``, each at least 2.
    """
    return (
        max(2, math.ceil(per_wavelength * Lx / wavelength)),
        max(2, math.ceil(per_wavelength * Ly / wavelength)),
    )


def relative_error(w: np.ndarray, reference_w: np.ndarray) -> float:
    """Return the relative L2 error ``||w - reference_w|| / ||reference_w||``.

    Parameters
    ----------
    w, reference_w : numpy.ndarray
        Complex displacements at the same points.

    Returns
    -------
    float
        Relative error.
    """
    return float(np.linalg.norm(w - reference_w) / np.linalg.norm(reference_w))


def fem_until_accurate(
    reference_w: np.ndarray,
    points: np.ndarray,
    Lx: float,
    Ly: float,
    E: float,
    nu: float,
    rho: float,
    h: float,
    eta: float,
    frequency: float,
    force_at: tuple[float, float],
    force: complex,
    target: float = 0.01,
    per_wavelength: tuple[float, ...] = tuple(np.arange(1.0, 16.001, 0.02)),
) -> tuple[FemResult, list[MeshTrial]]:
    """Refine the Argyris mesh until ``w`` at ``points`` matches a reference.

    Meshes are tried in order of increasing element density (intervals per
    bending wavelength, see :func:`mesh_intervals`), skipping densities that
    round to an already tried mesh.  The default steps are fine enough for
    ``n_x`` and ``n_y`` to grow one interval at a time on the bench plate:
    steps of 0.5 skipped meshes (at 1.6 kHz by three intervals at a time)
    and overshot the coarsest accurate one.

    Parameters
    ----------
    reference_w : numpy.ndarray
        Reference complex displacements at ``points``, shape ``(n,)``.
    points : numpy.ndarray
        Evaluation points, shape ``(n, 2)``.
    Lx, Ly, E, nu, rho, h, eta, frequency, force_at, force
        Problem data, as in :func:`solve_fem`.
    target : float, optional
        Relative L2 error to reach (default 1 %).
    per_wavelength : tuple of float, optional
        Element densities to try, in increasing order (default 1, 1.02, ..., 16).

    Returns
    -------
    result : FemResult
        The first (coarsest) solve whose relative error is below ``target``.
    table : list of MeshTrial
        Every mesh tried, in order, the last one being ``result``'s.

    Raises
    ------
    RuntimeError
        If no density in ``per_wavelength`` reaches ``target``.
    """
    wavelength = bending_wavelength(E, nu, rho, h, frequency)
    table: list[MeshTrial] = []
    tried: set[tuple[int, int]] = set()
    for density in per_wavelength:
        n_x, n_y = mesh_intervals(Lx, Ly, wavelength, density)
        if (n_x, n_y) in tried:
            continue
        tried.add((n_x, n_y))
        result = solve_fem(
            Lx, Ly, E, nu, rho, h, eta, frequency, force_at, force, points, n_x, n_y
        )
        error = relative_error(result.w, reference_w)
        table.append(
            MeshTrial(n_x, n_y, result.n_dofs, error, result.t_assembly, result.t_solve)
        )
        if error < target:
            return result, table
    raise RuntimeError(
        f"relative error {table[-1].error:.3g} still above {target} "
        f"on the finest mesh {table[-1].n_x} x {table[-1].n_y}"
    )


def navier_reference(
    Lx: float,
    Ly: float,
    E: float,
    nu: float,
    rho: float,
    h: float,
    eta: float,
    frequency: float,
    force_at: tuple[float, float],
    force: complex,
    points: np.ndarray,
    n_modes: int = 400,
) -> np.ndarray:
    """Navier double-sine series solution: the bench's own check of the FEM.

    Independent of both the FEM and the project's solver: the simply supported
    modes ``sin(m pi x / Lx) sin(n pi y / Ly)`` diagonalise the problem, so

        w = sum_mn 4 F phi_mn(x0) phi_mn(x) / (Lx Ly (D (1 + j eta) k_mn^4 - rho h omega^2)),
        k_mn^2 = (m pi / Lx)^2 + (n pi / Ly)^2.

    Parameters
    ----------
    Lx, Ly, E, nu, rho, h, eta, frequency, force_at, force, points
        Problem data, as in :func:`solve_fem`.
    n_modes : int, optional
        Number of terms kept in each direction (``m, n = 1 .. n_modes``).

    Returns
    -------
    numpy.ndarray
        Complex displacements at ``points``, shape ``(n,)``.
    """
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    omega = 2.0 * math.pi * frequency
    stiffness = bending_stiffness(E, nu, h) * (1.0 + 1j * eta)
    kx = np.arange(1, n_modes + 1) * math.pi / Lx
    ky = np.arange(1, n_modes + 1) * math.pi / Ly
    k2 = kx[:, None] ** 2 + ky[None, :] ** 2
    amplitude = (
        4.0 * force / (Lx * Ly)
        * np.outer(np.sin(kx * force_at[0]), np.sin(ky * force_at[1]))
        / (stiffness * k2**2 - rho * h * omega**2)
    )
    sin_x = np.sin(np.outer(points[:, 0], kx))
    sin_y = np.sin(np.outer(points[:, 1], ky))
    return np.einsum("pm,mn,pn->p", sin_x, amplitude, sin_y)


def _print_table(rows: list[MeshTrial]) -> None:
    """Print a convergence table, one row per mesh."""
    print(f"  {'mesh':>9} {'dofs':>7} {'rel. L2 error':>14} {'t_assembly':>11} {'t_solve':>9}")
    for row in rows:
        print(
            f"  {f'{row.n_x}x{row.n_y}':>9} {row.n_dofs:>7d} {row.error:>14.2e}"
            f" {row.t_assembly:>10.3f}s {row.t_solve:>8.4f}s"
        )


def _main() -> None:
    """Validate the FEM against the Navier series on the reference case."""
    plate = dict(Lx=0.5, Ly=0.4, E=210e9, nu=0.3, rho=7800.0, h=1e-3, eta=0.01)
    load = dict(force_at=(0.12, 0.31), force=1.0)
    x, y = np.meshgrid(
        np.linspace(0.0, plate["Lx"], 12)[1:-1], np.linspace(0.0, plate["Ly"], 12)[1:-1]
    )
    points = np.column_stack([x.ravel(), y.ravel()])
    n_modes = 400

    for frequency in (155.0, 400.0):
        reference = navier_reference(**plate, frequency=frequency, **load, points=points,
                                     n_modes=n_modes)
        doubled = navier_reference(**plate, frequency=frequency, **load, points=points,
                                   n_modes=2 * n_modes)
        wavelength = bending_wavelength(plate["E"], plate["nu"], plate["rho"], plate["h"],
                                        frequency)
        print(f"\n{frequency:g} Hz: bending wavelength {wavelength:.4f} m; Navier series with "
              f"{n_modes}^2 modes, change when doubled {relative_error(reference, doubled):.1e}")
        rows = []
        for density in (1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 6.0, 8.0, 12.0):
            n_x, n_y = mesh_intervals(plate["Lx"], plate["Ly"], wavelength, density)
            result = solve_fem(**plate, frequency=frequency, **load, points=points,
                               n_x=n_x, n_y=n_y)
            rows.append(MeshTrial(n_x, n_y, result.n_dofs, relative_error(result.w, reference),
                                  result.t_assembly, result.t_solve))
        _print_table(rows)

    print("\nCoarsest mesh reaching 1 % (fem_until_accurate) across the band:")
    print(f"  {'freq':>6} {'mesh':>9} {'dofs':>7} {'rel. L2 error':>14} {'t_assembly':>11}"
          f" {'t_solve':>9}")
    for frequency in (100.0, 155.0, 400.0, 800.0, 1600.0):
        reference = navier_reference(**plate, frequency=frequency, **load, points=points,
                                     n_modes=n_modes)
        result, table = fem_until_accurate(reference, points, **plate, frequency=frequency,
                                           **load)
        print(f"  {frequency:>5g}  {f'{result.n_x}x{result.n_y}':>9} {result.n_dofs:>7d}"
              f" {table[-1].error:>14.2e} {result.t_assembly:>10.3f}s {result.t_solve:>8.4f}s")


if __name__ == "__main__":
    _main()
