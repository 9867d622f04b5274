r"""Figures for the book: every function takes ``ax=None`` and returns the ``Axes``.

Holds the book's figures and its one figure style; each function draws on ``ax`` and returns it.
Does not hold models (it calls them) or sliders and players (:mod:`probrob.widgets`).

Plotting is kept apart from the maths: these functions call the models of
:mod:`probrob.motion` and :mod:`probrob.distributions` and draw what they return.
They never show a figure themselves (the caller or Jupyter does); matplotlib is imported
only when a figure is drawn.

**One figure style for the whole book.** Every chapter calls :func:`use_book_style`
once, right after its imports::

    import matplotlib.pyplot as plt
    from probrob.plotting import use_book_style

    use_book_style()

It sizes figures for the book's text column (:data:`BOOK_FIGURE_WIDTH` inches at
:data:`BOOK_DPI` dpi, at most :data:`BOOK_COLUMN_PX` px wide, so the browser never
shrinks them) and sets font sizes so that tick labels are 9 pt = 12.5 px on the page
(at least :data:`BOOK_MIN_FONT_PX`). Keep chapter ``figsize`` widths at or below
:data:`BOOK_FIGURE_WIDTH`; for several panels use more rows rather than a wider figure.
Layout is automatic (``figure.autolayout``). Conventions for every figure:

* axes labelled with units (``"$x$ [m]"``);
* every density image has a colorbar naming the quantity and its units
  (:data:`DENSITY_XY_LABEL` for densities over the plane);
* legends placed where they cover no data (outside the axes or in an empty corner);
* the frames of one player share their axes (:func:`probrob.widgets.parameter_player`).

Diagrams: :func:`plot_velocity_geometry` (Table 5.1's circle, :math:`r^*`,
:math:`\Delta\theta`, :math:`\hat\gamma`) and :func:`plot_odometry_deltas`
(:math:`\delta_{rot1}, \delta_{trans}, \delta_{rot2}`).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from . import _validation as check
from .angles import wrap_angle
from .distributions import (
    _sample_exact_normal,
    prob_normal_distribution,
    prob_triangular_distribution,
    sample_normal_distribution,
    sample_triangular_distribution,
)
from .motion import (
    apply_odometry_deltas,
    motion_model_odometry,
    motion_model_velocity,
    odometry_deltas,
    sample_motion_model_odometry,
    sample_motion_model_velocity,
    velocity_motion,
)

__all__ = [
    "BOOK_COLUMN_PX",
    "BOOK_DPI",
    "BOOK_FIGURE_WIDTH",
    "BOOK_MIN_FONT_PX",
    "DENSITY_XY_LABEL",
    "DISTRIBUTIONS",
    "book_style",
    "motion_extent",
    "motion_samples",
    "plot_density_xy",
    "plot_distribution",
    "plot_motion_model",
    "plot_occupancy_grid",
    "plot_odometry_deltas",
    "plot_particles",
    "plot_pose",
    "plot_samples",
    "plot_velocity_geometry",
    "use_book_style",
]


#: The noise distributions a reader can choose: name -> (``prob``, ``sample``).
DISTRIBUTIONS: dict[str, tuple[Callable, Callable]] = {
    "normal (12 uniforms)": (prob_normal_distribution, sample_normal_distribution),
    "normal (exact)": (prob_normal_distribution, _sample_exact_normal),
    "triangular": (prob_triangular_distribution, sample_triangular_distribution),
}

_MODELS = ("velocity", "odometry")

_ORIENTATIONS = ("vertical", "horizontal")

#: Colorbar label of the densities over the plane (``density="xy"``).
DENSITY_XY_LABEL = "density $p(x', y')$ [1/m²]"


def _axes(ax):
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots()
    return ax


# --------------------------------------------------------------------------- book style

#: Width of the book's text column in CSS pixels at a 1280-px window (Jupyter Book 1's
#: sphinx-book-theme; measured by ``.ci/browser_check.py``), and the figure resolution
#: that maps one inch of figure to ``BOOK_DPI`` pixels of page.
BOOK_COLUMN_PX = 690
BOOK_DPI = 100
#: Default figure width in inches: a figure this wide is shown at its own size, unscaled.
BOOK_FIGURE_WIDTH = 6.8
#: Smallest text in a figure, in CSS pixels (tick labels), when shown unscaled.
BOOK_MIN_FONT_PX = 9

_BOOK_RC = {
    "figure.dpi": BOOK_DPI,
    "savefig.dpi": "figure",
    "figure.figsize": (BOOK_FIGURE_WIDTH, 4.2),
    # tight_layout at every draw: room for labels and colorbars without calling it (a
    # chapter may still call fig.tight_layout(), which then changes nothing and warns not).
    "figure.autolayout": True,
    "font.size": 10,
    "axes.titlesize": 10,
    "axes.labelsize": 10,
    "xtick.labelsize": 9,
    "ytick.labelsize": 9,
    "legend.fontsize": 9,
    "legend.framealpha": 0.9,
    "image.cmap": "Greys",
    "animation.embed_limit": 40.0,  # MB; the players embed every frame as a PNG
}


def book_style() -> dict:
    """Return the book's matplotlib settings (a dict for ``plt.rcParams.update``).

    See :func:`use_book_style`.
    """
    return dict(_BOOK_RC)


def use_book_style() -> None:
    """Set the book's figure style: figures that fit its column, with readable text.

    Every chapter calls this once, after its imports. It sets ``figure.dpi`` to
    :data:`BOOK_DPI` and the default width to :data:`BOOK_FIGURE_WIDTH` inches, so a
    figure is at most :data:`BOOK_COLUMN_PX` pixels wide and the browser shows it at
    its own size (a wider image is shrunk into the column, and its text with it); text
    sizes in points give tick labels of 9 pt = 12.5 px, title and axis labels 10 pt.
    ``figure.autolayout`` makes every figure lay itself out tightly (no
    ``fig.tight_layout()`` needed). Chapters should keep ``figsize`` widths at or
    below :data:`BOOK_FIGURE_WIDTH`; the browser check fails on any figure that the
    page shrinks.
    """
    import matplotlib.pyplot as plt  # first, so a backend's own defaults do not win

    plt.rcParams.update(_BOOK_RC)


def _colorbar(mappable, ax, label, orientation="vertical"):
    """A colorbar beside ``ax`` (vertical) or under it (horizontal), labelled ``label``."""
    kw = {"fraction": 0.046, "pad": 0.04}
    if orientation == "horizontal":
        kw = {"fraction": 0.05, "pad": 0.18, "aspect": 30}
    bar = ax.figure.colorbar(mappable, ax=ax, orientation=orientation, label=label, **kw)
    bar.ax.tick_params(labelsize="small")
    return bar


def plot_distribution(prob, b2, *, samples=None, ax=None, bins=60, label=None, color=None):
    r"""Draw the density ``prob(a, b2)``, over a histogram of ``samples`` if given.

    Parameters
    ----------
    prob : callable
        ``prob(a, b2)``, e.g. :func:`~probrob.distributions.prob_normal_distribution`.
    b2 : float
        Variance :math:`b^2 > 0`.
    samples : array_like, shape (N,), optional
        Draws to histogram (normalised to a density) under the curve.
    ax : matplotlib.axes.Axes, optional
    bins : int
        Histogram bins.
    label, color : optional
        Legend label and colour of the curve.

    Returns
    -------
    ax : matplotlib.axes.Axes
    """
    check.callable_arg(prob, "prob")
    b = np.sqrt(check.positive_scalar(b2, "b2"))
    bins = check.count(bins, "bins", 1)
    if samples is not None:
        samples = check.finite(samples, "samples")
    ax = _axes(ax)
    a = np.linspace(-4.5 * b, 4.5 * b, 601)
    if samples is not None:
        ax.hist(
            samples.ravel(),
            bins=bins,
            range=(a[0], a[-1]),
            density=True,
            color=color,
            alpha=0.35,
            label=None if label is None else f"samples, {label}",
        )
    density = check.callable_result(prob(a, b2), "prob", a.shape, prob)
    ax.plot(a, np.broadcast_to(density, a.shape), color=color, lw=2, label=label)
    ax.set_xlabel("$a$")
    ax.set_ylabel("density $p(a)$")
    return ax


def plot_pose(pose, ax=None, *, length=0.15, color="k", label=None):
    """Draw a pose ``(x, y, θ)`` as a dot with a heading arrow of ``length`` metres.

    Returns
    -------
    ax : matplotlib.axes.Axes
    """
    x, y, th = check.single_pose(pose, "pose")
    length = check.positive_scalar(length, "length")
    ax = _axes(ax)
    ax.plot([x], [y], "o", color=color, ms=5, label=label)
    ax.annotate(
        "",
        xy=(x + length * np.cos(th), y + length * np.sin(th)),
        xytext=(x, y),
        arrowprops={"arrowstyle": "->", "color": color, "lw": 1.5},
    )
    return ax


def plot_samples(
    poses, ax=None, *, color="tab:red", s=3, alpha=0.5, label=None, n_headings=0, length=0.1
):
    """Scatter the positions of sampled poses of shape ``(N, 3)`` (or ``(N, 2)``).

    With ``n_headings > 0`` the first ``n_headings`` poses also get a heading line of
    ``length`` metres, which shows the spread of :math:`\theta'`.

    Returns
    -------
    ax : matplotlib.axes.Axes
    """
    poses = check.finite(poses, "poses")
    if poses.ndim != 2 or poses.shape[1] not in (2, 3):
        raise ValueError(f"poses must have shape (N, 3) or (N, 2), got shape {poses.shape}")
    n_headings = check.count(n_headings, "n_headings", 0)
    if n_headings and poses.shape[1] != 3:
        raise ValueError("n_headings > 0 needs poses with headings, shape (N, 3)")
    ax = _axes(ax)
    ax.scatter(poses[..., 0], poses[..., 1], s=s, color=color, alpha=alpha, lw=0, label=label)
    if n_headings:
        x, y, th = (poses.reshape(-1, 3)[:n_headings, k] for k in range(3))
        segments = np.stack(
            [np.c_[x, y], np.c_[x + length * np.cos(th), y + length * np.sin(th)]], 1
        )
        from matplotlib.collections import LineCollection

        ax.add_collection(LineCollection(segments, colors=color, linewidths=0.8, alpha=0.7))
    ax.set_aspect("equal")
    ax.set_xlabel("$x$ [m]")
    ax.set_ylabel("$y$ [m]")
    return ax


def plot_density_xy(
    xs,
    ys,
    p,
    ax=None,
    *,
    cmap="Greys",
    vmax=None,
    colorbar=False,
    label=DENSITY_XY_LABEL,
    orientation="vertical",
):
    """Draw a density tabulated on a grid, ``p[i, j]`` at ``(xs[j], ys[i])``, in 1/m².

    The colour scale is linear from 0 to ``vmax`` (default: the 99.5th percentile of
    the finite values, so that an integrable singularity does not wash out the plot).
    With ``colorbar=True`` a colorbar labelled ``label`` (the quantity and its units)
    is drawn beside the axes (``orientation="vertical"``) or under them
    (``"horizontal"``).

    Returns
    -------
    ax : matplotlib.axes.Axes
    """
    xs = check.finite(xs, "xs")
    ys = check.finite(ys, "ys")
    p = check.as_float_array(p, "p")
    colorbar = check.flag(colorbar, "colorbar")
    orientation = check.choice(orientation, "orientation", _ORIENTATIONS)
    if xs.ndim != 1 or ys.ndim != 1 or p.shape != (ys.size, xs.size):
        raise ValueError(
            f"p must have shape (len(ys), len(xs)) = ({ys.size}, {xs.size}) for 1-D xs and ys, "
            f"got p {p.shape}, xs {xs.shape}, ys {ys.shape}"
        )
    if np.isnan(p).any() or (p < 0).any():
        raise ValueError("p must be a density: no NaN, no negative values")
    if vmax is not None:
        vmax = check.positive_scalar(vmax, "vmax")
    ax = _axes(ax)
    if vmax is None:
        finite = p[np.isfinite(p)]
        vmax = np.percentile(finite, 99.5) if finite.size and finite.max() > 0 else 1.0
    mesh = ax.pcolormesh(xs, ys, np.nan_to_num(p, posinf=vmax), cmap=cmap, vmin=0, vmax=vmax)
    if colorbar:
        _colorbar(mesh, ax, label, orientation)
    ax.set_aspect("equal")
    ax.set_xlabel("$x$ [m]")
    ax.set_ylabel("$y$ [m]")
    return ax


def motion_extent(points, *, include=(), pad=0.15, min_size=0.5):
    """A square box ``(x0, x1, y0, y1)`` in metres around a sample cloud.

    The box holds the central 99 % of ``points`` (shape ``(N, ≥2)``) and every point
    of ``include`` (e.g. the start and end poses), padded by ``pad`` of its size on
    each side. Use one extent for all frames of a sweep so that they are comparable.
    """
    pts = check.finite(points, "points")
    if pts.ndim < 1 or pts.shape[-1] < 2 or pts.size == 0:
        raise ValueError(
            f"points must hold at least one point, shape (N, 2) or (N, 3); got shape {pts.shape}"
        )
    pts = pts[..., :2].reshape(-1, 2)
    pad = check.finite(pad, "pad")
    min_size = check.finite(min_size, "min_size")
    if pad.ndim or pad < 0 or min_size.ndim or min_size < 0:
        raise ValueError(f"pad and min_size must be numbers >= 0, got {pad!r}, {min_size!r}")
    with np.errstate(over="ignore", invalid="ignore"):  # ±1e308 points: reported below
        lo, hi = np.percentile(pts, 0.5, axis=0), np.percentile(pts, 99.5, axis=0)
    if len(include):
        extra = check.finite(include, "include")
        if extra.shape[-1] < 2:
            raise ValueError(
                f"include must hold points (..., 2) or poses (..., 3), got {extra.shape}"
            )
        extra = extra[..., :2].reshape(-1, 2)
        lo, hi = np.minimum(lo, extra.min(axis=0)), np.maximum(hi, extra.max(axis=0))
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is reported below
        centre = (lo + hi) / 2
        half = max(float(np.max(hi - lo)) / 2 * (1 + 2 * pad), min_size / 2)
        box = (centre[0] - half, centre[0] + half, centre[1] - half, centre[1] + half)
    check.no_overflow(box, "the extent", points=pts, include=include, pad=pad)
    return box


def _model_calls(model, u_t, x_prev, alpha, dt, noise, prob, sample):
    """Density and sampler of one model as functions of (positions) and (size, rng)."""
    check.choice(model, "model", _MODELS)
    if model == "velocity":
        end = velocity_motion(x_prev, u_t, dt)

        def density(xy):
            return motion_model_velocity(
                xy, u_t, x_prev, dt, alpha, prob=prob, noise=noise, density="xy"
            )

        def draw(size, rng):
            return sample_motion_model_velocity(
                u_t, x_prev, dt, alpha, sample=sample, noise=noise, size=size, rng=rng
            )

    else:
        u = check.finite(u_t, "u_t")
        end = apply_odometry_deltas(x_prev, *odometry_deltas(u[..., 0, :], u[..., 1, :]))

        def density(xy):
            return motion_model_odometry(
                xy, u, x_prev, alpha, prob=prob, noise=noise, density="xy"
            )

        def draw(size, rng):
            return sample_motion_model_odometry(
                u, x_prev, alpha, sample=sample, noise=noise, size=size, rng=rng
            )

    return end, density, draw


def motion_samples(
    model,
    u_t,
    x_prev,
    alpha,
    *,
    n=500,
    dt=1.0,
    distribution="normal (12 uniforms)",
    noise="variance",
    rng=0,
):
    """Return ``n`` samples of a motion model, shape ``(n, 3)``, and its noise-free end pose.

    The arguments are those of :func:`plot_motion_model`.
    """
    check.choice(distribution, "distribution", tuple(DISTRIBUTIONS))
    n = check.count(n, "n", 0)
    prob, sample = DISTRIBUTIONS[distribution]
    end, _, draw = _model_calls(model, u_t, x_prev, alpha, dt, noise, prob, sample)
    return draw(n, check.rng(rng)), end


def plot_motion_model(
    model,
    u_t,
    x_prev,
    alpha,
    *,
    dt=1.0,
    distribution="normal (12 uniforms)",
    noise="variance",
    n_samples=500,
    n_headings=0,
    grid=160,
    extent=None,
    show_density=True,
    colorbar=True,
    rng=0,
    ax=None,
    title=None,
):
    r"""Draw a motion model's density over the plane and a cloud of its samples.

    The density is ``density="xy"`` of :func:`~probrob.motion.motion_model_velocity` or
    :func:`~probrob.motion.motion_model_odometry`: the density over :math:`(x', y')`
    with the heading integrated out, as in the book's Figs. 5.3 and 5.7 (grey, darker
    is more probable). The red dots are ``n_samples`` draws of
    :func:`~probrob.motion.sample_motion_model_velocity` or
    :func:`~probrob.motion.sample_motion_model_odometry` (Figs. 5.4, 5.8). Arrows:
    the start pose (black) and the noise-free end pose (blue).

    Parameters
    ----------
    model : {"velocity", "odometry"}
    u_t : array_like
        ``(v, ω)`` for the velocity model; the odometry ``(x̄_{t-1}, x̄_t)``, shape
        ``(2, 3)``, for the odometry model.
    x_prev : array_like, shape (3,)
        Start pose.
    alpha : array_like, shape (6,) or (4,)
        Noise parameters.
    dt : float
        Time step of the velocity model, s.
    distribution : str
        A key of :data:`DISTRIBUTIONS`.
    noise : {"variance", "std"}
    n_samples : int
        Samples to draw (0 for none).
    n_headings : int
        How many of the samples also show their heading :math:`\theta'` as a line.
    grid : int
        Density grid points per axis.
    extent : tuple (x0, x1, y0, y1), optional
        Plot box in metres; default around the samples and the two poses.
    show_density : bool
        Draw the density image.
    colorbar : bool or {"vertical", "horizontal"}
        Give the density image a colorbar (quantity and units, :data:`DENSITY_XY_LABEL`)
        beside the axes (``True`` or ``"vertical"``) or under them (``"horizontal"``).
    rng : None, int or numpy.random.Generator
        Seed of the samples.
    ax : matplotlib.axes.Axes, optional
    title : str, optional

    Returns
    -------
    ax : matplotlib.axes.Axes
    """
    check.choice(distribution, "distribution", tuple(DISTRIBUTIONS))
    prob, sample = DISTRIBUTIONS[distribution]
    show_density = check.flag(show_density, "show_density")
    if isinstance(colorbar, str):
        orientation = check.choice(colorbar, "colorbar", _ORIENTATIONS)
        colorbar = True
    else:
        colorbar, orientation = check.flag(colorbar, "colorbar"), "vertical"
    x_prev = check.single_pose(x_prev, "x_prev")
    n_samples = check.count(n_samples, "n_samples", 0)
    n_headings = check.count(n_headings, "n_headings", 0)
    grid = check.count(grid, "grid", 2)
    if extent is not None:
        extent = check.finite(extent, "extent")
        if extent.shape != (4,) or not (extent[0] < extent[1] and extent[2] < extent[3]):
            raise ValueError(
                f"extent must be (x0, x1, y0, y1) with x0 < x1, y0 < y1, got {extent}"
            )
    end, density, draw = _model_calls(model, u_t, x_prev, alpha, dt, noise, prob, sample)
    samples = draw(max(n_samples, 1), check.rng(rng))  # also sets the box
    ax = _axes(ax)
    if extent is None:
        extent = motion_extent(samples, include=[x_prev, end])
    x0, x1, y0, y1 = extent
    if show_density:
        xs, ys = np.linspace(x0, x1, grid), np.linspace(y0, y1, grid)
        xy = np.stack(np.meshgrid(xs, ys), axis=-1)
        plot_density_xy(xs, ys, density(xy), ax=ax, colorbar=colorbar, orientation=orientation)
    size = 0.08 * (x1 - x0)
    if n_samples:
        plot_samples(samples, ax=ax, n_headings=min(n_headings, n_samples), length=size / 2)
    plot_pose(x_prev, ax=ax, length=size)
    plot_pose(end, ax=ax, length=size, color="tab:blue")
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_xlabel("$x$ [m]")
    ax.set_ylabel("$y$ [m]")
    if title:
        ax.set_title(title)
    return ax


# --------------------------------------------------------------------------- diagrams


def _angle_arc(
    ax, centre, radius, start, sweep, *, color, label=None, lw=1.4, text_pad=1.35, away=None
):
    """Draw an arc with an arrowhead from angle ``start`` through ``sweep`` (rad) about
    ``centre``; put ``label`` just outside its middle. Returns the label's Text (or None)."""
    cx, cy = centre
    t = start + np.linspace(0.0, sweep, 60)
    xs, ys = cx + radius * np.cos(t), cy + radius * np.sin(t)
    ax.plot(xs, ys, color=color, lw=lw)
    if abs(sweep) > 1e-3:
        ax.annotate(
            "",
            xy=(xs[-1], ys[-1]),
            xytext=(xs[-4], ys[-4]),
            arrowprops={"arrowstyle": "-|>", "color": color, "lw": lw, "mutation_scale": 10},
        )
    if label is None:
        return None
    mid = start + sweep / 2
    # The text runs from its anchor in the direction ``away`` (default: out of the arc's
    # middle), so that it does not cross the lines the arc sits between.
    ux, uy = (np.cos(mid), np.sin(mid)) if away is None else away
    return ax.text(
        cx + text_pad * radius * np.cos(mid),
        cy + text_pad * radius * np.sin(mid),
        label,
        color=color,
        ha="left" if ux > 0.3 else "right" if ux < -0.3 else "center",
        va="bottom" if uy > 0.3 else "top" if uy < -0.3 else "center",
    )


def _upright_degrees(angle):
    """Text rotation in degrees, in (-90, 90], for a direction ``angle`` in rad."""
    deg = float(np.degrees(wrap_angle(angle)))
    return deg - 180 if deg > 90 else deg + 180 if deg <= -90 else deg


def _finish_diagram(ax, points, pad=0.25):
    pts = np.asarray(points, dtype=float)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    centre, half = (lo + hi) / 2, float(np.max(hi - lo)) / 2 + pad
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_aspect("equal")
    ax.set_xlabel("$x$ [m]")
    ax.set_ylabel("$y$ [m]")
    return ax


def plot_velocity_geometry(x_prev, x_t, dt=1.0, ax=None, *, arrow=None):
    r"""Draw the geometry of Table 5.1: the circle that takes ``x_prev`` towards ``x_t``.

    *Probabilistic Robotics*, Table 5.1, lines 2–8. Shown: the start pose
    :math:`x_{t-1} = (x, y, \theta)` (black) and the hypothesis
    :math:`x_t = (x', y', \theta')` (blue); the chord between the two positions and its
    perpendicular bisector, on which the table's :math:`\mu` moves the centre
    :math:`(x^*, y^*)` from the chord's midpoint; the circle tangent to the heading
    :math:`\theta` through both positions, with its radius :math:`r^*` and the turn
    :math:`\Delta\theta` seen from the centre; the heading
    :math:`\theta + \Delta\theta` at the end of the arc (dashed) and the final turn
    :math:`\hat\gamma\Delta t` from it to :math:`\theta'`. The numbers are those of
    :func:`~probrob.motion.motion_model_velocity` (signed radius, wrapped angles); on a
    straight line (:math:`\mu` infinite) no centre is drawn.

    Parameters
    ----------
    x_prev, x_t : array_like, shape (3,)
        Start pose and hypothesised end pose.
    dt : float
        Time step in s (for the printed :math:`\hat v, \hat\omega`).
    ax : matplotlib.axes.Axes, optional
    arrow : float, optional
        Length of the heading arrows in m; default a quarter of the distance moved.

    Returns
    -------
    ax : matplotlib.axes.Axes
    """
    from .motion import _invert_velocity

    x_prev, x_t = check.poses(x_prev, "x_prev"), check.poses(x_t, "x_t")
    if x_prev.shape != (3,) or x_t.shape != (3,):
        raise ValueError("x_prev and x_t must each be one pose of shape (3,)")
    dt = check.positive_scalar(dt, "dt")
    if arrow is not None:
        arrow = check.positive_scalar(arrow, "arrow")
    ax = _axes(ax)  # after the checks: a bad argument leaves no empty figure behind
    x, y, th = x_prev
    xp, yp, _ = x_t
    v_hat, w_hat, g_hat, half = (float(q) for q in _invert_velocity(x_t, x_prev, dt))
    turn = 2 * half
    dist = float(np.hypot(xp - x, yp - y))
    arrow = (0.25 * dist if dist > 0 else 0.3) if arrow is None else arrow
    points = [x_prev[:2], x_t[:2]]
    for px, py, heading in ((x, y, th), (xp, yp, x_t[2])):
        points.append([px + arrow * np.cos(heading), py + arrow * np.sin(heading)])
    ax.plot([x, xp], [y, yp], ":", color="0.45", lw=1)  # the chord
    mid = np.array([(x + xp) / 2, (y + yp) / 2])
    if abs(turn) > 1e-9:
        r = v_hat / w_hat  # signed: > 0 turns left
        centre = np.array([x - r * np.sin(th), y + r * np.cos(th)])
        rad = abs(r)
        points.append(centre)
        full = np.linspace(0, 2 * np.pi, 200)
        ax.plot(
            *(centre[:, None] + rad * np.stack([np.cos(full), np.sin(full)])),
            "--",
            color="0.8",
            lw=1,
        )
        to_start = np.arctan2(y - centre[1], x - centre[0])
        t = to_start + np.linspace(0.0, turn, 100)
        arc = np.stack([centre[0] + rad * np.cos(t), centre[1] + rad * np.sin(t)], axis=-1)
        points.extend(arc[::10])
        ax.plot(*arc.T, color="tab:blue", lw=2.2)
        ax.plot(*centre, "+", color="tab:green", ms=10, mew=2)
        ax.annotate(
            "$(x^*, y^*)$",
            centre,
            xytext=(0, 9),
            textcoords="offset points",
            ha="center",
            color="tab:green",
        )
        ax.plot([mid[0], centre[0]], [mid[1], centre[1]], ":", color="tab:green", lw=1.2)
        ax.annotate(
            "$\\mu$ (line 2)",
            mid + 0.35 * (centre - mid),
            xytext=(6, -4),
            textcoords="offset points",
            color="tab:green",
        )
        for px, py in ((x, y), (xp, yp)):
            ax.plot([centre[0], px], [centre[1], py], color="tab:orange", lw=1.2)
        to_start_deg = _upright_degrees(np.arctan2(y - centre[1], x - centre[0]))
        ax.text(
            *(centre + 0.5 * np.array([x, y] - centre)),
            f"$r^* = {rad:.2f}$ m",
            color="tab:orange",
            rotation=to_start_deg,
            rotation_mode="anchor",
            ha="center",
            va="bottom",
        )
        _angle_arc(
            ax,
            centre,
            0.22 * rad,
            to_start,
            turn,
            color="tab:orange",
            label=f"$\\Delta\\theta = {turn:.2f}$ rad",
            text_pad=1.25,
        )
    else:
        ax.plot([x, xp], [y, yp], color="tab:blue", lw=2.2)
        ax.annotate(
            "straight: $\\mu = \\pm\\infty$",
            mid,
            xytext=(0, 8),
            textcoords="offset points",
            ha="center",
            color="tab:green",
        )
    # the heading at the end of the arc, and the final turn γ̂Δt to θ'
    arc_heading = th + turn
    ax.plot(
        [xp, xp + 1.3 * arrow * np.cos(arc_heading)],
        [yp, yp + 1.3 * arrow * np.sin(arc_heading)],
        "--",
        color="tab:blue",
        lw=1,
    )
    text = _angle_arc(
        ax,
        (xp, yp),
        0.9 * arrow,
        arc_heading,
        g_hat * dt,
        color="tab:red",
        label=f"$\\hat\\gamma\\Delta t = {g_hat * dt:.2f}$ rad",
        text_pad=1.2,
    )
    points.append(text.get_position())
    plot_pose(x_prev, ax=ax, length=arrow)
    plot_pose(x_t, ax=ax, length=arrow, color="tab:blue")
    ax.annotate("$x_{t-1}$", (x, y), xytext=(-6, -14), textcoords="offset points", ha="right")
    ax.annotate(
        "$x_t$", (xp, yp), xytext=(-8, 6), textcoords="offset points", ha="right", color="tab:blue"
    )
    ax.set_title(
        f"$\\hat v = {v_hat:.2f}$ m/s, $\\hat\\omega = {w_hat:.2f}$ rad/s, "
        f"$\\hat\\gamma = {g_hat:.2f}$ rad/s ($\\Delta t = {dt:g}$ s)"
    )
    return _finish_diagram(ax, points, pad=0.2 * max(dist, 0.5))


def plot_odometry_deltas(xbar_prev, xbar_t, ax=None, *, arrow=None, hat=False):
    r"""Draw :math:`\delta_{rot1}, \delta_{trans}, \delta_{rot2}` between two poses.

    *Probabilistic Robotics*, Table 5.5, lines 2–4 (Fig. 5.7's decomposition): turn by
    :math:`\delta_{rot1}` from the heading :math:`\bar\theta` towards the end position,
    drive :math:`\delta_{trans}` in a straight line, turn by :math:`\delta_{rot2}` to
    :math:`\bar\theta'`. The numbers are :func:`~probrob.motion.odometry_deltas` (wrapped).

    Parameters
    ----------
    xbar_prev, xbar_t : array_like, shape (3,)
        The two poses (e.g. odometry readings :math:`\bar x_{t-1}, \bar x_t`).
    ax : matplotlib.axes.Axes, optional
    arrow : float, optional
        Length of the heading arrows in m; default a quarter of :math:`\delta_{trans}`.
    hat : bool
        Label a hypothesis instead: :math:`\hat\delta` between :math:`x_{t-1}, x_t`
        (Table 5.5, lines 5–7) rather than :math:`\delta` between
        :math:`\bar x_{t-1}, \bar x_t`.

    Returns
    -------
    ax : matplotlib.axes.Axes
    """
    a, b = check.poses(xbar_prev, "xbar_prev"), check.poses(xbar_t, "xbar_t")
    if a.shape != (3,) or b.shape != (3,):
        raise ValueError("xbar_prev and xbar_t must each be one pose of shape (3,)")
    hat = check.flag(hat, "hat")
    if arrow is not None:
        arrow = check.positive_scalar(arrow, "arrow")
    ax = _axes(ax)  # after the checks: a bad argument leaves no empty figure behind
    rot1, trans, rot2 = (float(d) for d in odometry_deltas(a, b))
    arrow = (0.25 * trans if trans > 0 else 0.3) if arrow is None else arrow
    travel = a[2] + rot1
    d = "\\hat\\delta" if hat else "\\delta"
    name = "x" if hat else "\\bar x"
    right = np.array([np.sin(travel), -np.cos(travel)])  # normal to the right of travel
    ax.plot(
        [a[0], a[0] + 1.6 * arrow * np.cos(a[2])],
        [a[1], a[1] + 1.6 * arrow * np.sin(a[2])],
        "--",
        color="0.4",
        lw=1,
    )
    ax.plot([a[0], b[0]], [a[1], b[1]], color="tab:orange", lw=2)
    mid = (a[:2] + b[:2]) / 2
    normal = np.array([-np.sin(travel), np.cos(travel)])
    ax.annotate(
        f"${d}_{{trans}} = {trans:.2f}$ m",
        mid + 0.1 * (b[:2] - a[:2]),
        xytext=tuple(10 * normal),
        textcoords="offset points",
        ha="center",
        va="center",
        color="tab:orange",
        rotation=_upright_degrees(travel),
        rotation_mode="anchor",
    )
    ax.plot(
        [b[0], b[0] + 1.6 * arrow * np.cos(travel)],
        [b[1], b[1] + 1.6 * arrow * np.sin(travel)],
        "--",
        color="0.4",
        lw=1,
    )
    texts = [
        _angle_arc(
            ax,
            a[:2],
            1.4 * arrow,
            a[2],
            rot1,
            color="tab:green",
            label=f"${d}_{{rot1}} = {rot1:.2f}$ rad",
            text_pad=1.15,
            away=tuple(right * (1 if rot1 >= 0 else -1)),
        ),
        _angle_arc(
            ax,
            b[:2],
            1.4 * arrow,
            travel,
            rot2,
            color="tab:red",
            label=f"${d}_{{rot2}} = {rot2:.2f}$ rad",
            text_pad=1.15,
            away=tuple(right * (-1 if rot2 >= 0 else 1)),
        ),
    ]
    plot_pose(a, ax=ax, length=arrow)
    plot_pose(b, ax=ax, length=arrow, color="tab:blue")
    ax.annotate(
        f"${name}_{{t-1}}$", a[:2], xytext=(-6, -14), textcoords="offset points", ha="right"
    )
    ax.annotate(
        f"${name}_t$", b[:2], xytext=(6, -14), textcoords="offset points", color="tab:blue"
    )
    points = [a[:2], b[:2]] + [t.get_position() for t in texts]
    return _finish_diagram(ax, points, pad=1.2 * arrow)


# --------------------------------------------------------------------------- maps and particles
def plot_occupancy_grid(grid, ax=None, *, unexplored=True):
    """Draw an occupancy grid: occupied cells black, free cells white, unexplored cells grey.

    Parameters
    ----------
    grid : probrob.maps.OccupancyGrid
    ax : matplotlib Axes, optional
    unexplored : bool
        Shade the cells that are neither free nor occupied (:attr:`OccupancyGrid.free`).

    Returns
    -------
    ax : matplotlib Axes
        In metres, equal aspect, labelled.
    """
    from .maps import _check_grid

    grid = _check_grid(grid)
    unexplored = check.flag(unexplored, "unexplored")
    ax = _axes(ax)
    shade = np.where(grid.occupied, 1.0, 0.0)
    if unexplored:
        shade = np.where(~grid.occupied & ~grid.free, 0.25, shade)
    ax.imshow(
        shade, origin="lower", extent=grid.extent, cmap="Greys", vmin=0.0, vmax=1.0,
        interpolation="nearest",
    )  # fmt: skip
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    return ax


def plot_particles(particles, ax=None, *, color="tab:red", size=2.0, alpha=0.5, label=None):
    """Scatter the positions of a particle set ``(N, 3)`` (headings are not drawn).

    Returns
    -------
    ax : matplotlib Axes
    """
    x = check.poses(particles, "particles")
    if x.ndim != 2 or x.shape[0] == 0:
        raise ValueError(f"particles must have shape (N, 3) with N >= 1, got {x.shape}")
    ax = _axes(ax)
    ax.scatter(x[:, 0], x[:, 1], s=size, c=color, alpha=alpha, lw=0, label=label)
    return ax
