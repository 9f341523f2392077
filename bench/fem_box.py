r"""Finite-element reference for the forward problem of ``cases/box_with_wall.toml`` (the
model's joint parameters, not its ``[truth]``), scikit-fem, written apart from the VTCR solver
(it imports only the bench modules ``fem_corner``, ``fem_folded``, ``fem_clamped``).

The structure
-------------
Steel, ``E* = E (1 + j eta)`` (E = 210 GPa, nu = 0.3, rho = 7800 kg/m^3, eta = 0.01), h = 1 mm in
every plate, ``D* = E* h^3 / (12 (1 - nu^2))``, ``A* = E* h / (1 - nu^2)``; time factor
``exp(+j omega t)``; Kirchhoff bending and plane-stress membrane in each plate. Plate ``p``
occupies its local ``[0, Lx] x [0, Ly]``, placed by the toml's frame ``(o, e_x, e_y, e_z = e_x x
e_y)``: the local point ``(x, y)`` is ``o + x e_x + y e_y`` and the displacement the 3D vector
``u e_x + v e_y + w e_z`` (:data:`PLATES`, written by hand from the case's header table):

=========  ===========  ==================  =========  =========  ======
plate      size (m)     origin              e_x        e_y        e_z
=========  ===========  ==================  =========  =========  ======
Top1|2     0.3|0.2x0.4  (0|0.3, 0, 0.3)     +x         +y         +z
Bottom1|2  0.3|0.2x0.4  (0|0.3, 0.4, 0)     +x         -y         -z
Front1|2   0.3|0.2x0.3  (0|0.3, 0, 0)       +x         +z         -y
Back1|2    0.3|0.2x0.3  (0.3|0.5, 0.4, 0)   -x         +z         +y
Left       0.4x0.3      (0, 0.4, 0)         -y         +z         -x
Right      0.4x0.3      (0.5, 0, 0)         +y         +z         +x
Wall       0.4x0.3      (0.3, 0, 0)         +y         +z         +x
=========  ===========  ==================  =========  =========  ======

Nothing supports the box. Loads: 1 N along Top1's ``e_z`` at Top1's (0.17, 0.13) (the case's,
the fields kept) and, for reciprocity, 1 N along Right's ``e_z`` at Right's (0.23, 0.11).

The lines (the case's ``[joints]``, model values, not ``[truth]``)
------------------------------------------------------------------
* 16 hinges (:data:`HINGES`, the toml's ``between`` pairs, P first): right-angled folds whose
  3D translations are tied and whose rotations about the line are each the plate's own,
  coupled by the spring energy ``1/2 k int (theta_P . t - theta_Q . t)^2 ds``, ``k = 10^2``
  N m/m/rad, loss 0 (a line of two members, the first rigid: ``Theta = theta_P``, ``C_Q = k
  (Theta - theta_Q)``).
* 4 welds W_top, W_bottom, W_front, W_back (:data:`WELDS`): the face's two halves rigid to
  the line and the wall on ``k = 10^3``. Rigid halves with the same frame (checked) are one
  plate across the line: :func:`weld_ties` ties ``w``, its first derivatives, the tangential
  second and the mixed derivative at each line vertex, the midpoint normal derivative
  (the two facets' normals compared) and ``u``, ``v`` at every P5 node, so that ``w``,
  ``w_,b`` and ``(u, v)`` are continuous identically; ``w_,bb`` (``b`` across the line) is
  left free on each side, because the wall's couple jumps the moment there
  (``fem_junction``: tying it made the couple converge like ``1 / n``; here it changed
  ``w`` by 1e-2 between levels). The wall is then a spring fold with the first half
  (``W_top.Wall``: Top1's right edge and Wall's top edge), ``Theta = theta_Top1 =
  theta_Top2``, ``C_Wall = k (Theta - theta_Wall)``.

Signs: every fold's from the frames, by ``fem_corner.FoldGeometry`` (for any right-angled
fold; see its docstring): translation ``d_b,P = (e_b,P . e_z,Q) w_Q``, ``d_b,Q = (e_b,Q .
e_z,P) w_P``, ``d_a,Q = sigma_Q d_a,P``; rotation about the line ``theta . t = kappa w_,b``
with ``theta = w_y e_x - w_x e_y``, ``kappa = e_x . t`` (edge ``y = const``) or ``-e_y . t``
(edge ``x = const``). The spring (:func:`spring_matrix`) integrates ``k (kappa_P w_P,b -
kappa_Q w_Q,b)^2`` with 5 Gauss points per line interval (exact for the quartic traces of
``w_,b``). Check: the six rigid motions give springs' energy ``<= 3e-21 k |x|^2`` (below).

Weak form: ``fem_folded``'s bending and membrane forms summed over the 11 plates plus the 20
springs' energy, in the space of fields meeting the ties (their multipliers, the lines'
forces, do no virtual work there; the moment balance of each line is natural).

Discretisation and ties
-----------------------
``w``: Argyris (``fem_clamped.ArgyrisLocal`` via ``fem_corner.CornerPlate``), ``(u, v)``: P5
Lagrange; the folds' translation ties are ``fem_corner.fold_ties`` without its rotation rows
(master-slave, exact along the line: P5 normal components equal the other plate's quintic
Hermite trace of ``w``, tangential components node by node). Where lines meet (the box's 8
corners: three hinges; the wall's 4 corners: two hinges, two welds and two wall folds) all
ties located at the point are gathered and their dofs replaced by an orthonormal basis of
their null space (``fem_corner.reduction``). Ranks, printed: at a box corner 9 rows on 9
dofs (``w, u, v`` of three plates), rank 6 (three copies of one 3D translation), null space
3; at a wall corner 26 rows (two welds' 7 vertex ties each, four folds' 3 translation ties)
on 31 dofs (both halves' ``w, w_x, w_y, w_xy``, the tangential ``w_,aa``, ``u, v`` of two
faces and the wall's ``w, u, v``), rank 20 (14 weld + the wall's and the two faces' 3D
translations equal: 6), null space 11 (one 3D translation, and per face ``w_x, w_y, w_xy,
w_,aa``: the hinges leave the rotations free).

Meshes: per plate ``fem_folded.graded_mesh`` of squares ``0.05 / n``, graded (``min(0.05, 2 r)
/ n``) towards every corner (all are line ends; floor 1e-3, :data:`H_LINE_END`) and the load
on Top1 (floor 1e-3), refined until both plates of every line have the same vertices on it
(:func:`box_meshes`). Solve: ``T^T K T`` scaled by its diagonal, SuperLU (``MMD_AT_PLUS_A``,
partial pivoting), refinement with the residual in extended precision, kept while it falls.

Self-checks
-----------
Run, one process per level (the memory is then the level's own), on a 2-core AMD EPYC, one
BLAS thread, 2026-11-28::

    OPENBLAS_NUM_THREADS=1 python bench/fem_box.py 1.5   # 151 s, 1.8 GB
    OPENBLAS_NUM_THREADS=1 python bench/fem_box.py 2     # 241 s, 2.4 GB
    OPENBLAS_NUM_THREADS=1 python bench/fem_box.py 2.5   # 697 s, 5.0 GB
    python bench/fem_box.py --report 1.5 2 2.5           # the tables; /tmp/fem_box/fields.npz

Level 1.5: 4612 triangles, 1.36e5 unknowns (27 s, 38 s per solve of both loads); level 2:
5798, 1.71e5 (71 s, 62 s); level 2.5: 10740, 3.17e5 (248 s, 290 s; 43 s set-up).
``fields.npz`` holds level 2.5's ``w_{p}_{f}`` (225,) and ``uv_{p}_{f}`` (225, 2) on each
plate's ``fem_folded.inner_grid(Lx, Ly)`` at 189.6 and 277.5 Hz, and the change from level 2
per plate (``change_w_{f}``, ``change_uv_{f}``, the order of :data:`PLATES`). Measured:

* self-convergence, relative L2 change on the 225 points of each plate, 1.5 -> 2 then 2 ->
  2.5, range over the 11 plates: 277.5 Hz ``w`` 2.2e-5 to 8.1e-5, then 2.5e-6 to 8.7e-6;
  ``(u, v)`` 1.5e-5 to 9.0e-5, then 1.5e-6 to 9.6e-6 (a clean fall of about 8). 189.6 Hz
  ``w`` 1.1e-5 to 2.0e-5, then 3.0e-6 to 2.9e-5 (not falling on the Front and Back halves
  and Left: round-off, below); ``(u, v)`` 9e-6 to 1.3e-5, then 2.0e-6 to 5.3e-6. So level 2.5 is
  within about 1e-5 at 277.5 Hz and, at 189.6 Hz, about 3e-5 in ``w`` and 5e-6 in ``(u, v)``.
  The frequencies are the true structure's resonance peaks, where a relative shift ``d`` of a
  natural frequency changes the response by about ``2 d / eta = 200 d``.
* round-off (``--roundoff 2``, 356 s, 2.5 GB; ``--roundoff 2.5 189.6``, 481 s, 5.1 GB):
  every entry of the solve's matrix moved by one rounding moves level 2's fields by 5e-7 to
  2e-6 (``w``) and 3e-7 to 2e-6 (``(u, v)``) at both frequencies, and level 2.5's at 189.6 Hz
  by 9e-6 to 3e-5 (``w``) and 6e-6 to 1e-5 (``(u, v)``): as much as its change from level 2,
  so at 189.6 Hz level 2.5 is round-off limited (at 3e-5), not better than level 2.
  The 1 mm plates' membranes, 1e6 times stiffer than their bending over a plate's width,
  make the system badly conditioned: the LU's residual is 1e-8 to 2e-7 and the refinement in
  extended precision stalls there (at level 2.5, 189.6 Hz, it diverges, 2e-7 -> 8e-5; the
  first iterate is kept). SuperLU's symmetric mode (``fem_corner``'s) was no better (level
  1.5, 277.5 Hz: 1e-7 -> 2e-6, diverging).
* reciprocity (``w_Right(0.23, 0.11)`` under the load on Top1 against ``w_Top1(0.17, 0.13)``
  under the load on Right; exact for the symmetric discrete system, so round-off): 2.5e-6 /
  5.1e-7 / 4.1e-6 at 189.6 Hz, 2.3e-6 / 3.1e-7 / 1.9e-7 at 277.5 Hz (levels 1.5 / 2 / 2.5).
* ties: ``max |C T|`` = 5.0e-16 at every level; sampled at 401 points of every line (both
  loads), the two plates' 3D displacements differ by at most 2.7e-11 of their largest value,
  the welds' rotations about the line by 1.6e-13; the folds' twist (spring) is 0.2 to 8.7 of
  the rotation there, as it may. Clusters, at every level: at each of the 8 box corners 9
  rows on 9 dofs, rank 6, null space 3; at each of the 4 wall corners 26 rows on 31 dofs,
  rank 20, null space 11 (above).
* rigid motions (3 translations, 3 rotations of the whole box, interpolated in every plate):
  tie residual <= 3e-14, distance from the range of ``T`` <= 1e-15, ``|K x| / ||K| |x||`` <=
  3e-16, the springs' energy <= 2e-21 ``k_wall |x|^2``: the free box has all six.
* the spring against the rigid fold (``--spring-limit``: ``fem_corner``'s L fold, diaphragm
  ends, here 1 mm, level 2, 277.5 Hz; 66 s): the difference from the rigid fold (rotation
  tied, ``fem_corner.fold_ties``) in ``w`` (A / B) 1.0 / 1.1 (k = 1e2), 5.7e-2 / 6.2e-2
  (1e4), 5.4e-4 / 6.0e-4 (1e6), 5.4e-6 / 6.0e-6 (1e8): ``1 / k``, as it must.
* a first version tied ``w_,bb`` across the welds too: the fields then changed by 1e-2
  between levels 1 and 2 (and differed by as much from these).
"""

from __future__ import annotations

import math
import pickle
import resource
import sys
import time
from pathlib import Path

import numpy as np
from scipy.sparse import block_diag, coo_matrix, csr_matrix, diags
from scipy.sparse.linalg import splu
from skfem import MeshTri

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fem_corner import (
    EDGES,
    ROW,
    CornerModel,
    CornerPlate,
    FoldGeometry,
    PlateSpec,
    Structure,
    Tie,
    edge_line,
    fold_ties,
    line_traces,
    reduction,
    structure_meshes,
)
from fem_folded import relative

E, NU, RHO, H, ETA = 210e9, 0.3, 7800.0, 0.001, 0.01
D_STAR = E * (1 + 1j * ETA) * H ** 3 / (12 * (1 - NU ** 2))
A_STAR = E * (1 + 1j * ETA) * H / (1 - NU ** 2)
RHO_H = RHO * H
FREQUENCIES = (189.6, 277.5)
LEVELS = (1.5, 2, 2.5)
OUT = Path("/tmp/fem_box")
TOL = 1e-12
H_LINE_END = 1e-3  # grading floor at the plates' corners (all of them line ends)
K_HINGE = 10.0 ** 2.0  # the 16 folds, N m/m/rad, loss 0
K_WALL = 10.0 ** 3.0  # the wall's member of each weld line (the faces' halves: rigid)
MAX_REFINEMENT = 12


# ---------------------------------------------------------------------------------------------
# The structure (cases/box_with_wall.toml's header table, by hand)
# ---------------------------------------------------------------------------------------------
def _plate(lx, ly, origin, ex, ey) -> PlateSpec:
    return PlateSpec(lx, ly, origin, ex, ey, {})  # nothing supported: the box floats


PLATES = {
    "Top1": _plate(0.3, 0.4, (0.0, 0.0, 0.3), (1, 0, 0), (0, 1, 0)),
    "Top2": _plate(0.2, 0.4, (0.3, 0.0, 0.3), (1, 0, 0), (0, 1, 0)),
    "Bottom1": _plate(0.3, 0.4, (0.0, 0.4, 0.0), (1, 0, 0), (0, -1, 0)),
    "Bottom2": _plate(0.2, 0.4, (0.3, 0.4, 0.0), (1, 0, 0), (0, -1, 0)),
    "Front1": _plate(0.3, 0.3, (0.0, 0.0, 0.0), (1, 0, 0), (0, 0, 1)),
    "Front2": _plate(0.2, 0.3, (0.3, 0.0, 0.0), (1, 0, 0), (0, 0, 1)),
    "Back1": _plate(0.3, 0.3, (0.3, 0.4, 0.0), (-1, 0, 0), (0, 0, 1)),
    "Back2": _plate(0.2, 0.3, (0.5, 0.4, 0.0), (-1, 0, 0), (0, 0, 1)),
    "Left": _plate(0.4, 0.3, (0.0, 0.4, 0.0), (0, -1, 0), (0, 0, 1)),
    "Right": _plate(0.4, 0.3, (0.5, 0.0, 0.0), (0, 1, 0), (0, 0, 1)),
    "Wall": _plate(0.4, 0.3, (0.3, 0.0, 0.0), (0, 1, 0), (0, 0, 1)),
}

# right-angled lines of two members on a spring: (name, (P, edge), (Q, edge), k)
HINGES = (
    ("top1_front1", ("Top1", "bottom"), ("Front1", "top")),
    ("top1_back1", ("Top1", "top"), ("Back1", "top")),
    ("top1_left", ("Top1", "left"), ("Left", "top")),
    ("bottom1_back1", ("Bottom1", "bottom"), ("Back1", "bottom")),
    ("bottom1_front1", ("Bottom1", "top"), ("Front1", "bottom")),
    ("bottom1_left", ("Bottom1", "left"), ("Left", "bottom")),
    ("front1_left", ("Front1", "left"), ("Left", "right")),
    ("back1_left", ("Back1", "right"), ("Left", "left")),
    ("top2_front2", ("Top2", "bottom"), ("Front2", "top")),
    ("top2_right", ("Top2", "right"), ("Right", "top")),
    ("top2_back2", ("Top2", "top"), ("Back2", "top")),
    ("bottom2_back2", ("Bottom2", "bottom"), ("Back2", "bottom")),
    ("bottom2_right", ("Bottom2", "right"), ("Right", "bottom")),
    ("bottom2_front2", ("Bottom2", "top"), ("Front2", "bottom")),
    ("front2_right", ("Front2", "right"), ("Right", "left")),
    ("back2_right", ("Back2", "left"), ("Right", "right")),
)
# the welds: the face's first half, its second half (rigid to it: one C1 plate) and the wall
WELDS = (
    ("W_top", ("Top1", "right"), ("Top2", "left"), ("Wall", "top")),
    ("W_bottom", ("Bottom1", "right"), ("Bottom2", "left"), ("Wall", "bottom")),
    ("W_front", ("Front1", "right"), ("Front2", "left"), ("Wall", "left")),
    ("W_back", ("Back1", "left"), ("Back2", "right"), ("Wall", "right")),
)
SPRING_FOLDS = tuple((*h, K_HINGE) for h in HINGES) + tuple(
    (f"{name}.Wall", first, wall, K_WALL) for name, first, _, wall in WELDS)
LOADS = {"main": ("Top1", 0.17, 0.13), "recip": ("Right", 0.23, 0.11)}

BOX = Structure(plates=PLATES, folds=tuple(f[:3] for f in SPRING_FOLDS), loads=LOADS,
                h_fold_end=H_LINE_END)


def weld_geometry(structure: Structure, name: str, first, second) -> FoldGeometry:
    """A coplanar rigid joint of two plates with the same frame axes (a face's two halves),
    as a ``FoldGeometry`` (``cross`` 0: no right angle; only ``line_s``, ``local`` are used)."""
    (P, eP), (Q, eQ) = first, second
    specs = structure.plates
    assert np.allclose(specs[P].axes, specs[Q].axes), f"{name}: frames differ"
    _, _, aP, oP, t = edge_line(specs[P], eP)
    _, _, aQ, oQ, tQ = edge_line(specs[Q], eQ)
    sigma_Q = float(tQ @ t)
    assert abs(sigma_Q - 1) < TOL and np.linalg.norm(oQ - oP) < TOL, f"{name}: not one edge"
    assert abs(specs[P].size(aP) - specs[Q].size(aQ)) < TOL
    return FoldGeometry(name, P, Q, {P: eP, Q: eQ}, t, specs[P].size(aP), {P: 1.0, Q: 1.0},
                        0.0, {P: 0.0, Q: 0.0}, {P: 1.0, Q: 1.0})


def line_geometries(structure: Structure = BOX):
    """``(spring folds [(geometry, k)], welds [geometry])``."""
    folds = [(FoldGeometry.of(structure, name, a, b), k) for name, a, b, k in SPRING_FOLDS]
    welds = [weld_geometry(structure, name, a, b) for name, a, b, _ in WELDS]
    return folds, welds


def line_end_points(geometries, structure: Structure = BOX) -> list[np.ndarray]:
    """3D points where two line ends or more meet (the box's 8 corners and the wall's 4)."""
    ends = []
    for g in geometries:
        _, _, a, o, e = edge_line(structure.plates[g.P], g.edge[g.P])
        ends += [o, o + structure.plates[g.P].size(a) * e]
    points = []
    for p in ends:
        if (sum(np.linalg.norm(p - q) < TOL for q in ends) >= 2
                and not any(np.linalg.norm(p - q) < TOL for q in points)):
            points.append(p)
    return points


# ---------------------------------------------------------------------------------------------
# Meshes
# ---------------------------------------------------------------------------------------------
def box_meshes(structure: Structure, geometries, n: float) -> dict[str, MeshTri]:
    """``fem_corner.structure_meshes`` over every line (folds and welds): graded squares of
    ``0.05 / n``, refined until both plates of every line have the same vertices on it, Q's
    snapped to P's."""
    return structure_meshes(structure, n, folds=geometries)


# ---------------------------------------------------------------------------------------------
# Plates, ties, springs
# ---------------------------------------------------------------------------------------------
class BoxPlate(CornerPlate):
    """``fem_corner.CornerPlate`` with the box's 1 mm steel."""

    def dynamic(self, omega: float):
        return block_diag([D_STAR * self.bending.K - omega ** 2 * RHO_H * self.bending.M,
                           A_STAR * self.K_membrane - omega ** 2 * RHO_H * self.M_membrane])


def weld_ties(g: FoldGeometry, plates, offsets) -> list[Tie]:
    """Q = P on the shared edge: at each vertex the Argyris nodal values but ``w_,bb`` (``b``
    the axis across the line), the midpoint normal derivative (the facets' normals compared)
    and ``u``, ``v`` at every P5 node; the frames are the same, so ``w``, ``w_,b`` and ``(u,
    v)`` continue across (the whole ``C1`` field, the curvature across free to jump)."""
    P, Q = plates[g.P], plates[g.Q]
    oP, oQ = offsets[g.P], offsets[g.Q]
    vP, fP, nP, aP = P.edge(g.edge[g.P])
    vQ, fQ, nQ, aQ = Q.edge(g.edge[g.Q])
    kP, kQ = EDGES[g.edge[g.P]][0], EDGES[g.edge[g.Q]][0]
    assert kP == kQ and np.abs(aP - aQ).max() < 1e-10, f"{g.name}: P5 nodes differ"
    svP, svQ = P.mesh.p[1 - kP, vP], Q.mesh.p[1 - kQ, vQ]
    assert np.abs(svP - svQ).max() < 1e-12, f"{g.name}: vertices differ"
    spec = P.spec
    k, end = EDGES[g.edge[g.P]]

    def point(s):
        local = [0.0, 0.0]
        local[k], local[1 - k] = end * spec.size(k), s
        return spec.point3d(*local)[0]

    ties = []
    nodal_P, nodal_Q = P.bending.basis.nodal_dofs, Q.bending.basis.nodal_dofs
    # not w_,bb: the wall's couple jumps the moment across the line (fem_junction: tying it
    # made a stiff spring's couple converge like 1 / n)
    rows = [row for name, row in ROW.items() if name != ("u_xx", "u_yy")[kP]]
    for a, b, s in zip(vP, vQ, svP):
        for row in rows:
            ties.append(Tie(oQ + nodal_Q[row, b], np.array([oP + nodal_P[row, a]]),
                            np.ones(1), point(s), g.name, "weld bending"))
    nbP, nbQ = P.facet_normals(fP)[kP], Q.facet_normals(fQ)[kQ]
    midP = P.mesh.p[1 - kP, P.mesh.facets[:, fP]].mean(axis=0)
    midQ = Q.mesh.p[1 - kQ, Q.mesh.facets[:, fQ]].mean(axis=0)
    assert np.abs(midP - midQ).max() < 1e-12
    for a, b, r, s in zip(P.bending.basis.facet_dofs[0, fP], Q.bending.basis.facet_dofs[0, fQ],
                          np.round(nbQ / nbP), midP):
        ties.append(Tie(oQ + b, np.array([oP + a]), np.array([r]), point(s), g.name,
                        "weld bending"))
    for a, b, s in zip(nP, nQ, aP):
        for c in (0, 1):
            ties.append(Tie(oQ + Q.comp(c) + b, np.array([oP + P.comp(c) + a]), np.ones(1),
                            point(s), g.name, "weld membrane"))
    return ties


def rotation_rows(f: FoldGeometry, plates, offsets, size: int, n_gauss: int = 5):
    """``B`` with ``B x = theta_P . t - theta_Q . t`` at the Gauss points of the line's
    intervals (``theta . t = kappa w_,b`` on each plate's edge, ``fem_corner.FoldGeometry``)
    and their weights: 5 points per interval integrate the quartic ``w_,b`` traces' product
    exactly."""
    P = plates[f.P]
    kP = EDGES[f.edge[f.P]][0]
    s = np.sort(f.line_s(f.P, P.mesh.p[1 - kP, P.edge(f.edge[f.P])[0]]))
    g, gw = np.polynomial.legendre.leggauss(n_gauss)
    lengths = np.diff(s)
    sq = (s[:-1, None] + lengths[:, None] * 0.5 * (g + 1)).ravel()
    wq = (lengths[:, None] * 0.5 * gw).ravel()
    blocks = []
    for name, sign in ((f.P, 1.0), (f.Q, -1.0)):
        plate = plates[name]
        k, end = EDGES[f.edge[name]]
        a = f.local(name, sq)
        pts = np.zeros((2, a.size))
        pts[k], pts[1 - k] = end * plate.spec.size(k), a
        slope = plate.bending.eval_matrix(pts, plate.edge_cells(f.edge[name], a),
                                          what="dx" if k == 0 else "dy").tocoo()
        blocks.append(coo_matrix((sign * f.kappa[name] * slope.data,
                                  (slope.row, offsets[name] + slope.col)),
                                 shape=(sq.size, size)))
    return (blocks[0] + blocks[1]).tocsr(), wq


def spring_matrix(f: FoldGeometry, k: float, plates, offsets, size: int) -> csr_matrix:
    """``k int (theta_P . t - theta_Q . t)(same)^ ds``: the spring's energy, twice."""
    B, wq = rotation_rows(f, plates, offsets, size)
    return (k * (B.T @ diags(wq) @ B)).tocsr()


# ---------------------------------------------------------------------------------------------
# The model
# ---------------------------------------------------------------------------------------------
class BoxModel(CornerModel):
    """The box on the meshes of level ``n``: plates, ties (spring folds: translation; welds:
    everything), the reduction with the line-end clusters, springs and loads."""

    rounding = 0  # a seed: the solve's matrix perturbed by one rounding (round-off check)

    def __init__(self, n: float, structure: Structure = BOX, folds=None, welds=None):
        t0 = time.perf_counter()
        self.structure, self.n = structure, n
        if folds is None:
            folds, welds = line_geometries(structure)
        self.spring_folds, self.welds = folds, welds
        self.folds = [f for f, _ in folds]
        geometries = self.folds + self.welds
        self.place_plates(structure, box_meshes(structure, geometries, n), BoxPlate)
        self.ties = []
        for f, k in folds:  # k = inf: a rigid fold, its rotation tied (fem_corner)
            ties = fold_ties(f, self.plates, self.offsets)
            self.ties += ties if math.isinf(k) else [t for t in ties if t.kind != "rotation"]
        self.ties += [t for g in self.welds for t in weld_ties(g, self.plates, self.offsets)]
        self.junctions = line_end_points(geometries, structure)
        fixed = np.concatenate([self.offsets[name] + p.fixed() for name, p in self.plates.items()])
        self.reduction = reduction(self.size, fixed.astype(int), self.ties, self.junctions)
        self.T = self.reduction.T
        self.springs = csr_matrix((self.size, self.size), dtype=float)
        for f, k in folds:
            if not math.isinf(k):
                self.springs += spring_matrix(f, k, self.plates, self.offsets, self.size)
        self.loads = self.point_loads(structure)
        self.t_setup = time.perf_counter() - t0

    def solve(self, frequency: float) -> dict[str, np.ndarray]:
        """``fem_corner.CornerModel.solve`` with the springs added to the plates' matrix."""
        t0 = time.perf_counter()
        omega = 2 * math.pi * frequency
        K = (block_diag([p.dynamic(omega) for p in self.plates.values()]).tocsr()
             + self.springs)
        Kr = (self.T.T @ K @ self.T).tocsc()
        del K  # memory: the LU is what counts
        s = diags(1.0 / np.sqrt(np.abs(Kr.diagonal())))
        Ks = (s @ Kr @ s).tocsc()
        del Kr
        if self.rounding:  # every entry moved by ~one rounding, symmetrically (round-off check)
            noise = np.random.default_rng(self.rounding).standard_normal(Ks.data.size)
            Ks.data *= 1 + np.finfo(float).eps * noise
            Ks = ((Ks + Ks.T) * 0.5).tocsc()
        keys = list(self.loads)
        b = s @ (self.T.T @ np.column_stack([self.loads[k] for k in keys])).astype(complex)
        # partial pivoting: SuperLU's symmetric mode (fem_corner's) chose pivots whose LU made
        # the refinement diverge at 277.5 Hz, level 1.5 (residual 1e-7 -> 2e-6)
        lu = splu(Ks, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=1.0)
        x = lu.solve(b)
        KL, bL = Ks.astype(np.clongdouble), b.astype(np.clongdouble)
        del Ks
        # refinement with the residual in extended precision (fem_corner), kept while the
        # residual falls: the 1 mm plates' stiff membranes make the system far worse
        # conditioned than fem_corner's (it stalls at 1e-11 to 1e-9); the best iterate kept
        self.residuals, best = [], (math.inf, x)
        for _ in range(MAX_REFINEMENT):
            r = np.asarray(bL - KL @ x.astype(np.clongdouble), dtype=complex)
            self.residuals.append(float(np.linalg.norm(r) / np.linalg.norm(b)))
            if self.residuals[-1] < best[0]:
                best = (self.residuals[-1], x)
            if self.residuals[-1] < 1e-14 or (len(self.residuals) > 2
                                              and self.residuals[-1] > 0.5 * self.residuals[-2]):
                break
            x = x + lu.solve(r)
        self.residual, x = best
        self.t_solve = time.perf_counter() - t0
        full = self.T @ (s @ x)
        return {k: full[:, i] for i, k in enumerate(keys)}

    def line_mismatch(self, x: np.ndarray, n: int = 401) -> dict[str, dict[str, float]]:
        """Per line, at ``n`` points: the largest difference of the two plates' 3D
        displacements relative to the largest of them (``U``) and, on the welds, of the
        rotation about the line (``theta``; on a spring fold it differs by the spring's
        twist: ``twist`` its largest over the largest rotation there)."""
        out = {}
        parts = self.parts(x)
        for f in self.folds + self.welds:
            U, R = line_traces(parts, f, n)
            key = "theta" if f in self.welds else "twist"
            out[f.name] = {"U": float(np.abs(U[f.P] - U[f.Q]).max() / np.abs(U[f.P]).max()),
                           key: float(np.abs(R[f.P] - R[f.Q]).max() / np.abs(R[f.P]).max())}
        return out

    def spring_energy_of_rigid_motions(self) -> float:
        """``max |x^T S x| / (k_max |x|^2)`` over the six rigid motions (``S`` the springs):
        zero if the rotations about the lines are measured alike on both sides."""
        return max(abs(x @ (self.springs @ x)) / (K_WALL * (x @ x))
                   for x in self.rigid_motions())


# ---------------------------------------------------------------------------------------------
# Runs
# ---------------------------------------------------------------------------------------------
def peak_memory_gb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6


def run_level(n: float, frequencies=FREQUENCIES, rigid: bool = True) -> dict:
    """Build level ``n``, solve both loads at every frequency: fields on the inner grids,
    reciprocity, ties, rigid motions, clusters."""
    model = BoxModel(n)
    run = {"n": n, "dofs": model.n_dofs, "triangles": model.n_triangles,
           "setup": model.t_setup, "tie_residual": model.tie_residual(),
           "clusters": [(c["rows"], len(c["dofs"]), c["rank"], c["N"].shape[1])
                        for c in model.reduction.clusters],
           "w": {}, "uv": {}, "recip": {}, "mismatch": {}, "solve": {}, "residual": {}}
    if rigid:
        run["rigid"] = model.rigid_body_check()["modes"]
        run["rigid_spring"] = model.spring_energy_of_rigid_motions()
    (pa, *xa), (pc, *xc) = LOADS["main"], LOADS["recip"]
    for f in frequencies:
        xs = model.solve(f)
        run["solve"][f], run["residual"][f] = model.t_solve, model.residual
        run.setdefault("residuals", {})[f] = model.residuals
        run["w"][f], run["uv"][f] = model.fields(xs["main"])
        run["recip"][f] = (model.point_w(xs["main"], pc, xc), model.point_w(xs["recip"], pa, xa))
        run["mismatch"][f] = {k: model.line_mismatch(x) for k, x in xs.items()}
    print(f"level {n}: {model.n_triangles} triangles, {model.n_dofs} unknowns, set-up "
          f"{model.t_setup:.0f} s, solves "
          + ", ".join(f"{t:.0f} s" for t in run["solve"].values())
          + f", peak memory {peak_memory_gb():.2f} GB", flush=True)
    return run


def print_checks(runs: list[dict], frequencies=FREQUENCIES) -> None:
    plates = list(PLATES)
    for f in frequencies:
        print(f"\n{f:g} Hz: relative L2 change of w, then of (u, v), from the previous level "
              "on each plate's 225 inner points")
        print("  " + " ".join(f"{p:>8}" for p in plates))
        for prev, r in zip(runs, runs[1:]):
            for kind in ("w", "uv"):
                print(f"  {prev['n']:g} -> {r['n']:g} {kind:>2}: " + " ".join(
                    f"{relative(r[kind][f][p], prev[kind][f][p]):8.1e}" for p in plates))
        print("  reciprocity: w_Right(0.23, 0.11; load on Top1) vs w_Top1(0.17, 0.13; load "
              "on Right)")
        for r in runs:
            a, b = r["recip"][f]
            print(f"    n = {r['n']:g}: {a:.10e}  {b:.10e}  rel. diff {abs(a - b) / abs(a):.1e}")
        print("  lines sampled at 401 points, worst over both loads: |U_P - U_Q| / max |U|; "
              "welds |theta_P - theta_Q| / max |theta|; folds' twist")
        for r in runs:
            worst_U = max(m[line]["U"] for m in r["mismatch"][f].values() for line in m)
            worst_theta = max(m[line].get("theta", 0.0) for m in r["mismatch"][f].values()
                              for line in m)
            twist = [m[line]["twist"] for m in r["mismatch"][f].values() for line in m
                     if "twist" in m[line]]
            print(f"    n = {r['n']:g}: U {worst_U:.1e}, weld theta {worst_theta:.1e}, fold "
                  f"twist {min(twist):.1e} to {max(twist):.1e}; refinement residuals "
                  + " ".join(f"{x:.0e}" for x in r["residuals"][f]))
    print("\nties on the columns of T, max |C T|; clusters at the line ends (rows, dofs, rank, "
          "null space):")
    for r in runs:
        print(f"  n = {r['n']:g}: {r['tie_residual']:.1e}; {sorted(set(r['clusters']))}")
    print("rigid motions: tie residual, distance from range(T), |K x| / ||K| |x||; springs' "
          "energy / (k |x|^2):")
    for r in runs:
        if "rigid" in r:
            print(f"  n = {r['n']:g}: " + "; ".join(
                f"{m['mode']} {m['ties']:.0e} {m['range']:.0e} {m['stiffness']:.0e}"
                for m in r["rigid"]) + f"; springs {r['rigid_spring']:.0e}")


def save(runs: list[dict], frequencies=FREQUENCIES) -> Path:
    """``/tmp/fem_box/fields.npz``: the finest level's ``w_{p}_{f}`` (225,), ``uv_{p}_{f}``
    (225, 2) and the last change of ``w`` and ``(u, v)`` per plate, ``change_w_{f}``,
    ``change_uv_{f}`` (the order of ``PLATES``), and the levels."""
    OUT.mkdir(parents=True, exist_ok=True)
    last, prev = runs[-1], runs[-2] if len(runs) > 1 else None
    packed = {"levels": np.array([r["n"] for r in runs], float)}
    for f in frequencies:
        for p in PLATES:
            packed[f"w_{p}_{f:g}"] = last["w"][f][p]
            packed[f"uv_{p}_{f:g}"] = last["uv"][f][p]
        if prev is not None:
            for kind in ("w", "uv"):
                packed[f"change_{kind}_{f:g}"] = np.array(
                    [relative(last[kind][f][p], prev[kind][f][p]) for p in PLATES])
    path = OUT / "fields.npz"
    np.savez_compressed(path, **packed)
    return path


def spring_limit_check(n: float = 2, frequency: float = 277.5,
                       stiffnesses=(1e2, 1e4, 1e6, 1e8)) -> None:
    """``fem_corner``'s L fold (diaphragm ends; here 1 mm steel) with its fold on a spring of
    growing ``k`` against the rigid fold (``k = inf``, rotation tied as in ``fem_corner``):
    the difference must fall like ``1 / k``."""
    from fem_corner import L_FOLD
    name, first, second = L_FOLD.folds[0]
    geometry = FoldGeometry.of(L_FOLD, name, first, second)

    def fields(k):
        model = BoxModel(n, L_FOLD, [(geometry, k)], [])
        return model.fields(model.solve(frequency)["main"]), model.n_dofs

    (w0, uv0), dofs = fields(math.inf)
    print(f"\nspring limit, L fold of fem_corner (1 mm), level {n:g} ({dofs} unknowns), "
          f"{frequency:g} Hz: relative difference from the rigid fold, w then (u, v), A / B")
    for k in stiffnesses:
        (w, uv), _ = fields(k)
        print(f"  k = {k:.0e}: " + " / ".join(f"{relative(w[p], w0[p]):.1e}" for p in w0)
              + "; " + " / ".join(f"{relative(uv[p], uv0[p]):.1e}" for p in uv0), flush=True)


def roundoff_check(n: float, frequencies=FREQUENCIES) -> None:
    """Level ``n`` solved as it is and with every entry of its matrix moved by one rounding:
    the fields' change per plate is the round-off the conditioning allows."""
    model = BoxModel(n)
    for f in frequencies:
        model.rounding = 0
        exact = model.fields(model.solve(f)["main"])
        model.rounding = 1
        moved = model.fields(model.solve(f)["main"])
        print(f"round-off, level {n:g}, {f:g} Hz: w " + " ".join(
            f"{relative(moved[0][p], exact[0][p]):.0e}" for p in PLATES) + "; (u, v) "
            + " ".join(f"{relative(moved[1][p], exact[1][p]):.0e}" for p in PLATES), flush=True)


def main(argv) -> None:
    """``python bench/fem_box.py LEVEL``: solve one level and keep it in ``/tmp/fem_box/
    run_LEVEL.pkl`` (one process per level: the memory is the finest level's alone);
    ``--report L1 L2 ...``: the checks of those kept levels, and ``fields.npz`` of the last;
    ``--spring-limit``: the spring against the rigid fold."""
    t0 = time.perf_counter()
    if "--spring-limit" in argv:
        spring_limit_check()
        return
    if "--roundoff" in argv:  # --roundoff LEVEL [FREQUENCY ...]
        level, *frequencies = (float(a) for a in argv[argv.index("--roundoff") + 1:])
        roundoff_check(level, frequencies or FREQUENCIES)
        return
    levels = [float(a) for a in argv if not a.startswith("--")] or list(LEVELS)
    OUT.mkdir(parents=True, exist_ok=True)
    if "--report" in argv:
        runs = [pickle.loads((OUT / f"run_{n:g}.pkl").read_bytes()) for n in levels]
        print_checks(runs)
        print(f"wrote {save(runs)}")
        return
    for n in levels:
        run = run_level(n)
        (OUT / f"run_{n:g}.pkl").write_bytes(pickle.dumps(run))
    print(f"total {time.perf_counter() - t0:.0f} s, peak memory {peak_memory_gb():.2f} GB")


if __name__ == "__main__":
    main(sys.argv[1:])
