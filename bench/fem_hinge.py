r"""Finite-element reference for two plates joined by a hinge with a rotational spring and
free on their other edges (the paper's folded plate in its unfolded flat layout), scikit-fem,
written apart from the VTCR solver (it imports nothing of ``solver``, ``assembly`` or
``updating``; the validation imports ``tests/exact.py``).

The structure
-------------
Kirchhoff plates of steel, E = 210 GPa, nu = 0.3, rho = 7800 kg/m^3, eta = 1e-4, h = 0.7 mm:
``D* = E h^3 (1 + j eta) / (12 (1 - nu^2))`` (``|D*|`` = 6.596 N m), time factor
``exp(+j omega t)``, ``D* lap^2 w - rho h omega^2 w = F delta(x - x0)``. P1 is ``[0, 0.2]^2``,
P2 is global ``[0.2, 0.4] x [0, 0.2]`` with local ``x = x_global - 0.2`` (same ``y``); every
point and field below is in plate-local coordinates. The joint, the line ``x_global = 0.2``:
``w = 0`` on both plates along all of it, and a rotational spring of stiffness ``k`` (N m/m per
rad, ``k* = k``, no joint damping) on the jump of the slope,
``[w_x](y) = w_x^P1(0.2, y) - w_x^P2(0, y)``. Every other edge is free, or (validation only)
the edges ``y = 0, 0.2`` of both plates are simply supported (``y_edges``). F = 1 N on P1 at
(0.08, 0.13).

Weak form (bilinear, no conjugation)
------------------------------------
Find ``(w1, w2)`` in ``V`` (``H^2`` on each plate, ``w = 0`` on the joint, and on ``y = 0,
0.2`` when simply supported) such that for every ``(v1, v2)`` in ``V``

    sum_p int_p { D* [(1 - nu) w_,ab v_,ab + nu lap w lap v] - omega^2 rho h w v } dA
        + k* int_0^0.2 [w_x](y) [v_x](y) dy  =  1 * v1(0.08, 0.13),

i.e. the spring energy ``(1/2) int k* [w_x]^2 dy``. The free edges' conditions (``M_n = 0``,
``K_n = 0``, no corner force) and the joint's moments are natural.

The spring law and ``levy_chain``
---------------------------------
``tests/exact.py`` writes, on an edge of outward normal ``n``, ``theta = dw/dn = n_x w_x``
and ``M_n = -D* (w_nn + nu w_tt)``, and its ``hinge(k)`` is ``w_A = w_B = 0``,
``M_n^A = M_n^B = k* Theta`` with ``Theta = theta_A + theta_B`` (A's right edge, B's left
edge), ``k* = k (1 + j zeta)``, ``zeta = 0`` by default. So ``Theta = w_x^A - w_x^B = [w_x]``.
Integrating the form above by parts (``v = 0`` on the joint) leaves on the joint
``int (-M_n^P1 v1_x + M_n^P2 v2_x + k* [w_x] (v1_x - v2_x)) dy = 0``, i.e. ``M_n^P1 = M_n^P2 =
k* [w_x]``: the same law with the same ``k`` (checked by derivation, then numerically). With
simply supported y-edges, :func:`validate` compares with ``levy_chain([Section(0.2, D*, nu,
rho h)] * 2, 0.2, omega, [hinge(k)], left="free", right="free", point_forces=[(0, 0.08, 0.13,
1)])`` (``levy_chain`` accepts 'free' outer edges; its default 1000 harmonics, and 4000 change
``w`` by < 1e-15 at the grid points): ``w`` converges to it to 1e-9 and the joint's rotation
``[w_x]`` to its ``edge_slope('right') + edge_slope('left')``; the Levy solution with ``2 k``
or ``k / 2`` instead differs from the n = 3 FEM by 1.6e-3 to 2 (a factor two or a sign in the
law could not pass).

Discretisation
--------------
Argyris triangles (quintic, C1, 21 dofs), ``fem_clamped.PlateFE`` (scikit-fem's
``ElementTriArgyris`` with each triangle's basis in its own centred, scaled monomials:
``fem_argyris``'s global monomials leave a 1e-5 round-off floor on the small elements needed
here), one mesh per plate, both cut from one unfolded mesh so that their joint vertices are
identical; the two plates' dofs are separate. ``w = 0`` on an edge: ``u, u_y, u_yy`` at the
joint's vertices (``u, u_x, u_xx`` on simply supported y-edges), which makes the quintic trace
vanish. Spring: ``S = J^T diag(weights) J``, ``J`` the jump of ``w_x`` (``w_x`` of P1 minus
``w_x`` of P2, each evaluated in its joint cells) at 5 Gauss points per joint edge (the
product of two quartic traces is exact). The force sits on a mesh vertex; its load vector is
the Argyris basis there. The system ``(D* K - omega^2 rho h M + k S) u = f`` on the free dofs
is scaled by its diagonal and solved by SuperLU with three steps of iterative refinement
(relative residual 1e-11 to 1e-9; another ordering, COLAMD, moves ``w`` by <= 2e-9).

Meshes
------
:class:`MeshLevel` ``n``: squares of at most ``0.02 / n`` m on a grid holding the lines
``x = 0.08``, ``y = 0.13`` and the joint, refined (red-green-blue) until a triangle's longest
edge is at most ``sqrt(2) max(r / n, h_min)`` for each grading point (``r`` its distance to the
triangle's nearest vertex): size proportional to ``r``, finer with ``n``.

* The joint's ends (0.2, 0), (0.2, 0.2), seen from both plates, where the fields are not
  smooth: below ``D/k`` (6.6e-5 m at ``k = 1e5``, 2.6e-2 m at ``k = 10^2.4``) each plate sees
  a simply supported-free right corner (Williams' equation, solved numerically, has only
  integer roots there: the borderline angle, where ``r^2 log r`` terms can appear), above it,
  for stiff springs, one plate over a line support meeting a free edge. ``h_min = 1e-6``;
  1e-8 instead moves ``w`` by <= 5e-10 (n = 3).
* The far corners: free-free (Williams' equation, solved numerically: ``w ~ r^2.757``, moments
  bounded, shear not) with free y-edges, simply supported-free (graded like the joint's ends)
  for the validation. Free-free: ``h_min = 1e-3``. Where ``w`` is not held, smaller elements
  cost round-off (value dofs of stiffness ``D/h^2`` times ``w``, acting on the soft mode of a
  local translation; it grows like ``1/h^2``): grading a point of the validation's free edge
  (0, 0.1), where ``w`` is smooth, to 1e-3, 3e-4, 1e-4 adds <= 5e-10, 1.5e-8 to 4.7e-8, up to
  6.5e-8 to the n = 4 error against ``levy_chain`` (and 1e-6 about 1e-4 at n = 1); free
  corners graded to 3e-4 or 1e-4 differ from 1e-3 by up to 1.3e-7 and 4.4e-7 (n = 4), and
  by up to 5e-7 from each other. The floors' own error is measured by raising them
  (:data:`RAISED_FLOORS`) and counted in the accuracy (see :func:`reference`).
* The force (``w ~ r^2 log r``): ``h_min = 1e-3``; 3e-4 moves ``w`` by <= 4e-9 (n = 3).

Sizes (triangles / free dofs, both plates): free y-edges n = 3, 4, 5, 6: 9192 / 42982,
14380 / 66764, 20632 / 95250, 28480 / 130974 (raised floors at n = 6: 26720 / 122886);
simply supported y-edges n = 1, 2, 3, 4: 2820 / 13336, 5696 / 26390, 12072 / 55618,
18580 / 85048.

Measured accuracy
-----------------
Relative L2 norms over the 15 x 15 points ``GRID x GRID`` of each plate (P1 / P2).

* Validation (simply supported y-edges), error against ``levy_chain``, n = 1, 2, 3, 4:
  333.3 Hz, log10 k = 2.4: 4.5e-6 / 2.7e-6, 1.3e-7 / 4.0e-8, 1.5e-8 / 3.7e-9, 3.2e-9 / 5.4e-10;
  333.3 Hz, 5.0: 3.5e-6 / 2.4e-6, 9.4e-8 / 3.4e-8, 1.1e-8 / 3.1e-9, 2.3e-9 / 5.1e-10;
  550 Hz, 2.4: 1.3e-5 / 1.1e-5, 3.0e-7 / 1.0e-7, 3.3e-8 / 9.1e-9, 6.8e-9 / 1.4e-9;
  550 Hz, 5.0: 1.5e-5 / 8.7e-6, 3.8e-7 / 1.2e-7, 4.3e-8 / 1.1e-8, 9.1e-9 / 1.6e-9.
  At n = 4, ``w`` at the twelve points 1 mm and 0.1 mm from the joint (:data:`NEAR_JOINT`)
  1.4e-8 to 8.4e-8; the joint's rotation, at 333.3 / 550 Hz, 1.7e-8 / 2.1e-8 (log10 k = 2.4)
  and 5.3e-7 / 2.1e-6 (5.0: there ``[w_x] = M / k`` is a small difference of two slopes).
* Reference (free y-edges), change from the previous level, n = 4, 5, 6:
  333.3 Hz, 2.4: 1.3e-8 / 3.9e-9, 2.7e-9 / 2.6e-9, 1.1e-9 / 1.8e-9;
  333.3 Hz, 5.0: 1.2e-8 / 4.2e-9, 2.6e-9 / 3.2e-9, 1.8e-9 / 3.3e-9;
  550 Hz, 2.4: 2.7e-8 / 2.0e-8, 5.6e-9 / 4.4e-9, 1.5e-9 / 1.1e-9;
  550 Hz, 5.0: 2.8e-8 / 1.6e-8, 5.8e-9 / 4.4e-9, 1.9e-9 / 1.3e-9;
  1234.5 Hz, 2.4: 1.5e-7 / 1.6e-7, 2.9e-8 / 2.4e-8, 8.1e-9 / 6.9e-9;
  1234.5 Hz, 5.0: 8.7e-7 / 7.8e-7, 8.7e-8 / 8.0e-8, 2.2e-8 / 2.0e-8.
  Raised floors at n = 6 move ``w`` by 2.6e-9 to 6.1e-8; the estimated accuracy of the saved
  fields (last change plus half that) is 2.4e-9 to 1.7e-8, and 5.2e-8 / 4.8e-8 at 1234.5 Hz,
  log10 k = 5.0.

Data
----
:func:`reference` writes ``tests/data/fem_hinge_free_edges.npz`` (50 KB): ``xs``, ``ys``
(both ``GRID = linspace(0.01, 0.19, 15)``); for each frequency in 333.3, 550.0, 1234.5 Hz,
log10 k in 2.4, 5.0 and plate in P1, P2 the key ``f{frequency:.1f}_k{log10 k:.1f}_P{plate}``
(``f333.3_k2.4_P1``, ..., ``f1234.5_k5.0_P2``) holding 225 complex ``w`` (m) at ``[(x, y)
for x in xs for y in ys]`` (point ``15 i_x + i_y``, plate-local), and the floats ``<key>_change``
(the last change) and ``<key>_accuracy`` (the estimate above).

Run
---
``OPENBLAS_NUM_THREADS=1 python bench/fem_hinge.py [--validate | --reference]``: the
validation table, then the reference's table and the npz; both took 19 min 22 s on one core
(about 3 min for the validation), 2.7 GB.
"""

from __future__ import annotations

import itertools
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.sparse import block_diag, diags, hstack
from scipy.sparse.linalg import splu
from skfem import MeshTri

sys.path.insert(0, str(Path(__file__).resolve().parent))  # fem_clamped imports fem_argyris
from fem_clamped import PlateFE

E, NU, RHO, H, ETA = 210e9, 0.3, 7800.0, 0.7e-3, 1e-4
D_STAR = E * H ** 3 * (1 + 1j * ETA) / (12 * (1 - NU ** 2))
RHO_H = RHO * H
SIDE = 0.2  # each plate is [0, SIDE]^2 in its local coordinates; P2's local x = global x - SIDE
LOAD = (0.08, 0.13)  # the unit force, on P1
Y_EDGES = ("free", "simply_supported")
GRID = np.linspace(0.01, 0.19, 15)  # the reference's points, per plate and per axis
FREQUENCIES = (333.3, 550.0, 1234.5)
LOG10_K = (2.4, 5.0)
ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "fem_hinge_free_edges.npz"

# Argyris nodal dofs that vanish at the vertices of an edge along which w = 0 (the value and
# its first two tangential derivatives): the quintic trace then vanishes identically
ALONG_X_EDGE = ["u", "u_y", "u_yy"]  # an edge x = const (the joint)
ALONG_Y_EDGE = ["u", "u_x", "u_xx"]  # an edge y = const
GAUSS_NODES = 5  # per joint edge: exact for the spring's integrand, a polynomial of degree 8


def grid_points(xs=GRID, ys=GRID) -> np.ndarray:
    """``[(x, y) for x in xs for y in ys]`` as an ``(n, 2)`` array (``y`` fastest)."""
    return np.array([(x, y) for x in xs for y in ys], float)


# ---------------------------------------------------------------------------------------------
# Meshes
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class MeshLevel:
    """The mesh of refinement ``n``: squares of about ``CELL / n`` (two triangles each) whose
    grid has the lines ``x = 0.08``, ``y = 0.13`` (the force on a vertex) and ``x = SIDE`` (the
    joint), refined until a triangle's longest edge is at most ``sqrt(2) max(r / n, h_min)``
    for each grading point, ``r`` the distance from the triangle's nearest vertex to it."""

    n: int
    h_joint_corner: float = 1e-6
    h_free_corner: float = 1e-3
    h_load: float = 1e-3

    CELL = 0.02

    def grading_points(self, y_edges: str) -> list[tuple[float, float, float]]:
        """``(x, y, h_min)`` in the unfolded layout ``[0, 2 SIDE] x [0, SIDE]``: the joint's
        ends, the far corners (free-free, or simply supported-free when ``y_edges`` is
        'simply_supported') and the force."""
        far = self.h_free_corner if y_edges == "free" else self.h_joint_corner
        return ([(SIDE, y, self.h_joint_corner) for y in (0.0, SIDE)]
                + [(x, y, far) for x in (0.0, 2 * SIDE) for y in (0.0, SIDE)]
                + [(*LOAD, self.h_load)])


def axis_lines(breaks, cell: float) -> np.ndarray:
    """Grid lines through ``breaks`` (increasing), each interval cut into equal cells of at
    most ``cell``."""
    pieces = [np.linspace(a, b, math.ceil((b - a) / cell - 1e-9) + 1)[:-1]
              for a, b in itertools.pairwise(breaks)]
    return np.concatenate(pieces + [[breaks[-1]]])


def graded_mesh(level: MeshLevel, y_edges: str) -> MeshTri:
    """The unfolded mesh of ``[0, 2 SIDE] x [0, SIDE]`` (red-green-blue refinement of the
    tensor grid, see :class:`MeshLevel`)."""
    cell = level.CELL / level.n
    mesh = MeshTri.init_tensor(axis_lines([0.0, LOAD[0], SIDE, 2 * SIDE], cell),
                               axis_lines([0.0, LOAD[1], SIDE], cell))
    points = level.grading_points(y_edges)
    while True:
        P = mesh.p[:, mesh.t]
        edges = np.stack([P[:, 0] - P[:, 1], P[:, 1] - P[:, 2], P[:, 2] - P[:, 0]])
        size = np.sqrt((edges ** 2).sum(axis=1)).max(axis=0)
        target = np.full(mesh.t.shape[1], np.inf)
        for x, y, h_min in points:
            r = np.sqrt((P[0] - x) ** 2 + (P[1] - y) ** 2).min(axis=0)
            target = np.minimum(target, np.maximum(r / level.n, h_min))
        marked = np.nonzero(size > np.sqrt(2) * target * (1 + 1e-9))[0]
        if marked.size == 0:
            return mesh
        mesh = mesh.refined(marked)


def plate_meshes(level: MeshLevel, y_edges: str) -> tuple[MeshTri, MeshTri]:
    """The unfolded mesh split on the joint: P1's and P2's meshes in their local
    coordinates, with the same vertices on the joint."""
    mesh = graded_mesh(level, y_edges)
    centre_x = mesh.p[0, mesh.t].mean(axis=0)
    meshes = []
    for cells, shift in ((centre_x < SIDE, 0.0), (centre_x > SIDE, SIDE)):
        t = mesh.t[:, cells]
        used, t_new = np.unique(t, return_inverse=True)
        p = mesh.p[:, used] - np.array([[shift], [0.0]])
        meshes.append(MeshTri(np.ascontiguousarray(p),
                              np.ascontiguousarray(t_new.reshape(t.shape))))
    return meshes[0], meshes[1]


# ---------------------------------------------------------------------------------------------
# The model
# ---------------------------------------------------------------------------------------------
class HingePlate:
    """One plate: Argyris unit-stiffness and unit-mass matrices (``fem_clamped.PlateFE``), its
    joint edge ``x = joint_x`` and its constrained dofs (``w = 0`` on the joint and, when
    ``y_edges`` is 'simply_supported', on ``y = 0, SIDE``)."""

    def __init__(self, mesh: MeshTri, joint_x: float, y_edges: str):
        self.fe = PlateFE(None, None, NU, mesh=mesh)
        self.joint_x = joint_x
        joint = self.fe.facets(lambda x: np.abs(x[0] - joint_x) < 1e-12)
        ends = mesh.p[1, mesh.facets[:, joint]]
        joint = joint[np.argsort(ends.mean(axis=0))]
        self.joint_y = np.append(np.sort(ends.min(axis=0)), SIDE)  # the joint's vertices
        self.joint_cells = mesh.f2t[0, joint]  # the cell on each joint edge, in order
        basis = self.fe.basis
        fixed = [basis.get_dofs(facets=joint).all(ALONG_X_EDGE)]
        if y_edges == "simply_supported":
            ends = self.fe.facets(lambda x: (np.abs(x[1]) < 1e-12) | (np.abs(x[1] - SIDE) < 1e-12))
            fixed.append(basis.get_dofs(facets=ends).all(ALONG_Y_EDGE))
        self.fixed = np.unique(np.concatenate(fixed))

    def slope(self, y: np.ndarray):
        """Sparse matrix of ``w_x`` at the joint points ``(joint_x, y)``."""
        e = np.clip(np.searchsorted(self.joint_y, y, side="right") - 1, 0, len(self.joint_y) - 2)
        points = np.vstack([np.full(len(y), self.joint_x), y])
        return self.fe.eval_matrix(points, self.joint_cells[e], what="dx")

    def values(self, points: np.ndarray):
        """Sparse matrix of ``w`` at ``points`` (n, 2), local coordinates inside the plate."""
        return self.fe.eval_matrix(np.asarray(points, float).reshape(-1, 2).T)


def spring_matrix(p1: HingePlate, p2: HingePlate):
    """``S`` with ``u^T S u^ = int_0^SIDE [w_x](y) [w^_x](y) dy``, ``[w_x] = w_x^P1(SIDE, y) -
    w_x^P2(0, y)``, on the dofs of P1 then P2 (Gauss quadrature per joint edge)."""
    if not np.array_equal(p1.joint_y, p2.joint_y):
        raise ValueError("the plates' meshes differ on the joint")
    t, weights = np.polynomial.legendre.leggauss(GAUSS_NODES)
    y0, y1 = p1.joint_y[:-1, None], p1.joint_y[1:, None]
    y = (0.5 * (y0 + y1) + 0.5 * (y1 - y0) * t).ravel()
    jump = hstack([p1.slope(y), -p2.slope(y)]).tocsr()
    return (jump.T @ diags((0.5 * (y1 - y0) * weights).ravel()) @ jump).tocsr()


class HingeModel:
    """Both plates on the mesh ``MeshLevel(refinement)`` (or ``refinement`` itself, a
    :class:`MeshLevel`) with ``y_edges`` 'free' or 'simply_supported': unit matrices ``K``
    (bending), ``M`` (mass), ``S`` (spring) on the dofs of P1 then P2, the free dofs and the
    load vector; :meth:`solve` for any frequency and stiffness."""

    def __init__(self, refinement: int | MeshLevel, y_edges: str):
        if y_edges not in Y_EDGES:
            raise ValueError(f"y_edges must be one of {Y_EDGES}, got {y_edges!r}")
        t0 = time.perf_counter()
        level = refinement if isinstance(refinement, MeshLevel) else MeshLevel(refinement)
        meshes = plate_meshes(level, y_edges)
        self.n_triangles = sum(mesh.t.shape[1] for mesh in meshes)
        self.plates = (HingePlate(meshes[0], SIDE, y_edges), HingePlate(meshes[1], 0.0, y_edges))
        p1, p2 = self.plates
        self.offset = p1.fe.N
        self.K = block_diag([p1.fe.K, p2.fe.K]).tocsr()
        self.M = block_diag([p1.fe.M, p2.fe.M]).tocsr()
        self.S = spring_matrix(p1, p2)
        size = self.K.shape[0]
        fixed = np.concatenate([p1.fixed, self.offset + p2.fixed])
        self.free = np.setdiff1d(np.arange(size), fixed)
        self.load = np.zeros(size)
        self.load[:self.offset] = p1.values(np.array(LOAD)).toarray()[0]  # F = 1 N
        self.t_setup = time.perf_counter() - t0
        self.t_solve = self.residual = math.nan

    @property
    def n_dofs(self) -> int:
        """Number of free unknowns."""
        return self.free.size

    def solve(self, frequency: float, log10_k: float) -> tuple[np.ndarray, np.ndarray]:
        """The dofs of P1 and of P2 at ``frequency`` (Hz) and ``k = 10^log10_k``:
        ``(D* K - omega^2 rho h M + k S) u = f`` on the free dofs, scaled symmetrically by its
        diagonal, SuperLU (minimum degree on ``A^T + A``) and three steps of iterative
        refinement; sets ``t_solve`` and ``residual`` (the scaled system's relative one)."""
        t0 = time.perf_counter()
        omega = 2 * math.pi * frequency
        A = D_STAR * self.K - omega ** 2 * RHO_H * self.M + 10.0 ** log10_k * self.S
        A = A[self.free][:, self.free].tocsc()
        s = diags(1.0 / np.sqrt(np.abs(A.diagonal())))
        A = (s @ A @ s).tocsc()
        b = s @ self.load[self.free].astype(complex)
        lu = splu(A, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
        x = lu.solve(b)
        for _ in range(3):
            x = x + lu.solve(b - A @ x)
        self.residual = float(np.linalg.norm(b - A @ x) / np.linalg.norm(b))
        u = np.zeros(self.K.shape[0], complex)
        u[self.free] = s @ x
        self.t_solve = time.perf_counter() - t0
        return u[:self.offset], u[self.offset:]

    def w(self, u: tuple[np.ndarray, np.ndarray], points_1: np.ndarray,
          points_2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``w`` of the solution ``u`` (:meth:`solve`) at P1's ``points_1`` and P2's
        ``points_2`` (local coordinates)."""
        return (self.plates[0].values(points_1) @ u[0], self.plates[1].values(points_2) @ u[1])

    def joint_rotation(self, u: tuple[np.ndarray, np.ndarray], y: np.ndarray) -> np.ndarray:
        """``[w_x](y) = w_x^P1(SIDE, y) - w_x^P2(0, y)``, the spring's rotation."""
        return self.plates[0].slope(y) @ u[0] - self.plates[1].slope(y) @ u[1]


def hinge_w(frequency: float, log10_k: float, y_edges: str, refinement: int,
            points_1: np.ndarray, points_2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Complex ``w`` (m) of the structure at ``frequency`` (Hz), spring ``k = 10^log10_k``
    N m/m/rad, edges ``y = 0, SIDE`` of both plates ``y_edges`` ('free': the reference;
    'simply_supported': the validation), mesh ``MeshLevel(refinement)``, at P1's ``points_1``
    and P2's ``points_2`` (each (n, 2), plate-local coordinates)."""
    model = HingeModel(refinement, y_edges)
    return model.w(model.solve(frequency, log10_k), points_1, points_2)


# ---------------------------------------------------------------------------------------------
# Validation against the Levy series (y-edges simply supported)
# ---------------------------------------------------------------------------------------------
VALIDATION_FREQUENCIES = (333.3, 550.0)
VALIDATION_LEVELS = (1, 2, 3, 4)
REFERENCE_LEVELS = (3, 4, 5, 6)
RAISED_FLOORS = {"h_free_corner": 3e-3, "h_load": 3e-3}  # the floors' check (see reference)
NEAR_JOINT_Y = (0.05, 0.1, 0.15)
NEAR_JOINT = ([(x, y) for x in (0.199, 0.1999) for y in NEAR_JOINT_Y],  # on P1
              [(x, y) for x in (0.001, 0.0001) for y in NEAR_JOINT_Y])  # on P2
JOINT_Y = np.linspace(0.01, 0.19, 7)  # where the joint's rotation is compared


def relative(a: np.ndarray, b: np.ndarray) -> float:
    """``||a - b|| / ||b||``."""
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


def levy_fields(frequency: float, log10_k: float, points: np.ndarray) -> dict[str, np.ndarray]:
    """The exact solution with simply supported y-edges (``tests/exact.py``'s ``levy_chain``:
    two sections of 0.2 m, ``hinge(k)``, outer edges 'free', the force on plate 0): ``w`` at
    ``points`` of each plate ('P1', 'P2'), at :data:`NEAR_JOINT` ('J1', 'J2') and the joint's
    rotation ``theta_A + theta_B`` at :data:`JOINT_Y` ('rotation')."""
    sys.path.insert(0, str(ROOT / "tests"))
    from exact import Section, hinge, levy_chain

    section = Section(SIDE, D_STAR, NU, RHO_H)
    levy = levy_chain([section, section], SIDE, 2 * math.pi * frequency, [hinge(10.0 ** log10_k)],
                      left="free", right="free", point_forces=[(0, *LOAD, 1.0)])
    fields = {f"P{i + 1}": levy.w(*points.T, plate=i) for i in range(2)}
    fields.update({f"J{i + 1}": levy.w(*np.array(NEAR_JOINT[i]).T, plate=i) for i in range(2)})
    fields["rotation"] = (levy.plates[0].edge_slope("right", JOINT_Y)
                          + levy.plates[1].edge_slope("left", JOINT_Y))
    return fields


def fem_fields(model: HingeModel, frequency: float, log10_k: float,
               points: np.ndarray) -> dict[str, np.ndarray]:
    """The same fields as :func:`levy_fields` from ``model``."""
    u = model.solve(frequency, log10_k)
    fields = dict(zip(("P1", "P2"), model.w(u, points, points)))
    fields.update(zip(("J1", "J2"), model.w(u, *(np.array(p) for p in NEAR_JOINT))))
    fields["rotation"] = model.joint_rotation(u, JOINT_Y)
    return fields


def validate(levels=VALIDATION_LEVELS) -> None:
    """Print, per case and mesh level, the relative L2 errors against the Levy series of
    ``w`` on each plate's grid, of ``w`` at the six points per plate near the joint (both
    plates together) and of the joint's rotation."""
    points = grid_points()
    cases = [(f, k) for f in VALIDATION_FREQUENCIES for k in LOG10_K]
    exact = {case: levy_fields(*case, points) for case in cases}
    rows = {case: [] for case in cases}
    for n in levels:
        model = HingeModel(n, "simply_supported")
        for case in cases:
            fe = fem_fields(model, *case, points)
            near = [np.concatenate([fields["J1"], fields["J2"]]) for fields in (fe, exact[case])]
            rows[case].append(
                f"  {n:>2} {model.n_triangles:>6} {model.n_dofs:>7} {model.t_setup:>6.1f}s"
                f" {model.t_solve:>5.1f}s {model.residual:>7.1e}"
                f" {relative(fe['P1'], exact[case]['P1']):>9.2e}"
                f" {relative(fe['P2'], exact[case]['P2']):>9.2e} {relative(*near):>9.2e}"
                f" {relative(fe['rotation'], exact[case]['rotation']):>9.2e}")
        del model
    for (frequency, log10_k), lines in rows.items():
        print(f"\nvalidation, y-edges simply supported, {frequency:g} Hz, log10 k = {log10_k:g}:"
              f" relative L2 errors against levy_chain")
        print(f"  {'n':>2} {'tri':>6} {'dofs':>7} {'setup':>7} {'solve':>6} {'resid':>7}"
              f" {'w P1':>9} {'w P2':>9} {'w joint':>9} {'rotation':>9}")
        print("\n".join(lines))


# ---------------------------------------------------------------------------------------------
# The reference (free y-edges)
# ---------------------------------------------------------------------------------------------
def data_key(frequency: float, log10_k: float, plate: int) -> str:
    """``f333.3_k2.4_P1``: the npz key of ``w`` on plate ``plate`` (1 or 2)."""
    return f"f{frequency:.1f}_k{log10_k:.1f}_P{plate}"


def reference(levels=REFERENCE_LEVELS, path: Path = DATA) -> None:
    """Solve the six cases on each level and once more on the finest level with the floors
    :data:`RAISED_FLOORS`; print each plate's relative L2 change of ``w`` on ``grid_points()``
    from the previous level and with the raised floors, and save the finest fields to
    ``path``: ``data_key(...)`` (225 complex values), ``data_key(...) + '_change'`` (the last
    change) and ``data_key(...) + '_accuracy'`` (the last change plus half the floors'
    change: the error of an ``h_min`` floor, ``C h_min^p`` with ``p >= 1``, is at most half
    what tripling it changes), plus ``xs`` and ``ys``."""
    points = grid_points()
    cases = [(f, k) for f in FREQUENCIES for k in LOG10_K]
    fields, rows = {}, {case: [] for case in cases}
    for level in [MeshLevel(n) for n in levels] + [MeshLevel(levels[-1], **RAISED_FLOORS)]:
        model = HingeModel(level, "free")
        for case in cases:
            w = model.w(model.solve(*case), points, points)
            row = (f"  {level.n:>2} {model.n_triangles:>6} {model.n_dofs:>7}"
                   f" {model.t_setup:>6.1f}s {model.t_solve:>5.1f}s {model.residual:>7.1e}")
            if case in fields:
                row += "".join(f" {relative(a, b):>9.2e}" for a, b in zip(w, fields[case][-1]))
            rows[case].append(row)
            fields.setdefault(case, []).append(w)
        del model
    packed = {"xs": GRID, "ys": GRID}
    for case, lines in rows.items():
        print(f"\nreference, free y-edges, {case[0]:g} Hz, log10 k = {case[1]:g}: relative L2"
              f" change of w from the previous level (last row: the finest level with the"
              f" floors {', '.join(f'{k} {v:g}' for k, v in RAISED_FLOORS.items())})")
        print(f"  {'n':>2} {'tri':>6} {'dofs':>7} {'setup':>7} {'solve':>6} {'resid':>7}"
              f" {'P1':>9} {'P2':>9}")
        print("\n".join(lines))
        *_, previous, finest, raised = fields[case]
        for plate in (0, 1):
            key = data_key(*case, plate + 1)
            change = relative(finest[plate], previous[plate])
            packed[key] = finest[plate]
            packed[key + "_change"] = change
            packed[key + "_accuracy"] = change + 0.5 * relative(raised[plate], finest[plate])
            print(f"  P{plate + 1}: estimated accuracy {packed[key + '_accuracy']:.1e}")
    np.savez_compressed(path, **packed)
    print(f"\nwrote {path}")


if __name__ == "__main__":
    arguments = sys.argv[1:]
    if arguments not in ([], ["--validate"], ["--reference"]):
        raise SystemExit("usage: python bench/fem_hinge.py [--validate | --reference]")
    start = time.perf_counter()
    if arguments in ([], ["--validate"]):
        validate()
    if arguments in ([], ["--reference"]):
        reference()
    print(f"\ntotal {time.perf_counter() - start:.0f} s")
