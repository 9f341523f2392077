"""The LU factorisation by groups (solver.grouped_lu) against dense LAPACK, and its refusals.

The matrices are random with the structure of the interface systems (those of
``test_multifrontal.lattice_system``): groups of rows and unknowns as many as one another,
blocks between groups coupled along a graph (a chain, as a stiffened panel's weld lines; a
grid, whose elimination makes fill), the rows and unknowns of each group scattered through the
numbering as the joints' are.
"""

import numpy as np
import pytest
import scipy.sparse
from test_multifrontal import lattice_system

from solver import grouped_lu, interface
from solver.errors import GroupPivotError
from solver.grouped_lu import GroupedLU


def _group_matrix(n_x, n_y, seed, size=None):
    """The block-sparse matrix of :func:`test_multifrontal.lattice_system` (groups on an
    n_x x n_y lattice, coupled to their neighbours; all of ``size`` unknowns if given), its
    rows and its columns each shuffled: ``(dense, row_groups, col_groups)``, no longer
    Hermitian."""
    dense, groups = lattice_system(n_x, n_y, seed=seed, size=size)
    rng = np.random.default_rng(seed)
    rows, cols = rng.permutation(len(groups)), rng.permutation(len(groups))
    return dense[np.ix_(rows, cols)], groups[rows], groups[cols]


@pytest.mark.parametrize("n_x, n_y", [(6, 1), (3, 3)], ids=["chain", "grid"])
def test_the_solution_is_dense_lapacks(n_x, n_y):
    """Solutions for a vector and for a second vector from the same factors agree with
    numpy.linalg.solve to 1e-11 of their size (measured 9e-15 and 1e-13: condition numbers
    300 and 1.1e4, and moderate growth under restricted pivoting)."""
    dense, row_groups, col_groups = _group_matrix(n_x, n_y, seed=3)
    rows, cols = np.nonzero(dense)
    factor = GroupedLU(rows, cols, dense[rows, cols], row_groups, col_groups)
    rng = np.random.default_rng(4)
    for _ in range(2):
        rhs = rng.standard_normal(len(dense)) + 1j * rng.standard_normal(len(dense))
        reference = np.linalg.solve(dense, rhs)
        error = np.abs(factor.solve(rhs) - reference).max() / np.abs(reference).max()
        assert error < 1e-11


def test_a_singular_group_block_is_refused_and_superlu_takes_over():
    """Two groups whose own blocks are zero while the whole matrix is not singular (the rows
    of each group act on the other's unknowns only): restricted pivoting cannot eliminate it.
    The factorisation says so, and the interface solve's grouped path declines."""
    dense, row_groups, col_groups = _group_matrix(2, 1, seed=5, size=5)
    for v in range(2):
        dense[np.ix_(row_groups == v, col_groups == v)] = 0.0
    rows, cols = np.nonzero(dense)
    with pytest.raises(GroupPivotError, match="singular"):
        GroupedLU(rows, cols, dense[rows, cols], row_groups, col_groups)
    rhs = np.ones(10, dtype=complex)
    assert interface._grouped_solution(scipy.sparse.csr_matrix(dense), rows, rhs, row_groups,
                                       col_groups) is None


def test_a_group_needs_as_many_rows_as_unknowns():
    dense, row_groups, col_groups = _group_matrix(2, 1, seed=6)
    row_groups = row_groups.copy()
    row_groups[np.flatnonzero(row_groups == 0)[0]] = 1
    rows, cols = np.nonzero(dense)
    with pytest.raises(GroupPivotError, match="as many rows as unknowns"):
        GroupedLU(rows, cols, dense[rows, cols], row_groups, col_groups)


@pytest.mark.parametrize("n_x, n_y", [(4, 1), (2, 2)], ids=["chain", "grid"])
def test_blocks_with_zero_columns_and_rows_are_solved_on_their_entries(n_x, n_y, monkeypatch):
    """Groups of :data:`solver.grouped_lu.APART_FROM` unknowns whose blocks to their neighbours
    hold entries in some columns and rows only, as a moving-line panel's (a joint's loads act
    on one plate of two): the factorisation takes those columns and rows apart, and fills
    between groups coupled through an eliminated one (the grid) on them. The solution is
    dense LAPACK's to 1e-11 of its size, as in the test above; with every block taken whole
    it is the same."""
    size = grouped_lu.APART_FROM
    dense, groups = lattice_system(n_x, n_y, seed=7, size=size)
    rng = np.random.default_rng(8)
    for u in range(n_x * n_y):
        for w in range(n_x * n_y):
            if u != w:
                block = dense[np.ix_(groups == u, groups == w)]
                block[:, rng.random(size) < 0.5] = 0.0
                block[rng.random(size) < 0.5] = 0.0
                dense[np.ix_(groups == u, groups == w)] = block
    rows, cols = np.nonzero(dense)
    rhs = rng.standard_normal(len(dense)) + 1j * rng.standard_normal(len(dense))
    reference = np.linalg.solve(dense, rhs)
    apart = GroupedLU(rows, cols, dense[rows, cols], groups, groups)
    kept = [step for step in apart._steps if any(not isinstance(c, slice) for _, c in step[3])]
    assert kept, "no block was taken apart"
    monkeypatch.setattr(grouped_lu, "APART_FROM", len(groups) + 1)  # every block whole
    whole = GroupedLU(rows, cols, dense[rows, cols], groups, groups)
    for factor in (apart, whole):
        error = np.abs(factor.solve(rhs) - reference).max() / np.abs(reference).max()
        assert error < 1e-11
