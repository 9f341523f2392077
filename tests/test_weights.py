"""The scale-free weights (``updating.inverse.weights``, ``docs/updating.md`` section 2): the
balance of each joint's law against the data around it does not change with the size of the
structure, nor with the amplitude of its field."""

from __future__ import annotations

import numpy as np
import pytest

from updating.inverse.weights import SMALLEST_NOISE, scale_free_weights


def _chain(n, energies=None):
    """A chain of n plates and n - 1 joints, each joint between two neighbours."""
    plates = [f"P{i}" for i in range(n)]
    joints = {f"J{i}": (plates[i], plates[i + 1]) for i in range(n - 1)}
    energies = energies or {p: 1.0 + 0.5 * np.sin(i) ** 2 for i, p in enumerate(plates)}
    return joints, energies


def _law_to_data(weights, joints, energies, measured):
    r"""Per joint, the weight of its law per unit of its own plates' energy against the weight
    of one measured value of relative misfit: :math:`(1-r)\alpha_j s_j M / r`, which the rule
    makes :math:`\varepsilon^2\beta a_j/3` (``docs/updating.md`` section 2)."""
    total = sum(energies.values())
    return {j: (1 - weights.r) * weights.alpha[j] * sum(energies[p] for p in plates) / total
            * measured / weights.r for j, plates in joints.items()}


def test_each_joint_has_the_balance_the_rule_states_at_any_size():
    """For chains of 3 and 30 plates (20 values per plate), every joint's law-to-data weight is
    eps^2 beta / 3, to round-off, while r itself falls with the size (it weighs the paper's
    E_Gamma^2, a share of the whole structure's energy)."""
    r_values = []
    for n in (3, 30):
        joints, energies = _chain(n)
        weights = scale_free_weights(joints, [energies], [20 * n], 0.1, 2000.0)
        ratios = _law_to_data(weights, joints, energies, 20 * n)
        np.testing.assert_allclose(list(ratios.values()), 0.1**2 * 2000.0 / 3.0, rtol=1e-12)
        assert sum(weights.alpha.values()) == pytest.approx(1.0)
        r_values.append(weights.r)
    assert r_values[1] < r_values[0]


def test_the_weights_do_not_depend_on_the_field_amplitude():
    """Energies times 1e6 (a load 1000 times larger) give the same r and alpha."""
    joints, energies = _chain(5)
    base = scale_free_weights(joints, [energies], [100], 0.05, 2000.0)
    louder = scale_free_weights(joints, [{p: 1e6 * e for p, e in energies.items()}], [100],
                                0.05, 2000.0)
    assert louder.r == pytest.approx(base.r, rel=1e-12)
    for joint in joints:
        assert louder.alpha[joint] == pytest.approx(base.alpha[joint], rel=1e-12)


def test_noise_below_the_floor_is_taken_at_the_floor():
    joints, energies = _chain(4)
    exact = scale_free_weights(joints, [energies], [80], 0.0, 2000.0)
    floor = scale_free_weights(joints, [energies], [80], SMALLEST_NOISE, 2000.0)
    assert exact.noise == SMALLEST_NOISE and exact.r == floor.r
