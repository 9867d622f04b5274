"""Occupancy grids, the distance field and ray casting (probrob.maps)."""

import math

import numpy as np
import pytest

from probrob.maps import OccupancyGrid, ray_cast

RES = 0.1


def aw_reference(occ, res, origin, x, y, heading, max_range):
    """Amanatides–Woo grid traversal of one ray, scalar Python (the tests' reference).

    Written independently of the library: it walks cell by cell, stepping along x when
    the next x boundary is not farther than the next y boundary.
    """
    h, w = occ.shape
    gx, gy = (x - origin[0]) / res, (y - origin[1]) / res
    dx, dy = math.cos(heading), math.sin(heading)
    j, i = math.floor(gx), math.floor(gy)
    t_max = max_range / res
    t = 0.0
    while True:
        if not (0 <= i < h and 0 <= j < w) or t >= t_max:
            return max_range
        if occ[i, j]:
            return t * res
        tx = (j + (dx > 0) - gx) / dx if dx != 0 else math.inf
        ty = (i + (dy > 0) - gy) / dy if dy != 0 else math.inf
        if tx <= ty:
            t, j = tx, j + (1 if dx > 0 else -1)
        else:
            t, i = ty, i + (1 if dy > 0 else -1)


def cluttered_map(n=120, seed=0):
    """Border walls, thin walls and discs: grazing, corner and head-on beams."""
    rng = np.random.default_rng(seed)
    occ = np.zeros((n, n), bool)
    occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = True
    yy, xx = np.ogrid[:n, :n]
    for _ in range(25):
        cx, cy = rng.integers(5, n - 5, 2)
        r = int(rng.integers(1, 6))
        if rng.random() < 0.5:
            occ[(xx - cx) ** 2 + (yy - cy) ** 2 < r * r] = True
        else:
            occ[cy - r : cy + r, cx] = True  # a wall one cell thick
    return occ


def random_free_poses(grid, n, rng):
    free = np.argwhere(~grid.occupied)
    cells = free[rng.choice(len(free), n)]
    xy = grid.cell_to_world(cells) + rng.uniform(-0.49, 0.49, (n, 2)) * grid.resolution
    return np.c_[xy, rng.uniform(-np.pi, np.pi, n)]


@pytest.fixture(scope="module")
def cluttered():
    return OccupancyGrid(cluttered_map(), RES, origin=(-3.0, 2.0))


# ---------------------------------------------------------------------------- the grid
def test_world_cell_round_trip_and_conventions():
    occ = np.zeros((3, 5), bool)
    g = OccupancyGrid(occ, 0.5, origin=(1.0, -2.0))
    assert g.shape == (3, 5)
    assert g.extent == (1.0, 3.5, -2.0, -0.5)
    # Cell (i, j) covers x in [ox + j res, ...), y in [oy + i res, ...): row is y.
    np.testing.assert_array_equal(g.world_to_cell([1.0, -2.0]), [0, 0])
    np.testing.assert_array_equal(g.world_to_cell([3.49, -0.51]), [2, 4])
    np.testing.assert_array_equal(g.world_to_cell([1.6, -1.1]), [1, 1])
    ij = np.stack(np.meshgrid(range(3), range(5), indexing="ij"), -1)
    np.testing.assert_array_equal(g.world_to_cell(g.cell_to_world(ij)), ij)
    np.testing.assert_allclose(g.cell_to_world([0, 0]), [1.25, -1.75])
    np.testing.assert_array_equal(g.contains([[1.0, -2.0], [3.5, -1.0], [0.99, -1.0]]), [1, 0, 0])


def test_distance_field_matches_brute_force():
    occ = cluttered_map(40, seed=3)
    g = OccupancyGrid(occ, 0.05)
    occ_xy = g.cell_to_world(np.argwhere(occ))
    all_ij = np.argwhere(np.ones_like(occ))
    centers = g.cell_to_world(all_ij)
    brute = np.sqrt(((centers[:, None, :] - occ_xy[None]) ** 2).sum(-1)).min(axis=1)
    np.testing.assert_allclose(g.distance_field[all_ij[:, 0], all_ij[:, 1]], brute, atol=1e-12)
    assert not g.distance_field.flags.writeable


def test_distance_field_of_an_empty_map_is_inf():
    g = OccupancyGrid(np.zeros((4, 4), bool), 1.0)
    assert np.all(np.isinf(g.distance_field))


@pytest.mark.parametrize(
    ("occupied", "resolution", "origin", "match"),
    [
        (np.zeros((0, 3), bool), 0.1, (0, 0), "non-empty 2-D"),
        (np.zeros(5, bool), 0.1, (0, 0), "non-empty 2-D"),
        (np.full((2, 2), 0.5), 0.1, (0, 0), "boolean"),
        (np.zeros((2, 2), bool), -0.1, (0, 0), "resolution"),
        (np.zeros((2, 2), bool), 0.1, (0, 0, 0), "origin"),
        (np.zeros((2, 2), bool), 0.1, (np.nan, 0), "origin"),
    ],
)
def test_bad_grids_raise(occupied, resolution, origin, match):
    with pytest.raises(ValueError, match=match):
        OccupancyGrid(occupied, resolution, origin)


def test_from_scans_recovers_a_box_room():
    # A 4 m x 3 m room; scans from three poses inside, ranges ray cast exactly.
    occ = np.zeros((40, 50), bool)
    occ[5, 5:45] = occ[35, 5:45] = True
    occ[5:36, 5] = occ[5:36, 44] = True
    room = OccupancyGrid(occ, RES)
    poses = np.array([[1.5, 1.5, 0.0], [3.0, 2.5, 1.0], [2.5, 1.0, -2.0]])
    angles = np.deg2rad(np.arange(-180, 180, 0.5))
    ranges = ray_cast(room, poses, angles, 10.0) + 1e-3  # just inside the wall cell
    built = OccupancyGrid.from_scans(poses, ranges, angles, RES, max_range=10.0)
    # Every wall cell the scans saw is occupied in the built map, nothing else is.
    walls_xy = room.cell_to_world(np.argwhere(occ))
    walls_built = built.cell_to_world(np.argwhere(built.occupied))
    d_built = np.sqrt(((walls_built[:, None] - walls_xy[None]) ** 2).sum(-1)).min(axis=1)
    assert d_built.max() < 1e-9  # no phantom obstacles
    d_room = np.sqrt(((walls_xy[:, None] - walls_built[None]) ** 2).sum(-1)).min(axis=1)
    assert np.mean(d_room < 1e-9) > 0.95  # nearly every wall cell is recovered
    # The interior is free.
    inside = built.world_to_cell(np.array([[2.0, 2.0], [4.0, 3.0]]))
    assert not built.occupied[inside[:, 0], inside[:, 1]].any()


def test_from_scans_skips_max_range_readings_and_checks_shapes():
    poses = np.zeros((1, 3))
    angles = np.array([0.0, 1.0])
    built = OccupancyGrid.from_scans(poses, [[10.0, 1.0]], angles, RES, max_range=10.0)
    assert built.occupied.sum() == 1
    with pytest.raises(ValueError, match="ranges must have shape"):
        OccupancyGrid.from_scans(poses, [[1.0, 1.0, 1.0]], angles, RES, max_range=10.0)
    with pytest.raises(ValueError, match="non-negative"):
        OccupancyGrid.from_scans(poses, [[-1.0, 1.0]], angles, RES, max_range=10.0)


# ---------------------------------------------------------------------------- ray casting
@pytest.mark.parametrize("method", ["hybrid", "dda"])
def test_ray_cast_equals_the_scalar_amanatides_woo_reference(cluttered, method):
    rng = np.random.default_rng(1)
    poses = random_free_poses(cluttered, 40, rng)
    angles = np.deg2rad(np.arange(-90, 90, 3) + 0.5)
    got = ray_cast(cluttered, poses, angles, 9.0, method=method)
    ref = np.array(
        [
            [
                aw_reference(cluttered.occupied, RES, (-3.0, 2.0), *p[:2], p[2] + a, 9.0)
                for a in angles
            ]
            for p in poses
        ]
    )
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-9)
    assert (ref < 9.0).mean() > 0.9  # most beams hit something


def test_march_is_approximate_and_the_exact_methods_are_not(cluttered):
    rng = np.random.default_rng(2)
    poses = random_free_poses(cluttered, 200, rng)
    angles = np.linspace(-np.pi, np.pi, 90, endpoint=False)
    exact = ray_cast(cluttered, poses, angles, 9.0, method="dda")
    march = ray_cast(cluttered, poses, angles, 9.0, method="march")
    hybrid = ray_cast(cluttered, poses, angles, 9.0)
    np.testing.assert_allclose(hybrid, exact, rtol=0, atol=1e-9)
    err = np.abs(march - exact) / RES
    assert np.percentile(err, 50) < 1.0
    assert err.max() > 1.0  # ray marching does err by more than a cell somewhere


def test_ray_cast_axis_aligned_and_known_distances():
    occ = np.zeros((10, 10), bool)
    occ[:, 9] = True  # wall at x in [0.9, 1.0)
    g = OccupancyGrid(occ, RES)
    pose = [0.25, 0.55, 0.0]
    r = ray_cast(g, pose, [0.0, np.pi / 2, np.pi, np.pi / 4], 5.0)
    np.testing.assert_allclose(r, [0.65, 5.0, 5.0, 5.0], atol=1e-12)
    # The wall is entered at x = 0.9 along a 30° ray: 0.65 / cos 30°.
    np.testing.assert_allclose(
        ray_cast(g, [0.25, 0.05, np.pi / 6], [0.0], 5.0), [0.65 / np.cos(np.pi / 6)]
    )
    # Shorter max range: clipped; the pose's own cell occupied: 0.
    assert ray_cast(g, pose, [0.0], 0.5) == pytest.approx(0.5)
    assert ray_cast(g, [0.95, 0.5, 0.0], [2.0], 5.0) == 0.0


def test_ray_cast_shapes_and_batch_equals_one_at_a_time(cluttered):
    rng = np.random.default_rng(4)
    poses = random_free_poses(cluttered, 12, rng).reshape(3, 4, 3)
    angles = np.linspace(-1, 1, 5)
    out = ray_cast(cluttered, poses, angles, 5.0)
    assert out.shape == (3, 4, 5)
    assert ray_cast(cluttered, poses[0, 0], angles, 5.0).shape == (5,)
    for a in range(3):
        for b in range(4):
            np.testing.assert_array_equal(out[a, b], ray_cast(cluttered, poses[a, b], angles, 5.0))


def test_ray_cast_in_an_empty_map_returns_max_range():
    g = OccupancyGrid(np.zeros((20, 20), bool), RES)
    for method in ("hybrid", "dda", "march"):
        r = ray_cast(g, [1.0, 1.0, 0.3], np.linspace(-3, 3, 7), 50.0, method=method)
        np.testing.assert_array_equal(r, 50.0)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        (dict(poses=[5.0, 5.0, 0.0]), "outside the map"),
        (dict(poses=[1.0, 1.0]), "poses must have shape"),
        (dict(poses=[1.0, np.nan, 0.0]), "poses must be finite"),
        (dict(max_range=-1.0), "max_range"),
        (dict(beam_angles=[[0.0]]), "beam_angles"),
        (dict(method="bresenham"), "method"),
        (dict(grid=np.zeros((3, 3), bool)), "grid must be an OccupancyGrid"),
    ],
)
def test_ray_cast_bad_input(kwargs, match):
    args = dict(
        grid=OccupancyGrid(np.zeros((20, 20), bool), RES),
        poses=[1.0, 1.0, 0.0],
        beam_angles=[0.0],
        max_range=3.0,
    )
    args.update(kwargs)
    method = args.pop("method", "hybrid")
    with pytest.raises(ValueError, match=match):
        ray_cast(**args, method=method)
