r"""Sliders for Jupyter and kernel-free players for the static book.

Holds the Jupyter sliders and the kernel-free players of the chapters.
Does not hold the models or figures they show (:mod:`probrob.motion`, :mod:`probrob.plotting`).

* :func:`velocity_model_explorer`, :func:`odometry_model_explorer` — live
  ``ipywidgets`` sliders for every :math:`\alpha`, the motion, the noise distribution
  and the noise form. They need a running kernel: in the HTML book they do nothing,
  so chapters hide their output there and show players instead.
* :func:`parameter_player` — the book's one kernel-free player: a
  ``matplotlib.animation.FuncAnimation`` of a chapter's ``draw(ax, value)`` over the
  values to sweep, rendered with ``to_jshtml()`` (self-contained HTML/JavaScript, the
  frames embedded as PNGs), with axes fixed across frames, an ``alt`` text and a
  labelled slider. It works offline, without a kernel. Chapters use it for any sweep
  (a noise parameter, a sensor's σ, a filter's weight)::

      def draw(ax, sigma):
          plot_something(..., sigma=sigma, ax=ax)


      parameter_player(draw, np.linspace(0.1, 1.0, 6), label="σ")

* :func:`alpha_player` — its thin case for the motion models: sweeps one
  :math:`\alpha` of :func:`probrob.plotting.plot_motion_model`.
* the live widgets (``velocity_model_live``, ..., ``particle_filter_live``): kernel-free
  sliders that recompute a table in the reader's browser, made by :mod:`probrob.live` and
  re-exported here, the names the chapters call.

The callbacks are thin: they call :func:`probrob.plotting.plot_motion_model`, which
calls the models. ``ipywidgets`` and ``IPython`` are imported only when used.
"""

from __future__ import annotations

import base64
import re
import tempfile
from pathlib import Path

import numpy as np

from . import _validation as check
from .live import (
    beam_model_live,
    cir_step_live,
    distribution_live,
    ekf_step_live,
    landmark_model_live,
    live_widget,
    odometry_model_live,
    odometry_noise_forms_live,
    particle_filter_live,
    velocity_model_live,
    velocity_noise_forms_live,
)
from .plotting import DISTRIBUTIONS, motion_extent, motion_samples, plot_motion_model

# with the live widgets of probrob.live (live_widget and the *_live names), re-exported
__all__ = [
    "alpha_player",
    "beam_model_live",
    "cir_step_live",
    "distribution_live",
    "ekf_step_live",
    "landmark_model_live",
    "live_widget",
    "odometry_model_explorer",
    "odometry_model_live",
    "odometry_noise_forms_live",
    "parameter_player",
    "particle_filter_live",
    "velocity_model_explorer",
    "velocity_model_live",
    "velocity_noise_forms_live",
]

_CDN_STYLESHEET = re.compile(r"<link\s+rel=\"stylesheet\"\s+href=\"https?://[^\"]*\"\s*/?>")


def _slider(description, value, lo, hi, step, fmt=".3f", *, name=None):
    """A float slider; a start ``value`` outside ``[lo, hi]`` raises (ipywidgets would clamp)."""
    import ipywidgets as w

    value = check.in_range(value, name or description, lo, hi)
    return w.FloatSlider(
        value=value,
        min=lo,
        max=hi,
        step=step,
        description=description,
        continuous_update=False,
        readout_format=fmt,
        style={"description_width": "initial"},
    )


def _explorer_start(alpha, count, x_prev, n_samples, rng):
    """Check an explorer's start values; return its ``count`` α sliders, ``x_prev``, ``n_samples``."""
    alpha = check.alphas(alpha, "alpha", count)
    x_prev = check.single_pose(x_prev, "x_prev")
    n_samples = check.count(n_samples, "n_samples", 0)
    check.rng(rng)  # rejects a bad seed now, not at the first redraw inside the widget
    controls = {
        f"a{k + 1}": _slider(f"α{k + 1}", alpha[k], 0.0, 0.5, 0.005, name=f"alpha[{k}]")
        for k in range(count)
    }
    return controls, x_prev, n_samples


def _common_controls(distribution, noise):
    import ipywidgets as w

    check.choice(distribution, "distribution", tuple(DISTRIBUTIONS))
    check.choice(noise, "noise", ("variance", "std"))
    return {
        "distribution": w.Dropdown(
            options=list(DISTRIBUTIONS),
            value=distribution,
            description="noise distribution",
            style={"description_width": "initial"},  # the whole label, not "noise dist..."
        ),
        "noise": w.ToggleButtons(
            options=[("α·m² is a variance", "variance"), ("α·|m| is a std", "std")],
            value=noise,
            description="noise form",
        ),
    }


def _explorer(controls: dict, draw, columns: list[list[str]]):
    """Lay out ``controls`` in ``columns`` above one figure that ``draw(ax, **values)`` fills."""
    import ipywidgets as w
    import matplotlib.pyplot as plt
    from IPython.display import display

    out = w.Output()

    def redraw(**values):
        fig, ax = plt.subplots(figsize=(6.4, 5.2))
        draw(ax, **values)
        fig.tight_layout()
        with out:
            out.clear_output(wait=True)
            display(fig)
        plt.close(fig)

    w.interactive_output(redraw, controls)
    boxes = [w.VBox([controls[name] for name in column]) for column in columns]
    return w.VBox([w.HBox(boxes), out])


def velocity_model_explorer(
    *,
    x_prev=(0.0, 0.0, 0.0),
    v=1.0,
    w=0.5,
    dt=1.0,
    alpha=(0.02, 0.02, 0.02, 0.02, 0.02, 0.02),
    distribution="normal (12 uniforms)",
    noise="variance",
    n_samples=500,
    rng=0,
):
    r"""Return live sliders for the velocity motion model (Tables 5.1 and 5.3).

    Sliders: :math:`\alpha_1 \ldots \alpha_6`, :math:`v` (m/s), :math:`\omega` (rad/s)
    and :math:`\Delta t` (s); a menu for the noise distribution and buttons for the
    noise form. The figure shows :func:`~probrob.plotting.plot_motion_model`.

    Returns
    -------
    widget : ipywidgets.VBox
        Display it as the last expression of a cell.
    """
    controls, x_prev, n_samples = _explorer_start(alpha, 6, x_prev, n_samples, rng)
    controls |= {
        "v": _slider("v [m/s]", v, -2.0, 2.0, 0.05, ".2f", name="v"),
        "w": _slider("ω [rad/s]", w, -2.0, 2.0, 0.05, ".2f", name="w"),
        "dt": _slider("Δt [s]", dt, 0.1, 3.0, 0.1, ".1f", name="dt"),
    }
    controls |= _common_controls(distribution, noise)

    def draw(ax, a1, a2, a3, a4, a5, a6, v, w, dt, distribution, noise):
        plot_motion_model(
            "velocity",
            [v, w],
            x_prev,
            [a1, a2, a3, a4, a5, a6],
            dt=dt,
            distribution=distribution,
            noise=noise,
            n_samples=n_samples,
            n_headings=60,
            rng=rng,
            ax=ax,
            title=f"velocity model: v = {v:.2f} m/s, ω = {w:.2f} rad/s, Δt = {dt:.1f} s",
        )

    columns = [["a1", "a2", "a3", "a4", "a5", "a6"], ["v", "w", "dt", "distribution", "noise"]]
    return _explorer(controls, draw, columns)


def odometry_model_explorer(
    *,
    x_prev=(0.0, 0.0, 0.0),
    rot1=0.4,
    trans=1.0,
    rot2=-0.3,
    alpha=(0.05, 0.005, 0.05, 0.005),
    distribution="normal (12 uniforms)",
    noise="variance",
    n_samples=500,
    rng=0,
):
    r"""Return live sliders for the odometry motion model (Tables 5.5 and 5.6).

    Sliders: :math:`\alpha_1 \ldots \alpha_4` and the odometry's own motion
    :math:`\delta_{rot1}, \delta_{trans}, \delta_{rot2}`; the robot starts at
    ``x_prev`` and the odometry frame at the origin.

    Returns
    -------
    widget : ipywidgets.VBox
    """
    from .motion import apply_odometry_deltas

    controls, x_prev, n_samples = _explorer_start(alpha, 4, x_prev, n_samples, rng)
    controls |= {
        "rot1": _slider("δrot1 [rad]", rot1, -3.1, 3.1, 0.05, ".2f", name="rot1"),
        "trans": _slider("δtrans [m]", trans, 0.0, 3.0, 0.05, ".2f", name="trans"),
        "rot2": _slider("δrot2 [rad]", rot2, -3.1, 3.1, 0.05, ".2f", name="rot2"),
    }
    controls |= _common_controls(distribution, noise)
    origin = np.zeros(3)

    def draw(ax, a1, a2, a3, a4, rot1, trans, rot2, distribution, noise):
        u_t = np.stack([origin, apply_odometry_deltas(origin, rot1, trans, rot2)])
        plot_motion_model(
            "odometry",
            u_t,
            x_prev,
            [a1, a2, a3, a4],
            distribution=distribution,
            noise=noise,
            n_samples=n_samples,
            n_headings=60,
            rng=rng,
            ax=ax,
            title=f"odometry model: δ = ({rot1:.2f} rad, {trans:.2f} m, {rot2:.2f} rad)",
        )

    columns = [["a1", "a2", "a3", "a4"], ["rot1", "trans", "rot2", "distribution", "noise"]]
    return _explorer(controls, draw, columns)


def _player_limits(draw, values, figsize, dpi):
    """The union of the data limits that ``draw`` gives each value (a dry run, no pixels)."""
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=figsize, dpi=dpi)
    lo, hi = np.full(2, np.inf), np.full(2, -np.inf)
    try:
        for value in values:
            fig.clear()
            ax = fig.add_subplot()
            draw(ax, value)
            (x0, x1), (y0, y1) = sorted(ax.get_xlim()), sorted(ax.get_ylim())
            lo, hi = np.minimum(lo, [x0, y0]), np.maximum(hi, [x1, y1])
    finally:
        plt.close(fig)
    return (lo[0], hi[0]), (lo[1], hi[1])


def _first_frame_size(page: str) -> tuple[int, int]:
    """Width and height in pixels of the first PNG frame embedded in a player's HTML (read from
    the PNG's IHDR header)."""
    match = re.search(r"data:image/png;base64,([A-Za-z0-9+/]{32})", page)
    if match is None:
        raise RuntimeError("the player's HTML holds no PNG frame")
    header = base64.b64decode(match[1])
    return int.from_bytes(header[16:20], "big"), int.from_bytes(header[20:24], "big")


def _figsize(figsize) -> tuple[float, float]:
    """A figure size: (width, height), two positive numbers of inches."""
    size = check.finite(figsize, "figsize")
    if size.shape != (2,) or np.any(size <= 0):
        raise ValueError(f"figsize must be (width, height) > 0 in inches, got {figsize!r}")
    return float(size[0]), float(size[1])


def parameter_player(
    draw,
    values,
    *,
    label,
    xlim=None,
    ylim=None,
    fixed_axes=True,
    figsize=(5.6, 4.2),
    dpi=None,
    interval=700,
    fmt=".3g",
    alt=None,
):
    r"""Return a kernel-free player of ``draw(ax, value)`` for each of ``values``.

    The one player factory of the book: a chapter passes a function that draws one
    frame on a fresh ``Axes`` (calling :mod:`probrob.plotting`, which calls the
    models) and the values of the parameter to sweep. The player is what
    ``matplotlib.animation.FuncAnimation(...).to_jshtml()`` makes (written by
    matplotlib's ``HTMLWriter``, drawing each frame once): self-contained HTML and
    JavaScript with every frame embedded as a PNG, which runs offline in any browser,
    with no kernel and no network (the Font Awesome stylesheet that ``to_jshtml``
    links from a CDN is removed; the book's theme ships the icons). The frame image
    gets an ``alt`` text and the frame slider an ``aria-label``.

    All frames share their axes, so a reader sees the picture change, not the scale:
    ``xlim`` and ``ylim`` if given, else (``fixed_axes=True``) the union of the limits
    that ``draw`` sets or autoscales to over all values (found by a dry run that
    draws every frame once more without rendering it). Each frame without a title of
    its own is titled ``f"{label} = {value:{fmt}}"``.

    Parameters
    ----------
    draw : callable
        ``draw(ax, value)``; draws one frame. It may add colorbars (the figure is
        cleared between frames).
    values : array_like, shape (F,)
        The swept values, one frame each.
    label : str
        Name of the swept parameter, for titles and the accessible labels.
    xlim, ylim : (float, float), optional
        Axis limits shared by every frame.
    fixed_axes : bool
        Without ``xlim``/``ylim``, share the union of the frames' limits (default) or
        let each frame scale itself (``False``).
    figsize : (float, float)
        Frame size in inches; keep the width at most
        :data:`probrob.plotting.BOOK_FIGURE_WIDTH`.
    dpi : float, optional
        Resolution; default :data:`probrob.plotting.BOOK_DPI`.
    interval : int
        Milliseconds per frame when playing.
    fmt : str
        Format of the value in the default titles.
    alt : str, optional
        Text alternative of the player's image; default names the sweep.

    Returns
    -------
    player : IPython.display.HTML
        Display it (last expression of a cell, or ``display(player)``).
    """
    import html as html_lib

    import matplotlib.pyplot as plt
    from IPython.display import HTML
    from matplotlib.animation import HTMLWriter

    from .plotting import BOOK_DPI

    check.callable_arg(draw, "draw")
    values = list(np.asarray(values).ravel()) if np.ndim(values) else None
    if not values:
        raise ValueError("values must be a non-empty 1-D sequence of values to sweep")
    if not isinstance(label, str) or not label:
        raise ValueError(f"label must be a non-empty string, got {label!r}")
    dpi = BOOK_DPI if dpi is None else check.positive_scalar(dpi, "dpi")
    interval = check.positive_scalar(interval, "interval")
    figsize = _figsize(figsize)
    fixed_axes = check.flag(fixed_axes, "fixed_axes")
    if fixed_axes and (xlim is None or ylim is None):
        auto_x, auto_y = _player_limits(draw, values, figsize, dpi)
        xlim = auto_x if xlim is None else xlim
        ylim = auto_y if ylim is None else ylim
    fig = plt.figure(figsize=figsize, dpi=dpi)

    def frame(k):
        fig.clear()
        ax = fig.add_subplot()
        draw(ax, values[k])
        if xlim is not None:
            ax.set_xlim(*xlim)
        if ylim is not None:
            ax.set_ylim(*ylim)
        if not ax.get_title():
            ax.set_title(f"{label} = {values[k]:{fmt}}")

    # What FuncAnimation.to_jshtml does, without its extra full redraw of every frame
    # before the frame is saved: the HTMLWriter saves each frame once, as a PNG.
    writer = HTMLWriter(fps=1000 / interval, embed_frames=True, default_mode="once")
    try:
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp, "player.html")
            with writer.saving(fig, path, dpi=dpi):
                for k in range(len(values)):
                    frame(k)
                    writer.grab_frame()
            page = path.read_text(encoding="utf-8")
    finally:
        plt.close(fig)
    # to_jshtml links Font Awesome from a CDN for its button icons; the book's theme ships
    # Font Awesome itself, and a page that works offline must not reach out.
    page = _CDN_STYLESHEET.sub("", page)
    if alt is None:
        alt = (
            f"Player: {label} swept over {len(values)} frames, from "
            f"{values[0]:{fmt}} to {values[-1]:{fmt}}"
        )
    alt = html_lib.escape(alt, quote=True)
    # The frame's size in the <img> itself (no layout shift when the first frame arrives), as a
    # block of the column's width at most: on a phone the frame scales down with its box.
    width, height = _first_frame_size(page)
    page = page.replace(
        '<img id="_anim_img',
        f'<img alt="{alt}" width="{width}" height="{height}" '
        'style="display: block; max-width: 100%; height: auto" id="_anim_img',
        1,
    )
    slider = html_lib.escape(f"frame of the {label} sweep", quote=True)
    page = page.replace(
        '<input id="_anim_slider', f'<input aria-label="{slider}" id="_anim_slider', 1
    )
    # matplotlib names the loop-mode <form> ("Repetition mode"), which makes it a form landmark:
    # several players on a page then have landmarks of one name (axe "landmark-unique"). It is
    # a row of radio buttons, not a region a reader navigates to (its title stays a tooltip).
    page = page.replace(
        '<form title="Repetition mode" aria-label="Repetition mode"',
        '<form title="Repetition mode" role="none"',
        1,
    )
    return HTML(page)


def alpha_player(
    model,
    index,
    values,
    *,
    alpha,
    u_t,
    x_prev=(0.0, 0.0, 0.0),
    dt=1.0,
    n_samples=400,
    grid=120,
    rng=0,
    figsize=(5.6, 4.2),
    dpi=None,
    interval=700,
    **plot_kw,
):
    r"""Return a kernel-free player that sweeps :math:`\alpha_{index}` over ``values``.

    A thin case of :func:`parameter_player`: each frame is
    :func:`~probrob.plotting.plot_motion_model` (density with its colorbar, samples,
    start and noise-free end pose) with one noise parameter replaced. All frames
    share one plot box, which holds the sample clouds of every frame, so a reader
    sees the cloud grow rather than the axes rescale.

    Parameters
    ----------
    model : {"velocity", "odometry"}
    index : int
        Which :math:`\alpha` to sweep, 1-based as in the book.
    values : array_like, shape (F,)
        Its value in each of the F frames.
    alpha : array_like, shape (6,) or (4,)
        The other noise parameters.
    u_t, x_prev, dt
        As for :func:`~probrob.plotting.plot_motion_model`.
    n_samples, grid, rng, figsize, dpi, interval
        Samples per frame, density grid, seed, figure size (in), resolution (default
        the book's), and milliseconds per frame.
    **plot_kw
        Passed on to :func:`~probrob.plotting.plot_motion_model` (``distribution``,
        ``noise``).

    Returns
    -------
    player : IPython.display.HTML
    """
    n_samples = check.count(n_samples, "n_samples", 1)
    interval = check.positive_scalar(interval, "interval")
    alpha = check.finite(alpha, "alpha")
    if alpha.ndim != 1 or np.any(alpha < 0):
        raise ValueError(f"alpha must be non-negative noise parameters, got {alpha.tolist()}")
    values = check.finite(values, "values")
    if values.ndim != 1 or values.size == 0 or np.any(values < 0):
        raise ValueError("values must be a non-empty 1-D sequence of non-negative numbers")
    if not (isinstance(index, int | np.integer) and 1 <= index <= alpha.size):
        raise ValueError(f"index must be an integer in 1..{alpha.size}, got {index!r}")

    def with_value(value):
        a = alpha.copy()
        a[index - 1] = value
        return a

    common = {"dt": dt, "distribution": plot_kw.get("distribution", "normal (12 uniforms)")}
    common["noise"] = plot_kw.get("noise", "variance")
    clouds = [
        motion_samples(model, u_t, x_prev, with_value(v), n=n_samples, rng=rng, **common)
        for v in values
    ]
    x0, x1, y0, y1 = motion_extent(
        np.concatenate([c for c, _ in clouds]), include=[x_prev, clouds[0][1]]
    )

    def draw(ax, value):
        plot_motion_model(
            model,
            u_t,
            x_prev,
            with_value(value),
            n_samples=n_samples,
            n_headings=60,
            grid=grid,
            extent=(x0, x1, y0, y1),
            rng=rng,
            ax=ax,
            title=f"{model} model, α{index} = {value:.3g}",
            **common,
        )

    return parameter_player(
        draw,
        values,
        label=f"α{index}",
        xlim=(x0, x1),
        ylim=(y0, y1),
        figsize=figsize,
        dpi=dpi,
        interval=interval,
        alt=(
            f"Player: the {model} model's density and samples as α{index} goes from "
            f"{values[0]:.3g} to {values[-1]:.3g} in {len(values)} frames"
        ),
    )
