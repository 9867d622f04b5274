r"""Checks for the exercises of the MRCLAM chapter (``notebooks/mrclam_motion_noise.ipynb``).

Holds the checks of the MRCLAM chapter's exercises.
Does not hold the answers or the fits (each check computes the truth with :mod:`probrob.fitting`).

Each ``exercise_N(answer, ...)`` computes the truth with the library from the inputs the
chapter passes (the fitted :math:`\alpha`, the windows), returns ``None`` when the answer
is right and a short message of what is wrong otherwise, and never the right value. Use
them through :func:`probrob.exercises.check`, e.g.
``check("Exercise 1", answer, test=partial(exercise_1, alpha=alpha))``.

=========  =====================================================  ==========================
exercise   question                                               table
=========  =====================================================  ==========================
1          ratio of the velocity density at two end poses         5.1 (density, both modes)
2          variances of the translation factor at δ̂ and at δ      5.5 vs 5.6 (erratum O3)
3          fit on the last 30 %, score the first 70 %             ML fit (``probrob.fitting``)
4          the three standard deviations of the std noise form    5.1, noise forms
=========  =====================================================  ==========================
"""

from __future__ import annotations

import numpy as np

from ..fitting import fit_odometry_alpha, odometry_log_likelihood
from ..motion import (
    _odometry_variances,
    _velocity_controls,
    motion_model_velocity,
    odometry_deltas,
)
from . import agrees, more_digits, not_a_number

__all__ = ["EXERCISE_1", "exercise_1", "exercise_2", "exercise_3", "exercise_4"]

#: The question of Exercise 1: start pose, command, step, and the two end poses.
EXERCISE_1 = {
    "x_prev": (0.0, 0.0, 0.0),
    "u": (0.07, 0.0),
    "dt": 1.0,
    "x_a": (0.07, 0.0, 0.0),
    "x_b": (0.07, 0.0, 0.05),
}


def _numbers(answer, n: int, what: str):
    """The answer as ``n`` finite floats, or a message saying why it is not."""
    problem = not_a_number(answer)
    if problem:
        return None, f"{problem}; {what}"
    try:
        got = np.asarray(answer, dtype=float)
    except (TypeError, ValueError):
        return None, f"expected {what}"
    if got.shape != ((n,) if n > 1 else ()):
        return None, f"expected {what}, got shape {got.shape}"
    return got, None


def _close(got, want, rtol=1e-4) -> bool:
    return bool(np.allclose(got, want, rtol=rtol, atol=0.0))


def _like(got, want, rtol=1e-4) -> bool:
    """``got`` is ``want``, to the tolerance or to the digits it shows (a typed slip)."""
    return agrees(got, want, rtol=rtol)


def _off(names) -> str:
    """ "σ_v is off", "the first and the second are off", "σ_v, σ_ω and σ_γ are off"."""
    names = list(names)
    listed = names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]
    return f"{listed} {'is' if len(names) == 1 else 'are'} off"


def exercise_1(answer, *, alpha) -> str | None:
    r"""Exercise 1: :math:`p(x_b \mid u, x_{t-1}) / p(x_a \mid u, x_{t-1})`, Table 5.1.

    The scenario is :data:`EXERCISE_1`; ``alpha`` are the chapter's fitted velocity-model
    parameters, shape (6,), variance form. The ratio is the same in both density modes
    (the two end poses share :math:`\hat v, \hat\omega` and so the Jacobian).
    """
    got, problem = _numbers(answer, 1, "one number, the ratio p(x_b) / p(x_a)")
    if problem:
        return problem
    s = EXERCISE_1
    p = [
        motion_model_velocity(s[key], s["u"], s["x_prev"], s["dt"], alpha, density="book")
        for key in ("x_a", "x_b")
    ]
    want = p[1] / p[0]
    if _close(got, want):
        return None
    short = more_digits(got, want, rtol=1e-4)
    if short:
        return short
    if _like(got, 1 / want):
        return "that is p(x_a) / p(x_b): the ratio asked for has x_b on top"
    if _like(got, np.log(want)):
        return "that is the log of the ratio; give the ratio itself"
    if got >= 1:
        return "x_b needs a final turn γ̂ that x_a does not: its density is lower"
    return "only the γ̂ factor differs; its variance is α5 v² + α6 ω² (a variance, not a σ)"


def exercise_2(answer, *, x_prev, x_t, odometry, alpha) -> str | None:
    r"""Exercise 2 (erratum O3): the variance of the translation factor, two ways.

    ``answer = (var_55, var_56)``: :math:`\alpha_3\delta_{trans}^2 +
    \alpha_4(\delta_{rot1}^2 + \delta_{rot2}^2)` evaluated at the hypothesis' :math:`\hat\delta`
    (Table 5.5 as printed) and at the odometry's :math:`\delta` (Table 5.6, the sampler),
    variance form. ``x_prev, x_t`` shape (3,), ``odometry`` shape (2, 3), ``alpha`` (4,).
    """
    got, problem = _numbers(answer, 2, "two numbers: (variance at δ̂, variance at δ)")
    if problem:
        return problem
    hat = odometry_deltas(x_prev, x_t)
    odo = odometry_deltas(odometry[0], odometry[1])
    want = np.array(
        [_odometry_variances(alpha, *d, "variance")[1] for d in (hat, odo)], dtype=float
    )
    if _close(got, want):
        return None
    short = more_digits(got, want, rtol=1e-4)
    if short:
        return short
    if _like(got, want[::-1]):
        return "the two are swapped: Table 5.5 uses the hypothesis' δ̂, Table 5.6 the odometry's δ"
    if _like(got, np.sqrt(want)):
        return "those are standard deviations; the table's second argument is a variance"
    wrong = [k for k in range(2) if not _close(got[k], want[k])]
    names = ("the first (at δ̂, from x_prev to x_t)", "the second (at δ, from the odometry)")
    return _off(names[k] for k in wrong)


def exercise_3(answer, *, train, test) -> str | None:
    r"""Exercise 3: fit the odometry model on ``test``, score ``train`` (held out).

    ``answer = (score, "higher" or "lower")``: the mean log-likelihood per window of the
    swapped fit (variance form, ``density="pose"``), and how it compares with the fit on
    ``train`` scored on ``test``. ``train, test``: :class:`~probrob.fitting.MotionWindows`.
    """
    if not isinstance(answer, tuple | list) or len(answer) != 2:
        return 'expected a pair: (mean log-likelihood, "higher" or "lower")'
    score, word = answer
    got, problem = _numbers(score, 1, "a number as the first part")
    if problem:
        return problem
    if not isinstance(word, str) or word not in ("higher", "lower"):
        return 'the second part must be "higher" or "lower"'

    def held_out(fit_on, score_on):
        f = fit_odometry_alpha(fit_on.x_t, fit_on.odometry, fit_on.x_prev, density="pose")
        ll = odometry_log_likelihood(
            score_on.x_t, score_on.odometry, score_on.x_prev, f.alpha, density="pose"
        )
        return float(np.mean(ll)), f.mean_log_likelihood

    swapped, in_sample = held_out(test, train)
    original, _ = held_out(train, test)
    problems = []
    if not _close(got, swapped, rtol=1e-6):
        short = more_digits(got, swapped, rtol=1e-6)
        if short:
            problems.append(f"the score is {short}")
        elif _like(got, in_sample, rtol=1e-6):
            problems.append("that score is on the windows the model was fitted to")
        elif _like(got, original, rtol=1e-6):
            problems.append("that is the original fit's score: fit on test, score on train")
        else:
            problems.append("the score is off (variance form, density='pose')")
    if word != ("higher" if swapped > original else "lower"):
        problems.append("the comparison is the wrong way round")
    return "; ".join(problems) or None


def exercise_4(answer, *, alpha, v, w) -> str | None:
    r"""Exercise 4: the standard deviations of :math:`\hat v, \hat\omega, \hat\gamma`.

    ``answer = (σ_v, σ_ω, σ_γ)`` for the standard-deviation noise form
    (:math:`\sigma_1 = \alpha_1|v| + \alpha_2|\omega|`, ...) with the fitted std-form
    ``alpha`` (6,) at the command ``(v, w)``.
    """
    got, problem = _numbers(answer, 3, "three numbers: (σ for v̂, σ for ω̂, σ for γ̂)")
    if problem:
        return problem
    want = np.sqrt(np.array(_velocity_controls(alpha, np.array([v, w]), "std")[2:], dtype=float))
    if _close(got, want):
        return None
    short = more_digits(got, want, rtol=1e-4)
    if short:
        return short
    if _like(got, want**2):
        return "those are variances; give standard deviations"
    variance_form = np.sqrt(
        np.array(_velocity_controls(alpha, np.array([v, w]), "variance")[2:], dtype=float)
    )
    if _like(got, variance_form):
        return "that is the variance form's formula; in the std form α1|v| + α2|ω| is σ itself"
    wrong = [name for k, name in enumerate(("σ_v", "σ_ω", "σ_γ")) if not _close(got[k], want[k])]
    return _off(wrong)
