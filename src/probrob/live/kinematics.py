r"""Live widget of the CIR report's step (deck 003, eqs. 2-8): a differential drive's step.

Holds :func:`cir_step_live` (kernel ``assets/cir.js``, kind "scene"). Does not hold the
kinematics (:mod:`probrob.kinematics`, which the kernel mirrors).
"""

from __future__ import annotations

from .core import LiveWidget, live_widget, slider

__all__ = ["cir_step_live"]


def cir_step_live(*, s_sx=0.6, s_dx=0.3, wheelbase=0.4, theta=0.0) -> LiveWidget:
    r"""Return a live widget of one step about the CIR (the CIR report, eqs. 2–8).

    Sliders for the wheel arc lengths :math:`s_{sx}` (left) and :math:`s_{dx}` (right), the
    wheel base :math:`l` and the start heading :math:`\theta` (the report's convention:
    clockwise). The page computes :func:`~probrob.kinematics.cir_radius_angle`,
    :func:`~probrob.kinematics.cir_step_transform` and
    :func:`~probrob.kinematics.cir_state_function` as the library does, and draws the robot
    before (grey) and after (the foreground colour) the step from the origin, the paths of both
    wheels and of the middle of the axle (the state function at the fractions
    ``linspace(0, 1, 61)`` of the step), the CIR at :math:`(0, -(r + l/2))` in the start frame
    and its radii; on a straight line (:math:`s_{sx} = s_{dx}`, :math:`r = \pm\infty`) there is
    no CIR, and a rotation in place (:math:`s_{dx} = -s_{sx}`) turns about the middle of the
    axle.

    Parameters
    ----------
    s_sx, s_dx : float
        Initial arc lengths, each in [-1, 1.5] m.
    wheelbase : float
        Initial :math:`l`, in [0.1, 1] m.
    theta : float
        Initial start heading, in [-3.14, 3.14] rad (clockwise).

    Returns
    -------
    widget : LiveWidget
    """
    sliders = [
        slider("ssx", "s_sx [m] (left)", s_sx, -1.0, 1.5, 0.01, what="s_sx"),
        slider("sdx", "s_dx [m] (right)", s_dx, -1.0, 1.5, 0.01, what="s_dx"),
        slider("l", "l [m]", wheelbase, 0.1, 1.0, 0.01, what="wheelbase"),
        slider("theta", "θ start [rad]", theta, -3.14, 3.14, 0.01),
    ]
    return live_widget(
        "cir",
        sliders,
        title="One step about the CIR (the report's eqs. 2–8)",
        caption=(
            "Grey: the robot's axle and heading before the step, {black|white}: after it (the "
            "heading θ is clockwise, as in the report). Green and orange: the paths of the left "
            "and the right wheel; dashed: the middle of the axle. Red cross: the CIR, r from "
            "the right wheel and ρ = r + l/2 from the middle of the axle; red lines: its radii "
            "to the middle of the axle before and after. The view grows with the step; “fit "
            "view” zooms back in."
        ),
        aria_label=(
            "Plot in the x-y plane of one differential-drive step about the centre of "
            "instantaneous rotation: the robot before and after, both wheel paths, the CIR and "
            "its radii."
        ),
        draws={},
        n_particles=0,
        width=620,
        height=500,
    )
