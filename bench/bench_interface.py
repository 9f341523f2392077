"""Which sparse direct solver for the interface problem: SciPy's SuperLU orderings and forms.

The interface problem of an N x N grid of plates (``assembly.generate.plate_grid``, 250 Hz,
direct problem r = 0) is factorised in the ways a pure-SciPy (or METIS-assisted) path can:

* ``grouped``: the Hermitian augmented system ``[-I A 0; A^H 0 G^H; 0 G 0]`` of
  :mod:`solver.interface` (the residual samples as unknowns) factorised group by group by
  :class:`solver.multifrontal.GroupedLDL` (vtcr's path from 1500 variables on);
* ``augmented``: the same system, SuperLU with the COLAMD (vtcr's path below 1500 variables
  and its fallback) and the MMD(A^T + A) column orderings;
* ``normal``: the KKT system of the normal equations ``[sum A^H A, G^H; G, 0]`` (the
  previous dense path's matrix, which squares the conditioning), SuperLU with COLAMD;
* ``metis``: the augmented system pre-permuted by METIS nested dissection (only if
  ``pymetis`` is installed), SuperLU keeping that order;
* ``dense``: LAPACK LU of the normal-equations KKT (the code path before the sparse solve),
  for the sizes where it fits.

Each line gives the factorisation time (best of ``--repeats``), the entries of the LU factors,
and the quality of the solution: the relative difference of its interface unknowns from the
augmented COLAMD ones (the direct problem's cost is zero to round-off in the present
formulation, so costs no longer tell the variants apart), and its constraint residual. Run::

    OPENBLAS_NUM_THREADS=1 python bench/bench_interface.py --sizes 2 4 6 10
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

from assembly import parse_case
from assembly.generate import plate_grid
from solver import interface
from solver.channels import channel_blocks
from solver.joint_rules import joint_parameters
from solver.substructure import build_assembly_system

DENSE_LIMIT = 4000  # unknowns of the dense LU yardstick (2 GB of complex entries at most)


def normal_kkt(n_s, blocks, constraints):
    """``[sum A^H A, G^H; G, 0]`` and its right-hand side, sparse."""
    rows, cols, vals = [], [], []
    rhs = np.zeros(n_s, dtype=complex)
    for b in blocks:
        gram = b.matrix.conj().T @ b.matrix
        rows.append(np.repeat(b.index, len(b.index)))
        cols.append(np.tile(b.index, len(b.index)))
        vals.append(gram.ravel())
        rhs[b.index] -= b.matrix.conj().T @ b.offset
    g = constraints[0].tocoo()
    rows += [g.row + n_s, g.col]
    cols += [g.col, g.row + n_s]
    vals += [g.data, g.data.conj()]
    size = n_s + g.shape[0]
    matrix = scipy.sparse.coo_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(size, size))
    return matrix.tocsc(), np.concatenate([rhs, constraints[1]])


def augmented(n_s, blocks, constraints):
    """The augmented matrix of :mod:`solver.interface`, its right-hand side and S's offset."""
    lower, n_rho = interface._augmented_matrix(n_s, blocks, constraints[0])
    matrix = interface.hermitian_full(lower)
    rhs = np.concatenate([-np.concatenate([b.offset for b in blocks]),
                          np.zeros(n_s, dtype=complex), constraints[1]])
    return matrix, rhs, n_rho


def equilibrated(matrix):
    row_max = abs(matrix).max(axis=1).toarray().ravel()
    scale = 1.0 / np.sqrt(np.maximum(row_max, np.finfo(float).tiny))
    return (scipy.sparse.diags(scale) @ matrix @ scipy.sparse.diags(scale)).tocsc(), scale


def timed(factorise, repeats):
    best, result = np.inf, None
    for _ in range(repeats):
        t0 = time.perf_counter()
        result = factorise()
        best = min(best, time.perf_counter() - t0)
    return best, result


def sparse_variant(matrix, rhs, offset, n_s, permc, repeats, perm=None):
    """Factorise with SuperLU; returns (seconds, factor entries, S)."""
    scaled, scale = equilibrated(matrix)
    if perm is not None:
        scaled = scaled[perm][:, perm].tocsc()
    seconds, lu = timed(lambda: scipy.sparse.linalg.splu(scaled, permc_spec=permc,
                                                         diag_pivot_thresh=0.1), repeats)
    b = rhs * scale
    if perm is None:
        x = lu.solve(b)
    else:
        x = np.empty_like(b)
        x[perm] = lu.solve(b[perm])
    return seconds, lu.L.nnz + lu.U.nnz, (x * scale)[offset:offset + n_s]


def grouped_variant(matrix, rhs, offset, system, blocks, repeats):
    """Factorise with GroupedLDL, the groups of vtcr's path; returns (seconds, entries, S)."""
    from solver.multifrontal import GroupedLDL

    scaled, scale = equilibrated(matrix)
    groups = interface._variable_groups(blocks, offset,
                                        (system.unknown_groups, system.constraint_groups))
    seconds, lu = timed(lambda: GroupedLDL(scaled, groups), repeats)
    x = lu.solve(rhs * scale)
    return seconds, lu.nnz, (x * scale)[offset:offset + system.n_s]


def dense_variant(matrix, rhs, n_s, repeats):
    dense = matrix.toarray()
    scale = 1.0 / np.sqrt(np.abs(dense).max(axis=1))
    scaled = dense * scale[:, None] * scale[None, :]
    seconds, factor = timed(lambda: scipy.linalg.lu_factor(scaled, check_finite=False), repeats)
    x = scipy.linalg.lu_solve(factor, rhs * scale) * scale
    return seconds, dense.size, x[:n_s]


def metis_order(matrix):
    try:
        import pymetis
    except ImportError:
        return None
    pattern = (abs(matrix) + abs(matrix).T).tocsr()
    pattern.setdiag(0)
    pattern.eliminate_zeros()
    perm, _ = pymetis.nested_dissection(
        adjacency=pymetis.CSRAdjacency(pattern.indptr, pattern.indices))
    return np.asarray(perm)


def violation(system, s):
    g_mat, g = system.constraints
    return float(np.linalg.norm(g_mat @ s - g) / max(np.linalg.norm(g), 1e-300))


def bench(n, frequency, repeats):
    case = parse_case(plate_grid(n, n, frequency=frequency))
    system = build_assembly_system(case, frequency)
    blocks = channel_blocks(system.channels, joint_parameters(case, system.omega), case.updating.alpha)
    n_s = system.n_s
    aug, aug_rhs, n_rho = augmented(n_s, blocks, system.constraints)
    kkt, kkt_rhs = normal_kkt(n_s, blocks, system.constraints)
    variants = [
        ("augmented, COLAMD", lambda: sparse_variant(aug, aug_rhs, n_rho, n_s, "COLAMD", repeats)),
        ("augmented, grouped",
         lambda: grouped_variant(aug, aug_rhs, n_rho, system, blocks, repeats)),
        ("augmented, MMD(A^T+A)",
         lambda: sparse_variant(aug, aug_rhs, n_rho, n_s, "MMD_AT_PLUS_A", repeats)),
        ("normal KKT, COLAMD", lambda: sparse_variant(kkt, kkt_rhs, 0, n_s, "COLAMD", repeats)),
    ]
    perm = metis_order(aug)
    if perm is not None:
        variants.append(("augmented, METIS ND",
                         lambda: sparse_variant(aug, aug_rhs, n_rho, n_s, "NATURAL", repeats,
                                                perm)))
    if kkt.shape[0] <= DENSE_LIMIT:
        variants.append(("normal KKT, dense LU", lambda: dense_variant(kkt, kkt_rhs, n_s, repeats)))
    print(f"\nN = {n}: {len(case.plates)} plates, {len(case.joints)} joints, {n_s} interface "
          f"unknowns, augmented {aug.shape[0]} rows / {aug.nnz:.3g} entries, normal KKT "
          f"{kkt.shape[0]} rows / {kkt.nnz:.3g} entries")
    print(f"{'variant':<24} {'factor s':>9} {'LU entries':>11} {'|S - S_ref|':>13} "
          f"{'constraints':>11}")
    reference = None
    for name, run in variants:
        seconds, entries, s = run()
        reference = s if reference is None else reference
        difference = np.linalg.norm(s - reference) / np.linalg.norm(reference)
        print(f"{name:<24} {seconds:9.2f} {entries:11.3g} {difference:13.1e} "
              f"{violation(system, s):11.1e}", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[2, 4, 6])
    parser.add_argument("--frequency", type=float, default=250.0)
    parser.add_argument("--repeats", type=int, default=1)
    args = parser.parse_args()
    import platform

    print(f"Python {platform.python_version()}, NumPy {np.__version__}, SciPy "
          f"{scipy.__version__}; set OPENBLAS_NUM_THREADS=1 for the reference figures")
    for n in args.sizes:
        bench(n, args.frequency, args.repeats)


if __name__ == "__main__":
    main()
