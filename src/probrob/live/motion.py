r"""Live widgets of the motion models: Tables 5.1 and 5.3 (velocity), 5.5 and 5.6 (odometry).

Holds :func:`velocity_model_live`, :func:`odometry_model_live` (kernels ``assets/velocity.js``
and ``assets/odometry.js``, kind "cloud") and the Turkish lecture's two noise forms side by
side, :func:`velocity_noise_forms_live` and :func:`odometry_noise_forms_live` (the same kernels
drawn twice by ``assets/noise_forms.js``). Does not hold the models (:mod:`probrob.motion`,
which the kernels mirror and the parity tests hold them to).
"""

from __future__ import annotations

from .. import _validation as check
from .core import Choice, LiveWidget, alpha_sliders, live_widget, slider
from .distributions import distribution_choice

__all__ = [
    "odometry_model_live",
    "odometry_noise_forms_live",
    "velocity_model_live",
    "velocity_noise_forms_live",
]

NOISE_FORMS = (("variance", "α·m² is a variance"), ("std", "α·|m| is a std"))
DENSITY_MODES = (
    ("xy", "over (x′, y′), θ′ integrated out"),
    ("pose", "over (x′, y′, θ′) at the blue arrow's θ′"),
    ("book", "the table's value at the blue arrow's θ′"),
)
#: How the variance form's α relate to the sliders' (the standard-deviation form's) α.
PAIRINGS = (
    ("squared", "variance form at α²: the same noise for one term"),
    ("same", "variance form at the same α"),
)


def _choice(name, label, options, value) -> Choice:
    check.choice(value, name, tuple(v for v, _ in options))
    return Choice(name, label, options, value)


def _velocity_sliders(v, w, dt, theta, alpha):
    return [
        slider("v", "v [m/s]", v, -2.0, 2.0, 0.01),
        slider("w", "ω [rad/s]", w, -2.0, 2.0, 0.01),
        slider("dt", "Δt [s]", dt, 0.1, 3.0, 0.01),
        slider("theta", "θ start [rad]", theta, -3.14, 3.14, 0.01),
        *alpha_sliders(alpha, 6),
    ]


def _odometry_sliders(rot1, trans, rot2, theta, alpha):
    return [
        slider("rot1", "δrot1 [rad]", rot1, -3.14, 3.14, 0.01),
        slider("trans", "δtrans [m]", trans, 0.0, 3.0, 0.01),
        slider("rot2", "δrot2 [rad]", rot2, -3.14, 3.14, 0.01),
        slider("theta", "θ start [rad]", theta, -3.14, 3.14, 0.01),
        *alpha_sliders(alpha, 4),
    ]


def _model_widget(model, sliders, distribution, noise, density, n_particles, grid, rng):
    """The widget of ``model``'s kernel ("velocity" or "odometry") in one noise form."""
    tables = {"velocity": ("5.1", "5.3"), "odometry": ("5.5", "5.6")}[model]
    distribution = distribution_choice(distribution)
    choices = [
        _choice("noise", "noise form", NOISE_FORMS, noise),
        distribution,
        _choice("density", "density", DENSITY_MODES, density),
    ]
    return live_widget(
        model,
        sliders,
        choices,
        title=f"{model.capitalize()} motion model (Tables {tables[0]} and {tables[1]})",
        caption=(
            f"Red: {n_particles} samples of Table {tables[1]} (the first 60 with their heading); "
            f"grey: the density of Table {tables[0]} on a {grid} × {grid} grid ({{darker|lighter}} "
            "is more probable); {black|white} arrow: the start pose; blue arrow: the noise-free "
            "end pose. The view grows with the cloud; “fit view” zooms back in."
        ),
        aria_label=(
            f"Plot of the {model} motion model in the x-y plane: a cloud of sampled end poses "
            "over a density image, with the start pose and the noise-free end pose."
        ),
        n_particles=n_particles,
        grid=grid,
        rng=rng,
    )


def velocity_model_live(
    *,
    v=1.0,
    w=0.8,
    dt=1.0,
    theta=0.0,
    alpha=(0.02, 0.02, 0.02, 0.02, 0.01, 0.01),
    distribution="normal",
    noise="variance",
    density="xy",
    n_particles=2000,
    grid=100,
    rng=0,
) -> LiveWidget:
    r"""Return a live widget of the velocity motion model (Tables 5.1 and 5.3).

    Sliders for :math:`v` (m/s), :math:`\omega` (rad/s), :math:`\Delta t` (s), the start
    heading :math:`\theta` (rad) and :math:`\alpha_1 \ldots \alpha_6`; choices for the noise
    form, the distribution and the density shown: ``"xy"`` (heading integrated out, as the
    chapter's figures), or ``"pose"`` / ``"book"`` (see
    :func:`~probrob.motion.motion_model_velocity`) at the noise-free end heading. The robot
    starts at the origin. The cloud is :func:`~probrob.motion.sample_motion_model_velocity`
    with the embedded draws of :func:`~probrob.live.distributions.standard_draws`.

    Parameters
    ----------
    v, w, dt, theta : float
        Initial slider values (ranges: v, ω in [-2, 2], Δt in [0.1, 3], θ in [-3.14, 3.14]).
    alpha : array_like, shape (6,)
        Initial noise parameters, each in [0, 0.5].
    distribution : {"normal", "triangular"}
    noise : {"variance", "std"}
    density : {"xy", "pose", "book"}
    n_particles, grid, rng
        Particles, density grid points per axis, seed of the draws.

    Returns
    -------
    widget : LiveWidget
        Display it as the last expression of a cell.
    """
    sliders = _velocity_sliders(v, w, dt, theta, alpha)
    return _model_widget("velocity", sliders, distribution, noise, density, n_particles, grid, rng)


def odometry_model_live(
    *,
    rot1=0.6,
    trans=1.0,
    rot2=-0.4,
    theta=0.0,
    alpha=(0.05, 0.005, 0.05, 0.005),
    distribution="normal",
    noise="variance",
    density="xy",
    n_particles=2000,
    grid=100,
    rng=0,
) -> LiveWidget:
    r"""Return a live widget of the odometry motion model (Tables 5.5 and 5.6).

    Sliders for the odometry's motion :math:`\delta_{rot1}, \delta_{trans}, \delta_{rot2}`
    (the odometry poses are the origin and the pose this motion reaches from it), the
    robot's start heading :math:`\theta` and :math:`\alpha_1 \ldots \alpha_4`; the same
    choices as :func:`velocity_model_live`. The robot starts at the origin.

    Parameters
    ----------
    rot1, trans, rot2, theta : float
        Initial slider values (rotations in [-3.14, 3.14] rad, translation in [0, 3] m).
    alpha : array_like, shape (4,)
        Initial noise parameters, each in [0, 0.5].
    distribution, noise, density, n_particles, grid, rng
        As for :func:`velocity_model_live`.

    Returns
    -------
    widget : LiveWidget
    """
    sliders = _odometry_sliders(rot1, trans, rot2, theta, alpha)
    return _model_widget("odometry", sliders, distribution, noise, density, n_particles, grid, rng)


def _noise_forms_widget(model, sliders, distribution, density, pairing, n_particles, grid, rng):
    """The two-panel widget of ``model``'s kernel ("velocity" or "odometry") in both noise forms."""
    tables = {"velocity": "5.1 and 5.3", "odometry": "5.5 and 5.6"}[model]
    distribution = distribution_choice(distribution)
    density = _choice("density", "density", DENSITY_MODES, density)
    choices = [_choice("pairing", "variance form", PAIRINGS, pairing), distribution, density]
    return live_widget(
        f"{model}_forms",
        sliders,
        choices,
        title=f"{model.capitalize()} model, the two noise forms (Tables {tables})",
        caption=(
            'Left (above on a narrow page): noise="std", each noise term\'s standard deviation '
            'is a sum α·|m| + …; right (below): noise="variance", each variance is a sum '
            "α·m² + … (with α² by default, so that a sum of one term is the same noise in both). "
            f"Red: {n_particles} samples from the same draws (the first 60 with their heading); "
            f"grey: the density on a {grid} × {grid} grid, one scale for both ({{darker|lighter}} "
            "is more probable); {black|white} arrow: the start pose; blue arrow: the noise-free "
            "end pose. The view grows with the clouds; “fit view” zooms back in."
        ),
        aria_label=(
            f"Two plots of the {model} motion model in the x-y plane: the standard-deviation "
            "noise form and the variance form, each a cloud of sampled end poses over a density "
            "image."
        ),
        n_particles=n_particles,
        grid=grid,
        rng=rng,
        width=660,
        height=430,
        requires=(model, "noise_forms"),
    )


def velocity_noise_forms_live(
    *,
    v=1.0,
    w=0.8,
    dt=1.0,
    theta=0.0,
    alpha=(0.1, 0.1, 0.1, 0.1, 0.05, 0.05),
    pairing="squared",
    distribution="normal",
    density="xy",
    n_particles=1000,
    grid=70,
    rng=0,
) -> LiveWidget:
    r"""Return a live widget of the velocity model's two noise forms side by side (Tables 5.1, 5.3).

    The Turkish lecture gives the noise of :math:`\hat v, \hat\omega, \hat\gamma` as a standard
    deviation :math:`\alpha_1|v| + \alpha_2|\omega|` (``noise="std"``, left panel) and, on its
    *veya* slide, as a variance :math:`\alpha_1 v^2 + \alpha_2\omega^2` (``noise="variance"``,
    right panel). Both panels are :func:`velocity_model_live`'s kernel fed the same draws
    (:func:`~probrob.live.distributions.standard_draws`), the left one at the sliders'
    :math:`\alpha`, the right one at :math:`\alpha^2` (``pairing="squared"``: a sum of one term
    is then the same noise in both) or at the same :math:`\alpha` (``pairing="same"``). On a
    page too narrow for two plots of 250 CSS px side by side, the panels stack. Sliders and the
    other choices as :func:`velocity_model_live`.

    Parameters
    ----------
    v, w, dt, theta, distribution, density
        As for :func:`velocity_model_live`.
    alpha : array_like, shape (6,)
        Initial noise parameters of the standard-deviation form, each in [0, 0.5].
    pairing : {"squared", "same"}
    n_particles, grid, rng
        Particles per panel, density grid points per axis, seed of the draws. The defaults
        (1000 and 70, two panels) cost an update what :func:`velocity_model_live`'s 2000
        particles and 100 × 100 grid cost.

    Returns
    -------
    widget : LiveWidget
    """
    sliders = _velocity_sliders(v, w, dt, theta, alpha)
    return _noise_forms_widget(
        "velocity", sliders, distribution, density, pairing, n_particles, grid, rng
    )


def odometry_noise_forms_live(
    *,
    rot1=0.6,
    trans=1.0,
    rot2=-0.4,
    theta=0.0,
    alpha=(0.2, 0.1, 0.2, 0.1),
    pairing="squared",
    distribution="normal",
    density="xy",
    n_particles=1000,
    grid=70,
    rng=0,
) -> LiveWidget:
    r"""Return a live widget of the odometry model's two noise forms side by side (Tables 5.5, 5.6).

    As :func:`velocity_noise_forms_live` for :func:`odometry_model_live`'s kernel: the noise
    of :math:`\hat\delta_{rot1}` is :math:`\alpha_1|\delta_{rot1}| + \alpha_2\delta_{trans}`
    as a standard deviation (left) or :math:`\alpha_1\delta_{rot1}^2 + \alpha_2\delta_{trans}^2`
    as a variance (right), and likewise for :math:`\hat\delta_{trans}` and
    :math:`\hat\delta_{rot2}`.

    Parameters
    ----------
    rot1, trans, rot2, theta
        As for :func:`odometry_model_live`.
    alpha : array_like, shape (4,)
        Initial noise parameters of the standard-deviation form, each in [0, 0.5].
    pairing, distribution, density, n_particles, grid, rng
        As for :func:`velocity_noise_forms_live`.

    Returns
    -------
    widget : LiveWidget
    """
    sliders = _odometry_sliders(rot1, trans, rot2, theta, alpha)
    return _noise_forms_widget(
        "odometry", sliders, distribution, density, pairing, n_particles, grid, rng
    )
