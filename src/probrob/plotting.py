r"""Figures for the book: every function takes ``ax=None`` and returns the ``Axes``.

Plotting is kept apart from the maths: these functions call the models of
:mod:`probrob.motion` and :mod:`probrob.distributions` and draw what they return.
They never show a figure themselves (the caller or Jupyter does); matplotlib is imported
only when a figure is drawn.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from . import _validation as check
from .distributions import (
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
    "DISTRIBUTIONS",
    "motion_extent",
    "motion_samples",
    "plot_density_xy",
    "plot_distribution",
    "plot_motion_model",
    "plot_pose",
    "plot_samples",
]


def _sample_exact(b2, size=None, rng=None):
    return sample_normal_distribution(b2, size=size, rng=rng, method="exact")


#: The noise distributions a reader can choose: name -> (``prob``, ``sample``).
DISTRIBUTIONS: dict[str, tuple[Callable, Callable]] = {
    "normal (12 uniforms)": (prob_normal_distribution, sample_normal_distribution),
    "normal (exact)": (prob_normal_distribution, _sample_exact),
    "triangular": (prob_triangular_distribution, sample_triangular_distribution),
}

_MODELS = ("velocity", "odometry")


def _axes(ax):
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots()
    return ax


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
    ax.plot(a, prob(a, b2), color=color, lw=2, label=label)
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


def plot_density_xy(xs, ys, p, ax=None, *, cmap="Greys", vmax=None, colorbar=False):
    """Draw a density tabulated on a grid, ``p[i, j]`` at ``(xs[j], ys[i])``, in 1/m².

    The colour scale is linear from 0 to ``vmax`` (default: the 99.5th percentile of
    the finite values, so that an integrable singularity does not wash out the plot).

    Returns
    -------
    ax : matplotlib.axes.Axes
    """
    xs = check.finite(xs, "xs")
    ys = check.finite(ys, "ys")
    p = check.as_float_array(p, "p")
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
        ax.figure.colorbar(mesh, ax=ax, label="density [1/m²]")
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
    lo, hi = np.percentile(pts, 0.5, axis=0), np.percentile(pts, 99.5, axis=0)
    if len(include):
        extra = check.finite(include, "include")
        if extra.shape[-1] < 2:
            raise ValueError(
                f"include must hold points (..., 2) or poses (..., 3), got {extra.shape}"
            )
        extra = extra[..., :2].reshape(-1, 2)
        lo, hi = np.minimum(lo, extra.min(axis=0)), np.maximum(hi, extra.max(axis=0))
    centre = (lo + hi) / 2
    half = max(float(np.max(hi - lo)) / 2 * (1 + 2 * pad), min_size / 2)
    return (centre[0] - half, centre[0] + half, centre[1] - half, centre[1] + half)


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
        plot_density_xy(xs, ys, density(xy), ax=ax)
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
