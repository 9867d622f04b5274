r"""Live widgets: kernel-free sliders that recompute a model of the book in the reader's browser.

Holds the live widgets, one module per family named like the library module it shows, and
their small core. Does not hold the models: the JavaScript kernels mirror :mod:`probrob.motion`,
:mod:`probrob.sensors`, :mod:`probrob.kinematics`, :mod:`probrob.localization` and
:mod:`probrob.mcl`, and the parity tests hold each kernel to the library.

==============================================  ==============================================
module                                          holds
==============================================  ==============================================
:mod:`probrob.live.core`                        :class:`Slider`, :class:`Choice`,
                                                :class:`LiveWidget`, :func:`live_widget` (a
                                                model kernel's widget from its spec), the HTML
                                                block and the encoders
:mod:`probrob.live.distributions`               Table 5.2: :func:`distribution_live`, and
                                                :func:`standard_draws` (Table 5.4's draws)
:mod:`probrob.live.motion`                      Tables 5.1, 5.3, 5.5, 5.6:
                                                :func:`velocity_model_live`,
                                                :func:`odometry_model_live` and their two noise
                                                forms side by side
:mod:`probrob.live.sensors`                     Tables 6.1, 6.4, 6.5: :func:`beam_model_live`,
                                                :func:`landmark_model_live`
:mod:`probrob.live.kinematics`                  the CIR report: :func:`cir_step_live`
:mod:`probrob.live.localization`                Table 7.2: :func:`ekf_step_live`
:mod:`probrob.live.mcl`                         Tables 8.2–8.4: :func:`particle_filter_live`
:mod:`probrob.live.mcl_data`                    what it embeds: :func:`particle_filter_draws`,
                                                :func:`particle_filter_decoded`
==============================================  ==============================================

A live widget is one self-contained block of HTML, CSS and JavaScript (no CDN, no external
file, no build step) that works in the static book and in Jupyter (as a trusted output). Its
script is the runtime (``assets/runtime.js`` with its drawing helpers ``draw.js``, and
``runtime.css``), the library's shared helpers
(``assets/maths.js``), for a model kernel the plot layers (``assets/plots.js``), the kernel's
file(s) and the widget's spec (a JSON config: the sliders and choices, the constants and the
embedded data). The runtime owns what every widget shares: it builds the controls from the
spec, sizes the canvas (devicePixelRatio, resize; a plot is never narrower than 250 CSS px:
on a narrow page panels stack and a colour bar or a legend moves below), schedules and times
the redraws, takes its colours from the page's mode (light or dark: the book's
``<html data-theme>``, JupyterLab's ``<body data-jp-theme-light>``) and draws axes, arrows and
text. A kernel holds only its table's computation and drawing, with a header naming the table
and the Python function it mirrors; it is the one place where the maths is written a second
time, and its parity test (``tests/test_live_*.py``) compares it in headless Chromium with
:mod:`probrob` fed the same draws, to :math:`10^{-9}`.

Adding a widget for a new table is a kernel file ``assets/<name>.js`` that assigns
``kernels.<name>`` (the contract of its kind is at the top of ``assets/plots.js``;
``distribution.js`` is the smallest) and a function in the family module that calls
:func:`live_widget` with the kernel's name, its sliders and choices, any ``constants`` and the
embedded ``draws`` (:func:`distribution_live` is the smallest). A filter that runs over time
has its own layer (``render``, ``assets/mcl.js``, on ``assets/likelihood_field.js``).

Test hook (used by the tests and ``.ci/browser_check.py``): every widget on a page registers
itself in ``window.probrobLive.widgets`` (page order) as a handle with

* ``values()``, ``defaults()`` — the current and the initial parameter values by name;
* ``config()`` — the sliders (name, label, value, min, max, step) and the choices (name,
  options);
* ``set({name: value, ...}, refit)`` — set parameters (as the controls would), recompute and
  redraw synchronously (``refit``: fit the view to the new cloud), and return ``state()``;
* ``state()`` — ``{values, timings, mode, plots, ...}``: the milliseconds of the last update
  (``compute``: the model's numbers; ``draw``; ``total``), the colour mode drawn (``"light"``
  or ``"dark"``) and the plot boxes ``[x, y, w, h]`` in CSS px, and what the layer adds: for
  a model kernel ``{n, nx, ny, markers, theta, view, xs, ys, particles, density, panels,
  scene}``, the arrays as base64 of little-endian float64 (``particles`` is ``(n, 3)``, or
  ``(n,)`` for a curve, ``(k n, 3)`` for ``k`` panels; ``density`` is ``(k ny, nx)`` with
  ``density[i, j]`` at ``(xs[j], ys[i])``, ``ny = 1`` for a curve; ``theta`` the hypothesis
  heading of densities taken at one heading; ``scene`` a scene kernel's values by name); for
  the particle filter its step, particles, log-weights and estimate;
* ``draws(name)`` — one embedded array of draws, base64 float64 ``(k, n)``; ``field()`` — the
  particle filter's distance field;
* ``bench(count)`` — time ``count`` full updates (after 10 untimed ones), each with one
  parameter moved (the particle filter: one step); returns ``{count, compute, draw, total}``,
  each ``{median, p90, max}`` in milliseconds.

The canvas also carries ``data-plots``: the widths and heights of its plots in CSS px.
"""

from .core import Choice, LiveWidget, Slider, live_widget
from .distributions import distribution_live, standard_draws
from .kinematics import cir_step_live
from .localization import ekf_step_live
from .mcl import (
    particle_filter_beams,
    particle_filter_decoded,
    particle_filter_draws,
    particle_filter_kidnap_target,
    particle_filter_live,
)
from .motion import (
    odometry_model_live,
    odometry_noise_forms_live,
    velocity_model_live,
    velocity_noise_forms_live,
)
from .sensors import beam_model_live, landmark_draws, landmark_model_live

__all__ = [
    "Choice",
    "LiveWidget",
    "Slider",
    "beam_model_live",
    "cir_step_live",
    "distribution_live",
    "ekf_step_live",
    "landmark_draws",
    "landmark_model_live",
    "live_widget",
    "odometry_model_live",
    "odometry_noise_forms_live",
    "particle_filter_beams",
    "particle_filter_decoded",
    "particle_filter_draws",
    "particle_filter_kidnap_target",
    "particle_filter_live",
    "standard_draws",
    "velocity_model_live",
    "velocity_noise_forms_live",
]
