r"""Occupancy grids, their distance field, and ray casting (*Probabilistic Robotics*, ch. 6).

Holds occupancy grids, their distance field and ray casting.
Does not hold the range-finder models that use them (:mod:`probrob.sensors`).

* :class:`OccupancyGrid` — a boolean grid of occupied cells with a metric resolution
  and origin, built from an array or from laser scans at known poses
  (:meth:`OccupancyGrid.from_scans`), with world ↔ cell conversions and the metric
  :attr:`~OccupancyGrid.distance_field` (scipy's exact Euclidean distance transform).
* :func:`ray_cast` — the expected range :math:`z^*` of every beam of every pose
  (compiled per ray, for poses × beams at once): the distance from the sensor to the boundary of the
  first occupied cell the beam enters, or ``max_range``.

Conventions (the book's *conventions* page): ``occupied[i, j]`` is row ``i`` (y) and column ``j`` (x);
cell ``(i, j)`` covers :math:`x \in [o_x + j r, o_x + (j+1) r)`,
:math:`y \in [o_y + i r, o_y + (i+1) r)`. Space outside the grid is free: a beam that
leaves the grid returns ``max_range``.

Ray casting has three methods, the first two exact, the last approximate. Each is a loop
over one ray compiled by numba (``@njit(cache=True)``: compiled once per machine, about 5 s,
then loaded from the cache in well under a second), with no fast-math, so every operation
rounds as it does in IEEE double precision and the ranges are those of the scalar
algorithm to the last bit:

``"hybrid"`` (default)
    Sphere tracing across open space (jumps by the free radius while it exceeds a
    cell), then Amanatides–Woo grid traversal that keeps skipping free space: at each
    step the ray advances to the larger of the next cell boundary and the distance
    that the distance field proves free (the distance from the cell's centre to the
    nearest occupied centre, minus twice the half diagonal of a cell). A jump never
    enters an occupied cell, so the first occupied cell is entered where the plain
    traversal enters it. Both compute a boundary crossing by the same formula, so the
    ranges equal ``"dda"``'s to the last bit, also on poses on grid lines and corners
    with beams along the axes (the tests hold both to :math:`10^{-9}` m of an
    independent scalar traversal and to each other). Rays go through it sixteen at a
    time in lockstep, so that the table look-ups of independent rays overlap.
``"dda"``
    The plain Amanatides–Woo traversal (one cell per step), the reference.
``"march"``
    Plain sphere tracing (ray marching) on the distance field as in range_libc's
    ``RayMarching``: step by the distance to the nearest occupied cell centre and stop
    when it falls below half a cell. Approximate, with no bound on the error: a beam
    that passes within half a cell of an occupied cell's centre stops there, however far
    the cell it really hits (on the benchmark's 180,000 beams the error has median 0.5
    cells and 99th percentile 1 cell, but reaches hundreds of cells on a beam that grazes
    a corner); kept to show what the exact methods buy.

Every traversal terminates by construction: each step moves a ray at least one cell
forward (or, when marching, half a cell), so its loop is bounded by the grid's size; the
bounds are ``_step_bounds``, and a ray still in flight after its bound raises
``RuntimeError`` (a bug) instead of looping.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np
from numba import njit

from . import _validation as check

__all__ = ["OccupancyGrid", "ray_cast"]

_METHODS = ("hybrid", "dda", "march")
# Safety margin (in cells) on top of the half diagonal 1/√2: rounding never lets a
# sphere-tracing step enter an occupied cell.
_HALF_DIAGONAL = np.sqrt(0.5) + 1e-9
# How far back along the ray (in cells) the hybrid traversal locates a landing point: more
# than the rounding of a position (1e-16 per cell of coordinate), less than the 2e-9 cells
# by which a jump stays away from every occupied cell.
_PULL_BACK = 1e-10
# Smallest magnitude of a ray direction component (see ray_cast): the smallest normal double.
_TINY = np.finfo(float).tiny

# A cell index beyond 2**52 cells: floats no longer separate neighbouring cells there (and
# int64 wraps beyond 2**63); probrob.mcl refuses the same in its histogram bins.
_CELL_LIMIT = 2.0**52


class OccupancyGrid:
    r"""A 2-D occupancy grid map.

    Parameters
    ----------
    occupied : array_like of bool, shape (H, W)
        ``True`` where the cell is occupied; row ``i`` is y, column ``j`` is x.
    resolution : float
        Cell side in metres (> 0).
    origin : array_like, shape (2,)
        World coordinates (x, y) of the corner of cell ``(0, 0)``, in metres.

    Attributes
    ----------
    occupied : ndarray of bool, shape (H, W)
        Read-only copy of the grid.
    resolution : float
    origin : ndarray, shape (2,)
    free : ndarray of bool, shape (H, W)
        Read-only: the cells known to be free. By default every cell that is not occupied;
        a grid built :meth:`from_scans` knows only the cells its beams saw (a cell no beam
        crossed or ended in is neither free nor occupied: unexplored).
    """

    def __init__(self, occupied, resolution, origin=(0.0, 0.0), *, free=None):
        occ = np.asarray(occupied)
        if occ.dtype != bool:
            if not np.issubdtype(occ.dtype, np.number) or not np.all(np.isin(occ, (0, 1))):
                raise ValueError("occupied must be a boolean array (or of 0s and 1s)")
            occ = occ.astype(bool)
        if occ.ndim != 2 or occ.size == 0:
            raise ValueError(f"occupied must be a non-empty 2-D array, got shape {occ.shape}")
        self.occupied = occ.copy()
        self.occupied.flags.writeable = False
        self.resolution = check.positive_scalar(resolution, "resolution")
        origin = check.finite(origin, "origin")
        if origin.shape != (2,):
            raise ValueError(f"origin must have shape (2,), got {origin.shape}")
        self.origin = origin
        self.origin.flags.writeable = False
        if free is None:
            free = ~self.occupied
        else:
            free = np.asarray(free)
            if free.dtype != bool or free.shape != self.occupied.shape:
                raise ValueError(
                    f"free must be a boolean array of the shape of occupied {occ.shape}, got "
                    f"{free.dtype} {free.shape}"
                )
            if np.any(free & self.occupied):
                raise ValueError("free and occupied overlap: a cell cannot be both")
            free = free.copy()
        free.flags.writeable = False
        self.free = free
        self._likelihood_tables: dict = {}

    # ------------------------------------------------------------------ geometry
    @property
    def shape(self) -> tuple[int, int]:
        """``(H, W)``: rows (y) and columns (x)."""
        return self.occupied.shape

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """``(x_min, x_max, y_min, y_max)`` in metres (for ``imshow(extent=...)``)."""
        h, w = self.shape
        ox, oy = self.origin.tolist()
        return (ox, ox + w * self.resolution, oy, oy + h * self.resolution)

    def world_to_cell(self, xy) -> np.ndarray:
        """Return the integer cell indices ``(i, j)`` of world points.

        Parameters
        ----------
        xy : array_like, shape (..., 2)
            World coordinates in metres.

        Returns
        -------
        ij : ndarray of int64, shape (..., 2)
            Row ``i`` (y) and column ``j`` (x); may lie outside the grid (see
            :meth:`contains`).

        Raises
        ------
        ValueError
            Naming ``xy``, for a point 2**52 or more cells from the grid's origin: there a
            float coordinate no longer separates neighbouring cells (and beyond 2**63 an
            int64 index would wrap).
        """
        xy = check.vectors(xy, "xy", 2, "x, y")
        with np.errstate(over="ignore", invalid="ignore"):
            g = np.floor((xy - self.origin) / self.resolution)
        if not np.all(np.abs(g) < _CELL_LIMIT):
            k = tuple(int(n) for n in np.argwhere(~(np.abs(g) < _CELL_LIMIT))[0][:-1])
            raise ValueError(
                f"xy = {xy[k].tolist()} lies 2**52 or more cells of {self.resolution!r} m "
                f"from the grid's origin {self.origin.tolist()}: its cell cannot be told from "
                "its neighbours (is xy in metres?)"
            )
        return g.astype(np.int64)[..., ::-1]

    def cell_to_world(self, ij) -> np.ndarray:
        """Return the world coordinates of cell centres.

        Parameters
        ----------
        ij : array_like, shape (..., 2)
            Row ``i`` (y) and column ``j`` (x) indices.

        Returns
        -------
        xy : ndarray, shape (..., 2)
        """
        ij = check.vectors(ij, "ij", 2, "i, j")
        return self.origin + (ij[..., ::-1] + 0.5) * self.resolution

    def contains(self, xy) -> np.ndarray:
        """Return whether world points ``(..., 2)`` lie inside the grid (shape ``(...)``)."""
        xy = check.vectors(xy, "xy", 2, "x, y")
        x_min, x_max, y_min, y_max = self.extent
        x, y = xy[..., 0], xy[..., 1]
        return (x >= x_min) & (x < x_max) & (y >= y_min) & (y < y_max)

    # ------------------------------------------------------------------ fields
    @cached_property
    def distance_field(self) -> np.ndarray:
        """Metric distance from each cell centre to the nearest occupied cell centre.

        Computed with :func:`scipy.ndimage.distance_transform_edt` (exact Euclidean
        distance transform), times the resolution. Occupied cells hold 0; a grid with
        no occupied cell holds ``inf`` everywhere.

        Returns
        -------
        d : ndarray, shape (H, W), read-only
        """
        from scipy.ndimage import distance_transform_edt

        if not self.occupied.any():
            d = np.full(self.shape, np.inf)
        else:
            d = distance_transform_edt(~self.occupied) * self.resolution
        d.flags.writeable = False
        return d

    @cached_property
    def _traversal_tables(self):
        """Padded by one ring of cells: codes (0 free, 1 occupied, 2 outside) and, per
        cell, a lower bound (in cells) of the distance from any point of the cell to any
        occupied cell: the centre distance minus twice the half diagonal."""
        h, w = self.shape
        code = np.full((h + 2, w + 2), 2, dtype=np.uint8)
        code[1:-1, 1:-1] = self.occupied
        free = np.zeros((h + 2, w + 2))
        free[1:-1, 1:-1] = self.distance_field / self.resolution - 2.0 * _HALF_DIAGONAL
        return code.ravel(), free.ravel()

    # ------------------------------------------------------------------ building
    @classmethod
    def from_scans(
        cls,
        poses,
        ranges,
        beam_angles,
        resolution,
        *,
        max_range,
        margin=1.0,
        p_occupied=0.7,
        p_free=0.35,
    ):
        r"""Build a grid from range scans taken at known poses.

        Each beam carves free space along its path (every cell it passes before its
        end point) and marks the cell of its end point as hit; readings at or beyond
        ``max_range`` carry no end point and are skipped. A cell is occupied when its
        log-odds :math:`n_{hit} \log\frac{p_{occ}}{1-p_{occ}} + n_{free}
        \log\frac{p_{free}}{1-p_{free}}` is positive (*Probabilistic Robotics*,
        ch. 9, with the inverse sensor model reduced to two constants).

        Parameters
        ----------
        poses : array_like, shape (S, 3)
            Sensor poses (x, y, θ) of the S scans.
        ranges : array_like, shape (S, K)
            Measured ranges in metres.
        beam_angles : array_like, shape (K,)
            Beam directions relative to the heading, in radians.
        resolution : float
            Cell side in metres.
        max_range : float
            Readings ``>= max_range`` are "no return" and skipped.
        margin : float
            Free border (m) around the scan end points and poses.
        p_occupied, p_free : float
            Inverse sensor model: probability that a hit cell / a traversed cell is
            occupied (``p_free < 0.5 < p_occupied``).

        Returns
        -------
        grid : OccupancyGrid
            Its :attr:`free` cells are those that some beam saw and that are not occupied.
        """
        poses = check.poses(poses, "poses")
        ranges = check.finite(ranges, "ranges")
        angles = check.finite(beam_angles, "beam_angles")
        resolution = check.positive_scalar(resolution, "resolution")
        max_range = check.positive_scalar(max_range, "max_range")
        margin = check.finite(margin, "margin")
        if margin.ndim != 0 or margin < 0:
            raise ValueError(f"margin must be a scalar >= 0 (metres), got {check._short(margin)}")
        margin = float(margin)
        p_occupied = check.in_range(p_occupied, "p_occupied", 0.0, 1.0)
        p_free = check.in_range(p_free, "p_free", 0.0, 1.0)
        if not 0.5 < p_occupied < 1:
            raise ValueError(f"p_occupied must lie in (0.5, 1), got {p_occupied!r}")
        if not 0 < p_free < 0.5:
            raise ValueError(f"p_free must lie in (0, 0.5), got {p_free!r}")
        if poses.ndim != 2 or ranges.ndim != 2 or angles.ndim != 1:
            raise ValueError("poses, ranges and beam_angles must have shapes (S, 3), (S, K), (K,)")
        if ranges.shape != (poses.shape[0], angles.shape[0]):
            raise ValueError(
                f"ranges must have shape (S, K) = ({poses.shape[0]}, {angles.shape[0]}), "
                f"got {ranges.shape}"
            )
        if poses.shape[0] == 0:
            raise ValueError("poses must hold at least one scan pose, got shape (0, 3)")
        if np.any(ranges < 0):
            raise ValueError("ranges must be non-negative")
        phi = poses[:, 2:3] + angles
        valid = ranges < max_range
        with np.errstate(over="ignore", invalid="ignore"):
            ex = poses[:, 0:1] + ranges * np.cos(phi)
            ey = poses[:, 1:2] + ranges * np.sin(phi)
        for e in (ex, ey):
            check.no_overflow(
                np.where(valid, e, 0.0), "a scan end point", poses=poses, ranges=ranges
            )
        # The map spans the poses and the end points (only the poses if every reading is
        # at max range: then the grid is all free), with room for the cell of the largest.
        xs = np.concatenate([poses[:, 0], ex[valid]])
        ys = np.concatenate([poses[:, 1], ey[valid]])
        with np.errstate(over="ignore", invalid="ignore"):  # too many cells: reported below
            lo = np.array([xs.min(), ys.min()]) - margin
            hi = np.array([xs.max(), ys.max()]) + margin
            origin = np.floor(lo / resolution) * resolution
            size = np.floor((hi - origin) / resolution) + 1.0
        # Counts are at most one per beam and cell: the smallest unsigned type that holds S·K.
        count_type = np.min_scalar_type(ranges.size)
        cells = float(size[0]) * float(size[1])
        # two counts; occupied and free cells, their copies in the grid, one temporary
        need = cells * (2 * count_type.itemsize + 5)
        try:
            if not (np.all(np.isfinite(origin)) and cells < 2**62):
                raise MemoryError
            w, h = (int(n) for n in size)
            hits = np.zeros(h * w, dtype=count_type)
            free = np.zeros(h * w, dtype=count_type)
        except MemoryError:
            raise MemoryError(
                f"from_scans: the scans span {hi[0] - lo[0]:.4g} m x {hi[1] - lo[1]:.4g} m, "
                f"{size[1]:.4g} x {size[0]:.4g} cells at resolution {resolution!r} m, which "
                f"need about {need / 2**30:.3g} GiB; use a coarser resolution or fewer, "
                "closer scans"
            ) from None
        # End points: hit counts.
        hj = np.floor((ex[valid] - origin[0]) / resolution).astype(np.int64)
        hi_ = np.floor((ey[valid] - origin[1]) / resolution).astype(np.int64)
        _add_counts(hits, hi_ * w + hj)
        # Free space: points every half cell from the sensor up to one cell before
        # the end point (readings at max range carve nothing), processed in chunks.
        sx, sy = (
            np.broadcast_to(poses[:, 0:1], ranges.shape),
            np.broadcast_to(poses[:, 1:2], ranges.shape),
        )
        c, s = np.cos(phi), np.sin(phi)
        length = np.where(valid, ranges - resolution, 0.0)
        keep = length > 0
        sx, sy, c, s, length = sx[keep], sy[keep], c[keep], s[keep], length[keep]
        step = 0.5 * resolution
        n_steps = np.ceil(length / step).astype(np.int64) + 1
        start = 0
        chunk = max(1, 2_000_000 // max(1, int(n_steps.max(initial=1))))
        while start < length.size:
            sl = slice(start, start + chunk)
            n = n_steps[sl]
            total = int(n.sum())
            beam = np.repeat(np.arange(n.size), n)
            offs = np.arange(total) - np.repeat(np.cumsum(n) - n, n)
            t = np.minimum(offs * step, length[sl][beam])
            px = sx[sl][beam] + t * c[sl][beam]
            py = sy[sl][beam] + t * s[sl][beam]
            cj = np.floor((px - origin[0]) / resolution).astype(np.int64)
            ci = np.floor((py - origin[1]) / resolution).astype(np.int64)
            flat = ci * w + cj
            # Count each cell once per beam (a beam's samples are in order along it).
            new = np.ones(total, dtype=bool)
            new[1:] = (flat[1:] != flat[:-1]) | (beam[1:] != beam[:-1])
            _add_counts(free, flat[new])
            start += chunk
        l_occ = np.log(p_occupied / (1 - p_occupied))
        l_free = np.log(p_free / (1 - p_free))
        # Only a hit cell can have positive log-odds (l_free < 0): evaluate those alone.
        occupied = np.zeros(h * w, dtype=bool)
        hit = np.flatnonzero(hits)
        occupied[hit] = hits[hit] * l_occ + free[hit] * l_free > 0
        # The cells some beam saw (hit or crossed) and that are not occupied are free.
        seen = hits > 0
        seen |= free > 0
        seen &= ~occupied
        return cls(occupied.reshape(h, w), resolution, origin, free=seen.reshape(h, w))

    def __repr__(self) -> str:
        h, w = self.shape
        return (
            f"OccupancyGrid({h}x{w} cells of {self.resolution} m, "
            f"origin={tuple(self.origin.tolist())}, "
            f"{int(self.occupied.sum())} occupied)"
        )


def _add_counts(counts: np.ndarray, flat: np.ndarray) -> None:
    """``counts[k] += (number of times k occurs in flat)``, without a large int64 temporary.

    ``np.bincount`` (fast) while its int64 result stays small next to the work, else a sort.
    The caller guarantees that no count exceeds ``counts``' dtype.
    """
    if counts.size <= max(1 << 22, 4 * flat.size):
        np.add(counts, np.bincount(flat, minlength=counts.size), out=counts, casting="unsafe")
    else:
        cells, n = np.unique(flat, return_counts=True)
        counts[cells] += n.astype(counts.dtype)


def _check_grid(grid) -> OccupancyGrid:
    if not isinstance(grid, OccupancyGrid):
        raise ValueError(f"grid must be an OccupancyGrid, got {type(grid).__name__}")
    return grid


def _check_inside(grid: OccupancyGrid, xy: np.ndarray, name: str) -> None:
    inside = grid.contains(xy)
    if not np.all(inside):
        bad = xy[~inside][0]
        raise ValueError(
            f"{name}: {int((~inside).sum())} pose(s) lie outside the map "
            f"(extent {grid.extent}), e.g. ({bad[0]:.3f}, {bad[1]:.3f})"
        )


def ray_cast(grid, poses, beam_angles, max_range, *, method="hybrid"):
    r"""Return the expected range :math:`z^*` of each beam of each pose.

    The range is the distance from the pose to the boundary of the first occupied
    cell that the beam enters (0 if the pose's own cell is occupied), or
    ``max_range`` if there is none within ``max_range`` (space outside the grid is
    free). Used by the beam model, *Probabilistic Robotics*, Table 6.1 line 4.

    Parameters
    ----------
    grid : OccupancyGrid
    poses : array_like, shape (..., 3)
        Sensor poses (x, y, θ); each must lie inside the grid.
    beam_angles : array_like, shape (K,)
        Beam directions relative to the heading θ, in radians.
    max_range : float
        Maximum range in metres (> 0).
    method : {"hybrid", "dda", "march"}
        ``"hybrid"`` (default): exact traversal accelerated by sphere tracing;
        ``"dda"``: plain exact Amanatides–Woo traversal; ``"march"``: approximate ray
        marching (see the module docstring).

    Returns
    -------
    ranges : ndarray, shape (..., K)
    """
    grid = _check_grid(grid)
    poses = check.poses(poses, "poses")
    angles = check.finite(beam_angles, "beam_angles")
    if angles.ndim != 1:
        raise ValueError(f"beam_angles must have shape (K,), got {angles.shape}")
    max_range = check.positive_scalar(max_range, "max_range")
    method = check.choice(method, "method", _METHODS)
    _check_inside(grid, poses[..., :2], "poses")
    ranges, _ = _cast(grid, poses.reshape(-1, 3), angles, max_range, method)
    return ranges.reshape(*poses.shape[:-1], angles.size)


def _cast(grid, flat, angles, max_range, method):
    """:func:`ray_cast` on checked input: poses ``(N, 3)`` inside the grid, angles ``(K,)``.

    Returns
    -------
    ranges : ndarray, shape (N, K)
    steps : dict
        Loop iterations used by each stage (keys of ``_step_bounds``): the most that any
        one ray used.
    """
    res = grid.resolution
    # Ray r = p·K + k is beam k of pose p: its origin in cell units, and its direction
    # from cos(θ + a) = cos θ cos a − sin θ sin a (2N + 2K trig calls instead of 2NK).
    rays = (
        (flat[:, 0] - grid.origin[0]) / res,
        (flat[:, 1] - grid.origin[1]) / res,
        np.cos(flat[:, 2]),
        np.sin(flat[:, 2]),
        np.cos(angles),
        np.sin(angles),
    )
    t_max = max_range / res
    bounds = _step_bounds(grid.shape, t_max)
    h, w = grid.shape
    t = np.empty(flat.shape[0] * angles.size)
    if method == "hybrid":
        code, free = grid._traversal_tables
        stages = ("sphere", "hybrid")
        used = _cast_hybrid(code, free, h, w, rays, t_max, bounds["sphere"], bounds["hybrid"], t)
    elif method == "dda":
        stages = ("dda",)
        used = _cast_dda(grid.occupied.ravel(), h, w, rays, t_max, bounds["dda"], t)
    else:
        stages = ("march",)
        dist = grid.distance_field.ravel() / res
        used = _cast_march(dist, h, w, rays, t_max, 0.5, bounds["march"], t)
    steps = dict(zip(stages, used, strict=True))
    for stage, n in steps.items():
        if n > bounds[stage]:  # a ray still in flight after its bound: stopped there, NaN
            raise _unfinished(stage, int(np.isnan(t).sum()), bounds[stage])
    return np.minimum(t * res, max_range).reshape(flat.shape[0], angles.size), steps


def _step_bounds(shape, t_max) -> dict[str, int]:
    """Return the most loop iterations each ray-casting stage can take (the proof of termination).

    Every loop of :func:`ray_cast` runs at most this many times on a grid of ``shape``
    cells with ``t_max = max_range / resolution`` (in cells); a ray still in flight
    after its bound would be a bug, reported as ``RuntimeError``, never a hang.

    * ``"dda"``: each step moves one cell, always the same way along each axis, so a ray
      leaves the ``H × W`` grid after at most ``H + W`` steps.
    * ``"sphere"``: each jump advances more than one cell, and a ray that has travelled
      the diagonal of the padded grid stands on its outer ring (free radius 0), so at most
      ``ceil(min(t_max, hypot(H + 2, W + 2))) + 2`` jumps.
    * ``"hybrid"``: each step moves the cell at least one cell forward (in the ray's
      direction along one axis, never back along the other), in a grid padded by one ring:
      at most ``H + W + 4`` steps.
    * ``"march"``: each step advances at least half a cell (it stops below that), so at
      most ``ceil(2 min(t_max, hypot(H, W))) + 2`` steps.

    Parameters
    ----------
    shape : (int, int)
        ``(H, W)``, the grid's rows and columns.
    t_max : float
        Maximum range in cells (> 0).

    Returns
    -------
    bounds : dict
        ``{"dda": int, "sphere": int, "hybrid": int, "march": int}``.
    """
    h, w = shape
    reach = min(float(t_max), float(np.hypot(h + 2, w + 2)))
    return {
        "dda": h + w,
        "sphere": int(np.ceil(reach)) + 2,
        "hybrid": h + w + 4,
        "march": int(np.ceil(2.0 * min(float(t_max), float(np.hypot(h, w))))) + 2,
    }


def _unfinished(stage: str, n: int, bound: int) -> RuntimeError:
    return RuntimeError(
        f"ray casting ({stage}): {n} ray(s) still in flight after the proven bound of "
        f"{bound} steps; this is a bug in probrob.maps, please report it"
    )


# ------------------------------------------------------------------ the compiled traversals
# Compiled by numba, without fast-math (every operation rounds as in IEEE double
# precision, never fused or reordered: the ranges are the scalar algorithm's to the last
# bit); error_model="numpy" leaves out Python's zero-division checks (1/d is taken only
# for d != 0). A traversal returns the range in cells and the loop iterations it used; a
# ray still in flight after its bound returns NaN and ``bound + 1`` (``_cast`` raises).


@njit(cache=True, error_model="numpy")
def _crossing(x0, d):
    """``(inv, c)`` such that a ray in cell ``j`` crosses its next boundary along this axis at
    ``t = (j + c) * inv``: ``c = (d > 0) - x0``, ``inv = 1 / d``; ``c = inf``, ``inv = 1``
    for a ray that never crosses (``d == 0``). Both exact traversals use this one formula,
    so they order the crossings of a ray through a corner alike. A crossing beyond float64
    (``|d|`` near 1e-308) is at ``inf``.
    """
    if d != 0.0:
        return 1.0 / d, (1.0 if d > 0.0 else 0.0) - x0
    return 1.0, np.inf


@njit(cache=True, error_model="numpy")
def _floor_clip(v, lo, hi):
    """``clip(floor(v), lo, hi)``: the cell of coordinate ``v``, kept to ``[lo, hi]``."""
    return min(max(np.floor(v), lo), hi)


@njit(cache=True, error_model="numpy")
def _ray(rays, r):
    """Origin ``(x0, y0)`` and direction ``(dx, dy)`` of ray ``r`` (beam k of pose p,
    ``r = p·K + k``), in cell units, from ``rays = (x, y, cos θ, sin θ, cos a, sin a)``.

    A subnormal direction component (|d| < 2.2e-308, e.g. sin θ at θ = 1e-310) would
    overflow 1/d: it becomes ±2.2e-308, keeping its sign, so a ray along a grid line stays
    on its side.
    """
    x, y, cos_t, sin_t, cos_a, sin_a = rays
    p, k = divmod(r, cos_a.size)
    dx = cos_t[p] * cos_a[k] - sin_t[p] * sin_a[k]
    dy = sin_t[p] * cos_a[k] + cos_t[p] * sin_a[k]
    if dx != 0.0 and abs(dx) < _TINY:
        dx = np.copysign(_TINY, dx)
    if dy != 0.0 and abs(dy) < _TINY:
        dy = np.copysign(_TINY, dy)
    return x[p], y[p], dx, dy


@njit(cache=True, error_model="numpy")
def _dda_ray(occ, h, w, x0, y0, dx, dy, t_max, bound):
    """Plain Amanatides–Woo traversal of one ray in cell units, one cell per step.

    The ray enters cell (i, j) at distance t; the next boundary crossings are computed
    from the ray origin each step (no accumulated rounding). Every step moves the cell by
    one, the same way along each axis: at most ``bound = H + W`` steps.
    """
    j, i = int(np.floor(x0)), int(np.floor(y0))
    sx = 1 if dx > 0.0 else -1
    sy = 1 if dy > 0.0 else -1
    inv_dx, cx = _crossing(x0, dx)
    inv_dy, cy = _crossing(y0, dy)
    t = 0.0
    steps = 0
    while True:
        if steps == bound:
            return np.nan, bound + 1
        steps += 1
        if occ[i * w + j]:
            return t, steps
        # Next cell boundary along x and along y (distance from the origin).
        tx = (j + cx) * inv_dx
        ty = (i + cy) * inv_dy
        if tx <= ty:
            t, j = tx, j + sx
        else:
            t, i = ty, i + sy
        if t >= t_max or i < 0 or i >= h or j < 0 or j >= w:
            return t_max, steps


@njit(cache=True, error_model="numpy")
def _sphere_jump(free, h, w, x0, y0, dx, dy, t, t_max):
    """One step of sphere tracing: ``(t + free radius, True)`` while the radius at ``t``
    exceeds one cell and ``t < t_max``, else ``(t, False)`` (the ray stops there).

    Every landing point is in free space (the radius is a lower bound of the distance to
    any occupied cell) or outside the map (then on the outside ring, radius 0). Each jump
    advances more than one cell: at most ``_step_bounds(...)["sphere"]`` jumps.
    """
    jj = int(_floor_clip(x0 + t * dx, -1.0, float(w)))
    ii = int(_floor_clip(y0 + t * dy, -1.0, float(h)))
    f = free[(ii + 1) * (w + 2) + jj + 1]
    if f > 1.0 and t < t_max:
        return min(t + f, t_max), True
    return t, False


@njit(cache=True, error_model="numpy")
def _hybrid_step(code, free, h, w, ray, t, i, j, t_max):
    """One step of the traversal of :func:`_cast_hybrid` for one ray in cell ``(i, j)``,
    entered at distance ``t``: ``(done, t, i, j)`` after it.

    ``ray`` holds the ray's constants ``(bx, by, dx, dy, cx, cy, inv_dx, inv_dy, sx, sy)``.
    The ray is done in an occupied cell (range ``t``), on the outside ring or at
    ``t_max`` (range ``t_max``). Otherwise it either crosses the nearer cell boundary (t
    from the ray origin, no accumulated rounding) or, where the distance field proves a
    longer stretch free, jumps to ``t + free`` and re-locates the cell by flooring.
    """
    bx, by, dx, dy, cx, cy, inv_dx, inv_dy, sx, sy = ray
    cell = (i + 1) * (w + 2) + j + 1
    c = code[cell]
    if c != 0 or t >= t_max:
        return True, (t if c == 1 and t < t_max else t_max), i, j
    tx = (j + cx) * inv_dx  # a crossing beyond float64 is at inf
    ty = (i + cy) * inv_dy
    t_dda = max(min(tx, ty), t)
    t_jump = min(t + free[cell], t_max)
    if t_jump > t_dda:
        # Where the jump lands, never behind the current cell along either axis; taken
        # only if it leaves the cell.
        jj = int(_floor_clip(bx + t_jump * dx, -1.0, float(w)))
        ii = int(_floor_clip(by + t_jump * dy, -1.0, float(h)))
        jj = max(jj, j) if sx > 0.0 else min(jj, j)
        ii = max(ii, i) if sy > 0.0 else min(ii, i)
        if jj != j or ii != i:
            return False, t_jump, ii, jj
    step_x = tx <= ty  # one of the two, selected without a branch
    return False, t_dda, i + int(sy) * (1 - step_x), j + int(sx) * step_x


# Rays traced in lockstep by _cast_hybrid: one ray's step waits on a table look-up, and the
# steps of a block's independent rays overlap in the CPU (measured: sphere tracing 1.8x, the
# whole traversal 1.25x faster than ray after ray).
_BLOCK = 16


@njit(cache=True, error_model="numpy")
def _march_ray(dist, h, w, x0, y0, dx, dy, t_max, stop, bound):
    """Sphere tracing of one ray on the distance field (range_libc's ``RayMarching``).

    Each step advances by at least ``stop`` (a smaller distance is a hit), so the ray ends
    within ``_step_bounds(...)["march"]`` steps.
    """
    t = 0.0
    steps = 0
    while True:
        if steps == bound:
            return np.nan, bound + 1
        steps += 1
        # clipped to the ring around the grid: t may be 1e300 cells (an empty map)
        j = int(_floor_clip(x0 + t * dx, -1.0, float(w)))
        i = int(_floor_clip(y0 + t * dy, -1.0, float(h)))
        if i < 0 or i >= h or j < 0 or j >= w or t >= t_max:
            return t_max, steps
        d = dist[i * w + j]
        if d < stop:
            return t, steps
        t = min(t + d, t_max)


@njit(cache=True, error_model="numpy")
def _cast_hybrid(code, free, h, w, rays, t_max, bound_sphere, bound, out):
    """Amanatides–Woo traversal with sphere-tracing jumps, in cell units, for every ray.

    Each ray (:func:`_ray`) first crosses open space by
    sphere tracing alone (:func:`_sphere_jump`, a cheaper step) while the free radius
    exceeds a cell, then is traversed from where it stopped (:func:`_hybrid_step`), in a
    cell (i, j) from -1 to H (or W) with the ring of "outside" cells around the grid. A
    jump never enters an occupied cell, so the first occupied cell is entered exactly
    where the plain traversal (:func:`_dda_ray`) enters it. Positions stay in the grid's
    own cell coordinates (shifting them by the ring would round a pose a few ulps off a
    grid line onto it).

    Where a jump lands, the cell is found by flooring the position pulled back by
    ``_PULL_BACK`` cells along the ray. Flooring the position itself can round a point a
    few ulps before a boundary onto it (a pose near a grid line, a beam along it): the ray
    would continue one cell ahead of where the plain traversal is, in the wrong row or
    column. The pulled-back point lies in the right cell or in the one before it, which is
    free (within 2e-9 cells of the landing point) and whose boundary, now behind ``t``, the
    next step crosses at ``t``.

    Termination by construction: t never decreases (a boundary behind t is crossed at t),
    a located cell never lies behind the current one along either axis, and a jump is
    taken only if it moves the cell forward, so every step moves the cell at least one
    cell forward and a ray reaches the outside ring within ``bound`` steps. (Without
    these rules a pose on a grid line with a beam along it jumped back and forth between
    two cells for ever.)

    The rays go in blocks of ``_BLOCK``, each stage in lockstep; ``out[r]`` is ray r's
    range in cells (NaN for a ray still in flight after its bound). Returns the most
    sphere-tracing jumps and traversal steps that any ray used (``bound + 1`` if one
    was still in flight).
    """
    n = out.size
    t = np.zeros(_BLOCK)
    i = np.zeros(_BLOCK, np.int64)
    j = np.zeros(_BLOCK, np.int64)
    live = np.zeros(_BLOCK, np.bool_)
    ray = np.zeros((_BLOCK, 4))  # x0, y0, dx, dy
    const = np.zeros((_BLOCK, 10))  # the traversal's constants (see _hybrid_step)
    most_sphere = most = 0
    for start in range(0, n, _BLOCK):
        m = min(_BLOCK, n - start)
        # Open space first, by sphere tracing alone.
        for k in range(m):
            ray[k] = _ray(rays, start + k)
        t[:m] = 0.0
        live[:m] = True
        steps = 0
        in_flight = m
        while in_flight:
            if steps == bound_sphere:
                out[start : start + m][live[:m]] = np.nan
                return bound_sphere + 1, 0
            steps += 1
            in_flight = 0
            for k in range(m):
                if live[k]:
                    x0, y0, dx, dy = ray[k]
                    t[k], live[k] = _sphere_jump(free, h, w, x0, y0, dx, dy, t[k], t_max)
                    in_flight += live[k]
        most_sphere = max(most_sphere, steps)
        # Then the traversal from where each ray stopped. Next boundary crossing along x:
        # t_x = (j + cx) * inv_dx, as in _dda_ray. Cells are located from positions pulled
        # back by _PULL_BACK along the ray (see the docstring): a landing point rounded onto
        # the boundary ahead stays in the cell before. A ray that has not moved starts
        # where _dda_ray starts, in the cell of its origin. A ray never stands behind its
        # origin: the pulled-back cell is clipped to the grid on that side (a ray along the
        # map's edge stays on the map), to the outside ring ahead.
        for k in range(m):
            x0, y0, dx, dy = ray[k]
            inv_dx, cx = _crossing(x0, dx)
            inv_dy, cy = _crossing(y0, dy)
            sx = 1.0 if dx > 0.0 else -1.0
            sy = 1.0 if dy > 0.0 else -1.0
            bx = x0 - (sx * _PULL_BACK if dx != 0.0 else 0.0)
            by = y0 - (sy * _PULL_BACK if dy != 0.0 else 0.0)
            lox, hix = (0.0, float(w)) if sx > 0.0 else (-1.0, w - 1.0)
            loy, hiy = (0.0, float(h)) if sy > 0.0 else (-1.0, h - 1.0)
            moved = t[k] > 0.0
            j[k] = int(_floor_clip(bx + t[k] * dx if moved else x0, lox, hix))
            i[k] = int(_floor_clip(by + t[k] * dy if moved else y0, loy, hiy))
            const[k] = (bx, by, dx, dy, cx, cy, inv_dx, inv_dy, sx, sy)
            live[k] = True
        steps = 0
        in_flight = m
        while in_flight:
            in_flight = 0
            for k in range(m):
                if live[k]:
                    c = const[k]
                    done, t_k, i_k, j_k = _hybrid_step(
                        code,
                        free,
                        h,
                        w,
                        (c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], c[9]),
                        t[k],
                        i[k],
                        j[k],
                        t_max,
                    )
                    if done:
                        out[start + k] = t_k
                        live[k] = False
                    elif steps == bound:
                        out[start + k] = np.nan
                        return most_sphere, bound + 1
                    else:
                        t[k], i[k], j[k] = t_k, i_k, j_k
                        in_flight += 1
            steps += in_flight > 0
        most = max(most, steps)
    return most_sphere, most


@njit(cache=True, error_model="numpy")
def _cast_dda(occ, h, w, rays, t_max, bound, out):
    """:func:`_dda_ray` on every ray; ``out[r]`` its range; the most steps of any ray."""
    most = 0
    for r in range(out.size):
        x0, y0, dx, dy = _ray(rays, r)
        out[r], n = _dda_ray(occ, h, w, x0, y0, dx, dy, t_max, bound)
        most = max(most, n)
    return (most,)


@njit(cache=True, error_model="numpy")
def _cast_march(dist, h, w, rays, t_max, stop, bound, out):
    """:func:`_march_ray` on every ray; ``out[r]`` its range; the most steps of any ray."""
    most = 0
    for r in range(out.size):
        x0, y0, dx, dy = _ray(rays, r)
        out[r], n = _march_ray(dist, h, w, x0, y0, dx, dy, t_max, stop, bound)
        most = max(most, n)
    return (most,)
