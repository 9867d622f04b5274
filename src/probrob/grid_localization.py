r"""Grid localization: the histogram filter over a grid of poses (*Probabilistic Robotics*, Table 8.1).

Holds the grid of poses (:class:`PoseGrid`), the motion kernel of line 3
(:func:`motion_kernel`, :class:`MotionKernel`), line 3 alone (:func:`grid_prediction`) and
the whole update (:func:`grid_localization`). Does not hold the models it uses: the odometry
motion model is :mod:`probrob.motion` (Tables 5.5, 5.6), the likelihood field and its
tempering are :mod:`probrob.sensors` (Table 6.3) through
:func:`probrob.mcl.measurement_log_weights`, the map is :mod:`probrob.maps`.

Table 8.1 (Sec. 8.2), for all cells :math:`k` of a grid over :math:`(x, y, \theta)`:

.. math::
    \bar p_{k,t} &= \sum_i p_{i,t-1}\,
        \mathbf{motion\_model}(\mathrm{mean}(\mathbf x_k), u_t, \mathrm{mean}(\mathbf x_i))
        \qquad &\text{(line 3)}\\
    p_{k,t} &= \eta\ \mathbf{measurement\_model}(z_t, \mathrm{mean}(\mathbf x_k), m)\ \bar p_{k,t}
        \qquad &\text{(line 4)}

Conventions. A belief is an array of shape ``(ny, nx, n_headings)``: ``belief[i, j, k]`` is
the probability of the cell of row ``i`` (y), column ``j`` (x) and heading bin ``k``, with
the rows and columns of the map (:class:`~probrob.maps.OccupancyGrid`) at the pose grid's own
resolution, from the map's origin. Heading bin ``k`` is centred on
:math:`\theta_k = -\pi + k\,\Delta\theta`, :math:`\Delta\theta = 2\pi / n_{headings}`
(so bin 0 straddles :math:`\pm\pi`, and :math:`\theta = 0` is a centre when the number of
bins is even). The state space is the set of cells whose centre lies in a free cell of the
map (:attr:`PoseGrid.mask`); every other cell holds probability 0. ``u`` is an odometry pair
``(2, 3)`` as in :mod:`probrob.mcl`; ``alpha`` the four odometry noise parameters (variance
form, normal noise).

The rules of the discretisation (each is a choice; the docstrings say why):

* line 3 is the mid-point rule: the transition from cell :math:`i` to cell :math:`k` is the
  density :math:`p(x_t \mid u_t, x_{t-1})` of the odometry sampler
  (``motion_model_odometry(..., density="pose")``) between the two centres, times the
  cell's volume :math:`r^2 \Delta\theta`, over a window of offsets, normalised to sum 1 per
  source (:func:`motion_kernel`, which also offers the cells' probabilities under the
  sampler by quadrature: better when the noise is narrower than a cell);
* probability that line 3 carries onto a cell outside the state space (occupied, unexplored
  or off the grid) is dropped: the robot cannot be there; line 4's :math:`\eta` renormalises;
* line 4 weighs in log space (the tempered likelihood field of
  :func:`probrob.mcl.measurement_log_weights`) and normalises by log-sum-exp, so a scan of
  many beams never underflows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view
from scipy.special import logsumexp, ndtri

from . import _validation as check
from .maps import OccupancyGrid, _check_grid
from .mcl import _exponent, _odometry_pair, _params, _scan, measurement_log_weights
from .motion import _odometry_variances, apply_odometry_deltas, motion_model_odometry
from .motion import odometry_deltas as _odometry_deltas

__all__ = [
    "KernelBlock",
    "MotionKernel",
    "PoseGrid",
    "grid_localization",
    "grid_prediction",
    "motion_kernel",
]

_TWO_PI = 2.0 * math.pi
# A belief must sum to 1 within this (it is renormalised by every update anyway).
_SUM_TOLERANCE = 1e-6
# More cells than this (8 bytes each: 1.6 GB a belief) is a mistake, not a grid.
_MAX_CELLS = 200_000_000
# Nodes per axis of the polar mid-point rule in the source's own (x, y) cell.
_OWN_CELL_NODES = 32
# Equal-probability nodes per random noise term of the quadrature rule: with one or two
# random terms (a motion with a zero variance), and with three.
_QUADRATURE_NODES = 64
_QUADRATURE_NODES_3D = 32
_RULES = ("mid-point", "quadrature")
# The most offsets per source heading the mid-point rule evaluates (a few hundred MB).
_MAX_WINDOW = 10_000_000
# Sources gathered at once in line 3 (4 MB of float64: they stay in the cache).
_GATHER_ELEMENTS = 1 << 19


def _readonly(*arrays):
    for a in arrays:
        a.flags.writeable = False


# ---------------------------------------------------------------------- the grid of poses
@dataclass(frozen=True, eq=False)
class PoseGrid:
    r"""The grid of poses :math:`(x, y, \theta)` of grid localization, over a map.

    Cells of side ``resolution`` from the map's origin cover the map's extent (the last row
    and column may reach past it), times ``n_headings`` heading bins. The state space is
    the set of cells whose centre lies in a free cell of the map (``grid.free``, as
    :meth:`~probrob.maps.OccupancyGrid.world_to_cell` finds it): the robot is never in an
    occupied or unexplored cell. *Probabilistic Robotics*, Sec. 8.2 (the grid of Table 8.1).

    Parameters
    ----------
    grid : OccupancyGrid
        The map :math:`m`.
    resolution : float
        Side of an (x, y) cell in metres (> 0), e.g. 0.2.
    n_headings : int
        Number of heading bins (>= 1), e.g. 36 (10° bins).

    Attributes
    ----------
    mask : ndarray of bool, shape (ny, nx), read-only
        The (x, y) cells of the state space.
    headings : ndarray, shape (n_headings,), read-only
        The bin centres :math:`-\pi + k\,2\pi/n_{headings}`.
    """

    grid: OccupancyGrid
    resolution: float = 0.2
    n_headings: int = 36
    mask: np.ndarray = field(init=False, repr=False)
    headings: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        grid = _check_grid(self.grid)
        res = check.positive_scalar(self.resolution, "resolution")
        n = check.count(self.n_headings, "n_headings", 1)
        x_min, x_max, y_min, y_max = grid.extent
        # Cells to cover the extent; the relative 1e-12 keeps an exact multiple (4 m at
        # 0.2 m, computed as 20.000000000000004) from growing a row past the map.
        with np.errstate(over="ignore"):
            nx_f = (x_max - x_min) / res * (1.0 - 1e-12)
            ny_f = (y_max - y_min) / res * (1.0 - 1e-12)
        if not nx_f * ny_f * n <= _MAX_CELLS:
            raise ValueError(
                f"resolution {res!r} m and n_headings {n} make {ny_f:.3g} x {nx_f:.3g} x {n} "
                f"cells, more than {_MAX_CELLS:.0e}: use a coarser grid"
            )
        nx, ny = math.ceil(nx_f), math.ceil(ny_f)
        jj, ii = np.meshgrid(np.arange(nx), np.arange(ny))
        xy = grid.origin + (np.stack([jj, ii], axis=-1) + 0.5) * res
        inside = grid.contains(xy)
        cell = grid.world_to_cell(xy[inside])
        mask = np.zeros((ny, nx), dtype=bool)
        mask[inside] = grid.free[cell[:, 0], cell[:, 1]]
        if not mask.any():
            raise ValueError(
                f"resolution {res!r} m leaves no cell whose centre lies in a free cell of the "
                "map: the state space is empty"
            )
        headings = -math.pi + np.arange(n) * (_TWO_PI / n)
        _readonly(mask, headings)
        for name, value in [
            ("resolution", res),
            ("n_headings", n),
            ("mask", mask),
            ("headings", headings),
        ]:
            object.__setattr__(self, name, value)

    def __repr__(self) -> str:
        return (
            f"PoseGrid(shape={self.shape}, resolution={self.resolution!r}, "
            f"{int(self.mask.sum())} free (x, y) cells)"
        )

    # ------------------------------------------------------------------ geometry
    @property
    def origin(self) -> np.ndarray:
        """``(2,)``: the map's origin, the corner of cell ``(0, 0)``."""
        return self.grid.origin

    @property
    def shape(self) -> tuple[int, int, int]:
        """``(ny, nx, n_headings)``: the shape of a belief."""
        return (*self.mask.shape, self.n_headings)

    @property
    def n_states(self) -> int:
        """The number of cells in the state space (free (x, y) cells times headings)."""
        return int(self.mask.sum()) * self.n_headings

    @property
    def heading_resolution(self) -> float:
        r""":math:`\Delta\theta = 2\pi / n_{headings}` (rad)."""
        return _TWO_PI / self.n_headings

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """``(x_min, x_max, y_min, y_max)`` of the cells, in metres (for ``imshow``)."""
        ny, nx = self.mask.shape
        ox, oy = self.origin.tolist()
        return (ox, ox + nx * self.resolution, oy, oy + ny * self.resolution)

    def centres(self, *, free_only=False) -> np.ndarray:
        r"""Return the centres :math:`\mathrm{mean}(\mathbf x_k)` of the cells.

        Parameters
        ----------
        free_only : bool
            Return only the cells of the state space, in the order of
            ``belief[pose_grid.mask].ravel()``.

        Returns
        -------
        centres : ndarray, shape (ny, nx, n_headings, 3), or (K, 3) with ``free_only``
            :math:`(x, y, \theta)`; :math:`K` = :attr:`n_states`.
        """
        if check.flag(free_only, "free_only"):
            return self._free_centres.copy()
        ny, nx, n = self.shape
        out = np.empty((ny, nx, n, 3))
        out[..., 0] = (self.origin[0] + (np.arange(nx) + 0.5) * self.resolution)[None, :, None]
        out[..., 1] = (self.origin[1] + (np.arange(ny) + 0.5) * self.resolution)[:, None, None]
        out[..., 2] = self.headings
        return out

    @cached_property
    def _free_centres(self) -> np.ndarray:
        """(K, 3), read-only: the centres of the state space (line 4 weighs them)."""
        ii, jj = np.nonzero(self.mask)
        n = self.n_headings
        out = np.empty((ii.size, n, 3))
        out[..., 0] = (self.origin[0] + (jj + 0.5) * self.resolution)[:, None]
        out[..., 1] = (self.origin[1] + (ii + 0.5) * self.resolution)[:, None]
        out[..., 2] = self.headings
        out = out.reshape(-1, 3)
        out.flags.writeable = False
        return out

    def locate(self, poses) -> tuple[np.ndarray, np.ndarray]:
        r"""Return the cell of each pose, and whether it lies in the state space.

        Parameters
        ----------
        poses : array_like, shape (..., 3)
            :math:`(x, y, \theta)`; any heading (it is wrapped into the bins).

        Returns
        -------
        ijk : ndarray of int64, shape (..., 3)
            Row ``i`` (y), column ``j`` (x) and heading bin ``k``; ``i`` and ``j`` are
            clipped to ``[-1, ny]`` and ``[-1, nx]`` (off the grid).
        inside : ndarray of bool, shape (...)
            Whether the cell is one of the state space.
        """
        x = check.poses(poses, "poses")
        ny, nx, n = self.shape
        with np.errstate(over="ignore", invalid="ignore"):
            g = np.floor((x[..., :2] - self.origin) / self.resolution)
        j = np.clip(g[..., 0], -1, nx).astype(np.int64)
        i = np.clip(g[..., 1], -1, ny).astype(np.int64)
        k = _heading_bin(x[..., 2], n)
        on_grid = (i >= 0) & (i < ny) & (j >= 0) & (j < nx)
        inside = np.zeros(on_grid.shape, dtype=bool)
        inside[on_grid] = self.mask[i[on_grid], j[on_grid]]
        return np.stack([i, j, k], axis=-1), inside

    # ------------------------------------------------------------------ beliefs
    def uniform(self) -> np.ndarray:
        """Return the belief uniform over the state space, shape ``(ny, nx, n_headings)``.

        The prior of global localization (Sec. 8.2).
        """
        out = np.zeros(self.shape)
        out[self.mask] = 1.0 / self.n_states
        return out

    def point_mass(self, pose) -> np.ndarray:
        """Return the belief that puts all its probability on the cell of ``pose``.

        Parameters
        ----------
        pose : array_like, shape (3,)

        Returns
        -------
        belief : ndarray, shape (ny, nx, n_headings)
        """
        pose = check.single_pose(pose, "pose")
        (i, j, k), inside = self.locate(pose)
        if not inside:
            raise ValueError(f"pose {pose.tolist()} does not lie in the state space")
        out = np.zeros(self.shape)
        out[i, j, k] = 1.0
        return out

    def histogram(self, particles, weights=None) -> np.ndarray:
        """Return the normalised histogram of particles over the cells, shape ``(ny, nx, n_headings)``.

        For comparing a particle set (MCL) with a grid belief. Particles outside the state
        space (off the grid, or in a cell whose centre is not free) are left out, as line 3
        drops the probability that lands there; the histogram is normalised over the
        particles that remain (:meth:`locate` tells which they are).

        Parameters
        ----------
        particles : array_like, shape (N, 3)
        weights : array_like, shape (N,), optional
            Non-negative weights (default: equal).

        Returns
        -------
        belief : ndarray, shape (ny, nx, n_headings)
        """
        x = check.poses(particles, "particles")
        if x.ndim != 2 or x.shape[0] == 0:
            raise ValueError(f"particles must have shape (N, 3) with N >= 1, got {x.shape}")
        if weights is None:
            w = np.ones(x.shape[0])
        else:
            w = check.finite(weights, "weights")
            if w.shape != (x.shape[0],):
                raise ValueError(f"weights must have shape ({x.shape[0]},), got {w.shape}")
            if np.any(w < 0):
                raise ValueError(f"weights must be non-negative, got min {w.min()!r}")
        ijk, inside = self.locate(x)
        ny, nx, n = self.shape
        flat = (ijk[inside, 0] * nx + ijk[inside, 1]) * n + ijk[inside, 2]
        counts = np.bincount(flat, weights=w[inside], minlength=ny * nx * n)
        total = counts.sum()
        if not total > 0:
            raise ValueError("no particle (of positive weight) lies in the state space")
        return (counts / total).reshape(self.shape)

    def marginal_xy(self, belief) -> np.ndarray:
        """Return the probability of each (x, y) cell, summed over headings: shape ``(ny, nx)``.

        For a heat map (``imshow(..., origin="lower", extent=pose_grid.extent)``).
        """
        return _belief(belief, self).sum(axis=2)

    def mode(self, belief) -> np.ndarray:
        r"""Return the centre :math:`(x, y, \theta)` of the most probable cell, shape ``(3,)``.

        The pose estimate of a grid belief: unlike its mean, the mode of a multimodal belief
        is a pose the belief holds likely (not one between two modes, inside a wall). Ties go
        to the first cell in row-major order.
        """
        b = _belief(belief, self)
        i, j, k = np.unravel_index(int(np.argmax(b)), b.shape)
        return np.array(
            [
                self.origin[0] + (j + 0.5) * self.resolution,
                self.origin[1] + (i + 0.5) * self.resolution,
                self.headings[k],
            ]
        )


def _heading_bin(theta: np.ndarray, n: int) -> np.ndarray:
    """The bin (centred on -π + k 2π/n) of each heading, any magnitude."""
    step = _TWO_PI / n
    k = np.floor((np.mod(theta + math.pi, _TWO_PI)) / step + 0.5)
    return np.mod(k, n).astype(np.int64)


def _pose_grid(value) -> PoseGrid:
    if not isinstance(value, PoseGrid):
        raise ValueError(f"pose_grid must be a PoseGrid, got {type(value).__name__}")
    return value


def _belief(value, pose_grid: PoseGrid, name: str = "belief") -> np.ndarray:
    """A belief of the pose grid's shape: finite, >= 0, zero off the state space, sum 1."""
    b = check.finite(value, name)
    if b.shape != pose_grid.shape:
        raise ValueError(
            f"{name} must have the pose grid's shape (ny, nx, n_headings) = "
            f"{pose_grid.shape}, got {b.shape}"
        )
    if b.min() < 0:
        raise ValueError(f"{name} must be non-negative, got min {b.min()!r}")
    off = b[~pose_grid.mask].sum()
    if off > 0:
        raise ValueError(
            f"{name} puts probability {off:.3g} on cells outside the state space "
            "(pose_grid.mask is False there)"
        )
    total = b.sum()
    if not abs(total - 1.0) <= _SUM_TOLERANCE:
        raise ValueError(f"{name} must sum to 1 (within {_SUM_TOLERANCE:g}), got {total!r}")
    return b


# ---------------------------------------------------------------------- line 3: the kernel
@dataclass(frozen=True, eq=False)
class KernelBlock:
    """The transitions out of the cells of one source heading (read-only arrays)."""

    dtheta: np.ndarray
    """(a,) int: target heading bin minus source heading bin (taken modulo n_headings)."""
    dy: np.ndarray
    """(wy,) int, consecutive: target row minus source row."""
    dx: np.ndarray
    """(wx,) int, consecutive: target column minus source column."""
    weights: np.ndarray
    """(a, wy, wx): the probability of each offset (dθ, dy, dx). Sums to 1, less only when
    part of the motion lies beyond the grid's size (offsets that join no two cells are not
    stored)."""


@dataclass(frozen=True, eq=False)
class MotionKernel:
    r"""The transition of line 3 of Table 8.1 between cells, one block per source heading.

    Made by :func:`motion_kernel`. The transition depends on the source's heading but not on
    its (x, y) cell (the odometry model is the same everywhere), so one block of offsets
    per source heading holds all of it.
    """

    blocks: tuple
    """One :class:`KernelBlock` per source heading bin."""
    resolution: float
    """The pose grid's (x, y) resolution (m)."""
    n_headings: int
    deltas: tuple
    r""":math:`(\delta_{rot1}, \delta_{trans}, \delta_{rot2})` of the odometry ``u``."""
    alpha: np.ndarray
    """(4,): the noise parameters."""
    n_sigma: float
    """The mid-point rule's window: half width in standard deviations of each noise term."""
    rule: str
    """``"mid-point"`` (the density at the cell centres) or ``"quadrature"`` (the cells'
    probabilities under the sampler, also used for a motion with a zero variance, which has
    no density; see :func:`motion_kernel`)."""
    midpoint_sum: np.ndarray | None
    r"""(n_headings,): per source heading, the sum over the window before normalisation,
    :math:`\sum_k p(\mathrm{mean}(\mathbf x_k) \mid u_t, \mathrm{mean}(\mathbf x_i))\,
    r^2\Delta\theta` (the exact probabilities would sum to the probability of the window,
    about 1); ``None`` for the rule ``"quadrature"``, whose weights sum to 1 by
    construction."""

    @property
    def reach(self) -> tuple[int, int]:
        """``(max |dy|, max |dx|)`` over all blocks (the padding line 3 needs)."""
        dy = max((int(np.abs(b.dy).max()) for b in self.blocks if b.dy.size), default=0)
        dx = max((int(np.abs(b.dx).max()) for b in self.blocks if b.dx.size), default=0)
        return dy, dx

    @property
    def size(self) -> int:
        """The number of (source heading, offset) transitions stored."""
        return sum(b.weights.size for b in self.blocks)

    @property
    def nbytes(self) -> int:
        """Memory held by the blocks' arrays (bytes)."""
        return sum(
            b.dtheta.nbytes + b.dy.nbytes + b.dx.nbytes + b.weights.nbytes for b in self.blocks
        )


def _block(dtheta, dy, dx, weights) -> KernelBlock:
    """A block of weights (a, wy, wx), without the heading offsets of zero weight and cut to
    the rectangle of (dy, dx) offsets of positive weight (the rest costs work, adds nothing)."""
    positive = weights > 0
    if not positive.any():  # the whole motion leaves the grid
        rows, y_cut, x_cut = np.zeros(0, dtype=np.int64), slice(0, 0), slice(0, 0)
    else:
        rows = np.flatnonzero(positive.any(axis=(1, 2)))
        ys = np.flatnonzero(positive.any(axis=(0, 2)))
        xs = np.flatnonzero(positive.any(axis=(0, 1)))
        y_cut, x_cut = slice(ys[0], ys[-1] + 1), slice(xs[0], xs[-1] + 1)
    blk = KernelBlock(
        np.ascontiguousarray(dtheta[rows], dtype=np.int64),
        np.ascontiguousarray(dy[y_cut], dtype=np.int64),
        np.ascontiguousarray(dx[x_cut], dtype=np.int64),
        np.ascontiguousarray(weights[rows][:, y_cut, x_cut]),
    )
    _readonly(blk.dtheta, blk.dy, blk.dx, blk.weights)
    return blk


def _window(theta_i, deltas, sigmas, n_sigma, res, d_theta, shape):
    r"""The ranges ``(first, last)`` of the offsets (dθ bins, dy cells, dx cells) of the poses
    reachable from a cell centre of heading ``theta_i`` with every noise term within
    ``n_sigma`` standard deviations, plus one cell (and one bin) on each side (not cut to
    the grid); and the box's range of translations ``(t_lo, t_hi)``."""
    rot1, trans, rot2 = deltas
    s1, st, s2 = sigmas
    ny, nx, n = shape
    half_turn = n_sigma * s1 >= math.pi
    if half_turn:
        phi_lo, phi_hi = theta_i + rot1 - math.pi, theta_i + rot1 + math.pi
    else:
        phi_lo, phi_hi = theta_i + rot1 - n_sigma * s1, theta_i + rot1 + n_sigma * s1
    t_lo, t_hi = max(0.0, trans - n_sigma * st), trans + n_sigma * st
    # Bounding box of the annular sector {t (cos φ, sin φ)}: its corners and the points
    # where cos or sin peak inside the range of φ.
    if half_turn or not math.isfinite(t_hi):
        x_lo = y_lo = -t_hi
        x_hi = y_hi = t_hi
    else:
        quarter = math.pi / 2
        axes = np.arange(math.ceil(phi_lo / quarter), math.floor(phi_hi / quarter) + 1) * quarter
        phi = np.concatenate([[phi_lo, phi_hi], axes])
        t = np.array([t_lo, t_hi])[:, None]
        px, py = t * np.cos(phi), t * np.sin(phi)
        x_lo, x_hi, y_lo, y_hi = px.min(), px.max(), py.min(), py.max()

    def cells(lo, hi, count):  # the grid's every offset for an infinite window
        a = math.floor(lo / res) - 1 if math.isfinite(lo) else -(count - 1)
        b = math.ceil(hi / res) + 1 if math.isfinite(hi) else count - 1
        return a, b

    dx = cells(x_lo, x_hi, nx)
    dy = cells(y_lo, y_hi, ny)
    spread = n_sigma * (s1 + s2)
    mean = rot1 + rot2
    if math.isfinite(spread):
        lo = math.floor((mean - spread) / d_theta) - 1
        hi = math.ceil((mean + spread) / d_theta) + 1
    if not math.isfinite(spread) or hi - lo + 1 > n:  # every bin, once
        lo = round(mean / d_theta) - n // 2
        hi = lo + n - 1
    return (lo, hi), dy, dx, (t_lo, t_hi)


def _directions(rel, deltas, sigmas, n_sigma):
    r"""Per target heading offset ``rel`` (rad, shape (a,)), the interval of directions of
    travel :math:`\varphi = \hat\delta_{rot1}` (relative to the source's heading) where both
    :math:`\hat\delta_{rot1}` and :math:`\hat\delta_{rot2} = rel - \hat\delta_{rot1}` lie
    within ``n_sigma`` standard deviations of their means: two arcs of the circle, whose
    intersection is taken (the narrower arc when they are so wide that they meet twice)."""
    rot1, _, rot2 = deltas
    s1, _, s2 = sigmas
    w1, w2 = min(n_sigma * s1, math.pi), min(n_sigma * s2, math.pi)  # half widths
    c2 = rot1 + _wrap_array(rel - rot2 - rot1)  # the copy of the second arc nearest the first
    if w1 + w2 >= math.pi:
        if w1 <= w2:
            return np.full(rel.shape, rot1 - w1), np.full(rel.shape, rot1 + w1)
        return c2 - w2, c2 + w2
    lo, hi = np.maximum(rot1 - w1, c2 - w2), np.minimum(rot1 + w1, c2 + w2)
    return lo, np.maximum(hi, lo)  # an empty intersection has width 0


def _wrap_array(a):
    return np.mod(a + math.pi, _TWO_PI) - math.pi


def _own_cell_log_mass(theta_i, rel, u, alpha, deltas, sigmas, n_sigma, t_range, res, d_theta):
    r"""Log of the probability of each heading bin in the source's own (x, y) cell.

    The density of the odometry model has the factor :math:`1/\hat\delta_{trans}`, infinite
    at the source's own centre; in polar coordinates :math:`(\varphi, \hat\delta_{trans})`
    about the source it cancels with the area element :math:`\hat\delta_{trans}\,d\varphi\,
    d\hat\delta_{trans}`. The mid-point rule with ``_OWN_CELL_NODES`` nodes in φ (over the
    directions of :func:`_directions`, so that the nodes resolve the narrower of the two
    rotation noises) and as many in :math:`\hat\delta_{trans}` (from the window's lower
    bound to the cell's edge :math:`R(\varphi) = (r/2) / \max(|\cos\varphi|, |\sin\varphi|)`
    or the window's upper bound) integrates it over the part of the square cell inside the
    window; the heading is at the bin centres (mid-point in θ).
    """
    t_lo, t_hi = t_range
    m = _OWN_CELL_NODES
    lo, hi = _directions(rel, deltas, sigmas, n_sigma)
    d_phi = (hi - lo) / m  # (a,)
    phi = theta_i + lo[:, None] + (np.arange(m) + 0.5) * d_phi[:, None]  # (a, m)
    edge = 0.5 * res / np.maximum(np.abs(np.cos(phi)), np.abs(np.sin(phi)))
    d_r = np.maximum(np.minimum(edge, t_hi) - t_lo, 0.0) / m  # 0 where the window misses it
    r = t_lo + (np.arange(m) + 0.5) * d_r[..., None]  # (a, m φ, m r)
    pts = np.empty((*r.shape, 3))
    pts[..., 0] = r * np.cos(phi)[..., None]
    pts[..., 1] = r * np.sin(phi)[..., None]
    pts[..., 2] = (theta_i + rel)[:, None, None]
    log_p = motion_model_odometry(
        pts, u, np.array([0.0, 0.0, theta_i]), alpha, density="pose", log=True
    )
    with np.errstate(divide="ignore"):
        log_volume = np.log(r * d_r[..., None] * (d_phi * d_theta)[:, None, None])  # -inf: none
    return logsumexp(log_p + log_volume, axis=(1, 2))


def _midpoint_block(theta_i, u, alpha, deltas, sigmas, n_sigma, res, d_theta, shape):
    ranges, y_range, x_range, t_range = _window(
        theta_i, deltas, sigmas, n_sigma, res, d_theta, shape
    )
    size = math.prod(hi - lo + 1 for lo, hi in (ranges, y_range, x_range))
    if size > _MAX_WINDOW:
        raise ValueError(
            f"u and alpha make a window of {size:.3g} offsets per heading (more than "
            f"{_MAX_WINDOW:.0e}): the motion's noise spans too many cells of "
            f"{res!r} m for the mid-point rule; use rule='quadrature' or larger cells"
        )
    dth, dy, dx = (np.arange(lo, hi + 1) for lo, hi in (ranges, y_range, x_range))
    angles = theta_i + dth * d_theta
    yy, xx = np.meshgrid(dy, dx, indexing="ij")
    dy_all, dx_all = yy.ravel(), xx.ravel()
    targets = np.empty((dth.size, dy_all.size, 3))
    targets[..., 0] = dx_all * res
    targets[..., 1] = dy_all * res
    targets[..., 2] = angles[:, None]
    own = (dy_all == 0) & (dx_all == 0)
    targets[:, own, :2] = res  # a finite stand-in, replaced below
    log_p = motion_model_odometry(
        targets, u, np.array([0.0, 0.0, theta_i]), alpha, density="pose", log=True
    )
    log_mass = log_p + math.log(res * res * d_theta)  # the mid-point rule: density x volume
    if own.any():
        log_mass[:, own] = _own_cell_log_mass(
            theta_i, dth * d_theta, u, alpha, deltas, sigmas, n_sigma, t_range, res, d_theta
        )[:, None]
    total = logsumexp(log_mass)
    weights = np.exp(log_mass - total).reshape(dth.size, dy.size, dx.size)
    # offsets that join no two cells of the grid: their probability leaves the grid
    ny, nx, _ = shape
    rows, cols = np.abs(dy) < ny, np.abs(dx) < nx
    return _block(dth, dy[rows], dx[cols], weights[:, rows][:, :, cols]), float(np.exp(total))


def _normal_nodes(m: int) -> np.ndarray:
    """The means of the m equal-probability bins of the standard normal (each of weight 1/m)."""
    edges = ndtri(np.arange(m + 1) / m)  # -inf, ..., +inf
    density = np.exp(-0.5 * edges**2) / math.sqrt(_TWO_PI)  # 0 at the infinite ends
    return m * (density[:-1] - density[1:])


def _quadrature_block(theta_i, deltas, variances, res, d_theta, shape):
    """The probability of each cell under the sampler from a cell centre, by quadrature: each
    noise term with a positive variance takes the means of its equal-probability bins as
    nodes (one node, the mean, for a zero variance), every combination of nodes is pushed
    through Table 5.6's lines 8-10, and its weight goes to the cell that holds its end."""
    random = sum(v > 0 for v in variances)
    m = _QUADRATURE_NODES if random <= 2 else _QUADRATURE_NODES_3D
    z = _normal_nodes(m)
    nodes = [
        np.array([d]) if v == 0 else d + math.sqrt(v) * z
        for d, v in zip(deltas, variances, strict=True)
    ]
    r1, tr, r2 = np.meshgrid(*nodes, indexing="ij")
    end = apply_odometry_deltas(np.array([0.0, 0.0, theta_i]), r1, tr, r2)
    # the cell that holds each end pose (half-open cells about the source's centre)
    dx = np.floor(end[..., 0] / res + 0.5).astype(np.int64).ravel()
    dy = np.floor(end[..., 1] / res + 0.5).astype(np.int64).ravel()
    ny, nx, n = shape
    dth = np.floor((end[..., 2] - theta_i) / d_theta + 0.5).astype(np.int64).ravel() % n
    weight = 1.0 / dx.size
    on_grid = (np.abs(dy) < ny) & (np.abs(dx) < nx)  # the others join no two cells
    if not on_grid.any():
        return _block(np.zeros(0), np.zeros(0), np.zeros(0), np.zeros((0, 0, 0)))
    dth, dy, dx = dth[on_grid], dy[on_grid], dx[on_grid]
    th_u, th_idx = np.unique(dth, return_inverse=True)
    y_lo, x_lo = dy.min(), dx.min()
    counts = np.zeros((th_u.size, dy.max() - y_lo + 1, dx.max() - x_lo + 1))
    np.add.at(counts, (th_idx.ravel(), dy - y_lo, dx - x_lo), 1.0)
    ys, xs = np.arange(y_lo, dy.max() + 1), np.arange(x_lo, dx.max() + 1)
    return _block(th_u, ys, xs, counts * weight)


def motion_kernel(pose_grid, u, alpha, *, rule="mid-point", n_sigma=4.0) -> MotionKernel:
    r"""Return the transition of line 3 of Table 8.1 between the cells of a pose grid.

    *Probabilistic Robotics*, Table 8.1, line 3, with the odometry motion model (Table 5.6).
    The transition from cell :math:`i` to cell :math:`k` depends on the source's heading bin
    and on the offset from source to target, not on the source's (x, y) cell: one block of
    offsets per source heading holds all of it, computed in one call over all offsets.

    **The mid-point rule** (``rule="mid-point"``, the book's): the probability to move from
    cell :math:`i` to cell :math:`k` is the density of the odometry sampler between the
    centres, :math:`p(\mathrm{mean}(\mathbf x_k) \mid u_t, \mathrm{mean}(\mathbf x_i))`
    (:func:`~probrob.motion.motion_model_odometry` with ``density="pose"``, a density over
    :math:`(x', y', \theta')`), times the cell's volume :math:`r^2\,\Delta\theta`.

    * *Window.* The offsets of a source heading are those of the poses reachable with each
      of the three noise terms :math:`\hat\delta_{rot1}, \hat\delta_{trans},
      \hat\delta_{rot2}` within ``n_sigma`` standard deviations of its mean (a box of noise
      that holds all but at most :math:`3 \cdot 2\Phi(-n_\sigma)` of the motion, 1.9e-4 at
      4 σ), plus one cell (and one heading bin) on each side for the cells the box only
      clips. ``n_sigma=np.inf`` takes every offset that joins two cells of the grid.
      Offsets beyond the grid's size (a motion longer than the map) join no two cells and
      are not stored: their probability leaves the grid, as below.
    * *Normalisation.* The mid-point values do not sum to 1 over the window on a coarse
      grid (a density that varies within a cell is not its centre value times the volume;
      and the density over poses leaves out the sampler's negative translations, a mass
      :math:`\Phi(-\delta_{trans}/\sigma_{trans})`), so each source's block is divided by its
      sum over the window: the probability of leaving a cell is 1 before the map is
      consulted (and the probability that then lands on an occupied, unexplored or off-map
      cell is dropped by :func:`grid_prediction`). The sums
      before normalising are kept in :attr:`MotionKernel.midpoint_sum` (a chapter can print
      how far they are from 1).
    * *The source's own (x, y) cell.* There the centre-to-centre density is infinite (its
      factor :math:`1/\hat\delta_{trans}` at zero distance); the cell's probability is
      integrated instead, in polar coordinates about the source (where that factor cancels),
      by the mid-point rule on 32 × 32 nodes over the part of the cell inside the window.

    The mid-point rule is good when the motion's noise spans a few cells (a total-variation
    distance of 0.05 from the sampler's cell probabilities in the tests, with noise of
    σ 0.16 m and 0.24 rad on 20 cm × 10° cells, and 0.014 on 10 cm × 5° cells: second order
    in the cell size), and poor when it is narrower than a cell: then the density at the
    centres samples a narrow peak, and the kernel puts the probability on the wrong cells
    (with the noise fitted to the Intel lab's odometry, σ of a few cm and degrees, a step of
    half a metre on 20 cm × 10° cells moves about 60 % of the probability elsewhere than the
    sampler does; the book's remedy is finer cells or inflated noise).

    **The quadrature rule** (``rule="quadrature"``): the probability of each cell under the
    sampler from the source's centre, by quadrature. Each noise term with a positive
    variance takes as nodes the means of its 32 equal-probability bins (64 when at most two
    terms are random), every combination of nodes is pushed through Table 5.6's lines
    8–10 (:func:`~probrob.motion.apply_odometry_deltas`), and its weight goes to the cell
    that holds its end pose. The weights sum to 1 with no normalisation, negative
    translations included; ``n_sigma`` is not used. It is the better rule where the
    mid-point rule fails (0.007 in total variation in the Intel lab's case above) and the
    worse where that one is good: 32 nodes per term spread over many cells leave gaps
    between them (0.06 and 0.12 in the first case's two grids).

    **A motion with a zero variance** (no motion at all; a turn on the spot, whose
    :math:`\hat\delta_{rot1}` has variance :math:`\alpha_1\delta_{rot1}^2 +
    \alpha_2\delta_{trans}^2 = 0`; or a zero α) has no density over poses: it moves a cell
    centre onto a point, a line or a surface. Its kernel is the quadrature rule's, whatever
    ``rule`` says (:attr:`MotionKernel.rule` tells): no motion keeps every cell's
    probability where it is, a motion with no noise moves it to the cell of the end pose.

    Parameters
    ----------
    pose_grid : PoseGrid
    u : array_like, shape (2, 3)
        Odometry pair :math:`(\bar x_{t-1}, \bar x_t)`.
    alpha : array_like, shape (4,)
        Odometry noise :math:`\alpha_1 \ldots \alpha_4` (variance form, normal noise).
    rule : {"mid-point", "quadrature"}
        How the transition between cells is computed (above).
    n_sigma : float
        Half width of the mid-point rule's window in standard deviations (> 0; ``np.inf``
        for all offsets).

    Returns
    -------
    MotionKernel
    """
    pose_grid = _pose_grid(pose_grid)
    u = _odometry_pair(u)
    alpha = check.alphas(alpha, "alpha", 4)
    rule = check.choice(rule, "rule", _RULES)
    n_sigma = check.as_float_array(n_sigma, "n_sigma")
    if n_sigma.ndim != 0 or np.isnan(n_sigma) or not n_sigma > 0:
        raise ValueError(f"n_sigma must be a number > 0 (or np.inf), got {check._short(n_sigma)}")
    n_sigma = float(n_sigma)
    deltas = tuple(float(d) for d in _odometry_deltas(u[0], u[1]))
    variances = tuple(float(v) for v in _odometry_variances(alpha, *deltas, "variance", u=u))
    res, d_theta, shape = pose_grid.resolution, pose_grid.heading_resolution, pose_grid.shape
    if min(variances) == 0.0:
        rule = "quadrature"  # no density to evaluate
    blocks, sums = [], []
    for theta_i in pose_grid.headings:  # one block per source heading
        if rule == "quadrature":
            blocks.append(_quadrature_block(theta_i, deltas, variances, res, d_theta, shape))
        else:
            sigmas = tuple(math.sqrt(v) for v in variances)
            blk, total = _midpoint_block(
                theta_i, u, alpha, deltas, sigmas, n_sigma, res, d_theta, shape
            )
            blocks.append(blk)
            sums.append(total)
    midpoint_sum = None
    if rule == "mid-point":
        midpoint_sum = np.array(sums)
        _readonly(midpoint_sum)
    alpha = alpha.copy()
    _readonly(alpha)
    return MotionKernel(
        tuple(blocks), res, pose_grid.n_headings, deltas, alpha, n_sigma, rule, midpoint_sum
    )


def _kernel_for(kernel, pose_grid: PoseGrid, u, alpha) -> MotionKernel:
    if kernel is None:
        return motion_kernel(pose_grid, u, alpha)
    if not isinstance(kernel, MotionKernel):
        raise ValueError(f"kernel must be a MotionKernel, got {type(kernel).__name__}")
    if kernel.resolution != pose_grid.resolution or kernel.n_headings != pose_grid.n_headings:
        raise ValueError(
            f"kernel was made for a pose grid of resolution {kernel.resolution!r} m and "
            f"{kernel.n_headings} headings, not {pose_grid.resolution!r} m and "
            f"{pose_grid.n_headings}"
        )
    deltas = tuple(float(d) for d in _odometry_deltas(u[0], u[1]))
    if deltas != kernel.deltas or not np.array_equal(alpha, kernel.alpha):
        raise ValueError("kernel was made for another u or alpha than the ones given")
    return kernel


# ---------------------------------------------------------------------- line 3
def _line3(belief, kernel: MotionKernel, pose_grid: PoseGrid) -> np.ndarray:
    r"""pbar_k = sum_i p_i p(x_k | u, x_i) for the cells k of the state space: shape
    (n_free_xy, n_headings), the layout of ``belief[pose_grid.mask]``.

    For a block of target cells k, the probabilities of the sources at every offset of
    every source heading are gathered side by side (one column per source heading and
    offset) and multiplied with the matrix of the kernel's weights (one row per source
    heading and offset, one column per target heading): one matrix product per block of
    targets, so that BLAS sees a few large products rather than many small ones."""
    ny, nx, n = pose_grid.shape
    py, px = kernel.reach
    # p_{i,t-1} per source heading, padded so that every offset of the kernel stays inside
    p_prev = np.zeros((n, ny + 2 * py, nx + 2 * px))
    p_prev[:, py : py + ny, px : px + nx] = np.moveaxis(belief, 2, 0)
    # the source headings that hold probability and keep some of it on the grid
    sources = [i for i in range(n) if kernel.blocks[i].weights.size and p_prev[i].any()]
    row_k, col_k = np.nonzero(pose_grid.mask)  # the (x, y) cells k of the state space
    windows, corners, rows = [], [], []
    for i in sources:
        blk = kernel.blocks[i]
        wy, wx = blk.dy.size, blk.dx.size
        # windows[r, c] = p_prev[i][r : r + wy, c : c + wx]: for target (row, col) the sources
        # at (row - dy, col - dx), dy and dx from their largest down (a view, no copy)
        windows.append(sliding_window_view(p_prev[i], (wy, wx)))
        corners.append((py - int(blk.dy[-1]), px - int(blk.dx[-1])))
        weights = np.zeros((wy * wx, n))  # motion_model(x_k | u, x_i) by target heading
        weights[:, (i + blk.dtheta) % n] = blk.weights[:, ::-1, ::-1].reshape(-1, wy * wx).T
        rows.append(weights)
    p_bar = np.zeros((row_k.size, n))
    if not sources:
        return p_bar
    weights = np.concatenate(rows)
    step = max(64, _GATHER_ELEMENTS // max(weights.shape[0], 1))
    for start in range(0, row_k.size, step):
        k = slice(start, start + step)
        p_i = np.concatenate(  # p_{i,t-1} of the sources of each target cell k
            [
                view[row_k[k] + top, col_k[k] + left].reshape(-1, view[0, 0].size)
                for view, (top, left) in zip(windows, corners, strict=True)
            ],
            axis=1,
        )
        p_bar[k] = p_i @ weights  # line 3: the sum over the sources i
    return p_bar


def _as_belief(p_bar: np.ndarray, pose_grid: PoseGrid) -> np.ndarray:
    out = np.zeros(pose_grid.shape)
    out[pose_grid.mask] = p_bar
    return out


def grid_prediction(belief, u, pose_grid, alpha, *, kernel=None) -> np.ndarray:
    r"""Return :math:`\bar p_{k,t}` of Table 8.1, line 3 (the prediction), for every cell.

    .. math:: \bar p_{k,t} = \sum_i p_{i,t-1}\,
              p(\mathrm{mean}(\mathbf x_k) \mid u_t, \mathrm{mean}(\mathbf x_i))

    with the transition of :func:`motion_kernel`. For a block of target cells, the
    probabilities of their sources at every offset of every source heading are gathered side
    by side and multiplied with the kernel's weights: one matrix product per block of
    targets, no loop over cells. Probability carried onto a cell outside the state space is
    dropped, so the result sums to at most 1 (line 4 renormalises).

    Parameters
    ----------
    belief : array_like, shape (ny, nx, n_headings)
        :math:`p_{k,t-1}`: non-negative, zero off the state space, summing to 1.
    u : array_like, shape (2, 3)
        Odometry pair :math:`(\bar x_{t-1}, \bar x_t)`.
    pose_grid : PoseGrid
    alpha : array_like, shape (4,)
    kernel : MotionKernel, optional
        :func:`motion_kernel` of ``pose_grid``, ``u`` and ``alpha``, if already made (or to
        use its ``rule="quadrature"``); default: the mid-point rule.

    Returns
    -------
    p_bar : ndarray, shape (ny, nx, n_headings)
    """
    pose_grid = _pose_grid(pose_grid)
    b = _belief(belief, pose_grid)
    u = _odometry_pair(u)
    alpha = check.alphas(alpha, "alpha", 4)
    kernel = _kernel_for(kernel, pose_grid, u, alpha)
    return _as_belief(_line3(b, kernel, pose_grid), pose_grid)


# ---------------------------------------------------------------------- Table 8.1
def grid_localization(
    belief, u, z, pose_grid, beam_angles, alpha, params, *, exponent=1.0, kernel=None
) -> np.ndarray:
    r"""One step of grid localization (*Probabilistic Robotics*, Table 8.1).

    For all cells :math:`k` of the state space:

    .. math::
        \bar p_{k,t} &= \sum_i p_{i,t-1}\,
            \mathbf{motion\_model}(\mathrm{mean}(\mathbf x_k), u_t, \mathrm{mean}(\mathbf x_i))
            \qquad &\text{(line 3, } \texttt{grid\_prediction}\text{)}\\
        p_{k,t} &= \eta\ \mathbf{measurement\_model}(z_t, \mathrm{mean}(\mathbf x_k), m)\
            \bar p_{k,t} \qquad &\text{(line 4)}

    Line 3 uses the odometry model through :func:`motion_kernel` (its mid-point rule,
    window and normalisation are documented there). Line 4 weighs every cell with
    :math:`\bar p_{k,t} > 0` by the likelihood field (Table 6.3) at its centre, tempered by
    ``exponent`` (:func:`probrob.mcl.measurement_log_weights`, as MCL weighs its
    particles), in log space, and :math:`\eta` normalises by log-sum-exp: a scan of many
    beams never underflows.

    When the scan gives probability 0 to every cell that line 3 reached, the scan says
    nothing about them: the prediction is returned, normalised (as MCL keeps its prior
    then). When line 3 carries all the probability off the state space there is nothing to
    normalise: ``ValueError`` naming ``u``.

    Parameters
    ----------
    belief : array_like, shape (ny, nx, n_headings)
        :math:`\{p_{k,t-1}\}`: non-negative, zero off the state space, summing to 1
        (e.g. :meth:`PoseGrid.uniform`).
    u : array_like, shape (2, 3)
        Odometry pair :math:`(\bar x_{t-1}, \bar x_t)`.
    z : array_like, shape (K,)
        Ranges of the scan (m); readings at ``params.max_range`` are skipped.
    pose_grid : PoseGrid
        The cells, over the map :math:`m` (``pose_grid.grid``).
    beam_angles : array_like, shape (K,)
    alpha : array_like, shape (4,)
        Odometry noise :math:`\alpha_1 \ldots \alpha_4` (variance form).
    params : BeamModelParams
        Uses ``z_hit``, ``z_rand``, ``sigma_hit``, ``max_range``.
    exponent : float in (0, 1]
        Tempering of the product over beams (see :func:`probrob.mcl.measurement_log_weights`);
        1 is the book's.
    kernel : MotionKernel, optional
        :func:`motion_kernel` of ``pose_grid``, ``u`` and ``alpha``, if already made (or to
        use its ``rule="quadrature"``); default: the mid-point rule.

    Returns
    -------
    belief : ndarray, shape (ny, nx, n_headings)
        :math:`\{p_{k,t}\}`, summing to 1, zero off the state space.
    """
    pose_grid = _pose_grid(pose_grid)
    b = _belief(belief, pose_grid)
    u = _odometry_pair(u)
    z, angles = _scan(z, beam_angles)
    alpha = check.alphas(alpha, "alpha", 4)
    params = _params(params)
    exponent = _exponent(exponent)
    kernel = _kernel_for(kernel, pose_grid, u, alpha)

    p_bar = _line3(b, kernel, pose_grid).ravel()  # line 3, in the order of centres(free_only)
    reached = np.flatnonzero(p_bar > 0)
    if reached.size == 0:
        raise ValueError(
            "u carries all the probability off the state space (onto occupied, unexplored or "
            "off-map cells): the belief cannot be renormalised"
        )
    log_p = np.full(p_bar.size, -np.inf)
    log_p[reached] = np.log(p_bar[reached]) + measurement_log_weights(  # line 4
        pose_grid._free_centres[reached],
        z,
        pose_grid.grid,
        angles,
        params,
        exponent=exponent,
    )
    if np.isfinite(log_p).any():
        p = np.exp(log_p - logsumexp(log_p))  # eta
    else:
        p = p_bar / p_bar.sum()
    return _as_belief(p.reshape(-1, pose_grid.n_headings), pose_grid)
