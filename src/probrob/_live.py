r"""Live widgets: kernel-free sliders that recompute a model in the reader's browser.

Holds the live widgets: self-contained HTML and JavaScript that recompute a model in the browser.
Does not hold the models (the JavaScript mirrors :mod:`probrob.motion` and :mod:`probrob.sensors`).

A live widget is one self-contained block of HTML, CSS and JavaScript (no CDN, no external
file, no build step) that works in the static book and in Jupyter (as a trusted output). It
embeds a seeded set of *standardized draws* :math:`z` made by :mod:`probrob.distributions`
(float64, base64) and recomputes, on every slider ``input`` event,

* the sample cloud: the model's sampler with every noise term :math:`\varepsilon = b\,z`,
  :math:`b = \sqrt{b^2}`, the same arithmetic for the normal (sum of twelve uniforms) and
  the triangular sampler, so that a cloud for any :math:`\alpha` is the same draws rescaled;
* the density on a grid (default 100 × 100) over the plot box (or a curve);

and draws both on a ``<canvas>`` with markers (the start pose, the noise-free end pose, a
landmark), axes and a colour bar. The JavaScript is a second implementation of the book's
tables, so ``tests/test_live_widgets.py`` drives it in headless Chromium and compares its
particles and density grid with :mod:`probrob.motion` and :mod:`probrob.sensors` fed the same
draws, to a relative :math:`10^{-9}`.

Adding a model is one JavaScript kernel and one Python function. The generic part
(``_live_assets/live.js``, ``live.css``) lays out the controls, keeps the view, draws, times
each update and exposes the test hook. A kernel file ``_live_assets/<name>.js`` assigns
``kernels.<name>`` an object with ``markers``, ``heading``, ``sample``, ``density``, ``title``
and ``densityLabel`` (their contract is at the top of ``live.js``; ``landmark.js`` is the
shortest example). The Python function calls :func:`live_widget` with the kernel's name, its
:class:`Slider` and :class:`Choice` list, any fixed ``constants`` and the embedded ``draws``
(e.g. :func:`landmark_model_live`); a test then compares the kernel with the library. The
files are package data, read when a widget is made and inlined into its HTML. A model whose
picture is a curve of one variable, such as the beam model's :math:`p(z \mid z^*)` with its
six intrinsic parameters, is a kernel of ``kind: "curve"`` (a curve over a histogram of its
samples): :func:`beam_model_live` (``beam.js``) and :func:`distribution_live` (Table 5.2,
``distribution.js``). A kernel with ``panels: 2`` draws the same model twice side by side at
two sets of parameters (:func:`velocity_noise_forms_live`, ``noise_forms.js`` on the unchanged
``velocity.js``, pulled in by ``requires``); a kernel of ``kind: "scene"`` draws a geometric
construction and exposes its numbers (:func:`cir_step_live`, ``cir.js``; and
:func:`probrob.widgets.ekf_step_live`, ``ekf.js``: one step of Table 7.2 with its covariance
ellipses, held to :mod:`probrob.localization` by ``tests/test_live_widgets_t5.py``).

A filter that runs over time has its own mount: :func:`particle_filter_live` (``mcl.js``,
inlined after ``live.js`` and ``odometry.js``, whose helpers it uses) runs Monte Carlo
localization (Table 8.2) over a stretch of a laser log on a map, with step and play buttons. It
embeds the map's cells (2 bits each; the page computes the exact distance field and the
likelihood-field table), the log (ranges in whole millimetres), and the random numbers of
:func:`particle_filter_draws`; ``tests/test_live_mcl.py`` replays them through
:func:`probrob.mcl.mcl` (``sample=``, ``resample_offset=``) and holds the page's particles,
log-weights and estimates to it at every step. Its block states its own budgets
(``data-size-budget``, ``data-update-budget``), which the browser check reads.

Test hook (used by the tests and ``.ci/browser_check.py``): every widget on a page registers
itself in ``window.probrobLive.widgets`` (page order) as a handle with

* ``values()``, ``defaults()`` — the current and the initial parameter values by name;
* ``config()`` — the sliders (name, value, min, max) and the choices (name, options);
* ``set({name: value, ...}, refit)`` — set parameters (as the controls would), recompute and
  redraw synchronously (``refit``: fit the view to the new cloud), and return ``state()``;
* ``state()`` — ``{values, n, nx, ny, markers, theta, view, xs, ys, particles, density,
  timings}``: the arrays as base64 of little-endian float64 (``particles`` is ``(n, 3)``,
  or ``(n,)`` for a curve; ``density`` is ``(ny, nx)`` with ``density[i, j]`` at
  ``(xs[j], ys[i])``, ``ny = 1`` for a curve; ``theta`` the
  hypothesis heading of densities taken at one heading) and the milliseconds of the last
  update (``compute``: particles and grid; ``draw``; ``total``); and ``panels`` (``k``: with
  ``k > 1`` panels, ``particles`` is ``(k n, 3)`` and ``density`` ``(k ny, nx)``, panel after
  panel) and ``scene`` (a scene kernel's values by name, each base64 float64);
* ``draws(name)`` — one embedded array of draws, base64 float64 ``(k, n)``;
* ``bench(count)`` — time ``count`` full updates (after 10 untimed ones), each with one
  parameter moved; returns ``{count, compute, draw, total}``, each ``{median, p90, max}`` in
  milliseconds.
"""

from __future__ import annotations

import base64
import html
import itertools
import json
from dataclasses import dataclass
from importlib import resources

import numpy as np

from . import _validation as check
from .distributions import sample_normal_distribution, sample_triangular_distribution

__all__ = [
    "Choice",
    "LiveWidget",
    "Slider",
    "beam_model_live",
    "distribution_live",
    "landmark_draws",
    "landmark_model_live",
    "live_widget",
    "odometry_model_live",
    "particle_filter_beams",
    "particle_filter_decoded",
    "particle_filter_draws",
    "particle_filter_live",
    "standard_draws",
    "velocity_model_live",
]

_ASSETS = "_live_assets"
_COUNTER = itertools.count(1)

#: The noise distributions of the live widgets: the value of the ``distribution`` choice,
#: the label shown, and the standardized sampler (variance 1) of Table 5.4.
DISTRIBUTIONS = {
    "normal": ("normal (sum of 12 uniforms)", sample_normal_distribution),
    "triangular": ("triangular", sample_triangular_distribution),
}
NOISE_FORMS = (("variance", "α·m² is a variance"), ("std", "α·|m| is a std"))
DENSITY_MODES = (
    ("xy", "over (x′, y′), θ′ integrated out"),
    ("pose", "over (x′, y′, θ′) at the blue arrow's θ′"),
    ("book", "the table's value at the blue arrow's θ′"),
)


def _asset(name: str) -> str:
    return resources.files("probrob").joinpath(_ASSETS, name).read_text(encoding="utf-8")


@dataclass(frozen=True)
class Slider:
    """A numeric parameter: a range slider and a number box, ``lo <= value <= hi``."""

    name: str
    label: str
    value: float
    lo: float
    hi: float
    step: float


@dataclass(frozen=True)
class Choice:
    """A parameter with a few named values: a ``<select>`` of ``(value, text)`` options."""

    name: str
    label: str
    options: tuple[tuple[str, str], ...]
    value: str


class LiveWidget:
    """A live widget: display it (its ``_repr_html_``) or read its ``html``."""

    def __init__(self, html_text: str, kernel: str):
        self.html = html_text
        self.kernel = kernel

    def _repr_html_(self) -> str:
        return self.html

    def __repr__(self) -> str:
        return (
            f"<probrob live widget: {self.kernel} model, {len(self.html) / 1000:.0f} kB of HTML>"
        )


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


def _b64(arr: np.ndarray) -> str:
    return base64.b64encode(np.ascontiguousarray(arr, dtype="<f8").tobytes()).decode("ascii")


def _fmt(x: float) -> str:
    return repr(float(x))


def _controls_html(wid: str, sliders, choices) -> str:
    e = html.escape
    rows = ['<div class="pl-sliders">']
    for s in sliders:
        rid = f"{wid}-{s.name}"
        attrs = (
            f'min="{_fmt(s.lo)}" max="{_fmt(s.hi)}" step="{_fmt(s.step)}" value="{_fmt(s.value)}"'
        )
        rows.append(
            f'<div class="pl-row"><label for="{rid}">{e(s.label)}</label>'
            f'<input type="range" id="{rid}" data-param="{e(s.name)}" {attrs}>'
            f'<input type="number" id="{rid}-n" data-param="{e(s.name)}" {attrs} '
            f'aria-label="{e(s.label)}, value"></div>'
        )
    rows.append("</div>")
    for c in choices:
        cid = f"{wid}-{c.name}"
        options = "".join(
            f'<option value="{e(v)}"{" selected" if v == c.value else ""}>{e(t)}</option>'
            for v, t in c.options
        )
        rows.append(
            f'<div class="pl-choice"><label for="{cid}">{e(c.label)}</label>'
            f'<select id="{cid}" data-param="{e(c.name)}">{options}</select></div>'
        )
    return "\n".join(rows)


def live_widget(
    kernel: str,
    sliders,
    choices=(),
    *,
    title: str,
    caption: str,
    aria_label: str,
    draws: dict[str, np.ndarray] | None = None,
    constants: dict[str, float] | None = None,
    n_particles: int = 2000,
    grid: int = 100,
    headings: int = 60,
    rng=0,
    width: int = 600,
    height: int = 500,
    requires: tuple[str, ...] = (),
) -> LiveWidget:
    """Return a live widget of the model whose JavaScript kernel is ``_live_assets/<kernel>.js``.

    The generic mechanism: the model functions (:func:`velocity_model_live`,
    :func:`odometry_model_live`) only choose the kernel, the sliders and the choices.

    Parameters
    ----------
    kernel : str
        Name of the kernel file (without ``.js``) and of the entry it adds to ``kernels``.
    sliders : sequence of Slider
    choices : sequence of Choice
        A choice named ``distribution`` picks the draws and ``p.prob`` (its values must be
        keys of ``draws``); without one, the ``"normal"`` draws are used.
    title, caption, aria_label : str
        A heading above the widget, a sentence below the plot saying what it shows, and the
        canvas's accessible name.
    draws : dict of ndarray (k, n), optional
        Draws by name (``n = n_particles``): the kernel's ``sample`` gets the one named by the
        ``distribution`` choice and all of them; default :func:`standard_draws`
        ``(n_particles, rng)``. A kernel that draws no samples takes ``{}`` and
        ``n_particles=0``.
    constants : dict of float, optional
        Fixed parameters the kernel reads like slider values (e.g. a landmark's position).
    n_particles, grid, headings : int
        Particles, density grid points per axis, and how many particles show a heading.
    rng : None, int or numpy.random.Generator
        Seed of the default draws.
    width, height : int
        Canvas size in CSS pixels.
    requires : sequence of str
        Further kernel files (without ``.js``) inlined before the kernel's own, in this order:
        a kernel built on others (e.g. ``velocity_forms`` on ``velocity`` and ``noise_forms``).

    Returns
    -------
    widget : LiveWidget
    """
    try:
        kernel_js = _asset(f"{kernel}.js")
    except (FileNotFoundError, OSError) as exc:
        raise ValueError(f"kernel must name a file {_ASSETS}/<kernel>.js, got {kernel!r}") from exc
    try:
        kernel_js = "\n".join([*(_asset(f"{name}.js") for name in requires), kernel_js])
    except (FileNotFoundError, OSError, TypeError) as exc:
        raise ValueError(
            f"requires must name files {_ASSETS}/<name>.js, got {requires!r}"
        ) from exc
    n_particles = check.count(n_particles, "n_particles", 0)
    grid = check.count(grid, "grid", 2)
    headings = check.count(headings, "headings", 0)
    if draws is None:
        if n_particles < 1:
            raise ValueError(f"n_particles must be >= 1 with the default draws, got {n_particles}")
        draws = standard_draws(n_particles, rng)
    draws = {k: check.finite(v, f"draws[{k!r}]") for k, v in draws.items()}
    for k, v in draws.items():
        if v.ndim != 2 or v.shape[1] != n_particles:
            raise ValueError(f"draws[{k!r}] must have shape (k, {n_particles}), got {v.shape}")
    constants = {k: _constant(v, k) for k, v in (constants or {}).items()}
    names = [s.name for s in sliders] + [c.name for c in choices] + list(constants)
    if len(set(names)) != len(names):
        raise ValueError(f"parameter names must be unique, got {names}")
    for s in sliders:
        if not (s.lo <= s.value <= s.hi and s.step > 0):
            raise ValueError(f"{s.name} must lie in [{s.lo}, {s.hi}], got {s.value!r}")
    for c in choices:
        if c.value not in [v for v, _ in c.options]:
            raise ValueError(
                f"{c.name} must be one of {[v for v, _ in c.options]}, got {c.value!r}"
            )
    families = [v for c in choices if c.name == "distribution" for v, _ in c.options]
    if draws and not set(families or ["normal"]) <= set(draws):
        raise ValueError(f"every distribution needs its draws, have {sorted(draws)}")

    wid = f"probrob-live-{kernel}-{next(_COUNTER)}"
    config = {
        "kernel": kernel,
        "n": int(n_particles),
        "grid": int(grid),
        "headings": int(headings),
        "width": check.count(width, "width", 1),
        "height": check.count(height, "height", 1),
        "sliders": [
            {"name": s.name, "value": float(s.value), "min": float(s.lo), "max": float(s.hi)}
            for s in sliders
        ],
        "choices": [{"name": c.name, "value": c.value} for c in choices],
        "constants": constants,
        "draws": {k: _b64(v) for k, v in draws.items()},
    }
    config_js = json.dumps(config, ensure_ascii=True).replace("</", "<\\/")
    e = html.escape
    return LiveWidget(
        f"""<div class="probrob-live" id="{wid}" role="group" aria-label="{e(title)}">
<style>{_asset("live.css")}</style>
<div class="pl-title"><strong>{e(title)}</strong> (live: runs in this page, no kernel)</div>
<div class="pl-body">
<canvas width="{width}" height="{height}" role="img" aria-label="{e(aria_label)}">{e(aria_label)}</canvas>
<div class="pl-controls">
{_controls_html(wid, sliders, choices)}
<button type="button" data-action="reset">reset</button><button type="button" data-action="fit">fit view</button>
</div>
</div>
<p class="pl-caption">{e(caption)}</p>
<script>
(function () {{
"use strict";
{_asset("live.js")}
{kernel_js}
const config = {config_js};
// the script's own block (also when a front end runs it before the block is in the document,
// as JupyterLab does), else the block with this id
const script = document.currentScript;
const root = (script && script.closest(".probrob-live")) || document.getElementById("{wid}");
mountLiveWidget(root, config, kernels[config.kernel]);
}})();
</script>
</div>""",
        kernel,
    )


def _alpha_sliders(alpha, count):
    alpha = check.alphas(alpha, "alpha", count)
    if np.any(alpha > 0.5):
        raise ValueError(f"alpha must lie in [0, 0.5] (the sliders' range), got {alpha.tolist()}")
    return [
        Slider(f"a{k + 1}", f"α{k + 1}", float(alpha[k]), 0.0, 0.5, 0.001) for k in range(count)
    ]


def _common_choices(distribution, noise, density):
    check.choice(distribution, "distribution", tuple(DISTRIBUTIONS))
    check.choice(noise, "noise", tuple(v for v, _ in NOISE_FORMS))
    check.choice(density, "density", tuple(v for v, _ in DENSITY_MODES))
    return [
        Choice("noise", "noise form", NOISE_FORMS, noise),
        Choice(
            "distribution",
            "distribution",
            tuple((k, label) for k, (label, _) in DISTRIBUTIONS.items()),
            distribution,
        ),
        Choice("density", "density", DENSITY_MODES, density),
    ]


def _in_range(value, name, lo, hi):
    return check.in_range(value, name, lo, hi)


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
    with the embedded draws of :func:`standard_draws`.

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
    sliders = [
        Slider("v", "v [m/s]", _in_range(v, "v", -2, 2), -2.0, 2.0, 0.01),
        Slider("w", "ω [rad/s]", _in_range(w, "w", -2, 2), -2.0, 2.0, 0.01),
        Slider("dt", "Δt [s]", _in_range(dt, "dt", 0.1, 3), 0.1, 3.0, 0.01),
        Slider(
            "theta", "θ start [rad]", _in_range(theta, "theta", -3.14, 3.14), -3.14, 3.14, 0.01
        ),
        *_alpha_sliders(alpha, 6),
    ]
    return live_widget(
        "velocity",
        sliders,
        _common_choices(distribution, noise, density),
        title="Velocity motion model (Tables 5.1 and 5.3)",
        caption=(
            f"Red: {n_particles} samples of Table 5.3 (the first 60 with their heading); grey: "
            "the density of Table 5.1 on a 100 × 100 grid (darker is more probable); black "
            "arrow: the start pose; blue arrow: the noise-free end pose. The view grows with "
            "the cloud; “fit view” zooms back in."
        ),
        aria_label=(
            "Plot of the velocity motion model in the x-y plane: a cloud of sampled end poses "
            "over a grey density image, with the start pose and the noise-free end pose."
        ),
        n_particles=n_particles,
        grid=grid,
        rng=rng,
    )


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
    sliders = [
        Slider("rot1", "δrot1 [rad]", _in_range(rot1, "rot1", -3.14, 3.14), -3.14, 3.14, 0.01),
        Slider("trans", "δtrans [m]", _in_range(trans, "trans", 0, 3), 0.0, 3.0, 0.01),
        Slider("rot2", "δrot2 [rad]", _in_range(rot2, "rot2", -3.14, 3.14), -3.14, 3.14, 0.01),
        Slider(
            "theta", "θ start [rad]", _in_range(theta, "theta", -3.14, 3.14), -3.14, 3.14, 0.01
        ),
        *_alpha_sliders(alpha, 4),
    ]
    return live_widget(
        "odometry",
        sliders,
        _common_choices(distribution, noise, density),
        title="Odometry motion model (Tables 5.5 and 5.6)",
        caption=(
            f"Red: {n_particles} samples of Table 5.6 (the first 60 with their heading); grey: "
            "the density of Table 5.5 on a 100 × 100 grid (darker is more probable); black "
            "arrow: the start pose; blue arrow: the noise-free end pose. The view grows with "
            "the cloud; “fit view” zooms back in."
        ),
        aria_label=(
            "Plot of the odometry motion model in the x-y plane: a cloud of sampled end poses "
            "over a grey density image, with the start pose and the noise-free end pose."
        ),
        n_particles=n_particles,
        grid=grid,
        rng=rng,
    )


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
    sigmas = check.finite(sigmas, "sigmas")
    if sigmas.shape != (3,):
        raise ValueError(f"sigmas must hold (σ_r, σ_φ, σ_s), got shape {sigmas.shape}")
    landmark = check.vectors(landmark, "landmark", 3, "x, y, s")
    if landmark.shape != (3,):
        raise ValueError(f"landmark must be one row (x, y, s), got shape {landmark.shape}")
    mx, my, ms = landmark
    sliders = [
        Slider("r", "r [m]", _in_range(r, "r", 0, 5), 0.0, 5.0, 0.01),
        Slider("phi", "φ [rad]", _in_range(phi, "phi", -3.14, 3.14), -3.14, 3.14, 0.01),
        Slider("s", "s", _in_range(s, "s", 0, 3), 0.0, 3.0, 0.01),
        Slider("sr", "σr [m]", _in_range(sigmas[0], "sigmas[0]", 0, 1), 0.0, 1.0, 0.005),
        Slider("sphi", "σφ [rad]", _in_range(sigmas[1], "sigmas[1]", 0, 1), 0.0, 1.0, 0.005),
        Slider("ss", "σs", _in_range(sigmas[2], "sigmas[2]", 0, 1), 0.0, 1.0, 0.005),
        Slider(
            "theta", "θ image [rad]", _in_range(theta, "theta", -3.14, 3.14), -3.14, 3.14, 0.01
        ),
    ]
    return live_widget(
        "landmark",
        sliders,
        title="Landmark model (Tables 6.4 and 6.5)",
        caption=(
            f"Red: {n_particles} poses of Table 6.5 drawn from the feature (the first 60 with "
            "their heading): a ring around the landmark (blue square). Grey: the likelihood "
            "p(f | x, m) of Table 6.4 over (x, y) for poses with the heading θ of the slider "
            "(darker is more likely): the part of the ring from which the landmark is seen at "
            "bearing φ when facing θ. The signature s scales the whole image."
        ),
        aria_label=(
            "Plot of the landmark model in the x-y plane: a ring of sampled poses around the "
            "landmark, over a grey likelihood image for one heading."
        ),
        draws=landmark_draws(n_particles, rng),
        constants={"mx": mx, "my": my, "ms": ms},
        n_particles=n_particles,
        grid=grid,
        rng=rng,
    )


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
    check.choice(distribution, "distribution", tuple(DISTRIBUTIONS))
    return live_widget(
        "distribution",
        [Slider("b2", "b² (variance)", _in_range(b2, "b2", 0.01, 4), 0.01, 4.0, 0.01)],
        [
            Choice(
                "distribution",
                "distribution",
                tuple((k, label) for k, (label, _) in DISTRIBUTIONS.items()),
                distribution,
            )
        ],
        title="Noise distributions (Tables 5.2 and 5.4)",
        caption=(
            f"Blue: the density of Table 5.2 with variance b²; red: a histogram of {n_particles} "
            "samples of Table 5.4, the same standardized draws times b."
        ),
        aria_label=(
            "Plot of a zero-mean noise density against a, over a histogram of its samples."
        ),
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
    weights = check.finite(weights, "weights")
    if weights.shape != (4,):
        raise ValueError(f"weights must hold (z_hit, z_short, z_max, z_rand), got {weights.shape}")
    names = ("whit", "wshort", "wmax", "wrand")
    labels = ("z_hit", "z_short", "z_max", "z_rand")
    sliders = [
        Slider("zstar", "z* [m]", _in_range(z_star, "z_star", 0, zmax), 0.0, zmax, 0.01),
        *(
            Slider(n, lab, _in_range(w, f"weights[{k}]", 0, 1), 0.0, 1.0, 0.01)
            for k, (n, lab, w) in enumerate(zip(names, labels, weights, strict=True))
        ),
        Slider("sigma", "σ_hit [m]", _in_range(sigma_hit, "sigma_hit", 0.01, 1), 0.01, 1.0, 0.01),
        Slider(
            "lambda",
            "λ_short [1/m]",
            _in_range(lambda_short, "lambda_short", 0.05, 5),
            0.05,
            5.0,
            0.01,
        ),
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


def _constant(value, key) -> float:
    """One finite number for ``constants[key]`` (an array is an error, not float()'s TypeError)."""
    arr = check.finite(value, f"constants[{key!r}]")
    if arr.ndim != 0:
        raise ValueError(f"constants[{key!r}] must be a number, got shape {arr.shape}")
    return float(arr)


# ------------------------------------------------------------------ the live particle filter
#: Particles within which the live particle filter's ``estimate_pose`` clusters (m).
PF_RADIUS = 0.5
#: Heading sectors of the live particle filter's ``estimate_pose`` (its default, 30° each).
PF_HEADING_BINS = 12
#: The embedded ranges are whole millimetres (uint16); this code marks a max-range reading.
PF_MAX_RANGE_CODE = 0xFFFF


def particle_filter_draws(n_max=2000, steps=100, rng=0) -> dict[str, np.ndarray]:
    r"""Return the seeded random numbers the live particle filter embeds and replays.

    One generator makes, in this order,

    * ``"normal"`` shape ``(3 n_max,)``: a pool of standardized normals of
      :func:`~probrob.distributions.sample_normal_distribution` (the book's sum of twelve
      uniforms, variance 1), rounded to float32 (to halve their size in the page);
    * ``"offsets"`` shape ``(steps, 3)``: integers in ``[0, 3 n_max)``. At step ``t``
      (1-based) the motion sampler's noise term ``k`` (:math:`\hat\delta_{rot1}`,
      :math:`\hat\delta_{trans}`, :math:`\hat\delta_{rot2}`) of particle ``i`` is
      :math:`\sqrt{b^2}\, z` with ``z = normal[(offsets[t - 1, k] + i) % (3 n_max)]``: every
      step reads the pool from three fresh random places, so no particle index keeps its noise;
    * ``"resample"`` shape ``(steps,)``: uniforms in [0, 1), the low-variance sampler's
      random number of each step (``offset`` of :func:`probrob.mcl.low_variance_sampler`);
    * ``"uniforms"`` shape ``(n_max, 4)``: uniforms ``k / 2**24`` (exact in float32) for a global
      start (``uniforms`` of :func:`probrob.mcl.uniform_particles`).

    The known start uses the pool's first ``3 n_max``: particle ``i`` is
    ``start + spread * (normal[i], normal[n_max + i], normal[2 n_max + i])``.

    Parameters
    ----------
    n_max : int
        The most particles the widget offers (>= 1).
    steps : int
        Filter steps (>= 1).
    rng : None, int or numpy.random.Generator
        Seed.

    Returns
    -------
    draws : dict
    """
    n_max = check.count(n_max, "n_max", 1)
    steps = check.count(steps, "steps", 1)
    gen = check.rng(rng)
    pool = 3 * n_max
    normal = sample_normal_distribution(1.0, size=pool, rng=gen).astype(np.float32)
    return {
        "normal": normal.astype(np.float64),
        "offsets": gen.integers(0, pool, size=(steps, 3)),
        "resample": gen.random(steps),
        "uniforms": gen.integers(0, 2**24, size=(n_max, 4)) / 2.0**24,
    }


def particle_filter_beams(total, k) -> np.ndarray:
    """Return the indices of ``k`` of ``total`` beams spread evenly over the scan.

    ``round(linspace(0, total - 1, k))`` (half to even), the selection of the live particle
    filter's "beams" slider; shape ``(k,)``.
    """
    total = check.count(total, "total", 1)
    k = check.count(k, "k", 1)
    if k > total:
        raise ValueError(f"k must be at most the {total} beams of a scan, got {k}")
    return np.round(np.linspace(0, total - 1, k)).astype(np.intp)


def _b64_as(arr, dtype: str) -> str:
    return base64.b64encode(np.ascontiguousarray(arr, dtype=dtype).tobytes()).decode("ascii")


def _pf_cells(grid) -> str:
    """The grid's cells as 2-bit codes (0 unexplored, 1 free, 2 occupied), four per byte,
    row-major from row 0 (the lowest y); base64."""
    codes = grid.free.astype(np.uint8).ravel() + 2 * grid.occupied.astype(np.uint8).ravel()
    codes = np.concatenate([codes, np.zeros(-codes.size % 4, np.uint8)]).reshape(-1, 4)
    packed = codes[:, 0] | codes[:, 1] << 2 | codes[:, 2] << 4 | codes[:, 3] << 6
    return base64.b64encode(packed.astype(np.uint8).tobytes()).decode("ascii")


def _pf_ranges(scans, max_range) -> np.ndarray:
    """The ranges as whole millimetres, max-range readings (z >= max_range) as the code."""
    mm = np.round(scans * 1000.0)
    if np.any(mm[scans < max_range] >= PF_MAX_RANGE_CODE):
        raise ValueError(
            f"scans must be below {PF_MAX_RANGE_CODE / 1000} m (the page keeps whole "
            "millimetres in 16 bits) or at least params.max_range"
        )
    return np.where(scans < max_range, mm, PF_MAX_RANGE_CODE).astype(np.uint16)


def particle_filter_decoded(widget: LiveWidget) -> dict[str, np.ndarray]:
    """Return the arrays a live particle filter embeds, decoded as its JavaScript decodes them.

    ``scans`` in metres (a max-range reading as ``max_range``), ``odometry`` ``(T, 2, 3)``,
    ``truth`` ``(T + 1, 3)``, ``beam_angles`` ``(K,)`` and the draws of
    :func:`particle_filter_draws`; for feeding :mod:`probrob.mcl` exactly what the page uses.
    """
    import re

    match = re.search(r"const config = (\{.*?\});\n", widget.html)
    if widget.kernel != "mcl" or match is None:
        raise ValueError("widget must be a live particle filter (particle_filter_live)")
    config = json.loads(match.group(1))
    data = config["data"]

    def raw(name, dtype):
        return np.frombuffer(base64.b64decode(data[name]), dtype)

    steps, k, n_max = config["steps"], config["beamsTotal"], config["nMax"]
    mm = raw("scans", "<u2").reshape(steps, k).astype(np.float64)
    max_range = config["constants"]["maxRange"]
    return {
        "scans": np.where(mm == PF_MAX_RANGE_CODE, max_range, mm / 1000.0),
        "odometry": raw("odometry", "<f8").reshape(steps, 2, 3),
        "truth": raw("truth", "<f8").reshape(steps + 1, 3),
        "beam_angles": raw("beamAngles", "<f8"),
        "normal": raw("normal", "<f4").astype(np.float64),
        "offsets": raw("offsets", "<u4").reshape(steps, 3).astype(np.intp),
        "resample": raw("resample", "<f8"),
        "uniforms": raw("uniforms", "<f4").reshape(n_max, 4).astype(np.float64),
    }


def _snap(value, name, lo, hi, step):
    """A start value checked against its slider's range and rounded to the slider's step."""
    value = check.in_range(value, name, lo, hi)
    return float(min(hi, max(lo, round(round((value - lo) / step) * step + lo, 10))))


def particle_filter_live(
    odometry,
    scans,
    grid,
    beam_angles,
    alpha,
    params,
    truth,
    *,
    start="known",
    spread=(0.1, 0.1, 0.05),
    n_particles=500,
    n_max=2000,
    beams=60,
    exponent=1.0,
    step=0,
    view="map",
    rng=0,
    title="Monte Carlo localization (Table 8.2)",
    width=600,
    height=560,
) -> LiveWidget:
    r"""Return a live particle filter: MCL (Table 8.2) over a stretch of a laser log, in the page.

    The reader moves :math:`\alpha_1 \ldots \alpha_4` (the odometry model, Table 5.6),
    :math:`\sigma_{hit}`, the share :math:`z_{rand} / (z_{hit} + z_{rand})` (their sum held at
    ``params``'s), the number of beams (spread evenly by :func:`particle_filter_beams`), the
    exponent of the beam product (:func:`probrob.mcl.measurement_log_weights`) and the number
    of particles, chooses a known or a global start, and steps or plays the filter: one step
    is :func:`probrob.mcl.mcl` with the likelihood field (Table 6.3) and the low-variance
    sampler (Table 4.4). The canvas shows the map, the particles, the corrected pose
    (``truth``) and :func:`probrob.mcl.estimate_pose` with radius ``PF_RADIUS`` and
    ``PF_HEADING_BINS`` heading sectors; the text
    under it the estimate's error. Moving a slider re-runs the filter from the start to the
    step shown, on the same random numbers (:func:`particle_filter_draws`).

    The page embeds the map's cells (2 bits each) and computes the exact distance field and
    the likelihood-field table in the browser, so that the JavaScript computes what
    :mod:`probrob.mcl` computes on ``grid``: ``tests/test_live_mcl.py`` holds the two equal
    in Chromium, step by step, resampling included.

    Parameters
    ----------
    odometry : array_like, shape (T, 2, 3)
        One odometry pair per step (as :func:`probrob.mcl.run_mcl`), ``1 <= T <= 300``.
    scans : array_like, shape (T, K)
        The scan at the end of each step (m); kept to whole millimetres, and readings
        ``>= params.max_range`` as max-range readings.
    grid : OccupancyGrid
        The map (it must have an occupied and a free cell; at most 400,000 cells).
    beam_angles : array_like, shape (K,)
    alpha : array_like, shape (4,)
        Start values of :math:`\alpha_1 \ldots \alpha_4` (variance form), in [0, 0.5].
    params : BeamModelParams
        ``sigma_hit`` (in [0.01, 1] m), ``z_hit``, ``z_rand`` (their split is a slider) and
        ``max_range``.
    truth : array_like, shape (T + 1, 3)
        The reference poses (e.g. the log's corrected poses): the known start is
        ``truth[0]``, the error of step ``t`` is against ``truth[t]``.
    start : {"known", "global"}
        Start value of the start choice: ``truth[0]`` plus ``spread`` times normals, or
        :func:`probrob.mcl.uniform_particles` over ``grid.free``.
    spread : array_like, shape (3,)
        Standard deviations (m, m, rad) of the known start, each >= 0.
    n_particles : int
        Start value of the particles slider, in [100, n_max] (a multiple of 100).
    n_max : int
        Most particles (the slider's end), in [100, 5000], a multiple of 100.
    beams : int
        Start value of the beams slider, in [1, K].
    exponent : float
        Start value of the exponent slider, in [0.01, 1].
    step : int
        The step shown first, in [0, T].
    view : {"map", "robot"}
        The whole map, or a 12 m square around the reference pose.
    rng : None, int or numpy.random.Generator
        Seed of :func:`particle_filter_draws`.
    title : str
    width, height : int
        Canvas size in CSS pixels.

    Returns
    -------
    widget : LiveWidget
        Start values are rounded to their slider's step.
    """
    from .maps import _check_grid
    from .sensors import BeamModelParams

    u = check.finite(odometry, "odometry")
    if u.ndim != 3 or u.shape[1:] != (2, 3) or not 1 <= u.shape[0] <= 300:
        raise ValueError(f"odometry must have shape (T, 2, 3) with 1 <= T <= 300, got {u.shape}")
    steps = u.shape[0]
    angles = check.finite(beam_angles, "beam_angles")
    if angles.ndim != 1 or angles.size == 0:
        raise ValueError(f"beam_angles must have shape (K,) with K >= 1, got {angles.shape}")
    z = check.finite(scans, "scans")
    if z.shape != (steps, angles.size):
        raise ValueError(
            f"scans must have shape (T, K) = {(steps, angles.size)} (odometry's T, "
            f"beam_angles' K), got {z.shape}"
        )
    if np.any(z < 0):
        raise ValueError(f"scans must be non-negative ranges, got min {z.min()!r}")
    grid = _check_grid(grid)
    if grid.occupied.size > 400_000:
        raise ValueError(f"grid must have at most 400,000 cells, got {grid.occupied.size:,}")
    if not grid.occupied.any() or not grid.free.any():
        raise ValueError("grid must have an occupied cell and a free cell")
    alpha = check.alphas(alpha, "alpha", 4)
    if np.any(alpha > 0.5):
        raise ValueError(f"alpha must lie in [0, 0.5] (the sliders' range), got {alpha.tolist()}")
    if not isinstance(params, BeamModelParams):
        raise ValueError(f"params must be a BeamModelParams, got {type(params).__name__}")
    if params.z_hit + params.z_rand <= 0:
        raise ValueError("params must have z_hit + z_rand > 0 (the likelihood field's weights)")
    truth = check.poses(truth, "truth")
    if truth.shape != (steps + 1, 3):
        raise ValueError(f"truth must have shape (T + 1, 3) = {(steps + 1, 3)}, got {truth.shape}")
    check.choice(start, "start", ("known", "global"))
    check.choice(view, "view", ("map", "robot"))
    spread = check.finite(spread, "spread")
    if spread.shape != (3,) or np.any(spread < 0):
        raise ValueError(f"spread must be 3 standard deviations >= 0, got {spread.tolist()}")
    n_max = check.count(n_max, "n_max", 100)
    if n_max > 5000 or n_max % 100:
        raise ValueError(f"n_max must be a multiple of 100 in [100, 5000], got {n_max}")
    n_particles = check.count(n_particles, "n_particles", 1)
    if not 100 <= n_particles <= n_max:
        raise ValueError(f"n_particles must lie in [100, n_max = {n_max}], got {n_particles}")
    beams = check.count(beams, "beams", 1)
    if beams > angles.size:
        raise ValueError(f"beams must be at most the {angles.size} beams of a scan, got {beams}")
    step = check.count(step, "step", 0)
    if step > steps:
        raise ValueError(f"step must lie in [0, T = {steps}], got {step}")
    h_sum = params.z_hit + params.z_rand
    share = params.z_rand / h_sum
    sliders = [
        Slider("t", "step t", float(step), 0.0, float(steps), 1.0),
        *(
            Slider(f"a{k + 1}", f"α{k + 1}", _snap(a, f"alpha[{k}]", 0, 0.5, 1e-4), 0.0, 0.5, 1e-4)
            for k, a in enumerate(alpha)
        ),
        Slider(
            "sigma",
            "σ_hit [m]",
            _snap(params.sigma_hit, "params.sigma_hit", 0.01, 1.0, 0.001),
            0.01,
            1.0,
            0.001,
        ),
        Slider(
            "zrand", "z_rand share", _snap(share, "z_rand share", 0, 1, 0.001), 0.0, 1.0, 0.001
        ),
        Slider("beams", "beams", float(beams), 1.0, float(angles.size), 1.0),
        Slider("kappa", "exponent", _snap(exponent, "exponent", 0.01, 1, 0.01), 0.01, 1.0, 0.01),
        Slider(
            "n",
            "particles",
            _snap(n_particles, "n_particles", 100, n_max, 100),
            100.0,
            n_max,
            100.0,
        ),
    ]
    choices = [
        Choice("start", "start", (("known", "known pose"), ("global", "uniform (global)")), start),
        Choice("view", "view", (("map", "whole map"), ("robot", "around the robot")), view),
    ]
    draws = particle_filter_draws(n_max, steps, rng)
    h, w = grid.shape
    config = {
        "kernel": "mcl",
        "width": check.count(width, "width", 1),
        "height": check.count(height, "height", 1),
        "steps": steps,
        "beamsTotal": int(angles.size),
        "nMax": n_max,
        "sliders": [{"name": s.name, "value": s.value, "min": s.lo, "max": s.hi} for s in sliders],
        "choices": [{"name": c.name, "value": c.value} for c in choices],
        "constants": {
            "zSum": h_sum,
            "maxRange": params.max_range,
            "radius": PF_RADIUS,
            "headingBins": PF_HEADING_BINS,
            "spread": spread.tolist(),
        },
        "map": {
            "h": h,
            "w": w,
            "origin": [float(grid.origin[0]), float(grid.origin[1])],
            "resolution": float(grid.resolution),
            "cells": _pf_cells(grid),
        },
        "data": {
            "odometry": _b64(u),
            "scans": _b64_as(_pf_ranges(z, params.max_range), "<u2"),
            "truth": _b64(truth),
            "beamAngles": _b64(angles),
            "normal": _b64_as(draws["normal"], "<f4"),
            "offsets": _b64_as(draws["offsets"], "<u4"),
            "resample": _b64(draws["resample"]),
            "uniforms": _b64_as(draws["uniforms"], "<f4"),
        },
    }
    config_js = json.dumps(config, ensure_ascii=True).replace("</", "<\\/")
    wid = f"probrob-live-mcl-{next(_COUNTER)}"
    e = html.escape
    aria = (
        "Map of the building with the particle cloud of Monte Carlo localization (red dots), "
        "the reference pose (green circle) and the filter's estimate (blue arrow)."
    )
    caption = (
        f"One step of Table 8.2 per scan, {steps} scans of the log: every particle moves by the "
        "odometry model (Table 5.6) with the α of the sliders, is weighted by the likelihood "
        "field (Table 6.3) of the chosen beams, and the set is redrawn by the low-variance "
        "sampler (Table 4.4). Black: occupied cells; white: free; grey: unexplored. Green: "
        "the reference (corrected) path and pose; blue arrow: the estimate (the heaviest "
        f"cluster, {PF_RADIUS} m cells and {360 // PF_HEADING_BINS}° of heading). Moving a "
        "slider re-runs the filter from the start "
        "on the same random numbers. Step, play or drag the step slider."
    )
    return LiveWidget(
        f"""<div class="probrob-live" id="{wid}" role="group" aria-label="{e(title)}" data-size-budget="400000" data-update-budget="16">
<style>{_asset("live.css")}</style>
<div class="pl-title"><strong>{e(title)}</strong> (live: runs in this page, no kernel)</div>
<div class="pl-body">
<canvas width="{width}" height="{height}" role="img" aria-label="{e(aria)}">{e(aria)}</canvas>
<div class="pl-controls">
{_controls_html(wid, sliders, choices)}
<button type="button" data-action="step">step</button><button type="button" data-action="play" aria-pressed="false">play</button><button type="button" data-action="start">to start</button><button type="button" data-action="reset">reset</button>
<p class="pl-status" aria-live="polite"></p>
</div>
</div>
<p class="pl-caption">{e(caption)}</p>
<script>
(function () {{
"use strict";
{_asset("live.js")}
{_asset("odometry.js")}
{_asset("mcl.js")}
const config = {config_js};
const script = document.currentScript;
const root = (script && script.closest(".probrob-live")) || document.getElementById("{wid}");
mountParticleFilter(root, config);
}})();
</script>
</div>""",
        "mcl",
    )


# ---- the Turkish lecture's two noise forms side by side, and the CIR report's step (issue 17):
# kernels noise_forms.js (on velocity.js / odometry.js) and cir.js ---------------------------

__all__ += ["cir_step_live", "odometry_noise_forms_live", "velocity_noise_forms_live"]

#: How the variance form's α relate to the sliders' (the standard-deviation form's) α.
PAIRINGS = (
    ("squared", "variance form at α²: the same noise for one term"),
    ("same", "variance form at the same α"),
)


def _forms_choices(distribution, density, pairing):
    check.choice(distribution, "distribution", tuple(DISTRIBUTIONS))
    check.choice(density, "density", tuple(v for v, _ in DENSITY_MODES))
    check.choice(pairing, "pairing", tuple(v for v, _ in PAIRINGS))
    return [
        Choice("pairing", "variance form", PAIRINGS, pairing),
        Choice(
            "distribution",
            "distribution",
            tuple((k, label) for k, (label, _) in DISTRIBUTIONS.items()),
            distribution,
        ),
        Choice("density", "density", DENSITY_MODES, density),
    ]


_FORMS_CAPTION = (
    'Left: noise="std", each noise term\'s standard deviation is a sum α·|m| + …; right: '
    'noise="variance", each variance is a sum α·m² + … (with α² by default, so that a sum of '
    "one term is the same noise in both). Red: {n} samples from the same draws (the first 60 "
    "with their heading); grey: the density on a {grid} × {grid} grid, one grey scale for both "
    "(darker is more probable); black arrow: the start pose; blue arrow: the noise-free end "
    "pose. The view grows with the clouds; “fit view” zooms back in."
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
    (:func:`standard_draws`), the left one at the sliders' :math:`\alpha`, the right one at
    :math:`\alpha^2` (``pairing="squared"``: a sum of one term is then the same noise in both)
    or at the same :math:`\alpha` (``pairing="same"``). Sliders and the other choices as
    :func:`velocity_model_live`.

    Parameters
    ----------
    v, w, dt, theta : float
        Initial slider values (v, ω in [-2, 2], Δt in [0.1, 3], θ in [-3.14, 3.14]).
    alpha : array_like, shape (6,)
        Initial noise parameters of the standard-deviation form, each in [0, 0.5].
    pairing : {"squared", "same"}
    distribution : {"normal", "triangular"}
    density : {"xy", "pose", "book"}
    n_particles, grid, rng
        Particles per panel, density grid points per axis, seed of the draws. The defaults
        (1000 and 70, two panels) cost an update what :func:`velocity_model_live`'s 2000
        particles and 100 × 100 grid cost.

    Returns
    -------
    widget : LiveWidget
    """
    sliders = [
        Slider("v", "v [m/s]", _in_range(v, "v", -2, 2), -2.0, 2.0, 0.01),
        Slider("w", "ω [rad/s]", _in_range(w, "w", -2, 2), -2.0, 2.0, 0.01),
        Slider("dt", "Δt [s]", _in_range(dt, "dt", 0.1, 3), 0.1, 3.0, 0.01),
        Slider(
            "theta", "θ start [rad]", _in_range(theta, "theta", -3.14, 3.14), -3.14, 3.14, 0.01
        ),
        *_alpha_sliders(alpha, 6),
    ]
    return _noise_forms_widget(
        "velocity", sliders, distribution, density, pairing, n_particles, grid, rng,
        title="Velocity model, the two noise forms (Tables 5.1 and 5.3)",
    )  # fmt: skip


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
    rot1, trans, rot2, theta : float
        Initial slider values (rotations in [-3.14, 3.14] rad, translation in [0, 3] m).
    alpha : array_like, shape (4,)
        Initial noise parameters of the standard-deviation form, each in [0, 0.5].
    pairing, distribution, density, n_particles, grid, rng
        As for :func:`velocity_noise_forms_live`.

    Returns
    -------
    widget : LiveWidget
    """
    sliders = [
        Slider("rot1", "δrot1 [rad]", _in_range(rot1, "rot1", -3.14, 3.14), -3.14, 3.14, 0.01),
        Slider("trans", "δtrans [m]", _in_range(trans, "trans", 0, 3), 0.0, 3.0, 0.01),
        Slider("rot2", "δrot2 [rad]", _in_range(rot2, "rot2", -3.14, 3.14), -3.14, 3.14, 0.01),
        Slider(
            "theta", "θ start [rad]", _in_range(theta, "theta", -3.14, 3.14), -3.14, 3.14, 0.01
        ),
        *_alpha_sliders(alpha, 4),
    ]
    return _noise_forms_widget(
        "odometry", sliders, distribution, density, pairing, n_particles, grid, rng,
        title="Odometry model, the two noise forms (Tables 5.5 and 5.6)",
    )  # fmt: skip


def _noise_forms_widget(
    model, sliders, distribution, density, pairing, n_particles, grid, rng, *, title
):
    """The two-panel widget of ``model``'s kernel ("velocity" or "odometry") in both noise forms."""
    return live_widget(
        f"{model}_forms",
        sliders,
        _forms_choices(distribution, density, pairing),
        title=title,
        caption=_FORMS_CAPTION.format(n=n_particles, grid=grid),
        aria_label=(
            f"Two plots of the {model} motion model in the x-y plane, side by side: the "
            "standard-deviation noise form on the left and the variance form on the right, each "
            "a cloud of sampled end poses over a grey density image."
        ),
        n_particles=n_particles,
        grid=grid,
        rng=rng,
        width=660,
        height=316,
        requires=(model, "noise_forms"),
    )


def cir_step_live(*, s_sx=0.6, s_dx=0.3, wheelbase=0.4, theta=0.0) -> LiveWidget:
    r"""Return a live widget of one step about the CIR (the CIR report, eqs. 2–8).

    Sliders for the wheel arc lengths :math:`s_{sx}` (left) and :math:`s_{dx}` (right), the
    wheel base :math:`l` and the start heading :math:`\theta` (the report's convention:
    clockwise). The page computes :func:`~probrob.kinematics.cir_radius_angle`,
    :func:`~probrob.kinematics.cir_step_transform` and
    :func:`~probrob.kinematics.cir_state_function` as the library does, and draws the robot
    before (grey) and after (black) the step from the origin, the paths of both wheels and of
    the middle of the axle (the state function at the fractions ``linspace(0, 1, 61)`` of the
    step), the CIR at :math:`(0, -(r + l/2))` in the start frame and its radii; on a straight
    line (:math:`s_{sx} = s_{dx}`, :math:`r = \pm\infty`) there is no CIR, and a rotation in
    place (:math:`s_{dx} = -s_{sx}`) turns about the middle of the axle.

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
        Slider("ssx", "s_sx [m] (left)", _in_range(s_sx, "s_sx", -1, 1.5), -1.0, 1.5, 0.01),
        Slider("sdx", "s_dx [m] (right)", _in_range(s_dx, "s_dx", -1, 1.5), -1.0, 1.5, 0.01),
        Slider("l", "l [m]", _in_range(wheelbase, "wheelbase", 0.1, 1), 0.1, 1.0, 0.01),
        Slider(
            "theta", "θ start [rad]", _in_range(theta, "theta", -3.14, 3.14), -3.14, 3.14, 0.01
        ),
    ]
    return live_widget(
        "cir",
        sliders,
        title="One step about the CIR (the report's eqs. 2–8)",
        caption=(
            "Grey: the robot's axle and heading before the step, black: after it (the heading "
            "θ is clockwise, as in the report). Green and orange: the paths of the left and the "
            "right wheel; dashed: the middle of the axle. Red cross: the CIR, r from the right "
            "wheel and ρ = r + l/2 from the middle of the axle; red lines: its radii to the "
            "middle of the axle before and after. The view grows with the step; “fit view” "
            "zooms back in."
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
