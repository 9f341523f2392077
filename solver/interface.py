r"""Sparse solve of the interface problem of a jointed assembly.

Every interface problem of the substructured VTCR — the direct problem (r = 0), the modified
problem of the updating (r > 0), a synthetic experiment — is a constrained linear least-squares
problem in the interface unknowns :math:`S` (``docs/method.md`` sections 7.3 and 7.4):

.. math::
    \min_S \sum_b \|A_b S_{I_b} + a_b\|^2 \quad\text{subject to}\quad GS = g ,

where each *block* :math:`b` — the weighted residual samples of one joint channel, or the
weighted misfit at the measured points of one plate — acts only on the interface unknowns
:math:`I_b` that its plates see. The blocks are solved in augmented form, with their residuals
:math:`\rho_b = A_bS_{I_b} + a_b` as unknowns:

.. math::
    \begin{bmatrix} -I & A & 0\\ A^H & 0 & G^H\\ 0 & G & 0\end{bmatrix}
    \begin{bmatrix}\rho\\ S\\ \lambda\end{bmatrix} =
    \begin{bmatrix}-a\\ 0\\ g\end{bmatrix} ,

(eliminating :math:`\rho` gives the KKT system of the normal equations,
:math:`[A^HA\ G^H; G\ 0]`). The matrix is Hermitian, sparse, with
:math:`2\sum_b \mathrm{rows}_b|I_b| + 2\,\mathrm{nnz}(G)` entries besides the identity:
linear in the number of joints, where the Gram matrices :math:`A_b^HA_b` would be quadratic
in the size of each neighbourhood, and the condition number is that of :math:`A`, not its
square. Only its lower triangle (:math:`-I`, :math:`A^H` and :math:`G`) is stored. After a
symmetric equilibration it is factorised group by group: each joint's load
unknowns, residual rows and constraint rows form a group with as many rows as unknowns, whose
block is the joint's compliance to its own loads, and the groups are eliminated in a
minimum-degree order of the graph of groups that see a common plate, with symmetric
(Bunch–Kaufman) interchanges inside each group (:class:`solver.multifrontal.GroupedLDL`). The
general sparse LU with partial pivoting (SuperLU, ``scipy.sparse.linalg.splu``, COLAMD
ordering) must allow for interchanges between any rows, and its fill follows the wider graph
of joints two plates apart: on the 10 x 10 grid, 2.0e7 entries in 5.3 s against 1.1e7 in
1.0 s (the grouped LU then; 0.67 s and 5.4e6 entries now). SuperLU remains the path for small
systems, where it is faster, for groups with fewer rows than unknowns, and whenever the
grouped solution's backward error exceeds :data:`BACKWARD_ERROR`. ``bench/bench_interface.py``
compares the alternatives.

**A forward solve** (no measurement rows) has as many law samples and constraint rows as
unknowns: the minimum is zero, and the minimiser solves the square system
:math:`[A; G]S = [-a; g]`, half the augmented size (:func:`_determined_solution`). Updating
keeps the augmented system: its measurement rows make a least-squares problem, and
:mod:`solver.condensation` solves with its factorisation.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg
from numpy.typing import ArrayLike

from solver.errors import GroupPivotError
from solver.grouped_lu import GroupedLU
from solver.multifrontal import GroupedLDL

__all__ = ["BACKWARD_ERROR", "DENSE_FILL", "GROUPED_LU_MIN_SIZE", "GROUPED_MIN_SIZE", "Block",
           "InterfaceFactor", "factorise_interface", "backward_error", "hermitian_full",
           "residual_weight", "squared_norm", "stacked_blocks"]

# Largest backward error accepted from the grouped factorisation, whose row interchanges stay
# inside each group: SuperLU's partial pivoting gives 1e-18 to 1e-16 on these systems, and so
# does the grouped one on every case and stiffness measured (four plates at log10 k = -3 to 12,
# the boxes, the stiffened panel, the 10 x 10 grid).
BACKWARD_ERROR = 1e-14
# Below this size of the augmented system SuperLU is faster (measured on the N x N grids and the
# cases: N = 3, 656 variables, 22 against 29 ms; N = 4, 1320, 91 against 87 ms; N = 8, 6216,
# 2.4 s against 1.0 s).
GROUPED_MIN_SIZE = 1500
# Above this fraction of filled entries, a forward solve's square system is factorised dense:
# the moving-line panel's (808 unknowns, 71 % filled) in 0.036 s against SuperLU's 0.052 s;
# the grids' (5 to 16 % filled) stay with SuperLU.
DENSE_FILL = 0.3
# From this many unknowns on, a forward solve's square system is factorised by groups
# (solver.grouped_lu): measured faster than SuperLU on the grids (1.13x at 6 x 6, 1.57x at
# 10 x 10), the moving-line panels (6 bays, 2048 unknowns: 1.9x; 12 bays: 4.4x; 2.6x and 6.5x
# since the blocks' zero columns are set apart) and the held-line panel (24 bays, 4071
# unknowns: 1.13x, 0.9x before) (bench/bench_square_solve.py).
GROUPED_LU_MIN_SIZE = 2000


def residual_weight(c: complex, crossover: float = math.inf) -> float:
    r"""Weight :math:`g` of a joint channel's residual energy :math:`e^2 = g(c)\int|r|^2`.

    .. math:: g(c) = \frac{1}{2\max(\mathrm{Re}\,c,\ |c|^2/c_\times)} .

    Below the crossover :math:`c_\times` this is the constitutive-relation error in the energy
    norm, :math:`|r|^2/(2k)` (``docs/method.md`` section 6.3). Above it the residual is measured
    in compliance form, :math:`e^2 = \tfrac12c_\times|r/c|^2 = \tfrac12c_\times|[q] - \Lambda/c|^2`:
    the jump of a discretised near-rigid joint cannot fall below the discretisation floor of
    the continuity it approximates (1.6e-5 of the plates' rotations on ``two_plates.toml``),
    and the energy norm would multiply that floor by :math:`k` without bound (the floor of
    :math:`E_\Gamma^2` grew tenfold per decade of :math:`k` above :math:`10^8`). Both forms agree
    at :math:`|c| = c_\times` and :math:`g` is continuous in :math:`c`.
    """
    return 1.0 / (2.0 * max(c.real, abs(c) ** 2 / crossover))


@dataclass(frozen=True)
class Block:
    """Rows of the least-squares objective acting on a few interface unknowns.

    Attributes
    ----------
    index : ndarray of int, shape (m,)
        Interface unknowns the rows act on.
    matrix : ndarray of complex, shape (rows, m)
    offset : ndarray of complex, shape (rows,)
    group : int
        The group of unknowns its rows are eliminated with (:mod:`solver.multifrontal`): the
        joint whose residual they are; -1 for rows that form a group of their own.
    """

    index: np.ndarray
    matrix: np.ndarray
    offset: np.ndarray
    group: int = -1

    def residual(self, s: np.ndarray) -> np.ndarray:
        """:math:`A_bS_{I_b} + a_b` for interface unknowns ``s`` of shape (n_s,), or of shape
        (n_s, k) for k sets of them at once (one column each)."""
        product = self.matrix @ s[self.index]
        return product + (self.offset if product.ndim == 1 else self.offset[:, None])

    def scaled(self, factor: complex | np.ndarray) -> Block:
        """The Block with its rows multiplied by ``factor`` (a scalar or one value per row)."""
        factor = np.asarray(factor)
        return Block(self.index, (factor.T * self.matrix.T).T, factor * self.offset, self.group)

    def projected(self, projection: np.ndarray) -> Block:
        """The Block's rows replaced by ``projection`` of them (for instance on a joint's
        load functions, :func:`solver.joint_rules.load_function_projection`)."""
        return Block(self.index, projection @ self.matrix, projection @ self.offset, self.group)

    def constraint(self, group: int) -> Block:
        """The rows ``matrix S_I = -offset`` as a constraint Block of ``group``: the sign of
        :math:`GS = g` from a quantity :math:`AS_I + a` that must vanish."""
        return Block(self.index, self.matrix, -self.offset, group)

    @staticmethod
    def union(*blocks: Block) -> Block:
        """Sum of Blocks with as many rows as one another, as one Block over the union of their
        unknowns."""
        index = np.unique(np.concatenate([b.index for b in blocks]))
        matrix = np.zeros((blocks[0].matrix.shape[0], len(index)), dtype=complex)
        for b in blocks:
            matrix[:, np.searchsorted(index, b.index)] += b.matrix
        return Block(index, matrix, sum(b.offset for b in blocks))


def squared_norm(r: np.ndarray) -> float | np.ndarray:
    r""":math:`\|r\|^2` of a vector, or of each column of a matrix (an array of them)."""
    if np.ndim(r) == 1:
        return float(np.vdot(r, r).real)
    return np.einsum("ij,ij->j", r.conj(), r).real


def _augmented_matrix(n_s: int, blocks: Sequence[Block],
                      g_mat: scipy.sparse.spmatrix) -> tuple[scipy.sparse.coo_matrix, int]:
    """The lower triangle of the Hermitian augmented matrix ``[-I A 0; A^H 0 G^H; 0 G 0]`` in
    COO form (:func:`hermitian_full` completes it), and the number of residual rows."""
    a = stacked_blocks(blocks, n_s).tocoo()
    n_rho = a.shape[0]
    g = g_mat.tocoo()
    diag = np.arange(n_rho, dtype=np.int32)
    n = n_rho + n_s + g_mat.shape[0]
    lower = scipy.sparse.coo_matrix(
        (np.concatenate([-np.ones(n_rho), a.data.conj(), g.data]),  # -I, A^H and G
         (np.concatenate([diag, (a.col + n_rho).astype(np.int32),
                          (g.row + n_rho + n_s).astype(np.int32)]),
          np.concatenate([diag, a.row.astype(np.int32), (g.col + n_rho).astype(np.int32)]))),
        shape=(n, n), dtype=complex)
    return lower, n_rho


def _hermitian_product(lower: scipy.sparse.coo_matrix, x: ArrayLike) -> np.ndarray:
    """:math:`Hx` for the Hermitian :math:`H` whose lower triangle is ``lower`` (COO, each
    entry once)."""
    on = lower.row == lower.col
    diagonal = np.zeros(lower.shape[0], dtype=lower.dtype)
    diagonal[lower.row[on]] = lower.data[on]
    x = np.asarray(x)
    product = lower @ x + (lower.T @ x.conj()).conj()
    return product - diagonal.reshape((-1,) + (1,) * (x.ndim - 1)) * x


def hermitian_full(lower: scipy.sparse.coo_matrix) -> scipy.sparse.csc_matrix:
    """The whole Hermitian matrix (CSC) whose lower triangle is ``lower`` (COO)."""
    strict = lower.row != lower.col
    return scipy.sparse.coo_matrix(
        (np.concatenate([lower.data, lower.data[strict].conj()]),
         (np.concatenate([lower.row, lower.col[strict]]),
          np.concatenate([lower.col, lower.row[strict]]))), shape=lower.shape).tocsc()


@dataclass
class InterfaceFactor:
    """A factorised interface problem: its solution and solves with other right-hand sides.

    Attributes
    ----------
    lu : SuperLU or GroupedLDL or None
        The factorisation; None when it was not kept (``factorise_interface(keep=False)``).
    s : ndarray of complex, shape (n_s,)
        The minimiser.
    residuals : list of ndarray
        :math:`\\rho_b` of each block at the minimiser.
    block_rows : list of slice
        The rows of each block, in the order they were given, in the augmented system (its
        residual rows :math:`\\rho`): what a caller keeps of the solves without counting rows.
    """

    lu: object
    scale: np.ndarray
    n_rho: int
    n_s: int
    s: np.ndarray
    residuals: list
    constraint_rhs: np.ndarray
    block_rows: list

    def solve(self, rhs: ArrayLike) -> np.ndarray:
        """The whole augmented solution :math:`(\\rho, S, \\lambda)` for ``rhs`` (n_s, k) in
        the S rows, zero elsewhere."""
        rhs = np.asarray(rhs, dtype=complex).reshape(self.n_s, -1)
        full = np.zeros((len(self.scale), rhs.shape[1]), dtype=complex)
        full[self.n_rho:self.n_rho + self.n_s] = rhs
        return self.lu.solve(full * self.scale[:, None]) * self.scale[:, None]

    def solve_interface(self, rhs: ArrayLike) -> np.ndarray:
        """S-part of the augmented solve with ``rhs`` (n_s, k) in the S rows, zero elsewhere.

        This is :math:`[A^HA\\ G^H; G\\ 0]^{-1}[rhs; 0]` restricted to S.
        """
        return self.solve(rhs)[self.n_rho:self.n_rho + self.n_s].copy()

    def resolve(self, offsets: Iterable[Iterable[np.ndarray]]) -> np.ndarray:
        """Minimisers for other block offsets :math:`a_b` (same matrices, same constraints).

        Parameters
        ----------
        offsets : sequence of sequences of ndarray
            For each problem, the offsets of every block, in the order of the factorisation.

        Returns
        -------
        ndarray of complex, shape (len(offsets), n_s)
        """
        rhs = np.column_stack([
            np.concatenate([-np.concatenate(list(problem)), np.zeros(self.n_s, dtype=complex),
                            self.constraint_rhs]) for problem in offsets])
        x = self.lu.solve(rhs * self.scale[:, None]) * self.scale[:, None]
        return x[self.n_rho:self.n_rho + self.n_s].T

    @property
    def cost(self) -> float:
        """:math:`\\sum_b\\|\\rho_b\\|^2` at the minimiser."""
        return float(sum(np.vdot(r, r).real for r in self.residuals))


def factorise_interface(n_s: int, blocks: Sequence[Block],
                        constraints: tuple[scipy.sparse.spmatrix, ArrayLike],
                        groups: tuple[np.ndarray, np.ndarray] | None = None,
                        keep: bool = True) -> InterfaceFactor:
    """Factorise and solve :math:`\\min\\sum_b\\|A_bS_{I_b}+a_b\\|^2` s.t. :math:`GS = g`.

    Parameters
    ----------
    n_s : int
        Number of interface unknowns.
    blocks : sequence of Block
    constraints : (scipy.sparse matrix (n_g, n_s), ndarray (n_g,))
    groups : (ndarray (n_s,), ndarray (n_g,)) of int, optional
        Group of each interface unknown and constraint row (``Block.group`` gives the blocks'
        rows theirs). With them, a system of at least :data:`GROUPED_MIN_SIZE` variables is
        factorised group by group (:class:`solver.multifrontal.GroupedLDL`) when every group
        holds at least as many rows as unknowns, and its solution is kept if its backward
        error is below :data:`BACKWARD_ERROR`; otherwise, and without groups, by SuperLU.
    keep : bool
        Keep the factorisation for other right-hand sides (:meth:`InterfaceFactor.solve`,
        :meth:`InterfaceFactor.resolve`). Without, only the minimiser is wanted and the
        result's ``lu`` is None (the factors are freed on return).

    Returns
    -------
    InterfaceFactor
    """
    g_mat = scipy.sparse.csr_matrix(constraints[0])
    g_rhs = np.asarray(constraints[1], dtype=complex)
    if not keep and sum(len(b.offset) for b in blocks) + g_mat.shape[0] == n_s:
        return _minimiser(blocks, n_s, _determined_solution(n_s, blocks, g_mat, g_rhs, groups),
                          g_rhs)
    matrix, n_rho, scale = _equilibrated(n_s, blocks, g_mat)
    rhs = np.concatenate([-np.concatenate([b.offset for b in blocks]) if blocks
                          else np.zeros(0, dtype=complex), np.zeros(n_s, dtype=complex), g_rhs])
    scaled_rhs = rhs * scale
    lu, x = None, None
    variable_groups = (_variable_groups(blocks, n_rho, groups)
                       if groups is not None and matrix.shape[0] >= GROUPED_MIN_SIZE else None)
    if variable_groups is not None:
        holder = [matrix]  # the factorisation frees the entries as it goes
        del matrix
        try:
            lu = GroupedLDL(holder, variable_groups)
            x = lu.solve(scaled_rhs)
        except GroupPivotError:
            lu = None
        matrix = _equilibrated(n_s, blocks, g_mat)[0]  # again, for the check (0.05 s at most)
        if lu is not None and backward_error(matrix, x, scaled_rhs) > BACKWARD_ERROR:
            lu = None
    if lu is None:
        # The transfer operators of enriched Trefftz bases make this system as ill-conditioned
        # as the plate blocks (``docs/method.md`` section 9.1); LU with partial pivoting is
        # backward stable, and accuracy is judged on fields and energies.
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", scipy.sparse.linalg.MatrixRankWarning)
            lu = scipy.sparse.linalg.splu(hermitian_full(matrix), permc_spec="COLAMD",
                                          diag_pivot_thresh=0.1)
        x = lu.solve(scaled_rhs)
    x = x * scale
    return _minimiser(blocks, n_s, x[n_rho:n_rho + n_s], g_rhs, lu if keep else None, scale)


def _minimiser(blocks: Sequence[Block], n_s: int, s: np.ndarray, g_rhs: np.ndarray,
               lu: object = None, scale: np.ndarray | None = None) -> InterfaceFactor:
    """The InterfaceFactor of the minimiser ``s``, with its factorisation if kept."""
    ends = np.cumsum([len(b.offset) for b in blocks], dtype=int)
    rows = [slice(int(end - len(b.offset)), int(end)) for b, end in zip(blocks, ends)]
    n_rho = int(ends[-1]) if len(blocks) else 0
    return InterfaceFactor(lu, scale, n_rho, n_s, s, [b.residual(s) for b in blocks], g_rhs, rows)


def _determined_solution(n_s: int, blocks: Sequence[Block], g_mat: scipy.sparse.csr_matrix,
                         g_rhs: np.ndarray,
                         groups: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    r"""The minimiser of a problem with as many residual rows and constraints as unknowns: the
    solution of the square system

    .. math:: K S = \begin{bmatrix} A \\ G \end{bmatrix} S
              = \begin{bmatrix} -a \\ g \end{bmatrix},

    whose residuals vanish, equilibrated by rows and then columns (:func:`_equilibration`) and
    factorised:

    * from :data:`GROUPED_LU_MIN_SIZE` unknowns on, given the ``groups`` of the unknowns and
      the constraint rows, by groups (:class:`solver.grouped_lu.GroupedLU`), refined once and
      kept if its backward error is below :data:`BACKWARD_ERROR`;
    * else, when more than :data:`DENSE_FILL` of its entries are filled, by LAPACK;
    * else by SuperLU (COLAMD).

    The last two pivot by rows (backward stable, like the augmented system's factorisations).

    A forward solve is such a problem: every joint holds as many law samples and constraints
    as load unknowns (:func:`_variable_groups`), and only measurements add rows. :math:`K` has
    half the size of the augmented matrix :math:`[-I\ A\ 0;\ A^H\ 0\ G^H;\ 0\ G\ 0]`:
    on the moving-line stiffened panel at 2500 Hz (808 unknowns) the interface solve takes
    0.04 s against 0.17 s, on the 8 x 8 grid (3108) 0.22 s against 0.35 s
    (``docs/method.md`` section 7.4).
    """
    if n_s == 0:  # plates without joints
        return np.zeros(0, dtype=complex)
    # one copy of the entries, in compressed rows: the largest data of a solve
    k_mat = scipy.sparse.vstack([stacked_blocks(blocks, n_s), g_mat], format="csr")
    k_mat.sum_duplicates()
    rows = np.repeat(np.arange(n_s), np.diff(k_mat.indptr))
    row_scale, col_scale = _equilibration(n_s, rows, k_mat.indices, k_mat.data)
    k_mat.data *= row_scale[rows] * col_scale[k_mat.indices]
    rhs = np.concatenate([-b.offset for b in blocks] + [g_rhs]) * row_scale
    if groups is not None and n_s >= GROUPED_LU_MIN_SIZE:
        row_groups = np.concatenate([np.full(len(b.offset), b.group) for b in blocks]
                                    + [np.asarray(groups[1], dtype=int)])
        solution = _grouped_solution(k_mat, rows, rhs, row_groups,
                                     np.asarray(groups[0], dtype=int))
        if solution is not None:
            return col_scale * solution
    del rows
    if k_mat.nnz > DENSE_FILL * n_s ** 2:
        factors = scipy.linalg.lu_factor(k_mat.toarray(), overwrite_a=True, check_finite=False)
        return col_scale * scipy.linalg.lu_solve(factors, rhs, check_finite=False)
    return col_scale * scipy.sparse.linalg.splu(k_mat.tocsc(), permc_spec="COLAMD").solve(rhs)


def stacked_blocks(blocks: Sequence[Block], n_columns: int) -> scipy.sparse.csr_matrix:
    """The Blocks' matrices stacked, row after row, as one sparse matrix of ``n_columns``
    columns (each Block's rows act on its own unknowns ``index``). Built in compressed rows
    directly, without the row and column index of every entry, and made canonical (columns
    sorted in each row, each once)."""
    if not blocks:
        return scipy.sparse.csr_matrix((0, n_columns), dtype=complex)
    index_type = np.int32 if n_columns < 2**31 else np.int64  # what the matrix will store
    lengths = np.concatenate([np.full(len(block.offset), len(block.index)) for block in blocks])
    indptr = np.concatenate([[0], np.cumsum(lengths)])
    indices = np.concatenate([np.tile(block.index.astype(index_type), len(block.offset))
                              for block in blocks])
    data = np.concatenate([block.matrix.ravel() for block in blocks]).astype(complex, copy=False)
    matrix = scipy.sparse.csr_matrix((data, indices, indptr), shape=(len(lengths), n_columns))
    matrix.sum_duplicates()
    return matrix


def _equilibration(n: int, rows: np.ndarray, cols: np.ndarray,
                   values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r"""Row then column scales of an n x n matrix given by its entries (no entry twice):
    :math:`r_i = 1/\max_j|K_{ij}|`, :math:`c_j = 1/\max_i r_i|K_{ij}|`: every column of
    :math:`\mathrm{diag}(r)K\mathrm{diag}(c)` has largest entry 1, and no entry exceeds 1."""
    tiny = np.finfo(float).tiny
    magnitude = np.abs(values)
    row_max = np.zeros(n)
    np.maximum.at(row_max, rows, magnitude)
    row_scale = 1.0 / np.maximum(row_max, tiny)
    col_max = np.zeros(n)
    np.maximum.at(col_max, cols, magnitude * row_scale[rows])
    return row_scale, 1.0 / np.maximum(col_max, tiny)


def _grouped_solution(k_mat: scipy.sparse.csr_matrix, rows: np.ndarray, rhs: np.ndarray,
                      row_groups: np.ndarray, col_groups: np.ndarray) -> np.ndarray | None:
    r"""The solution of :math:`Kx = b` (``rows``: the row of each stored entry) by
    :class:`solver.grouped_lu.GroupedLU` and one step of iterative refinement, or None where
    it cannot serve: rows without a group, a group without as many rows as unknowns or with a
    singular block, or a backward error
    :math:`\|Kx - b\|_\infty / (\|K\|_\infty\|x\|_\infty + \|b\|_\infty)` above
    :data:`BACKWARD_ERROR` (restricted pivoting does not bound the growth of the updates)."""
    if row_groups.min(initial=0) < 0:
        return None
    try:
        factor = GroupedLU(rows, k_mat.indices, k_mat.data, row_groups, col_groups)
    except GroupPivotError:
        return None
    x = factor.solve(rhs)
    x += factor.solve(rhs - k_mat @ x)
    error = _normwise_backward_error(k_mat @ x - rhs,
                                     np.bincount(rows, np.abs(k_mat.data), len(rhs)), x, rhs)
    return x if error <= BACKWARD_ERROR else None


def _equilibrated(n_s: int, blocks: Iterable[Block],
                  g_mat: scipy.sparse.spmatrix) -> tuple[scipy.sparse.coo_matrix, int, np.ndarray]:
    r"""The lower triangle of the augmented matrix scaled symmetrically, ``D H D``, with
    :math:`D_{ii} = (\max_j|H_{ij}|)^{-1/2}` (its rows mix residuals, energies per unit load
    and displacements), the number of residual rows and the scale D."""
    matrix, n_rho = _augmented_matrix(n_s, blocks, g_mat)
    row_max = np.zeros(matrix.shape[0])
    np.maximum.at(row_max, matrix.row, np.abs(matrix.data))
    np.maximum.at(row_max, matrix.col, np.abs(matrix.data))
    scale = 1.0 / np.sqrt(np.maximum(row_max, np.finfo(float).tiny))
    matrix.data *= scale[matrix.row] * scale[matrix.col]
    return matrix, n_rho, scale


def backward_error(lower: scipy.sparse.coo_matrix, x: np.ndarray, rhs: np.ndarray) -> float:
    r"""Normwise backward error :math:`\|Hx - b\|_\infty / (\|H\|_\infty\|x\|_\infty +
    \|b\|_\infty)` of a solution ``x`` of :math:`Hx = b`, :math:`H` Hermitian given by its
    lower triangle ``lower`` (COO)."""
    magnitude = np.abs(lower.data)
    off = np.where(lower.row != lower.col, magnitude, 0.0)
    row_sums = (np.bincount(lower.row, magnitude, lower.shape[0])
                + np.bincount(lower.col, off, lower.shape[0]))
    return _normwise_backward_error(_hermitian_product(lower, x) - rhs, row_sums, x, rhs)


def _normwise_backward_error(residual: np.ndarray, row_sums: np.ndarray, x: np.ndarray,
                             rhs: np.ndarray) -> float:
    r""":math:`\|r\|_\infty / (\|K\|_\infty\|x\|_\infty + \|b\|_\infty)`, the matrix norm
    the largest of its ``row_sums`` of absolute values."""
    return float(np.max(np.abs(residual))
                 / (row_sums.max() * np.max(np.abs(x)) + np.max(np.abs(rhs))))


def _variable_groups(blocks: Sequence[Block], n_rho: int,
                     groups: tuple[np.ndarray, np.ndarray]) -> np.ndarray | None:
    """Group of every variable of the augmented system — ``rho`` rows by their blocks, then
    S, then the multipliers — or None when a group holds fewer rows than unknowns (its pivot
    block would be singular: a joint without residual weight, say)."""
    unknown_groups, constraint_groups = groups
    sizes = [len(b.offset) for b in blocks]
    own = np.repeat(np.array([b.group for b in blocks], dtype=int), sizes)
    alone = own < 0  # rows of their own: a group per block
    first = max(unknown_groups.max(initial=-1), constraint_groups.max(initial=-1)) + 1
    own[alone] = first + np.repeat(np.arange(len(blocks)), sizes)[alone]
    labels = np.concatenate([own, unknown_groups, constraint_groups])
    _, labels = np.unique(labels, return_inverse=True)
    is_row = np.ones(len(labels), dtype=bool)
    is_row[n_rho:n_rho + len(unknown_groups)] = False
    rows = np.bincount(labels[is_row], minlength=labels.max() + 1)
    unknowns = np.bincount(labels[~is_row], minlength=labels.max() + 1)
    return labels if np.all(rows >= unknowns) else None
