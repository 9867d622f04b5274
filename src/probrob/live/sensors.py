r"""Live widgets of the measurement models: Tables 6.4 and 6.5 (landmarks), Table 6.1 (beams).

Holds :func:`landmark_draws` and :func:`landmark_model_live` (kernel ``assets/landmark.js``,
kind "cloud") and :func:`beam_model_live` (kernel ``assets/beam.js``, kind "curve"). Does not
hold the models (:mod:`probrob.sensors`, which the kernels mirror).
"""

from __future__ import annotations

import numpy as np

from .. import _validation as check
from ..distributions import sample_normal_distribution
from .core import LiveWidget, live_widget, slider

__all__ = ["beam_model_live", "landmark_draws", "landmark_model_live"]


def landmark_draws(n=2000, rng=0) -> dict[str, np.ndarray]:
    r"""Return seeded draws for Table 6.5: standardized normals and the ring angle :math:`\hat\gamma`.

    One generator makes ``"normal"`` (shape ``(3, n)``,
    :func:`~probrob.distributions.sample_normal_distribution` with variance 1; rows 0 and 1
    are the range and bearing noise) and then ``"gamma"`` (shape ``(1, n)``,
    :math:`\mathrm{rand}(0, 2\pi)` by ``Generator.uniform``). A generator in that state, passed
    to :func:`~probrob.sensors.sample_landmark_model_known_correspondence`, draws the same
    :math:`\hat\gamma` first.

    Parameters
    ----------
    n : int
        Draws per row (poses).
    rng : None, int or numpy.random.Generator
        Seed.

    Returns
    -------
    draws : dict
        ``{"normal": ndarray (3, n), "gamma": ndarray (1, n)}``.
    """
    n = check.count(n, "n", 1)
    rng = check.rng(rng)
    z = sample_normal_distribution(1.0, size=(3, int(n)), rng=rng)
    return {"normal": z, "gamma": rng.uniform(0.0, 2.0 * np.pi, size=(1, int(n)))}


def _row(value, name, n, what) -> np.ndarray:
    arr = check.finite(value, name)
    if arr.shape != (n,):
        raise ValueError(f"{name} must hold {what}, got shape {arr.shape}")
    return arr


def landmark_model_live(
    *,
    r=2.0,
    phi=0.5,
    s=1.0,
    sigmas=(0.1, 0.05, 0.2),
    theta=0.0,
    landmark=(0.0, 0.0, 1.0),
    n_particles=2000,
    grid=100,
    rng=0,
) -> LiveWidget:
    r"""Return a live widget of the landmark model (Tables 6.4 and 6.5).

    Sliders for the feature :math:`f = (r, \phi, s)`, the standard deviations
    :math:`(\sigma_r, \sigma_\phi, \sigma_s)` and the heading :math:`\theta` at which the
    likelihood is drawn. Red: poses of
    :func:`~probrob.sensors.sample_landmark_model_known_correspondence` (the embedded draws of
    :func:`landmark_draws`); grey:
    :func:`~probrob.sensors.landmark_model_known_correspondence` over :math:`(x, y)` for poses
    with heading :math:`\theta`; blue square: the landmark.

    Parameters
    ----------
    r, phi, s : float
        The feature: range in [0, 5] m, bearing in [-3.14, 3.14] rad, signature in [0, 3].
    sigmas : array_like, shape (3,)
        :math:`(\sigma_r, \sigma_\phi, \sigma_s)`, each in [0, 1].
    theta : float
        Heading of the likelihood image, in [-3.14, 3.14] rad.
    landmark : array_like, shape (3,)
        The landmark :math:`(x, y, s)` the feature corresponds to.
    n_particles, grid, rng
        Poses, likelihood grid points per axis, seed of the draws.

    Returns
    -------
    widget : LiveWidget
    """
    n_particles = check.count(n_particles, "n_particles", 1)
    sigmas = _row(sigmas, "sigmas", 3, "(σ_r, σ_φ, σ_s)")
    landmark = check.vectors(landmark, "landmark", 3, "x, y, s")
    if landmark.shape != (3,):
        raise ValueError(f"landmark must be one row (x, y, s), got shape {landmark.shape}")
    mx, my, ms = landmark
    sliders = [
        slider("r", "r [m]", r, 0.0, 5.0, 0.01),
        slider("phi", "φ [rad]", phi, -3.14, 3.14, 0.01),
        slider("s", "s", s, 0.0, 3.0, 0.01),
        slider("sr", "σr [m]", sigmas[0], 0.0, 1.0, 0.005, what="sigmas[0]"),
        slider("sphi", "σφ [rad]", sigmas[1], 0.0, 1.0, 0.005, what="sigmas[1]"),
        slider("ss", "σs", sigmas[2], 0.0, 1.0, 0.005, what="sigmas[2]"),
        slider("theta", "θ image [rad]", theta, -3.14, 3.14, 0.01),
    ]
    return live_widget(
        "landmark",
        sliders,
        title="Landmark model (Tables 6.4 and 6.5)",
        caption=(
            f"Red: {n_particles} poses of Table 6.5 drawn from the feature (the first 60 with "
            "their heading): a ring around the landmark (blue square). Grey: the likelihood "
            "p(f | x, m) of Table 6.4 over (x, y) for poses with the heading θ of the slider "
            "({darker|lighter} is more likely): the part of the ring from which the landmark is "
            "seen at bearing φ when facing θ. The signature s scales the whole image."
        ),
        aria_label=(
            "Plot of the landmark model in the x-y plane: a ring of sampled poses around the "
            "landmark, over a likelihood image for one heading."
        ),
        draws=landmark_draws(n_particles, rng),
        constants={"mx": mx, "my": my, "ms": ms},
        n_particles=n_particles,
        grid=grid,
        rng=rng,
    )


def beam_model_live(
    *,
    z_star=5.0,
    weights=(0.7, 0.15, 0.05, 0.1),
    sigma_hit=0.2,
    lambda_short=0.6,
    max_range=10.0,
    grid=400,
) -> LiveWidget:
    r"""Return a live widget of the beam model's :math:`p(z \mid z^*)` (Table 6.1, lines 5-6).

    Sliders for the expected range :math:`z^*`, the four mixing weights
    :math:`(z_{hit}, z_{short}, z_{max}, z_{rand})` (the widget divides them by their sum, as
    the title shows), :math:`\sigma_{hit}` and :math:`\lambda_{short}`; the curve is
    :func:`~probrob.sensors.beam_mixture` over :math:`[0, z_{max})` (the point mass at
    :math:`z_{max}` has the weight :math:`z_{max}`). No samples: the library's sampler inverts
    the normal CDF, which the page does not carry.

    Parameters
    ----------
    z_star : float
        Expected range, in [0, max_range].
    weights : array_like, shape (4,)
        Initial mixing weights, each in [0, 1] (normalised by their sum).
    sigma_hit, lambda_short : float
        In [0.01, 1] m and [0.05, 5] 1/m.
    max_range : float
        The sensor's maximum range, m (fixed).
    grid : int
        Points of the curve.

    Returns
    -------
    widget : LiveWidget
    """
    zmax = check.positive_scalar(max_range, "max_range")
    weights = _row(weights, "weights", 4, "(z_hit, z_short, z_max, z_rand)")
    names = ("whit", "wshort", "wmax", "wrand")
    labels = ("z_hit", "z_short", "z_max", "z_rand")
    sliders = [
        slider("zstar", "z* [m]", z_star, 0.0, zmax, 0.01, what="z_star"),
        *(
            slider(n, lab, w, 0.0, 1.0, 0.01, what=f"weights[{k}]")
            for k, (n, lab, w) in enumerate(zip(names, labels, weights, strict=True))
        ),
        slider("sigma", "σ_hit [m]", sigma_hit, 0.01, 1.0, 0.01, what="sigma_hit"),
        slider("lambda", "λ_short [1/m]", lambda_short, 0.05, 5.0, 0.01, what="lambda_short"),
    ]
    return live_widget(
        "beam",
        sliders,
        title="Beam model p(z | z*) (Table 6.1)",
        caption=(
            "Blue: the mixture z_hit p_hit + z_short p_short + z_rand p_rand of Table 6.1 over "
            "[0, z_max), in 1/m; the weights are the sliders divided by their sum. The point "
            "mass z_max at z = z_max is not drawn."
        ),
        aria_label="Plot of the beam model's density of a measured range z given the expected range.",
        draws={},
        constants={"zmax": zmax},
        n_particles=0,
        grid=grid,
    )
