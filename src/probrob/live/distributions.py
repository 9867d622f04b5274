r"""Live widget of Table 5.2 and the standardized draws every sampling widget embeds.

Holds :func:`standard_draws` (the seeded draws of Table 5.4's samplers, variance 1, which the
motion widgets rescale) and :func:`distribution_live` (kernel ``assets/distribution.js``, the
smallest widget: a kernel file and this spec). Does not hold the densities and samplers
themselves (:mod:`probrob.distributions`).
"""

from __future__ import annotations

import numpy as np

from .. import _validation as check
from ..distributions import sample_normal_distribution, sample_triangular_distribution
from .core import Choice, live_widget, slider

__all__ = ["DISTRIBUTIONS", "distribution_choice", "distribution_live", "standard_draws"]

#: The noise distributions of the live widgets: the value of the ``distribution`` choice,
#: the label shown, and the standardized sampler (variance 1) of Table 5.4.
DISTRIBUTIONS = {
    "normal": ("normal (sum of 12 uniforms)", sample_normal_distribution),
    "triangular": ("triangular", sample_triangular_distribution),
}


def standard_draws(n=2000, rng=0) -> dict[str, np.ndarray]:
    r"""Return seeded standardized draws, shape ``(3, n)``, of each noise distribution.

    Row ``k`` holds the draws of the ``k``-th noise term of a motion sampler (Tables 5.3 and
    5.6 draw three per particle). They are :func:`~probrob.distributions.sample_normal_distribution`
    (the book's sum of twelve uniforms) and
    :func:`~probrob.distributions.sample_triangular_distribution` with variance 1, so the
    sampler's draw for a variance :math:`b^2` is :math:`\sqrt{b^2}\,z`.

    Parameters
    ----------
    n : int
        Draws per row (particles).
    rng : None, int or numpy.random.Generator
        Seed; one generator serves both distributions, normal first.

    Returns
    -------
    draws : dict
        ``{"normal": ndarray (3, n), "triangular": ndarray (3, n)}``.
    """
    n = check.count(n, "n", 1)
    rng = check.rng(rng)
    return {
        name: sampler(1.0, size=(3, int(n)), rng=rng)
        for name, (_, sampler) in DISTRIBUTIONS.items()
    }


def distribution_choice(value) -> Choice:
    """The ``distribution`` choice: which draws and which density of Table 5.2 a widget uses."""
    check.choice(value, "distribution", tuple(DISTRIBUTIONS))
    options = tuple((k, label) for k, (label, _) in DISTRIBUTIONS.items())
    return Choice("distribution", "distribution", options, value)


def distribution_live(*, b2=1.0, distribution="normal", n_particles=2000, grid=200, rng=0):
    r"""Return a live widget of the zero-mean densities of Table 5.2 and their samplers.

    A slider for the variance :math:`b^2` and a choice of distribution; the curve is
    :func:`~probrob.distributions.prob_normal_distribution` or
    :func:`~probrob.distributions.prob_triangular_distribution` over :math:`\pm 4.5\,b`, the
    histogram is the embedded standardized draws of :func:`standard_draws` times :math:`b`
    (Table 5.4's samplers). The smallest widget of ``kind: "curve"``.

    Parameters
    ----------
    b2 : float
        Initial variance, in [0.01, 4].
    distribution : {"normal", "triangular"}
    n_particles, grid, rng
        Samples, curve points, seed of the draws.

    Returns
    -------
    widget : LiveWidget
    """
    choice = distribution_choice(distribution)
    return live_widget(
        "distribution",
        [slider("b2", "b² (variance)", b2, 0.01, 4.0, 0.01)],
        [choice],
        title="Noise distributions (Tables 5.2 and 5.4)",
        caption=(
            f"Blue: the density of Table 5.2 with variance b²; red: a histogram of {n_particles} "
            "samples of Table 5.4, the same standardized draws times b."
        ),
        aria_label="Plot of a zero-mean noise density against a, over a histogram of its samples.",
        n_particles=n_particles,
        grid=grid,
        rng=rng,
    )
