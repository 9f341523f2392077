"""The sparse, joint-local interface solve against a dense reference, and the condensation.

The dense reference assembles the normal-equations KKT system
``[sum A^H A, G^H; G, 0] [S; lambda] = [-sum A^H a; g]`` over all interface unknowns from the same
residual rows and solves it with LAPACK; the sparse path solves the augmented form with SuperLU,
and the condensation on one joint (Sherman-Morrison-Woodbury on its residual samples) must give
the cost of a full re-solve. These systems inherit the Trefftz bases' ill-conditioning
(condition estimates 1e9-1e16): the interface unknowns themselves may differ far beyond
round-off between two stable algorithms, so fields, residuals and costs are compared, which are
well determined.
"""

from __future__ import annotations

import numpy as np
import pytest
from support import CASES, dense_interface, field_difference, grid, mixed_chain

from assembly import load_case, parse_case
from assembly.generate import plate_grid
from solver.channels import channel_blocks, joint_residuals
from solver.joint_rules import joint_parameters
from solver.substructure import build_assembly_system, solve_assembly
from updating.data.measurements import simulate_measurements
from updating.inverse.cost import ModifiedProblem, channel_parameters, with_joint


@pytest.mark.parametrize("case", [mixed_chain(), load_case(CASES / "four_plates.toml")],
                         ids=["chain", "four_plates"])
def test_direct_problem_matches_the_dense_reference(case):
    frequency = case.frequencies[0]
    system = build_assembly_system(case, frequency)
    solution = solve_assembly(case, frequency, system=system)
    params = joint_parameters(case, system.omega)
    blocks = channel_blocks(system.channels, params, case.updating.alpha)
    reference = dense_interface(system, blocks)
    # measured: 1e-10 (chain) and 4e-12 (four plates); both are far below the discretisation
    # error (1e-4..1e-3), and a wrong assembly (a misplaced block) shows at order 1
    assert field_difference(system, solution.interface, reference) < 1e-8
    dense_residuals = joint_residuals(system.channels, params, reference,
                                      solution.reference.total)
    for jid, value in solution.residuals.items():
        assert value == pytest.approx(dense_residuals[jid], rel=1e-6, abs=1e-14)


@pytest.fixture(scope="module")
def four_plates(four_plates_case):
    case = four_plates_case
    return ModifiedProblem(case, simulate_measurements(case))


def test_modified_problem_matches_the_dense_reference(four_plates):
    problem = four_plates
    parameters = with_joint(problem.initial_parameters(), "G2", log10_stiffness=3.3)
    evaluation = problem.evaluate(parameters)
    e_mod = 0.0
    for frequency, freq in problem.frequencies.items():
        system = freq.system
        params = channel_parameters(parameters, system.omega)
        blocks = (channel_blocks(system.channels, params, problem.joint_weights(freq))
                  + freq.blocks(freq.data, problem.r))
        reference = dense_interface(system, blocks)
        # measured up to 2e-8 (309.4 Hz): the reference's normal equations square the
        # condition number; still four decades below the discretisation error of the fields
        assert field_difference(system, evaluation.interface[frequency], reference) < 1e-6
        e_mod += sum(np.linalg.norm(b.residual(reference)) ** 2 for b in blocks)
    assert evaluation.e_mod == pytest.approx(e_mod, rel=1e-10)


@pytest.mark.parametrize("joint", ["G1", "G2"])
def test_condensed_cost_equals_a_full_solve(four_plates, joint):
    """Over 16 decades of k, with damping, and at the base point (to round-off there)."""
    problem = four_plates
    base = problem.initial_parameters()
    local = problem.correction(base, joint)
    assert local.cost() == pytest.approx(problem.cost(base), rel=1e-12)
    for values in ({"log10_stiffness": -3.0}, {"log10_stiffness": 0.5},
                   {"log10_stiffness": 4.5}, {"log10_stiffness": 12.0},
                   {"log10_stiffness": 1.0, "loss_factor": 0.3}):
        full = problem.cost(with_joint(base, joint, **values))
        # measured 1e-12..1e-9 (the stiff end loses digits to the condition of the system)
        assert local.cost(**values) == pytest.approx(full, rel=1e-7), values


def test_neighbourhood_cost_of_the_condensation_equals_a_full_solve(four_plates):
    """The condensed neighbourhood cost updates only the unknowns its channels and plates see;
    it must equal the neighbourhood cost of a full re-solve (residuals and misfits)."""
    problem = four_plates
    base = problem.initial_parameters()
    local = problem.correction(base, "G4")
    assert problem.neighbourhood("G4") == (["G1", "G3", "G4"], ["P1", "P3"])
    for value in (-1.0, 1.5, 5.0):
        full = problem.evaluate(with_joint(base, "G4", log10_stiffness=value))
        expected = problem.neighbourhood_cost("G4", full.residuals, full.misfits)
        # measured 1e-11: the same minimiser through the Woodbury identity
        assert local.neighbourhood_cost(log10_stiffness=value) == pytest.approx(expected,
                                                                                rel=1e-8)


def test_data_live_with_their_plates_and_joints():
    """A plate's transfer operator and a joint's samples span its neighbourhood only: the same
    sizes for the corner plate of a 2 x 2 and of a 3 x 3 arrangement."""
    def sizes(n):
        case = parse_case(plate_grid(n, n))
        system = build_assembly_system(case, 250.0)
        channel = next(ch for ch in system.channels if ch.joint == "H1_1")
        return system.n_s, system.transfer["P1_1"].shape, channel.kinematic.matrix.shape

    (n_small, transfer_small, channel_small) = sizes(2)
    (n_large, transfer_large, channel_large) = sizes(3)
    assert n_large > 2 * n_small
    assert transfer_small == transfer_large
    # H1_1's plates see one more joint in the 3 x 3 grid (P2_1 gains H2_1): the channel
    # grows by that joint's unknowns only, not with the number of interface unknowns
    assert channel_large[1] - channel_small[1] < n_small // 2


def test_six_by_six_stiff_grid_is_the_single_plate_of_navier():
    """36 plates of 0.5 x 0.4 m, 60 coplanar joints with log10 k = 6 (the rotational stiffness
    of a continuous plate here is about D kappa0 = 460 N: 1e6 N is rigid to 1e-3), outer edges
    simply supported: the single simply supported 3.0 x 2.4 m plate of the Navier series, at
    140 Hz (about 13 x 10 bending wavelengths), through the sparse interface solve of 2000
    unknowns with 25 four-plate junction points."""
    from exact import complex_rigidity, navier_point_force

    from solver import solve_case

    n, size, frequency, force_at = 6, (0.5, 0.4), 140.0, (0.17, 0.13)  # force in P1_1
    case = parse_case(plate_grid(n, n, frequency=frequency, log10_stiffness=6.0,
                                 force_at=force_at))
    solution = solve_case(case)
    d = complex_rigidity(210e9, 0.001, 0.3, 0.01)
    x0, y0 = force_at
    num = den = 0.0
    for pid, plate in case.plates.items():
        points = grid(*size, 5)
        ox, oy = plate.origin
        ref = navier_point_force(n * size[0], n * size[1], d, 7.8, 2 * np.pi * frequency,
                                 x0, y0, 1.0, points[:, 0] + ox, points[:, 1] + oy)
        num += np.linalg.norm(solution.w(pid, points) - ref) ** 2
        den += np.linalg.norm(ref) ** 2
    # measured 5.3e-3 at the default resolution (deterministic; the 2 x 2 test of
    # test_assemblies holds the same 1e-2): a wrong junction or joint term shows at order 1
    assert np.sqrt(num / den) < 1e-2


def test_identical_plates_share_their_basis_and_nothing_changes(monkeypatch):
    """The plates of a grid share one ray basis, their joint traces are computed once, and
    the unforced plates with the same edges share their factorised block; the system is the
    same, to the bit, as with a basis of its own for every plate."""
    from solver import channels, substructure
    from solver.plate import edge_values
    from solver.problems import plate_basis

    case = parse_case(plate_grid(3, 3))
    shared = build_assembly_system(case, 250.0)
    assert len({id(b) for b in shared.bases.values()}) == 1

    def own_bases(case, problems, resolution):
        return {pid: plate_basis(case, pid, p, resolution) for pid, p in problems.items()}

    def uncached_edge_values(problem, basis, edge, s, cache=None):
        return edge_values(problem, basis, edge, s)

    monkeypatch.setattr(substructure, "plate_bases", own_bases)
    monkeypatch.setattr(channels, "edge_values", uncached_edge_values)
    alone = build_assembly_system(case, 250.0)
    assert len({id(b) for b in alone.bases.values()}) == len(case.plates)
    for a, b in zip(shared.channels, alone.channels):
        for part in ("load", "kinematic"):
            assert np.array_equal(getattr(a, part).matrix, getattr(b, part).matrix)
            assert np.array_equal(getattr(a, part).offset, getattr(b, part).offset)
    assert (shared.constraints[0] != alone.constraints[0]).nnz == 0
    for pid in case.plates:
        assert np.array_equal(shared.transfer[pid], alone.transfer[pid])
        assert np.array_equal(shared.u0[pid], alone.u0[pid])
        assert shared.rcond[pid] == alone.rcond[pid]


def test_the_trace_cache_tells_edges_and_points_apart():
    """Cached joint traces equal fresh ones for every edge and both directions of travel, asked
    in any order (a key missing the edge or the points would hand one edge's to another)."""
    from solver.joint_rules import joint_gauss
    from solver.plate import edge_values

    case = parse_case(plate_grid(2, 2))
    system = build_assembly_system(case, 250.0)
    problem, basis = system.problems["P1_1"], system.bases["P1_1"]
    sigma, _ = joint_gauss(0.4, float(np.max(np.abs(basis.k))))
    cache = {}
    for edge in ("left", "right", "bottom", "top"):
        for s in (sigma, 0.4 - sigma):
            rays, _ = edge_values(problem, basis, edge, s, cache)
            fresh, _ = edge_values(problem, basis, edge, s)
            assert np.array_equal(rays["w"], fresh["w"]), edge
            assert np.array_equal(rays["slope"], fresh["slope"]), edge
    assert len(cache) == 8


def test_stacked_blocks_are_the_blocks_row_after_row():
    """Blocks on overlapping unknowns, one with an unknown given twice (its two columns add),
    one without rows, stacked: the dense matrix written entry by entry here."""
    from solver.interface import Block, stacked_blocks

    rng = np.random.default_rng(3)
    blocks = [Block(np.array([4, 1, 6]), rng.standard_normal((2, 3)) + 0j, np.zeros(2)),
              Block(np.array([2]), np.zeros((0, 1), dtype=complex), np.zeros(0)),
              Block(np.array([0, 6, 0]), rng.standard_normal((3, 3)) + 1j, np.zeros(3))]
    dense = np.zeros((5, 8), dtype=complex)
    row = 0
    for block in blocks:
        for values in block.matrix:
            for column, value in zip(block.index, values):
                dense[row, column] += value
            row += 1
    stacked = stacked_blocks(blocks, 8)
    assert stacked.has_canonical_format
    assert np.array_equal(stacked.toarray(), dense)
