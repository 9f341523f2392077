r"""Weights of the modified error that do not depend on the size of the structure.

The modified error of the paper, :math:`E_{mod}^2 = (1-r)\sum_j\alpha_jE_{\Gamma_j}^2 + rE_{mes}^2`
with :math:`\alpha_j = 1/N_J` and :math:`E_{\Gamma_j}^2 = e_j^2/E_{ref}` (:math:`e_j^2` the
joint's constitutive-relation error in energy, :math:`E_{ref}` the energy of the whole
structure), weighs each joint's law by :math:`(1-r)/(N_JE_{ref})` against data weighed by
:math:`r/\|\tilde u\|^2`. Both denominators grow with the structure, at different rates: on a
grid of P plates :math:`N_JE_{ref}` grows as :math:`P^2` and :math:`\|\tilde u\|^2` as P, so a
joint's law weighs P times less against the data around it on 100 plates than on one (45 times
less on the 10 x 10 grid than on four plates at r = 0.8). The modified field then follows the
noisy data near every joint, right ones included, and a wrong joint no longer stands out of
the noise: the dilution measured in ``bench/bench_power.py``.

Scale-free weights (``docs/updating.md``, section 2) make the balance at each joint local. The
minimised cost is, up to a constant factor,

.. math::
    J = \beta\sum_j a_j\frac{e_j^2}{E_j}
        + \sum_p\frac{\|\Pi_pu - \tilde u_p\|^2}{\sigma_p^2},\qquad
    \sigma_p^2 = \frac{\varepsilon^2}{3}\frac{\|\tilde u_p\|^2}{m_p},

with :math:`E_j` the energy of the joint's own plates (twice their kinetic energy in the
model's response at p0), :math:`\sigma_p^2` the variance of one value of plate p under the
stated uniform relative noise :math:`\pm\varepsilon` (:math:`m_p` values), :math:`a_j` the
relative joint weights (``[updating] alpha``, 1 by default) and :math:`\beta` the
dimensionless ``[updating] balance``. The weight of joint j's law against plate p's data,
:math:`\beta a_j\varepsilon^2\|\tilde u_p\|^2/(3m_pE_j)`, involves only the joint's own plates:
it is the same in a 2 x 2 and a 20 x 20 grid, near the load or far from it (field amplitudes
cancel). Both terms are sums over the structure, like a log-likelihood: each joint is judged by
the data around it.

In the paper's form this is :math:`r` and :math:`\alpha_j` (the residual :math:`E_{\Gamma_j}^2`
shown and ranked stays the paper's): with :math:`s_j = E_j/E_{ref}` the joint's share of the
reference energy, :math:`M` the measured values per frequency and :math:`E_{mes}^2` the
point-weighted per-plate misfit (:func:`updating.inverse.problem_data._norms`),

.. math::
    \alpha_j = \frac{a_j/s_j}{\sum_k a_k/s_k},\qquad
    \frac{1-r}{r} = \frac{\varepsilon^2\beta}{3M}\sum_k\frac{a_k}{s_k}.

The :math:`r` so obtained falls with the size of the structure (each :math:`E_{\Gamma}^2` is a
share of the whole structure's energy): it is the paper's fixed :math:`r` that diluted.

:math:`\beta` weighs the joint law as a prior weighs a parameter against data of variance
:math:`\sigma^2` (maximum a posteriori): more noise, more weight to the law. Below
:data:`SMALLEST_NOISE` the noise is taken at that level: noise-free data would weigh the law
to nothing, and plates without data would be left undetermined.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["ScaleFreeWeights", "scale_free_weights", "SMALLEST_NOISE"]

SMALLEST_NOISE = 0.01
"""Relative noise below which the weights take it at this level (a measured field is rarely
known better than to 1 %, and the model's discretisation error is of that order at the
resolutions the updating uses)."""


@dataclass(frozen=True)
class ScaleFreeWeights:
    """The paper's ``r`` and ``alpha`` that make the balance local (module docstring), and
    what they came from."""

    r: float
    alpha: dict  # joint -> alpha_j, sum 1
    energy_shares: dict  # joint -> s_j = E_j / E_ref, mean over the frequencies
    noise: float  # the relative noise the data are weighed by
    balance: float  # beta

    def describe(self) -> str:
        """One line for the reports."""
        return (f"scale-free weights: balance {self.balance:g} at ±{100 * self.noise:.3g} % "
                f"noise, r = {self.r:.3g}")


def scale_free_weights(joint_plates: Mapping[str, Sequence[str]],
                       plate_energies: Sequence[Mapping[str, float]],
                       measured_values: Sequence[int], noise: float, balance: float,
                       relative: Mapping[str, float] | None = None) -> ScaleFreeWeights:
    r"""The scale-free ``r`` and ``alpha`` (module docstring).

    Parameters
    ----------
    joint_plates : mapping of str to sequence of str
        Each updatable joint's plates (a junction member's: every plate of its line).
    plate_energies : sequence of mapping of str to float
        Per frequency, each plate's energy in the model's response at p0 (J).
    measured_values : sequence of int
        Per frequency, the number of measured values :math:`M`.
    noise : float
        Stated relative noise :math:`\varepsilon` (uniform half-width); taken at least
        :data:`SMALLEST_NOISE`.
    balance : float
        :math:`\beta`.
    relative : mapping of str to float, optional
        Relative joint weights :math:`\alpha` of the description (sum 1; default equal).
    """
    joints = list(joint_plates)
    shares = np.zeros(len(joints))
    for energies in plate_energies:
        total = sum(energies.values())
        shares += [sum(energies[p] for p in joint_plates[j]) / total for j in joints]
    shares /= len(plate_energies)
    # a joint between plates the load does not reach: its share is held at a round-off level
    # of the largest, so that its weight stays finite
    shares = np.maximum(shares, 1e-12 * shares.max())
    relative = relative or dict.fromkeys(joints, 1.0 / len(joints))
    a = np.array([relative[j] for j in joints]) * len(joints)
    inverse = a / shares
    epsilon = max(noise, SMALLEST_NOISE)
    points = float(np.mean(measured_values))
    ratio = epsilon**2 * balance * float(inverse.sum()) / (3.0 * points)  # (1 - r) / r
    return ScaleFreeWeights(1.0 / (1.0 + ratio), dict(zip(joints, inverse / inverse.sum())),
                            dict(zip(joints, shares)), epsilon, balance)
