"""The factorisation by groups (solver.multifrontal) against dense LAPACK and against SuperLU.

Pure numerics first (random block-sparse systems, whose exact solution dense LAPACK gives to
round-off), then the interface problems of the cases: the grouped path must give the fields,
residuals and costs of the SuperLU path, and must give way to it where restricted pivoting
cannot work.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse
from support import CASES, dense_interface, field_difference, mixed_chain

from assembly import load_case, parse_case
from assembly.generate import plate_grid
from solver import interface, multifrontal
from solver.channels import channel_blocks, joint_residuals
from solver.errors import GroupPivotError
from solver.joint_rules import joint_parameters
from solver.multifrontal import GroupedLDL, minimum_degree_order
from solver.substructure import build_assembly_system, solve_assembly, solve_interface
from solver.vtcr import solve_case
from updating.data.measurements import simulate_measurements
from updating.inverse.cost import ModifiedProblem, with_joint


def lattice_system(n_x, n_y, seed=0, zero_diagonal=False, size=None):
    """A random Hermitian matrix coupling the groups of an n_x x n_y lattice to their four
    neighbours (group sizes 2 to 6, or all ``size``), and its group labels. With
    ``zero_diagonal`` every group's block is ``[[0, B], [B^H, 0]]`` (as a KKT block: no
    diagonal pivot exists, only 2 x 2 ones)."""
    rng = np.random.default_rng(seed)
    sizes = rng.integers(2, 7, n_x * n_y) if size is None else np.full(n_x * n_y, size)
    if zero_diagonal:
        sizes = 2 * (sizes // 2)
    starts = np.concatenate([[0], np.cumsum(sizes)])
    n = starts[-1]
    dense = np.zeros((n, n), dtype=complex)

    def part(g):
        return slice(starts[g], starts[g + 1])

    for i in range(n_x):
        for j in range(n_y):
            g = i * n_y + j
            m = sizes[g]
            block = rng.normal(size=(m, m)) + 1j * rng.normal(size=(m, m))
            block = block + block.conj().T + 3 * np.eye(m)
            if zero_diagonal:
                h = m // 2
                block[:h, :h] = 0.0
                block[h:, h:] = 0.0
            dense[part(g), part(g)] = block
            for di, dj in ((1, 0), (0, 1)):
                if i + di < n_x and j + dj < n_y:
                    k = (i + di) * n_y + j + dj
                    dense[part(g), part(k)] = 0.3 * rng.normal(size=(m, sizes[k]))
                    dense[part(k), part(g)] = dense[part(g), part(k)].conj().T
    return dense, np.repeat(np.arange(n_x * n_y), sizes)


@pytest.mark.parametrize("zero_diagonal", [False, True], ids=["general", "kkt-blocks"])
def test_grouped_ldl_solves_a_block_sparse_system(zero_diagonal):
    dense, groups = lattice_system(6, 5, zero_diagonal=zero_diagonal)
    lu = GroupedLDL(scipy.sparse.csc_matrix(dense), groups)
    rng = np.random.default_rng(1)
    rhs = rng.normal(size=(len(groups), 3)) + 1j * rng.normal(size=(len(groups), 3))
    exact = np.linalg.solve(dense, rhs)
    # condition numbers about 1e2-1e3: Bunch-Kaufman pivoting reaches 1e-14 here; an assembly,
    # extend-add or pivoting error shows at order 1
    assert np.linalg.norm(lu.solve(rhs) - exact) < 1e-11 * np.linalg.norm(exact)
    assert np.linalg.norm(lu.solve(rhs[:, 0]) - exact[:, 0]) < 1e-11 * np.linalg.norm(exact)
    if zero_diagonal:  # every pivot of the first groups is a 2 x 2 block
        assert len(lu.factors[0][3].pairs) > 0


def test_fronts_leave_out_the_variables_they_do_not_touch(monkeypatch):
    """Neighbouring groups coupled through some of their variables only (half the columns of
    each block between two groups zero, the Hermitian partner's rows with them), as a joint's
    loads reach one plate of two: the fronts leave the untouched variables out
    (multifrontal._held_variables), so the factors are smaller than with every variable of
    the coupled groups kept, and both solve as dense LAPACK does (tolerance as above)."""
    dense, groups = lattice_system(5, 4, seed=5, size=8)
    rng = np.random.default_rng(6)
    n_groups = groups.max() + 1
    for u in range(n_groups):
        for w in range(u + 1, n_groups):
            rows, cols = np.flatnonzero(groups == u), np.flatnonzero(groups == w)
            dropped = cols[rng.random(len(cols)) < 0.5]
            dense[np.ix_(rows, dropped)] = 0.0
            dense[np.ix_(dropped, rows)] = 0.0
    rhs = rng.normal(size=len(groups)) + 1j * rng.normal(size=len(groups))
    exact = np.linalg.solve(dense, rhs)
    held = GroupedLDL(scipy.sparse.csc_matrix(dense), groups)
    monkeypatch.setattr(multifrontal, "_held_variables",
                        lambda later, holders, touched: np.concatenate(later) if later
                        else np.zeros(0, dtype=int))
    whole = GroupedLDL(scipy.sparse.csc_matrix(dense), groups)
    assert held.nnz < 0.9 * whole.nnz
    for lu in (held, whole):
        assert np.linalg.norm(lu.solve(rhs) - exact) < 1e-11 * np.linalg.norm(exact)


def test_a_chain_of_groups_is_eliminated_without_fill():
    """Block-tridiagonal: the minimum-degree order eliminates from the ends, so every front
    holds its group and one neighbour; eliminating the middle first would couple both sides."""
    dense, groups = lattice_system(12, 1, size=4)
    sizes = np.bincount(groups)
    lu = GroupedLDL(scipy.sparse.csc_matrix(dense), groups)
    # every front is coupled to one neighbouring group at most: no fill
    assert max(len(coupled) for _, coupled, *_ in lu.factors) == 4
    path = scipy.sparse.diags([np.ones(11), np.ones(11)], [-1, 1]).tocsr()
    order = minimum_degree_order(path, sizes)
    assert order[0] in (0, 11)


def test_either_entry_of_each_pair_is_enough():
    """The factorisation reads a Hermitian matrix from its lower triangle, its upper one, a
    random choice of one entry per pair, or all of it, and gives the same solution; given in
    a list, the matrix is taken out of it (the factorisation holds the only reference)."""
    dense, groups = lattice_system(5, 4, seed=3)
    rng = np.random.default_rng(4)
    rhs = rng.normal(size=len(groups)) + 1j * rng.normal(size=len(groups))
    exact = np.linalg.solve(dense, rhs)
    lower = np.tril(dense)
    pick = np.tril(rng.random(dense.shape) < 0.5, -1)
    mixed = np.where(pick, dense, 0.0) + np.where(pick.T, 0.0, np.triu(dense))
    for form in (lower, np.triu(dense), mixed, dense):
        holder = [scipy.sparse.coo_matrix(form)]
        solution = GroupedLDL(holder, groups).solve(rhs)
        assert holder == []
        # as the block-sparse test: an entry read from the wrong side shows at order 1
        assert np.linalg.norm(solution - exact) < 1e-11 * np.linalg.norm(exact)


def test_the_backward_error_of_a_matrix_given_by_its_lower_triangle():
    """:func:`solver.interface.backward_error` and :func:`solver.interface.hermitian_full`
    against the dense matrix: the same residual, norm and completion."""
    dense, _ = lattice_system(3, 3, seed=6)
    lower = scipy.sparse.coo_matrix(np.tril(dense))
    assert np.array_equal(interface.hermitian_full(lower).toarray(), dense)
    rng = np.random.default_rng(7)
    x = rng.normal(size=len(dense)) + 1j * rng.normal(size=len(dense))
    rhs = dense @ x + 1e-3 * rng.normal(size=len(dense))
    expected = (np.max(np.abs(dense @ x - rhs))
                / (np.abs(dense).sum(axis=1).max() * np.max(np.abs(x)) + np.max(np.abs(rhs))))
    assert interface.backward_error(lower, x, rhs) == pytest.approx(expected, rel=1e-12)


def test_a_singular_group_block_is_refused():
    """Nonsingular as a whole (determinant -2), but the first group's 1 x 1 block is zero."""
    matrix = np.array([[0.0, 1.0, 0.0], [1.0, 1.0, 1.0], [0.0, 1.0, 2.0]], dtype=complex)
    with pytest.raises(GroupPivotError):
        GroupedLDL(scipy.sparse.csc_matrix(matrix), np.array([0, 1, 2]))


def _direct_blocks(case):
    system = build_assembly_system(case, case.frequencies[0])
    params = joint_parameters(case, system.omega)
    return system, params, channel_blocks(system.channels, params, case.updatable_alpha())


def test_the_grouped_and_superlu_paths_agree_on_a_grid():
    """5 x 5 grid (2208 variables, above GROUPED_MIN_SIZE: the grouped path by default)."""
    case = parse_case(plate_grid(5, 5))
    system, params, blocks = _direct_blocks(case)
    grouped = solve_interface(system, blocks)
    superlu = interface.factorise_interface(system.n_s, blocks, system.constraints)
    assert isinstance(grouped.lu, GroupedLDL)
    assert isinstance(superlu.lu, scipy.sparse.linalg.SuperLU)
    minimiser = solve_interface(system, blocks, keep=False)  # the square system's
    assert minimiser.lu is None and field_difference(system, minimiser.s, grouped.s) < 1e-9
    # measured 2e-12: both backward stable on a system of condition about 1e10
    assert field_difference(system, grouped.s, superlu.s) < 1e-9
    ref = joint_residuals(system.channels, params, superlu.s, 1.0)  # compared with each other
    for name, value in joint_residuals(system.channels, params, grouped.s, 1.0).items():
        assert value == pytest.approx(ref[name], rel=1e-6, abs=1e-20)


@pytest.mark.parametrize("case", [mixed_chain(), load_case(CASES / "box_with_wall.toml"),
                                  load_case(CASES / "stiffened_panel.toml")],
                         ids=["chain", "box_with_wall", "stiffened_panel"])
def test_the_grouped_path_on_junctions_corners_and_line_masses(case, monkeypatch):
    """Junction lines (with and without a rigid member), static junction corners, a line mass
    and a hinge: every kind of group, factorised by groups against the dense reference."""
    monkeypatch.setattr(interface, "GROUPED_MIN_SIZE", 0)
    system, _, blocks = _direct_blocks(case)
    grouped = solve_interface(system, blocks)
    assert isinstance(grouped.lu, GroupedLDL)
    # measured 1.5e-11 to 6.7e-11, as SuperLU's (the dense reference squares the condition)
    assert field_difference(system, grouped.s, dense_interface(system, blocks)) < 1e-8


@pytest.mark.parametrize("case", [mixed_chain(), load_case(CASES / "box_with_wall.toml"),
                                  load_case(CASES / "stiffened_panel.toml")],
                         ids=["chain", "box_with_wall", "stiffened_panel"])
@pytest.mark.parametrize("path", ["dense", "superlu", "grouped"])
def test_a_forward_solve_is_the_square_system_of_the_laws_and_constraints(case, path,
                                                                          monkeypatch):
    """Without measurements the laws' samples and the constraints are as many as the
    unknowns: the forward solve takes the square system K S = (-a, g), half the augmented
    one's size, and finds the dense normal equations' minimiser, whose residuals vanish;
    factorised dense, by SuperLU or by groups (solver.grouped_lu)."""
    monkeypatch.setattr(interface, "DENSE_FILL", 0.0 if path == "dense" else 2.0)
    monkeypatch.setattr(interface, "GROUPED_LU_MIN_SIZE", 0 if path == "grouped" else 10**9)
    system, _, blocks = _direct_blocks(case)
    calls, grouped = [], []
    square, by_groups = interface._determined_solution, interface._grouped_solution
    monkeypatch.setattr(interface, "_determined_solution",
                        lambda *args: calls.append(1) or square(*args))
    monkeypatch.setattr(interface, "_grouped_solution",
                        lambda *args: grouped.append(by_groups(*args)) or grouped[-1])
    minimiser = solve_interface(system, blocks, keep=False)
    assert calls and minimiser.lu is None
    # the grouped path serves (no fallback) when it is asked for, and only then
    assert [x is not None for x in grouped] == ([True] if path == "grouped" else [])
    # measured 4e-12 to 4e-11, as the grouped and SuperLU paths against the same reference
    assert field_difference(system, minimiser.s, dense_interface(system, blocks)) < 1e-8
    offsets = np.concatenate([b.offset for b in blocks])
    residuals = np.concatenate(minimiser.residuals)
    # a square system's minimum is zero: what is left is round-off on the offsets' scale
    assert np.linalg.norm(residuals) < 1e-9 * np.linalg.norm(offsets)
    assert len(offsets) + system.constraints[0].shape[0] == system.n_s


def test_a_plate_without_joints_has_an_empty_interface():
    """No joint, no interface unknown: the forward solve is the plate's own."""
    case = load_case(CASES / "single_plate.toml")
    frequency = case.frequencies[0]
    assembled = solve_assembly(case, frequency)
    assert assembled.interface.shape == (0,)
    points = np.array([[0.1, 0.1], [0.3, 0.2]])
    alone = solve_case(case, frequency).plates["P1"].field(points)["w"]
    # the same plate system, solved by the same factorisation
    assert np.allclose(assembled.plates["P1"].field(points)["w"], alone, rtol=1e-12, atol=0)


@pytest.fixture(scope="module")
def four_plates(four_plates_case):
    case = four_plates_case
    return ModifiedProblem(case, simulate_measurements(case))


@pytest.mark.parametrize("log10_stiffness", [-3.0, 2.0, 12.0])
def test_the_grouped_path_on_the_modified_problem(four_plates, monkeypatch, log10_stiffness):
    """Measurement rows (groups of their own), over 15 decades of one joint's stiffness."""
    parameters = with_joint(four_plates.initial_parameters(), "G2",
                            log10_stiffness=log10_stiffness)
    superlu = four_plates.evaluate(parameters)
    monkeypatch.setattr(interface, "GROUPED_MIN_SIZE", 0)
    grouped = four_plates.evaluate(parameters)
    # measured: costs 2e-15 to 3e-13 apart (the stiff end loses digits to the condition of
    # the system), fields 8e-11 to 3e-9
    assert grouped.e_mod == pytest.approx(superlu.e_mod, rel=1e-9)
    for frequency, freq in four_plates.frequencies.items():
        assert field_difference(freq.system, grouped.interface[frequency],
                                superlu.interface[frequency]) < 1e-8


def test_superlu_takes_over_where_groups_cannot_pivot(four_plates_case, monkeypatch):
    """A joint without residual weight leaves its group with fewer rows than unknowns, and a
    backward error above the bound rejects a grouped solution: both go to SuperLU."""
    monkeypatch.setattr(interface, "GROUPED_MIN_SIZE", 0)
    case = four_plates_case
    system, _, blocks = _direct_blocks(case)
    weighted = [b for b in blocks if b.group != 0]
    factor = solve_interface(system, weighted)
    assert isinstance(factor.lu, scipy.sparse.linalg.SuperLU)
    monkeypatch.setattr(interface, "BACKWARD_ERROR", 0.0)
    factor = solve_interface(system, blocks)
    assert isinstance(factor.lu, scipy.sparse.linalg.SuperLU)
    monkeypatch.setattr(interface, "BACKWARD_ERROR", 1e-14)
    assert isinstance(solve_interface(system, blocks).lu, GroupedLDL)


def test_corrections_and_floors_through_the_grouped_factorisation(four_plates_case, monkeypatch):
    """The condensation on one joint (solves with many right-hand sides through the kept
    factorisation) and the noise floors (the factorisation re-solved with the offsets of each
    noise draw) give, through GroupedLDL, what they give through SuperLU."""
    case = four_plates_case
    measurements = simulate_measurements(case)
    values = [{"log10_stiffness": v} for v in (-1.0, 1.5, 5.0)]
    reference = ModifiedProblem(case, measurements)
    base = reference.initial_parameters()
    expected = [reference.correction(base, "G4").cost(**v) for v in values]
    expected_floors, expected_e_mod = reference.noise_floor(base, 0.1)

    splu, square, in_square = (interface.scipy.sparse.linalg.splu,
                               interface._determined_solution, [])

    def forward_solve(*args):  # a forward solve's square system is SuperLU's to factorise
        in_square.append(True)
        try:
            return square(*args)
        finally:
            in_square.pop()

    def no_superlu(*args, **kwargs):
        if not in_square:
            raise AssertionError("SuperLU used where the grouped factorisation should be")
        return splu(*args, **kwargs)

    made = []

    class CountedLU(GroupedLDL):
        def __init__(self, *args):
            super().__init__(*args)
            made.append(self)

    monkeypatch.setattr(interface, "GROUPED_MIN_SIZE", 0)
    monkeypatch.setattr(interface.scipy.sparse.linalg, "splu", no_superlu)
    monkeypatch.setattr(interface, "_determined_solution", forward_solve)
    monkeypatch.setattr(interface, "GroupedLDL", CountedLU)
    problem = ModifiedProblem(case, measurements)
    grouped = problem.correction(base, "G4")
    for v, cost in zip(values, expected):
        # measured 1e-12: the same minimisers through two backward-stable factorisations
        assert grouped.cost(**v) == pytest.approx(cost, rel=1e-9), v
    floors, e_mod = problem.noise_floor(base, 0.1)
    assert made
    # measured up to 2e-9: the floors' draws go through the enriched solve and the modified
    # problem, both factorised anew, the same minimisers to the conditioning of those systems
    assert e_mod == pytest.approx(expected_e_mod, rel=1e-7)
    for name, value in expected_floors.items():
        assert floors[name] == pytest.approx(value, rel=1e-7), name


def test_the_minimum_degree_weights_are_those_of_the_elimination_graph():
    """The weights kept up to date as cliques form give the order that recomputing every
    weight from the elimination graph gives (the definition, written here), on random graphs
    with random group sizes and ties."""
    rng = np.random.default_rng(7)
    for n in (5, 30, 80):
        dense = np.triu(rng.random((n, n)) < 4.0 / n, 1)
        adjacency = scipy.sparse.csr_matrix((dense | dense.T).astype(float))
        sizes = rng.integers(1, 4, n)
        neighbours = [set(np.flatnonzero((dense | dense.T)[v]).tolist()) for v in range(n)]
        reference = []
        left = set(range(n))
        while left:
            v = min(left, key=lambda u: (sum(sizes[x] for x in neighbours[u]), u))
            reference.append(v)
            left.remove(v)
            for u in neighbours[v]:
                neighbours[u] |= neighbours[v] - {u}
                neighbours[u].discard(v)
        assert minimum_degree_order(adjacency, sizes).tolist() == reference
