"""Detection power that does not dilute with the size of the structure (the scale-free weights,
``updating.inverse.weights``), and the identification of a co-identified loss factor.

Each figure in a docstring was measured with ``[updating] r = 0.8`` (the paper's weights,
``alpha = 1/N_joints``) beside the default: the tests that compare the two fail with the paper's
weights as default. ±10 % uniform noise, simulated experiments at the descriptions' finer
measurement resolution; "excess" is a joint's residual over its calibrated threshold (above 1:
it stands out).
"""

from __future__ import annotations

import pytest

from assembly import parse_case
from assembly.generate import plate_grid
from updating.data.measurements import simulate_measurements
from updating.inverse.cost import ModifiedProblem
from updating.inverse.strategy import excess_ratios, localise, update_joints


def _grid(n, truth, seed=1, **updating):
    description = plate_grid(n, n, truth=truth, seed=seed)
    description["updating"] = {"bounds": [-1.0, 6.0], **updating}
    return parse_case(description)


def _excess(case, measurements=None):
    """Each joint's residual over its threshold in the first localisation."""
    problem = ModifiedProblem(case, measurements or simulate_measurements(case))
    step = localise(problem, problem.initial_parameters(), noise=case.measurement.noise)
    return excess_ratios(step, case.updating.stop_ratio), problem


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_right_4x4_grid_shows_nothing_standing_out_with_the_default_weights(seed):
    """The thresholds stay calibrated at the scale-free weights: a right model's largest joint
    stands at 0.64-0.83 of its threshold over seeds 1-5."""
    excess, problem = _excess(_grid(4, {}, seed))
    assert problem.weights is not None
    assert max(excess.values()) < 1.0


def test_a_wrong_joint_of_a_4x4_grid_is_found_where_the_papers_weights_miss_it():
    """V2_2 0.7 decade stiffer than modelled, away from the loaded corner plate: with the
    default weights it stands out (3.4 times its threshold) and is the joint that stands out
    most; with r = 0.8 and alpha = 1/N_joints it stands at 0.96 of its threshold, unseen.
    vtcr update corrects it and no other joint (to 2.85 in [2.73, 3.22] for this seed: one of
    the 10 % of intervals that miss; their coverage is measured in bench/bench_power.py)."""
    case = _grid(4, {"V2_2": 2.7})
    measurements = simulate_measurements(case)
    excess, problem = _excess(case, measurements)
    assert excess["V2_2"] > 2.0 and max(excess, key=excess.get) == "V2_2"
    paper, _ = _excess(_grid(4, {"V2_2": 2.7}, r=0.8), measurements)
    assert paper["V2_2"] < 1.0
    result = update_joints(problem, case.updating, noise=case.measurement.noise)
    final = result.parameters
    assert abs(final["V2_2"]["log10_stiffness"] - 2.7) < 0.2, final["V2_2"]
    assert all(final[j]["log10_stiffness"] == 2.0 for j in final if j != "V2_2")
    assert result.status == 0


def test_the_same_wrong_joint_gets_the_same_decision_in_a_2x2_and_a_6x6_grid():
    """H1_1 half a decade softer than modelled, beside the loaded plate: 15 and 12 times its
    threshold in the 2 x 2 and the 6 x 6 grid with the default weights, the joint that stands
    out most in both; with the paper's weights 10.7 in the 2 x 2 grid and 0.68 in the 6 x 6
    one, where it is lost among 60 joints."""
    decisions = []
    for n in (2, 6):
        excess, _ = _excess(_grid(n, {"H1_1": 1.5}))
        decisions.append((excess["H1_1"] > 3.0, max(excess, key=excess.get)))
    assert decisions == [(True, "H1_1")] * 2


CHAIN = """
name = "chain3"
frequency = 180.0
[materials.alu]
young_modulus = 70e9
poisson_ratio = 0.33
density = 2700.0
loss_factor = 0.005
[plates.A]
material = "alu"
thickness = 0.0015
size = [0.4, 0.3]
[plates.B]
material = "alu"
thickness = 0.0015
size = [0.5, 0.3]
origin = [0.4, 0.0]
[plates.C]
material = "alu"
thickness = 0.0015
size = [0.3, 0.3]
origin = [0.9, 0.0]
[joints.J1]
kind = "coplanar"
between = ["A.right", "B.left"]
log10_stiffness = 2.0
loss_factor = 0.01
[joints.J2]
kind = "coplanar"
between = ["B.right", "C.left"]
log10_stiffness = 2.0
loss_factor = START
[[boundaries]]
edge = "A.left"
condition = "clamped"
[[boundaries]]
edge = "C.right"
condition = "simply_supported"
[[loads]]
kind = "point_force"
plate = "A"
at = [0.11, 0.17]
amplitude = 1.0
[measurement]
noise = 0.05
seed = 2
[updating]
identify = ["stiffness", "damping"]
[truth.joints.J2]
log10_stiffness = 0.8
loss_factor = 0.05
"""


def test_a_co_identified_loss_factor_moves_where_its_data_say_from_any_start():
    """J2 (truth log10 k 0.8, loss factor 0.05; ±5 % noise) corrected with its loss factor
    from starts 0.01, 0.03 and 0.1: the loss factor comes out at 0.055-0.057 each time, inside
    its interval ([0.02, 0.10]), where L-BFGS-B on the raw cost (E_mod^2 of order 1e-6 against
    its absolute tolerances) returned each start unchanged."""
    import tomllib

    for start in (0.01, 0.03, 0.1):
        case = parse_case(tomllib.loads(CHAIN.replace("START", str(start))))
        problem = ModifiedProblem(case, simulate_measurements(case))
        result = update_joints(problem, case.updating, noise=case.measurement.noise)
        loss_factor = result.parameters["J2"]["loss_factor"]
        assert abs(loss_factor - 0.05) < 0.015, (start, loss_factor)
        assert abs(loss_factor - start) > 0.004, start
        assert result.parameter_intervals["J2", "loss_factor"].holds(0.05)


def test_the_summary_names_the_joint_that_stands_out_most_and_its_neighbours():
    """Three joints above their thresholds, two of them sharing a plate with the first: the
    sentence names the first, counts the others and says that neighbours may stand out only
    through it; without neighbours among them, it says so; nothing standing out gives None."""
    from updating.inverse.strategy import Step, standing_summary

    joints = ["A", "B", "C", "D"]
    parameters = {j: {"log10_stiffness": 2.0, "loss_factor": 0.0, "mass": 0.0} for j in joints}
    step = Step(0, None, parameters, {"A": 9.0, "B": 2.0, "C": 3.0, "D": 0.5},
                dict.fromkeys(joints, 0.1), 1.0, 1.0, 1.0, thresholds=dict.fromkeys(joints, 1.0))
    text = standing_summary(step, lambda j: ["A", "B", "C"], 3.0)
    assert text.startswith("A stands out most (9.0 times its threshold); 2 others stand out, "
                           "2 of them sharing a plate with it: a joint next to a wrong one")
    assert standing_summary(step, lambda j: [j], 3.0).endswith("none sharing a plate with it")
    quiet = Step(0, None, parameters, dict.fromkeys(joints, 0.5), dict.fromkeys(joints, 0.1),
                 1.0, 1.0, 1.0, thresholds=dict.fromkeys(joints, 1.0))
    assert standing_summary(quiet, lambda j: [j], 3.0) is None
