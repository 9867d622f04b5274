r"""Occupancy grids, their distance field, and ray casting (*Probabilistic Robotics*, ch. 6).

Holds occupancy grids, their distance field and ray casting.
Does not hold the range-finder models that use them (:mod:`probrob.sensors`).

* :class:`OccupancyGrid` — a boolean grid of occupied cells with a metric resolution
  and origin, built from an array or from laser scans at known poses
  (:meth:`OccupancyGrid.from_scans`), with world ↔ cell conversions and the metric
  :attr:`~OccupancyGrid.distance_field` (scipy's exact Euclidean distance transform).
* :func:`ray_cast` — the expected range :math:`z^*` of every beam of every pose,
  vectorised over poses × beams: the distance from the sensor to the boundary of the
  first occupied cell the beam enters, or ``max_range``.

Conventions (the book's *conventions* page): ``occupied[i, j]`` is row ``i`` (y) and column ``j`` (x);
cell ``(i, j)`` covers :math:`x \in [o_x + j r, o_x + (j+1) r)`,
:math:`y \in [o_y + i r, o_y + (i+1) r)`. Space outside the grid is free: a beam that
leaves the grid returns ``max_range``.

Ray casting has three methods, all exact up to floating-point rounding except the
last:

``"hybrid"`` (default)
    Sphere tracing across open space (jumps by the free radius while it exceeds a
    cell), then Amanatides–Woo grid traversal that keeps skipping free space: at each
    step the ray advances to the larger of the next cell boundary and the distance
    that the distance field proves free (the distance from the cell's centre to the
    nearest occupied centre, minus twice the half diagonal of a cell). A jump never
    enters an occupied cell, so the first occupied cell is entered where the plain
    traversal enters it. Both compute a boundary crossing by the same formula, so the
    ranges equal ``"dda"``'s, also on poses on grid lines and corners with beams along
    the axes (the tests hold both to :math:`10^{-9}` m of an independent scalar
    traversal and to each other; the benchmark finds them identical on all of its
    180,000 beams).
``"dda"``
    The plain vectorised Amanatides–Woo traversal (one cell per step), the reference.
``"march"``
    Plain sphere tracing (ray marching) on the distance field as in range_libc's
    ``RayMarching``: step by the distance to the nearest occupied cell centre and stop
    when it falls below half a cell. Approximate, with no bound on the error: a beam
    that passes within half a cell of an occupied cell's centre stops there, however far
    the cell it really hits (on the benchmark's 180,000 beams the error has median 0.5
    cells and 99th percentile 1 cell, but reaches 353 cells on a beam that grazes a
    corner); kept to show what the exact methods buy.

Every traversal terminates by construction: each step moves a ray at least one cell
forward (or, when marching, half a cell), so its loop is bounded by the grid's size; the
bounds are ``_step_bounds``, and a ray still in flight after its bound raises
``RuntimeError`` (a bug) instead of looping.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

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
        Loop iterations used by each stage (keys of ``_step_bounds``).
    """
    res = grid.resolution
    gx = np.repeat((flat[:, 0] - grid.origin[0]) / res, angles.size)
    gy = np.repeat((flat[:, 1] - grid.origin[1]) / res, angles.size)
    # cos(θ + a) = cos θ cos a − sin θ sin a: 2N + 2K trig calls instead of 2NK.
    ct, st = np.cos(flat[:, 2:3]), np.sin(flat[:, 2:3])
    ca, sa = np.cos(angles), np.sin(angles)
    dx = (ct * ca - st * sa).ravel()
    dy = (st * ca + ct * sa).ravel()
    # A subnormal component (|d| < 2.2e-308, e.g. sin θ at θ = 1e-310) would overflow 1/d:
    # it becomes ±2.2e-308, keeping its sign, so a ray along a grid line stays on its side.
    for d in (dx, dy):
        tiny = (d != 0) & (np.abs(d) < _TINY)
        d[tiny] = np.copysign(_TINY, d[tiny])
    t, steps = _CASTERS[method](grid, gx, gy, dx, dy, max_range / res)
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


def _traverse(grid, gx, gy, dx, dy, t_max):
    """Plain Amanatides–Woo traversal in cell units, one cell per step (the reference).

    State per active ray: its cell (i, j) and the distance t at which it entered it.
    The next boundary crossings are computed from the ray origin each step (no
    accumulated rounding). Every step moves the cell by one, the same way along each
    axis, so the loop ends within ``_step_bounds(...)["dda"]`` steps.

    Returns
    -------
    t : ndarray, shape (n,)
        Ranges in cells.
    steps : dict
        ``{"dda": loop iterations used}``.
    """
    h, w = grid.shape
    bound = _step_bounds(grid.shape, t_max)["dda"]
    occ = grid.occupied.ravel()
    n = gx.size
    out = np.full(n, t_max)
    idx = np.arange(n)
    j = np.floor(gx).astype(np.int64)
    i = np.floor(gy).astype(np.int64)
    sx = np.where(dx > 0, 1, -1)
    sy = np.where(dy > 0, 1, -1)
    inv_dx, cx = _crossing_terms(gx, dx)
    inv_dy, cy = _crossing_terms(gy, dy)
    t = np.zeros(n)
    steps = 0
    while idx.size:
        if steps == bound:
            raise _unfinished("dda", idx.size, bound)
        steps += 1
        hit = occ[i * w + j]
        if hit.any():
            out[idx[hit]] = t[hit]
            keep = ~hit
            idx, i, j, t = idx[keep], i[keep], j[keep], t[keep]
            cx, cy = cx[keep], cy[keep]
            sx, sy, inv_dx, inv_dy = sx[keep], sy[keep], inv_dx[keep], inv_dy[keep]
        # Next cell boundary along x and along y (distance from the origin).
        with np.errstate(over="ignore"):  # a crossing beyond float64 is at inf
            tx = (j + cx) * inv_dx
            ty = (i + cy) * inv_dy
        step_x = tx <= ty
        t = np.where(step_x, tx, ty)
        j = j + np.where(step_x, sx, 0)
        i = i + np.where(step_x, 0, sy)
        done = (t >= t_max) | (i < 0) | (i >= h) | (j < 0) | (j >= w)
        if done.any():
            keep = ~done
            idx, i, j, t = idx[keep], i[keep], j[keep], t[keep]
            cx, cy = cx[keep], cy[keep]
            sx, sy, inv_dx, inv_dy = sx[keep], sy[keep], inv_dx[keep], inv_dy[keep]
    return out, {"dda": steps}


def _crossing_terms(x0, dx):
    """``(inv, c)`` such that a ray in cell ``j`` crosses its next boundary along this axis at
    ``t = (j + c) * inv``: ``c = (dx > 0) - x0``, ``inv = 1 / dx``; ``c = inf``, ``inv = 1``
    for a ray that never crosses (``dx == 0``). Both traversals use this one formula, so
    they order the crossings of a ray through a corner alike. A crossing beyond float64
    (``|dx|`` near 1e-308) is at ``inf``: the caller ignores that overflow.
    """
    moving = dx != 0
    inv = np.where(moving, 1.0 / np.where(moving, dx, 1.0), 1.0)
    return inv, np.where(moving, (dx > 0) - x0, np.inf)


def _traverse_hybrid(grid, gx, gy, dx, dy, t_max):
    """Amanatides–Woo traversal with sphere-tracing jumps, in cell units.

    State per ray in flight: its cell (i, j), from -1 to H (or W) with the ring of
    "outside" cells around the grid, and the distance t at which it entered the cell.
    Each step either crosses the nearer cell boundary (t from the ray origin, no
    accumulated rounding) or, where the distance field proves a longer stretch free,
    jumps to ``t + free`` and re-locates the cell by flooring. A jump never enters an
    occupied cell, so the first occupied cell is entered exactly where the plain
    traversal enters it. Rays reaching an occupied cell, the outside ring or ``t_max``
    leave the arrays. Positions stay in the grid's own cell coordinates (shifting them by
    the ring would round a pose a few ulps off a grid line onto it).

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
    cell forward and a ray reaches the outside ring within ``_step_bounds(...)["hybrid"]``
    steps. (Without these rules a pose on a grid line with a beam along it jumped back and
    forth between two cells for ever.)

    Returns
    -------
    t : ndarray, shape (n,)
        Ranges in cells.
    steps : dict
        ``{"sphere": jumps of :func:`_sphere_trace`, "hybrid": traversal iterations}``.
    """
    h, w = grid.shape
    bound = _step_bounds(grid.shape, t_max)["hybrid"]
    code, free = grid._traversal_tables
    wf = float(w + 2)
    pad = wf + 1.0  # table index of cell (i, j): i * wf + j + pad
    out = np.full(gx.size, t_max)
    x0, y0 = gx, gy
    # Next boundary crossing along x: t_x = (j + cx) * inv_dx, as in _traverse.
    inv_dx, cx = _crossing_terms(x0, dx)
    inv_dy, cy = _crossing_terms(y0, dy)
    sx = np.where(dx > 0, 1.0, -1.0)
    sy = np.where(dy > 0, 1.0, -1.0)
    # Open space first, by sphere tracing alone (a cheaper step), while the free radius
    # exceeds a cell; then the traversal below from where each ray stopped.
    t, sphere_steps = _sphere_trace(free, grid.shape, x0, y0, dx, dy, t_max)
    # Cells are located from positions pulled back by _PULL_BACK along the ray (see the
    # docstring): a landing point rounded onto the boundary ahead stays in the cell before.
    # A ray that has not moved starts where _traverse starts, in the cell of its origin.
    # A ray never stands behind its origin: the pulled-back cell is clipped to the grid on
    # that side (a ray along the map's edge stays on the map), to the outside ring ahead.
    bx = x0 - np.where(dx != 0, sx * _PULL_BACK, 0.0)
    by = y0 - np.where(dy != 0, sy * _PULL_BACK, 0.0)
    lox, hix = np.where(sx > 0, 0.0, -1.0), np.where(sx > 0, w, w - 1.0)
    loy, hiy = np.where(sy > 0, 0.0, -1.0), np.where(sy > 0, h, h - 1.0)
    px, py = sx > 0, sy > 0
    moved = t > 0
    j = np.clip(np.floor(np.where(moved, bx + t * dx, x0)), lox, hix)
    i = np.clip(np.floor(np.where(moved, by + t * dy, y0)), loy, hiy)
    idx = np.arange(gx.size)
    steps = 0
    while idx.size:
        cell = (i * wf + j + pad).astype(np.intp)
        c = code[cell]
        done = (c != 0) | (t >= t_max)
        if done.any():
            hit = done & (c == 1) & (t < t_max)
            out[idx[hit]] = t[hit]
            keep = ~done
            bx, by, dx, dy, px, py = bx[keep], by[keep], dx[keep], dy[keep], px[keep], py[keep]
            inv_dx, inv_dy, cx, cy = inv_dx[keep], inv_dy[keep], cx[keep], cy[keep]
            sx, sy, idx, i, j, t = sx[keep], sy[keep], idx[keep], i[keep], j[keep], t[keep]
            cell = cell[keep]
            if not idx.size:
                break
        if steps == bound:
            raise _unfinished("hybrid", idx.size, bound)
        steps += 1
        with np.errstate(over="ignore"):  # a crossing beyond float64 is at inf
            tx = (j + cx) * inv_dx
            ty = (i + cy) * inv_dy
            step_x = tx <= ty
            t_dda = np.maximum(np.minimum(tx, ty), t)
            t_jump = np.minimum(t + free[cell], t_max)
            # Where the jump lands, never behind the current cell along either axis.
            # (the clamp below keeps the pulled-back cell on the grid's side behind the ray)
            jj = np.clip(np.floor(bx + t_jump * dx), -1.0, float(w))
            ii = np.clip(np.floor(by + t_jump * dy), -1.0, float(h))
        jj = np.where(px, np.maximum(jj, j), np.minimum(jj, j))
        ii = np.where(py, np.maximum(ii, i), np.minimum(ii, i))
        jump = (t_jump > t_dda) & ((jj != j) | (ii != i))
        t = np.where(jump, t_jump, t_dda)
        j = np.where(jump, jj, j + sx * step_x)
        i = np.where(jump, ii, i + sy * ~step_x)
    return out, {"sphere": sphere_steps, "hybrid": steps}


def _sphere_trace(free, shape, x0, y0, dx, dy, t_max):
    """Jump each ray by its cell's free radius while that exceeds one cell; return the t reached.

    Every landing point is in free space (the radius is a lower bound of the distance to
    any occupied cell) or outside the map (then on the outside ring, radius 0). Each jump
    advances more than one cell: at most ``_step_bounds(...)["sphere"]`` jumps.

    Returns
    -------
    t : ndarray
        Where each ray stopped, in cells.
    steps : int
        Loop iterations used.
    """
    h, w = shape
    wf = float(w + 2)
    bound = _step_bounds(shape, t_max)["sphere"]
    t_out = np.zeros(x0.size)
    idx = np.arange(x0.size)
    t = np.zeros(x0.size)
    steps = 0
    while idx.size:
        if steps == bound:
            raise _unfinished("sphere tracing", idx.size, bound)
        steps += 1
        jj = np.clip(np.floor(x0 + t * dx), -1.0, float(w))
        ii = np.clip(np.floor(y0 + t * dy), -1.0, float(h))
        f = free[(ii * wf + jj + (wf + 1.0)).astype(np.intp)]
        go = (f > 1.0) & (t < t_max)
        if not go.all():
            stop = ~go
            t_out[idx[stop]] = t[stop]
            idx, t, f = idx[go], t[go], f[go]
            x0, y0, dx, dy = x0[go], y0[go], dx[go], dy[go]
        t = np.minimum(t + f, t_max)
    return t_out, steps


def _march(grid, gx, gy, dx, dy, t_max, *, stop=0.5):
    """Sphere tracing on the distance field (range_libc's ``RayMarching``), cell units.

    Each step advances by at least ``stop`` (a smaller distance is a hit), so every ray
    ends within ``_step_bounds(...)["march"]`` steps.

    Returns
    -------
    t : ndarray, shape (n,)
        Ranges in cells.
    steps : dict
        ``{"march": loop iterations used}``.
    """
    h, w = grid.shape
    bound = _step_bounds(grid.shape, t_max)["march"]
    dist = grid.distance_field.ravel() / grid.resolution
    n = gx.size
    out = np.full(n, t_max)
    idx = np.arange(n)
    t = np.zeros(n)
    steps = 0
    while idx.size:
        if steps == bound:
            raise _unfinished("march", idx.size, bound)
        steps += 1
        # clipped to the ring around the grid: t may be 1e300 cells (an empty map)
        j = np.floor(np.clip(gx + t * dx, -1.0, float(w))).astype(np.int64)
        i = np.floor(np.clip(gy + t * dy, -1.0, float(h))).astype(np.int64)
        outside = (i < 0) | (i >= h) | (j < 0) | (j >= w) | (t >= t_max)
        d = np.where(outside, 0.0, dist[np.clip(i, 0, h - 1) * w + np.clip(j, 0, w - 1)])
        hit = ~outside & (d < stop)
        out[idx[hit]] = t[hit]
        keep = ~(outside | hit)
        idx, t = idx[keep], np.minimum(t[keep] + d[keep], t_max)
        gx, gy, dx, dy = gx[keep], gy[keep], dx[keep], dy[keep]
    return out, {"march": steps}


_CASTERS = {"hybrid": _traverse_hybrid, "dda": _traverse, "march": _march}
