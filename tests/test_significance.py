"""The thresholds at which a joint stands out (``updating.inverse.significance``), against exact
distributions: the Sidak level of independent chi-square joints, and the familywise rate of
right models whose residuals are correlated quadratic forms with long tails."""

import numpy as np
import pytest
from scipy import stats

from updating.inverse.significance import (
    chi_square_quantile,
    chi_square_tail,
    familywise_level,
    scaled_chi_square,
    standing_thresholds,
)


def test_chi_square_tail_and_quantile_are_scipy_stats():
    """The incomplete-gamma forms against ``scipy.stats.chi2`` (to round-off)."""
    x, dof = np.array([0.3, 4.0, 40.0]), np.array([2.0, 5.5, 11.0])
    np.testing.assert_allclose(chi_square_tail(x, dof), stats.chi2.sf(x, dof), rtol=1e-12)
    tail = np.array([0.5, 1e-3, 1e-6])
    np.testing.assert_allclose(chi_square_quantile(tail, dof), stats.chi2.isf(tail, dof),
                               rtol=1e-10)


def test_scaled_chi_square_recovers_scale_and_dof():
    """Draws of g chi2_nu give back g and nu (to their sampling error: 20000 draws, 3 %)."""
    rng = np.random.default_rng(0)
    scale, dof = np.array([0.5, 2e-3]), np.array([3.0, 9.0])
    draws = scale[:, None] * rng.chisquare(dof[:, None], (2, 20000))
    g, nu = scaled_chi_square(draws)
    np.testing.assert_allclose(g, scale, rtol=0.05)
    np.testing.assert_allclose(nu, dof, rtol=0.05)


def test_level_of_independent_chi_square_joints_is_sidaks():
    """For J independent joints with exact chi-square residuals, P(min_j p_j < c) = alpha gives
    c = 1 - (1 - alpha)^(1/J). 4000 draws set the alpha quantile to about 7 % (binomial, 2
    sigma); the moments estimated from the draws add a few per cent: 20 % tolerance."""
    rng = np.random.default_rng(1)
    joints, count, alpha = 40, 4000, 0.05
    dof = rng.uniform(2.0, 12.0, joints)
    scale = 10.0 ** rng.uniform(-4.0, -1.0, joints)
    draws = scale[:, None] * rng.chisquare(dof[:, None], (joints, count))
    expected = 1.0 - (1.0 - alpha) ** (1.0 / joints)
    assert familywise_level(draws, alpha) == pytest.approx(expected, rel=0.2)


def _right_models(rng, joints, count, mixing):
    """``count`` residual sets of a right model: per joint a quadratic form |B z|^2 of shared
    Gaussian noise z, with unequal weights (a long tail no chi-square matches), neighbouring
    joints sharing noise through ``mixing``."""
    noise = rng.standard_normal((count, joints + 8, 6))
    weights = np.array([4.0, 1.0, 0.5, 0.3, 0.2, 0.1])
    forms = np.stack([(mixing * noise[:, j:j + 8].mean(axis=1)
                       + noise[:, j]) ** 2 @ weights for j in range(joints)], axis=1)
    return forms.T  # joints x count


def test_familywise_rate_of_right_models():
    """Over many right models, each with its own draws for the thresholds and one
    independent "measured" set, any joint stands out in about alpha of them (300 models:
    binomial 99 % range of 0.05 is [0.02, 0.09]). A fixed ratio of three to the floor flags
    most of them, and per-joint Bonferroni on the chi-square tail without the calibration
    about twice alpha on these long tails."""
    rng = np.random.default_rng(2)
    joints, models, alpha = 60, 300, 0.05
    flagged = flagged_by_ratio = flagged_by_bonferroni = 0
    for _ in range(models):
        sets = _right_models(rng, joints, 129, mixing=2.0)
        draws, measured = sets[:, :-1], sets[:, -1]
        flagged += np.any(measured > standing_thresholds(draws, alpha))
        flagged_by_ratio += np.any(measured > 3.0 * draws.mean(axis=1))
        scale, dof = scaled_chi_square(draws)
        flagged_by_bonferroni += np.any(
            measured > scale * stats.chi2.isf(alpha / joints, dof))
    assert 0.02 <= flagged / models <= 0.09
    assert flagged_by_ratio / models > 0.5
    assert flagged_by_bonferroni / models > 0.09


def test_a_joint_far_above_its_floor_stands_out_alone():
    """A right model's joints stay below their thresholds and a joint at ten times its floor
    stands out, at 5 % among 60 joints."""
    rng = np.random.default_rng(3)
    sets = _right_models(rng, 60, 130, mixing=2.0)
    draws, measured = sets[:, :-2], sets[:, -1].copy()
    thresholds = standing_thresholds(draws, 0.05)
    measured[17] = 10.0 * draws[17].mean()
    assert np.flatnonzero(measured > thresholds).tolist() == [17]


def test_without_spread_the_threshold_is_the_floor():
    """Noise-free floors (one draw, or identical draws) leave nothing to calibrate: each
    threshold is the joint's mean, and ``stop_ratio`` decides (``updating.inverse.strategy``)."""
    floors = np.array([[1e-4], [3e-6]])
    np.testing.assert_array_equal(standing_thresholds(floors, 0.05), floors[:, 0])
    repeated = np.repeat(floors, 5, axis=1)
    np.testing.assert_allclose(standing_thresholds(repeated, 0.05), floors[:, 0], rtol=1e-12)


def test_a_right_model_has_no_joint_standing_out():
    """A 3 x 3 grid measured on itself (its simulated experiment, +-10 % noise): with
    ``stop_ratio`` just above 1 the calibrated thresholds alone decide, and no joint stands
    out, where a ratio to the floor flags several of the 12 (residuals spread around their
    floors)."""
    from assembly import parse_case
    from assembly.generate import plate_grid
    from updating.data.measurements import simulate_measurements
    from updating.inverse.cost import ModifiedProblem
    from updating.inverse.strategy import localise, thresholds

    description = plate_grid(3, 3, frequency=150.0)
    description["updating"] = {**description["updating"], "stop_ratio": 1.01}
    case = parse_case(description)
    problem = ModifiedProblem(case, simulate_measurements(case))
    step = localise(problem, problem.initial_parameters(), noise=case.measurement.noise)
    limits = thresholds(step, case.updating.stop_ratio)
    assert not [j for j in step.residuals if step.residuals[j] > limits[j]]
    assert sum(step.residuals[j] > 1.01 * step.floors[j] for j in step.residuals) >= 2
