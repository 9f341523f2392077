r"""When a joint's residual stands out of noise and discretisation: thresholds calibrated over
the whole structure.

A right model's residuals are not their floors: each joint's :math:`E_\Gamma^2` under noise is
a quadratic form in the noisy data, spread around its mean (the floor) with a few degrees of
freedom, and among hundreds of joints some stand several times above their floors by noise
alone (on the 10 x 10 grid with right joints, four of 180 exceed three times theirs). A fixed
ratio to the floor therefore flags right joints the more of them there are, and lets a
correction loop chase noise. The thresholds here are set so that a right model shows *any*
joint above its threshold with probability ``significance`` (familywise), whatever the number
of joints, from draws of synthetic experiments on the model itself
(:meth:`updating.inverse.cost.ModifiedProblem.floor_draws`):

* **Per joint, a scaled chi-square** matching the mean :math:`m_j` and variance :math:`s_j^2`
  of its draws (Satterthwaite): :math:`E_{\Gamma_j}^2 \approx g_j\chi^2_{\nu_j}` with
  :math:`g_j = s_j^2/(2m_j)`, :math:`\nu_j = 2m_j^2/s_j^2`; its upper-tail probability
  :math:`p_j(x) = P(\chi^2_{\nu_j} > x/g_j)` puts the joints on one scale (a joint whose
  residual has few degrees of freedom has a long tail, one with many a short one).
* **Familywise calibration** (in the manner of Westfall and Young's minimum-p adjustment): in
  each draw :math:`k`, the smallest :math:`p_j` over the joints, each from the moments of the
  *other* draws (as the measured residual is not among the draws that set its moments);
  :math:`c` is the ``significance`` quantile of those minima. The chi-square tail is only an
  approximation (on the 10 x 10 grid its Bonferroni level is four times too liberal), and the
  joints' residuals are correlated through the plates they share: both are absorbed by
  calibrating on the draws themselves.
* **Threshold** of joint :math:`j`: :math:`t_j = g_j\,\chi^{2\,-1}_{\nu_j}(1 - c)`, the
  residual whose tail probability is :math:`c`. A joint stands out when
  :math:`E_{\Gamma_j}^2 > t_j`.

With :math:`K` draws the familywise level is reached within about
:math:`\sqrt{\alpha(1-\alpha)/K}` (0.02 at 128 draws and 5 %).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from scipy import special

if TYPE_CHECKING:
    import numpy.typing as npt

__all__ = ["FLOOR_DRAWS", "scaled_chi_square", "chi_square_tail", "chi_square_quantile",
           "familywise_level", "standing_thresholds"]

FLOOR_DRAWS = 128
"""Synthetic experiments behind the floors and thresholds of one localisation: they share one
factorisation, and their residuals are evaluated for all draws at once (10 x 10 grid: 128
draws 1.7 s against 1.2 s for 4, the factorisation included)."""


def scaled_chi_square(draws: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    r"""Per row of ``draws`` (one joint, one column per draw), the scale and degrees of freedom
    of the chi-square matching its mean and variance: :math:`g = s^2/(2m)`,
    :math:`\nu = 2m^2/s^2`. Rows without spread (no noise) have :math:`g = 0`,
    :math:`\nu = \infty`."""
    draws = np.asarray(draws, dtype=float)
    mean = draws.mean(axis=1)
    variance = draws.var(axis=1, ddof=1)
    return _scale_and_dof(mean, variance)


def _scale_and_dof(mean: np.ndarray, variance: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    with np.errstate(divide="ignore", invalid="ignore"):
        spread = (variance > 0) & (mean > 0)
        scale = np.where(spread, variance / (2.0 * mean), 0.0)
        dof = np.where(spread, 2.0 * mean**2 / variance, np.inf)
    return scale, dof


def _tail(values: np.ndarray, scale: np.ndarray, dof: np.ndarray) -> np.ndarray:
    """:math:`P(g\\chi^2_\\nu > x)`; 1 where the joint has no spread (never stands out by the
    tail: its threshold is its floor)."""
    spread = scale > 0
    out = np.ones(values.shape)
    out[spread] = chi_square_tail(values[spread] / scale[spread], dof[spread])
    return out


def chi_square_tail(x: np.ndarray, dof: np.ndarray) -> np.ndarray:
    r""":math:`P(\chi^2_\nu > x) = Q(\nu/2, x/2)`, the regularised upper incomplete gamma
    function (``scipy.stats`` would cost a third of a second to import)."""
    return special.gammaincc(dof / 2.0, x / 2.0)


def chi_square_quantile(tail: float | np.ndarray, dof: np.ndarray) -> np.ndarray:
    r"""The :math:`x` with :math:`P(\chi^2_\nu > x) =` ``tail``: :math:`2\,Q^{-1}(\nu/2, tail)`."""
    return 2.0 * special.gammainccinv(dof / 2.0, tail)


def familywise_level(draws: npt.ArrayLike, significance: float) -> float:
    r"""The per-joint tail probability :math:`c` below which, in a fraction ``significance`` of
    the draws, at least one joint falls: the ``significance`` quantile over the draws of
    :math:`\min_j p_j(x_{jk})`, each :math:`p_j` from the moments of the other draws
    (leave-one-out)."""
    draws = np.asarray(draws, dtype=float)
    count = draws.shape[1]
    total = draws.sum(axis=1, keepdims=True)
    squares = (draws**2).sum(axis=1, keepdims=True)
    mean = (total - draws) / (count - 1)
    variance = np.maximum(squares - draws**2 - (count - 1) * mean**2, 0.0) / (count - 2)
    scale, dof = _scale_and_dof(mean, variance)
    smallest = np.sort(_tail(draws, scale, dof).min(axis=0))
    # floor(alpha K) draws lie below the level: a fraction of at most alpha
    return float(smallest[int(np.floor(significance * count))])


def standing_thresholds(draws: npt.ArrayLike, significance: float) -> np.ndarray:
    r"""Per joint (rows of ``draws``, a right model's residuals in columns of synthetic
    experiments), the residual :math:`t_j = g_j\chi^{2\,-1}_{\nu_j}(1 - c)` above which it
    stands out at familywise level ``significance`` (module docstring). With fewer than three
    draws (no noise: the floor is deterministic) there is nothing to calibrate and each
    threshold is the joint's mean."""
    draws = np.asarray(draws, dtype=float)
    mean = draws.mean(axis=1)
    if draws.shape[1] < 3:
        return mean
    level = familywise_level(draws, significance)
    scale, dof = scaled_chi_square(draws)
    spread = scale > 0
    thresholds = mean.copy()
    thresholds[spread] = scale[spread] * chi_square_quantile(level, dof[spread])
    return thresholds
