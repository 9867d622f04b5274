r"""Live widget of Trabalho 5's EKF step: one step of Table 7.2 with its covariance ellipses.

Holds :func:`ekf_step_live` (kernel ``assets/ekf.js``, kind "scene"). Does not hold the filter
(:mod:`probrob.localization`, which the kernel mirrors, with :mod:`probrob.motion`'s Jacobians,
:mod:`probrob.sensors`' h and :func:`probrob.evaluation.covariance_ellipse`).
"""

from __future__ import annotations

from .. import _validation as check
from .core import LiveWidget, alpha_sliders, live_widget, slider

__all__ = ["ekf_step_live"]


def _vector(value, name, n, what):
    arr = check.finite(value, name)
    if arr.shape != (n,):
        raise ValueError(f"{name} must hold {n} values ({what}), got shape {arr.shape}")
    return arr


def _ekf_sliders(mu, prior_std, u, alpha, sigmas, landmark, innovation):
    """The sliders of the step: prior, control, noise, landmark, sensor, measurement."""
    return [
        slider("x0", "μ x [m]", mu[0], -3.0, 3.0, 0.01, what="mu[0]"),
        slider("y0", "μ y [m]", mu[1], -3.0, 3.0, 0.01, what="mu[1]"),
        slider("th0", "μ θ [rad]", mu[2], -3.14, 3.14, 0.01, what="mu[2]"),
        slider("sx", "σx prior [m]", prior_std[0], 0.01, 1.0, 0.005, what="prior_std[0]"),
        slider("sy", "σy prior [m]", prior_std[1], 0.01, 1.0, 0.005, what="prior_std[1]"),
        slider("sth", "σθ prior [rad]", prior_std[2], 0.01, 1.0, 0.005, what="prior_std[2]"),
        slider("v", "v [m/s]", u[0], -2.0, 2.0, 0.01, what="u[0]"),
        slider("w", "ω [rad/s]", u[1], -2.0, 2.0, 0.01, what="u[1]"),
        *alpha_sliders(alpha, 4),
        slider("mx", "landmark x [m]", landmark[0], -5.0, 5.0, 0.01, what="landmark[0]"),
        slider("my", "landmark y [m]", landmark[1], -5.0, 5.0, 0.01, what="landmark[1]"),
        slider("sr", "σr [m]", sigmas[0], 0.01, 1.0, 0.005, what="sigmas[0]"),
        slider("sphi", "σφ [rad]", sigmas[1], 0.005, 0.5, 0.005, what="sigmas[1]"),
        slider("dr", "z_r − r̂ [m]", innovation[0], -1.0, 1.0, 0.01, what="innovation[0]"),
        slider("dphi", "z_φ − φ̂ [rad]", innovation[1], -0.5, 0.5, 0.005, what="innovation[1]"),
    ]


def ekf_step_live(
    *,
    mu=(0.0, 0.0, 0.0),
    prior_std=(0.15, 0.3, 0.1),
    u=(1.0, 0.4),
    dt=1.0,
    alpha=(0.05, 0.01, 0.01, 0.05),
    sigmas=(0.1, 0.05),
    landmark=(2.5, 1.5),
    innovation=(0.15, -0.04),
    p=0.95,
) -> LiveWidget:
    r"""Return a live widget of one step of EKF localization with known correspondences (Table 7.2).

    Sliders for the prior :math:`\mu_{t-1} = (x, y, \theta)` and its standard deviations
    (:math:`\Sigma_{t-1} = \mathrm{diag}(\sigma_x^2, \sigma_y^2, \sigma_\theta^2)`), the control
    :math:`u_t = (v, \omega)`, :math:`\alpha_1 \ldots \alpha_4` (the variances of
    :math:`M_t`), the landmark :math:`m_j = (m_{j,x}, m_{j,y})`, :math:`\sigma_r, \sigma_\phi`
    and the measurement, given as its difference from the prediction: the page measures
    :math:`z = (\max(0, \hat r + \Delta r),\ \mathrm{wrap}(\hat\phi + \Delta\phi))` with
    :math:`\hat z = (\hat r, \hat\phi) = h(\bar\mu_t, m_j)`. It computes the step as
    :func:`~probrob.localization.ekf_localization_known_correspondences` does (lines 2–7: the
    velocity model's :math:`g, G_t, V_t, M_t`; lines 11–21 for the one range–bearing feature:
    :math:`\hat z, H, S, K`, :math:`\mu_t, \Sigma_t` and :math:`\log p(z_t)`) and draws the
    ``p``-probability ellipses of :func:`~probrob.evaluation.covariance_ellipse` of the prior,
    the prediction and the posterior, their means with their headings, the landmark and the
    measured point. ``tests/test_live_widgets_t5.py`` holds the page's numbers equal to the
    library's in Chromium.

    Parameters
    ----------
    mu : array_like, shape (3,)
        Prior mean: x, y in [-3, 3] m, θ in [-3.14, 3.14] rad.
    prior_std : array_like, shape (3,)
        :math:`(\sigma_x, \sigma_y)` in [0.01, 1] m and :math:`\sigma_\theta` in [0.01, 1] rad.
    u : array_like, shape (2,)
        :math:`(v, \omega)`, each in [-2, 2] (m/s, rad/s).
    dt : float
        The step's :math:`\Delta t` in (0, 3] s (fixed, not a slider).
    alpha : array_like, shape (4,)
        :math:`\alpha_1 \ldots \alpha_4`, each in [0, 0.5].
    sigmas : array_like, shape (2,)
        :math:`\sigma_r` in [0.01, 1] m, :math:`\sigma_\phi` in [0.005, 0.5] rad.
    landmark : array_like, shape (2,)
        The landmark's position, each coordinate in [-5, 5] m.
    innovation : array_like, shape (2,)
        :math:`(\Delta r, \Delta\phi)`: :math:`\Delta r` in [-1, 1] m, :math:`\Delta\phi` in
        [-0.5, 0.5] rad.
    p : float
        Probability of the ellipses, in (0, 1).

    Returns
    -------
    widget : LiveWidget
    """
    mu = _vector(mu, "mu", 3, "x, y, theta")
    prior_std = _vector(prior_std, "prior_std", 3, "sigma_x, sigma_y, sigma_theta")
    u = _vector(u, "u", 2, "v, omega")
    dt = check.in_range(check.positive_scalar(dt, "dt"), "dt", 0.0, 3.0)
    sigmas = _vector(sigmas, "sigmas", 2, "sigma_r, sigma_phi")
    landmark = _vector(landmark, "landmark", 2, "x, y")
    innovation = _vector(innovation, "innovation", 2, "delta_r, delta_phi")
    p = check.finite(p, "p")
    if p.ndim != 0 or not 0.0 < p < 1.0:
        raise ValueError(f"p must be a probability in (0, 1), got {p!r}")
    sliders = _ekf_sliders(mu, prior_std, u, alpha, sigmas, landmark, innovation)
    pct = f"{100 * float(p):g} %"
    return live_widget(
        "ekf",
        sliders,
        title="One EKF localization step (Table 7.2)",
        caption=(
            f"The {pct} position ellipses (covariance_ellipse) of the prior μ, Σ (grey, "
            "dashed), of the prediction μ̄, Σ̄ after the control u with the velocity model's "
            "noise M (orange, lines 2–7) and of the posterior after one range–bearing "
            "measurement of the landmark ({black|white} square) (blue, lines 8–20); dots with "
            "ticks: the means and their headings. Thin dotted line: the line of sight from μ̄ to "
            "the landmark, the prediction ẑ = (r̂, φ̂); red dashed line and ×: the measurement z "
            "= ẑ + (z_r − r̂, z_φ − φ̂) seen from μ̄. Beside the plot (below it on a narrow "
            f"page): ẑ, z, the wrapped innovation ν and log p(z) of line 21. Δt = {float(dt):g} "
            "s. The view grows with the ellipses; “fit view” zooms back in."
        ),
        aria_label=(
            "Plot in the x-y plane of one EKF localization step: the prior, predicted and "
            f"posterior {pct} covariance ellipses with their means and headings, a landmark, "
            "and the measured range and bearing drawn from the predicted mean."
        ),
        draws={},
        constants={"dt": float(dt), "p": float(p)},
        n_particles=0,
        width=620,
        height=500,
    )
