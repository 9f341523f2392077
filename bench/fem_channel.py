r"""Finite-element reference for a U channel of three plates (bending and membrane) whose two
fold lines end on free edges, scikit-fem, written apart from the VTCR solver: the plates,
ties, reduction, solve and tables are ``fem_corner``'s (which imports ``fem_folded``,
``fem_clamped``, ``fem_argyris``); nothing of ``tests/support.py`` (it imports the solver).

The structure
-------------
Steel, ``E* = E (1 + j eta)`` (E = 210 GPa, nu = 0.3, rho = 7800 kg/m^3, eta = 0.01), h = 2 mm,
``D* = E* h^3 / (12 (1 - nu^2))``, ``A* = E* h / (1 - nu^2)``; time factor ``exp(+j omega t)``;
Kirchhoff bending and plane-stress membrane in each plate. Plate ``p`` occupies its local
``[0, Lx] x [0, Ly]``, placed by its frame ``(o, e_x, e_y, e_z = e_x x e_y)``: the local point
``(x, y)`` is ``o + x e_x + y e_y`` and the displacement the 3D vector ``u e_x + v e_y + w e_z``
(:data:`CHANNEL`):

* A (web): 0.4 x 0.5, ``o = 0``, ``e_x = (1, 0, 0)``, ``e_y = (0, 1, 0)``, ``e_z = (0, 0, 1)``:
  ``(x, y) -> (x, y, 0)``, displacement ``(u, v, w)``;
* B (flange): 0.3 x 0.5, ``o = 0``, ``e_x = (0, 0, 1)``, ``e_y = (0, 1, 0)``, ``e_z = (-1, 0,
  0)``: ``(x, y) -> (0, y, x)``, displacement ``(-w, v, u)``;
* C (flange): 0.2 x 0.5, ``o = (0.4, 0, 0)``, the axes of B: ``(x, y) -> (0.4, y, x)``,
  displacement ``(-w, v, u)``.

Both flanges rise from the web towards ``+Z``. Folds (rigid): AB = A's left (x = 0) with B's
left (x = 0), the line ``X = Z = 0`` along Y; AC = A's right (x = 0.4) with C's left (x = 0),
the line ``X = 0.4, Z = 0`` along Y. B's right (x = 0.3) and C's right (x = 0.2) are simply
supported (``w = 0``) and fixed in plane (``u = v = 0``). Every other edge, the bottom (y = 0)
and top (y = 0.5) of all three plates, is free: traction-free in bending and in plane (the
natural conditions), so both fold lines end on free edges at y = 0 and y = 0.5 (the four free
ends ``(0, 0, 0)``, ``(0, 0.5, 0)``, ``(0.4, 0, 0)``, ``(0.4, 0.5, 0)``). Loads: 1 N along A's
``e_z`` at A's (0.17, 0.13) (the fields kept) and, for reciprocity, 1 N along C's ``e_z`` at
C's (0.07, 0.31). Weak form: ``fem_folded``'s, summed over the three plates, in the space of
fields meeting the supports and the fold ties (their multipliers do no virtual work there).

The rigid folds (every sign)
----------------------------
*Translation* (the 3D displacements agree on the line):

* AB (``(0, y)`` of A = ``(0, y)`` of B = ``(0, y, 0)``): ``(u_A, v_A, w_A) = (-w_B, v_B,
  u_B)``, so ``u_A = -w_B``, ``v_A = v_B``, ``w_A = u_B``;
* AC (``(0.4, y)`` of A = ``(0, y)`` of C = ``(0.4, y, 0)``): ``u_A = -w_C``, ``v_A = v_C``,
  ``w_A = u_C``.

*Rotation* (``theta = w_y e_x - w_x e_y``, ``fem_corner``; the line's direction ``t = (0, 1,
0)`` is every plate's ``e_y``, so ``theta . t = -w_,x`` on all three): ``w_A,x(0, y) =
w_B,x(0, y)`` and ``w_A,x(0.4, y) = w_C,x(0, y)``, and along the line ``w_A,xy = w_B,xy``,
``w_A,xy = w_C,xy``. Check: the rigid rotation ``phi`` about the line ``X = 0.4, Z = 0``
moves ``X`` by ``phi (Z, 0, -(X - 0.4))``: on A ``w_A = -phi (x - 0.4)``, on C (``X = 0.4``,
``Z = x``) ``U = phi (x, 0, 0)`` and ``w_C = U . (-1, 0, 0) = -phi x``: both ``w_,x = -phi``;
about ``X = Z = 0`` the same with B. ``fem_corner.FoldGeometry`` derives the ties from the
frames; :func:`check_signs` asserts it finds these (``u_A = cross_A w_Q``, ``cross_A = -1``,
``u_Q = cross_Q w_A``, ``cross_Q = 1``, ``kappa = -1`` on every plate, ``sigma_Q = 1``).

The fold ends are free: no junction (each end carries one fold), so every tie is
master-slave (A's ``w`` and normal derivative the masters); nothing is fixed there.

Discretisation, meshes, solve
-----------------------------
``fem_corner``'s: Argyris ``w``, P5 ``(u, v)``, the exact master-slave fold coupling;
``fem_folded.graded_mesh`` per plate, squares of ``0.05 / n``, element size ``min(0.05, 2 r) /
n`` towards the four free ends (on A and on the flanges), the loads (floor 1e-3) and, through
``Structure.grading``, the four corners where a supported edge meets a free one (B's (0.3, 0),
(0.3, 0.5), C's (0.2, 0), (0.2, 0.5); floor 1e-6: in plane a clamped-free right angle has
singular stresses): every corner of every plate is graded. The floor at the free ends is 1e-4
(``Structure.h_fold_end``), not ``fem_corner``'s 1e-6: the free ends move (the web sways in
``X``, held only by bending), and elements of 1e-6 where the field is large cost round-off, as
at a force (``fem_folded``): with 1e-6, one random ulp on every entry of the plates' matrices
moves ``w`` by up to 3.7e-7 and ``(u, v)`` by 1e-5 at 300 Hz (level 4; all of it from the
bending block) and the 3 -> 4 change of ``w`` was that round-off (7e-7); with 1e-4, 2e-10 and
6e-10. The floor itself costs little: 1e-4 against 1e-5 changes ``w`` by <= 1.8e-8 and ``(u,
v)`` by <= 6.3e-8 at level 4, by <= 8.7e-9 and <= 1.2e-7 at level 6 (1e-3 against 1e-4, level
4: 4.5e-7 and 9e-7). SuperLU of the diagonally scaled reduced system, the refinement residual
in extended precision.

Self-checks
-----------
``OPENBLAS_NUM_THREADS=1 python bench/fem_channel.py --write`` (levels 4 6 8; 21 minutes on one
core, 16 GB) prints the tables and writes ``tests/data/fem_channel.npz`` (the finest level:
``w_{A,B,C}_{300,1000}`` (225,), ``uv_..`` (225, 2) on ``inner_grid(Lx, Ly)`` of each plate's
local frame, ``change_{300,1000}``: the last level change of ``w`` per plate, A, B, C);
``python bench/fem_channel.py 2 3 4`` the coarser tables (without ``--write`` nothing is
written under ``tests``). Printed: level-to-level relative L2 changes on the 225 points of each
plate; reciprocity (``w_C(0.07, 0.31)`` under the load on A against ``w_A(0.17, 0.13)`` under
the load on C); the fold ties sampled on the lines and ``max |C T|``; the dofs of the free ends
(columns of ``T``); the six rigid motions (tie residual, distance from the range of ``T``
without supports, stiffness); the free edges' tractions (:func:`free_edge_tractions`); time and
peak memory per level. Measured (relative L2 change from the previous level on the 225 points
of a plate, A / B / C):

* ``w``, 300 Hz: 2 -> 3 1.3e-6 / 8.5e-7 / 1.6e-6, 3 -> 4 9.0e-8 / 4.0e-8 / 4.8e-8, 4 -> 6
  1.8e-8 / 1.6e-8 / 1.9e-8, 6 -> 8 3.9e-9 / 1.2e-8 / 2.9e-9; 1 kHz: 6.3e-5 / 5.4e-5 / 1.2e-4,
  2.5e-6 / 2.4e-6 / 4.1e-6, 3.2e-7 / 4.1e-7 / 5.4e-7, 2.1e-8 / 2.8e-8 / 2.6e-8;
* ``(u, v)``, 300 Hz: 4 -> 6 1.2e-8 / 2.7e-7 / 2.3e-6, 6 -> 8 2.2e-9 / 1.4e-8 / 1.2e-7; 1 kHz:
  4.8e-7 / 1.5e-6 / 7.6e-6, 1.4e-8 / 6.9e-8 / 5.5e-7 (the largest changes in the flanges are at
  the grid column nearest the fold, 4 to 6 mm from it);
* so the error of level 8 is about 1e-8 (300 Hz) to 3e-8 (1 kHz) in ``w``, with the floor's
  <= 1e-8, and 1e-8 to 1e-7 in ``(u, v)`` (C at 1 kHz: ~5e-7);
* reciprocity: 1.2e-12 to 8.5e-12 (300 Hz), 1.9e-13 to 8.7e-13 (1 kHz), levels 4 / 6 / 8 (no
  junction: ``T`` holds only the fold weights, so ``T^T K T`` rounds nearly symmetrically);
* ties: ``max |C T|`` = 0, the folds sampled at 401 points: 3D displacements within 5.3e-13 of
  their largest value, rotations 1.6e-13; no junction cluster, no free dof forced to zero; at
  the four free ends every vertex dof of both plates is free (one column of ``T`` each);
* rigid motions (3 translations, 3 rotations): tie residual <= 3e-14, distance from the range
  of ``T`` (without supports) <= 8e-16, ``|K x| / ||K| |x||`` <= 2e-15;
* free edges (1 % from the ends), relative to the largest force inside, largest / median, levels
  4 / 6 / 8: ``|(N_nn, N_nt)|`` 1.6e-4 / 3.7e-5 / 2.0e-5 and 2.2e-7 / 3.1e-8 / 7.9e-9 (300 Hz);
  ``|M_nn|`` 6.6e-5 / 2.3e-5 / 9.5e-6 and 3.3e-6 / 6.9e-7 / 2.2e-7; ``|V_n|`` 1.8e-2 / 5.7e-3 /
  2.1e-3 and 1.8e-4 / 6.0e-5 / 2.5e-5 (the largest 1 % from the free ends); 1 kHz similar
  (largest ``V_n`` 1.1e-2 / 3.3e-3 / 1.5e-3);
* level 4: 10644 triangles, 3.2e5 unknowns, 122 s, 3.8 GB; level 6: 22880, 6.8e5, 353 s, 8.7
  GB; level 8: 36298, 1.07e6, 806 s (82 s set-up, 281 s and 357 s for the two frequencies'
  solves), 15.3 GB (peak resident memory; 16.0 GB for the whole run).
"""

from __future__ import annotations

import resource
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fem_corner import (
    EDGES,
    FREQUENCIES,
    H_CORNER,
    LEVELS,
    TOL,
    CornerModel,
    PlateSpec,
    Structure,
    folds_of,
    print_tables,
    run_level,
    write,
)
from fem_folded import inner_grid

ROOT = Path(__file__).resolve().parents[1]
OUT = Path("/tmp/fem_channel")
TEST_DATA = ROOT / "tests" / "data" / "fem_channel.npz"
NU = 0.3

CHANNEL = Structure(
    plates={"A": PlateSpec(0.4, 0.5, (0, 0, 0), (1, 0, 0), (0, 1, 0), {}),
            "B": PlateSpec(0.3, 0.5, (0, 0, 0), (0, 0, 1), (0, 1, 0), {"right": "uv"}),
            "C": PlateSpec(0.2, 0.5, (0.4, 0, 0), (0, 0, 1), (0, 1, 0), {"right": "uv"})},
    folds=(("AB", ("A", "left"), ("B", "left")),
           ("AC", ("A", "right"), ("C", "left"))),
    loads={"main": ("A", 0.17, 0.13), "recip": ("C", 0.07, 0.31)},
    # the supported-free corners of the flanges (the fold ends are graded anyway)
    grading=tuple((p, x, y, H_CORNER) for p, x in (("B", 0.3), ("C", 0.2)) for y in (0, 0.5)),
    # the free ends move: 1e-6 there cost round-off (module docstring)
    h_fold_end=1e-4)

# the hand-derived signs of the module docstring, per fold: cross (u_P = cross_P w_Q,
# u_Q = cross_Q w_P), kappa (theta . t = kappa w_,x), sigma (Q's line coordinate = sigma y)
HAND_SIGNS = {"AB": {"cross": {"A": -1, "B": 1}, "kappa": {"A": -1, "B": -1},
                     "sigma": {"A": 1, "B": 1}},
              "AC": {"cross": {"A": -1, "C": 1}, "kappa": {"A": -1, "C": -1},
                     "sigma": {"A": 1, "C": 1}}}


def check_signs(structure: Structure = CHANNEL) -> None:
    """Assert that ``fem_corner.FoldGeometry`` derives the docstring's signs from the frames
    and that the folds start at 0 on every plate (``beta = 0``)."""
    for f in folds_of(structure):
        hand = HAND_SIGNS[f.name]
        for key in ("cross", "kappa", "sigma"):
            got = {p: round(v) for p, v in getattr(f, key).items()}
            assert got == hand[key], f"fold {f.name}: {key} {got} != {hand[key]}"
        assert abs(f.beta) < TOL and np.allclose(f.t, (0, 1, 0)), f"fold {f.name}"
    print("fold signs from the frames = the hand-derived ones: "
          + "; ".join(f"{f.name} cross {f.cross} kappa {f.kappa}" for f in folds_of(structure)))


def free_edges(structure: Structure) -> list[tuple[str, str]]:
    """``(plate, edge)`` of every edge neither supported nor on a fold."""
    on_fold = {side for _, *sides in structure.folds for side in sides}
    return [(name, edge) for name, spec in structure.plates.items() for edge in EDGES
            if edge not in spec.supports and (name, edge) not in on_fold]


def w_hessian(plate, xw: np.ndarray, points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """``[[w_xx, w_xy], [w_xy, w_yy]]`` (2, 2, n) of the Argyris field ``xw`` at local
    ``points`` (n, 2), each evaluated with the polynomial of its cell in ``cells`` (the point
    may lie just outside it: the quintic is extended)."""
    b = plate.bending.basis
    X = b.mapping.invF(points.T[:, :, None], tind=cells)
    dofs = b.element_dofs[:, cells]
    H = np.zeros((2, 2, len(cells)), dtype=xw.dtype)
    for k in range(b.Nbfun):
        H += plate.bending.elem.gbasis(b.mapping, X, k, tind=cells)[0].hess[:, :, :, 0] \
            * xw[dofs[k]]
    return H


def cell_size(plate, cells: np.ndarray) -> np.ndarray:
    """Longest edge of each cell."""
    P = plate.mesh.p[:, plate.mesh.t[:, cells]]
    edges = np.stack([P[:, 0] - P[:, 1], P[:, 1] - P[:, 2], P[:, 2] - P[:, 0]])
    return np.sqrt((edges ** 2).sum(axis=1)).max(axis=0)


def bending_inside(plate, xw: np.ndarray, points: np.ndarray) -> tuple[float, float]:
    """Largest unit-rigidity moment ``|M_ab|`` (``M = -(1 - nu) w_,ab - nu lap w I``) and
    shear force ``|Q| = |grad lap w|`` at ``points``; the third derivatives by the central
    five-point difference of the Hessian (a cubic in each cell, so the difference is exact;
    the step is a quarter of the cell, within the cell's polynomial)."""
    cells = plate.mesh.element_finder(mapping=plate.bending.basis.mapping)(*points.T)
    H = w_hessian(plate, xw, points, cells)
    M = np.array([H[0, 0] + NU * H[1, 1], H[1, 1] + NU * H[0, 0], (1 - NU) * H[0, 1]])
    delta = 0.25 * cell_size(plate, cells)
    Q = []
    for axis in (0, 1):
        step = np.zeros_like(points)
        step[:, axis] = delta
        lap = {j: np.trace(w_hessian(plate, xw, points + j * step, cells))
               for j in (-2, -1, 1, 2)}
        Q.append((lap[-2] - 8 * lap[-1] + 8 * lap[1] - lap[2]) / (12 * delta))
    return float(np.abs(M).max()), float(np.abs(np.array(Q)).max())


def free_edge_tractions(model: CornerModel, xs: dict, n: int = 201) -> dict[str, tuple]:
    """The natural conditions on the free edges under the main load: the in-plane traction
    ``|(N_nn, N_nt)|``, bending moment ``|M_nn|`` (``w_,nn + nu w_,tt``) and Kirchhoff shear
    ``|V_n|`` (``w_,nnn + (2 - nu) w_,ntt``) at ``n`` points of each free edge (ends excluded
    by 1 %), relative to the largest membrane force, moment and shear force on the plates'
    ``inner_grid`` points (unit rigidities): ``{"N": (largest, median), "M": .., "V": ..}``
    over all the free edges' points. The derivative across the edge is the one-sided
    four-point difference of the Hessian (exact for its cubic), inwards by steps of a quarter
    of the cell."""
    x = xs["main"]
    parts = model.parts(x)
    scale = {"N": 0.0, "M": 0.0, "V": 0.0}
    for plate, xp in parts.values():
        pts = inner_grid(plate.spec.lx, plate.spec.ly)
        scale["N"] = max(scale["N"], float(np.abs(plate.membrane_forces(xp, pts)).max()))
        m, q = bending_inside(plate, xp[:plate.n_w], pts)
        scale["M"], scale["V"] = max(scale["M"], m), max(scale["V"], q)
    values = {"N": [], "M": [], "V": []}
    for name, edge in free_edges(model.structure):
        plate, xp = parts[name]
        k, end = EDGES[edge]
        a = np.linspace(0.01, 0.99, n) * plate.spec.size(1 - k)
        pts = np.zeros((n, 2))
        pts[:, k], pts[:, 1 - k] = end * plate.spec.size(k), a
        cells = plate.edge_cells(edge, a)
        N = plate.membrane_forces(xp, pts, cells)
        values["N"].append(np.hypot(np.abs(N[k]), np.abs(N[2])))
        xw = xp[:plate.n_w]
        H = w_hessian(plate, xw, pts, cells)
        values["M"].append(np.abs(H[k, k] + NU * H[1 - k, 1 - k]))
        inward = 1.0 if end == 0 else -1.0
        delta = 0.25 * cell_size(plate, cells)
        step = np.zeros_like(pts)
        step[:, k] = inward * delta
        g = [H[k, k] + (2 - NU) * H[1 - k, 1 - k]]
        for j in (1, 2, 3):
            Hj = w_hessian(plate, xw, pts + j * step, cells)
            g.append(Hj[k, k] + (2 - NU) * Hj[1 - k, 1 - k])
        V = (-11 * g[0] + 18 * g[1] - 9 * g[2] + 2 * g[3]) / (6 * delta)
        values["V"].append(np.abs(V))
    return {key: (float(np.max(v)) / scale[key], float(np.median(v)) / scale[key])
            for key, v in ((key, np.concatenate(v)) for key, v in values.items())}


def peak_memory_gb() -> float:
    """The process's peak resident memory so far (Linux ``ru_maxrss`` is in kB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2 ** 20


def main(argv) -> None:
    """Levels (positional, default 4 6 8) of the channel at 300 Hz and 1 kHz: tables and
    checks; ``--write``: write ``tests/data/fem_channel.npz`` from the finest level."""
    t0 = time.perf_counter()
    levels = sorted(int(a) for a in argv if not a.startswith("--")) or list(LEVELS)
    write_npz = "--write" in argv
    if write_npz and len(levels) < 2:
        raise SystemExit("--write needs two levels or more (the last change is written)")
    check_signs()
    print("free edges: " + ", ".join(f"{p} {e}" for p, e in free_edges(CHANNEL)))
    OUT.mkdir(parents=True, exist_ok=True)
    runs, cost = [], []
    for n in levels:
        t = time.perf_counter()
        runs.append(run_level(n, FREQUENCIES, structure=CHANNEL, extra=free_edge_tractions))
        # ru_maxrss never decreases; levels ascend, so this is the peak of the finest so far
        cost.append((n, time.perf_counter() - t, peak_memory_gb()))
        r = runs[-1]
        np.savez(OUT / f"level_{n}.npz", **{f"{k}_{p}_{f:g}": getattr(r, k)[f][p]
                                            for k in ("w", "uv") for f in FREQUENCIES
                                            for p in CHANNEL.plates})
    last = print_tables(runs, FREQUENCIES, CHANNEL)
    print("free edges (load on A), |(N_nn, N_nt)|, |M_nn|, |V_n| (1 % from the ends) relative "
          "to the largest N, M, Q inside, largest / median:")
    for f in FREQUENCIES:
        for r in runs:
            print(f"  {f:g} Hz, n = {r.n}: " + ", ".join(f"{key} {a:.1e} / {b:.1e}"
                                                       for key, (a, b) in r.extra[f].items()))
    print("time and peak memory per level:")
    for (n, seconds, gb), r in zip(cost, runs):
        print(f"  n = {n}: {r.n_triangles} triangles, {r.n_dofs} unknowns, {seconds:.0f} s "
              f"(set-up {r.t_setup:.0f} s), peak {gb:.1f} GB")
    if write_npz:
        write(runs[-1], last, FREQUENCIES, TEST_DATA, CHANNEL)
    print(f"total {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main(sys.argv[1:])
