"""Likelihood field range finder model, Table 6.3 (errata B5)."""

import numpy as np
import pytest
from scipy import stats

from probrob.maps import OccupancyGrid
from probrob.sensors import (
    BeamModelParams,
    likelihood_field_range_finder_model,
    likelihood_field_table,
)

P = BeamModelParams(0.8, 0.0, 0.05, 0.15, 0.1, 0.5, 6.0)
RES = 0.05


@pytest.fixture(scope="module")
def grid():
    rng = np.random.default_rng(0)
    occ = rng.random((30, 40)) < 0.04
    occ[0, :] = True
    return OccupancyGrid(occ, RES, origin=(-1.0, 0.5))


def brute_force(z, pose, grid, angles, params, offset=(0.0, 0.0)):
    """Table 6.3 line by line, one beam at a time, nearest obstacle by exhaustive search."""
    x, y, th = pose
    xs, ys = offset
    occ_xy = grid.cell_to_world(np.argwhere(grid.occupied))
    log_q = 0.0
    for zk, ak in zip(z, angles, strict=True):
        if zk >= params.max_range:
            continue
        xz = x + xs * np.cos(th) - ys * np.sin(th) + zk * np.cos(th + ak)
        yz = y + ys * np.cos(th) + xs * np.sin(th) + zk * np.sin(th + ak)
        if grid.contains([xz, yz]):
            # The distance is looked up at the centre of the end point's cell.
            cx, cy = grid.cell_to_world(grid.world_to_cell([xz, yz]))
            dist = np.min(np.hypot(occ_xy[:, 0] - cx, occ_xy[:, 1] - cy))
            p = params.z_hit * stats.norm.pdf(dist, 0, params.sigma_hit)
        else:
            p = 0.0
        log_q += np.log(p + params.z_rand / params.max_range)
    return log_q


def test_matches_brute_force_nearest_obstacle_search(grid):
    rng = np.random.default_rng(1)
    angles = np.deg2rad(np.arange(-90, 90, 7.5))
    offset = (0.12, -0.05)
    for _ in range(10):
        pose = [rng.uniform(-0.9, 0.9), rng.uniform(0.6, 1.9), rng.uniform(-np.pi, np.pi)]
        z = rng.uniform(0.0, 2.0, angles.size)
        z[[3, 7]] = P.max_range  # skipped
        got = likelihood_field_range_finder_model(
            z, pose, grid, angles, P, log=True, sensor_offset=offset
        )
        assert got == pytest.approx(brute_force(z, pose, grid, angles, P, offset), rel=1e-12)


def test_continuous_distance_is_within_half_a_cell_diagonal(grid):
    # The table stores the distance at the cell centre; the end point's own distance
    # differs from it by at most the half diagonal res / sqrt(2).
    occ_xy = grid.cell_to_world(np.argwhere(grid.occupied))
    rng = np.random.default_rng(2)
    pts = rng.uniform([-1.0, 0.5], [1.0, 2.0], (500, 2))
    exact = np.min(np.hypot(*(pts[:, None, :] - occ_xy[None]).transpose(2, 0, 1)), axis=1)
    ij = grid.world_to_cell(pts)
    table_d = grid.distance_field[ij[:, 0], ij[:, 1]]
    assert np.all(np.abs(exact - table_d) <= RES / np.sqrt(2) + 1e-12)


def deck_factor(dist, params):
    """Deck 001's Table 6.3 line 8 as printed: z_hit prob(dist, σ_hit) + z_random / z_hit."""
    return params.z_hit * stats.norm.pdf(dist, 0, params.sigma_hit) + params.z_rand / params.z_hit


def test_deck_formula_z_rand_over_z_hit_is_wrong(grid):
    """Errata B5: z_rand / z_max is the uniform density of random readings on
    [0, z_max]; its integral over the range is z_rand <= 1. The deck's z_rand / z_hit
    integrates to z_rand z_max / z_hit, here 25 times more than the whole probability."""
    params = BeamModelParams(0.8, 0.0, 0.0, 0.2, 0.1, 0.5, 20.0)
    z = np.linspace(0.0, 20.0, 20_001)[:-1] + 0.0005  # midpoints, 1 mm apart
    # A beam from a pose at the map's edge pointing away: every end point is off the map.
    pose = [grid.extent[0] + 1e-6, 1.0, np.pi]
    lq = likelihood_field_range_finder_model(z[:, None], pose, grid, [0.0], params, log=True)
    book_integral = np.exp(lq).sum() * 0.001
    assert book_integral == pytest.approx(params.z_rand, rel=1e-9)
    deck_integral = deck_factor(np.inf, params) * params.max_range
    assert deck_integral == pytest.approx(5.0)
    assert deck_integral > 1.0  # more than all the probability there is


def test_max_range_readings_are_skipped(grid):
    angles = np.array([0.0, 0.5])
    pose = [0.0, 1.0, 0.3]
    both = likelihood_field_range_finder_model([0.4, P.max_range], pose, grid, angles, P, log=True)
    one = likelihood_field_range_finder_model([0.4], pose, grid, angles[:1], P, log=True)
    assert both == one
    assert likelihood_field_range_finder_model([P.max_range] * 2, pose, grid, angles, P) == 1.0


def test_batches_and_log(grid):
    rng = np.random.default_rng(3)
    angles = np.linspace(-1.5, 1.5, 180)
    poses = np.c_[
        rng.uniform(-0.9, 0.9, (6, 1)), rng.uniform(0.6, 1.9, (6, 1)), rng.uniform(-3, 3, (6, 1))
    ]
    z = rng.uniform(0.1, 1.0, 180)
    lq = likelihood_field_range_finder_model(z, poses.reshape(2, 3, 3), grid, angles, P, log=True)
    assert lq.shape == (2, 3)
    for k in range(6):
        assert lq.ravel()[k] == pytest.approx(
            likelihood_field_range_finder_model(z, poses[k], grid, angles, P, log=True), rel=1e-12
        )
    q = likelihood_field_range_finder_model(z[:5], poses[0], grid, angles[:5], P)
    assert np.log(q) == pytest.approx(
        likelihood_field_range_finder_model(z[:5], poses[0], grid, angles[:5], P, log=True)
    )
    # Per-scan z of shape (N, K) with poses (N, 3).
    zz = np.tile(z, (6, 1))
    np.testing.assert_allclose(
        likelihood_field_range_finder_model(zz, poses, grid, angles, P, log=True), lq.ravel()
    )


def test_table_is_cached_and_read_only(grid):
    t1 = likelihood_field_table(grid, P)
    assert likelihood_field_table(grid, P) is t1
    assert t1.shape == (grid.shape[0] + 2, grid.shape[1] + 2)
    assert not t1.flags.writeable
    assert t1[0, 0] == pytest.approx(np.log(P.z_rand / P.max_range))


def test_bad_input(grid):
    angles = np.zeros(2)
    with pytest.raises(ValueError, match="outside the map"):
        likelihood_field_range_finder_model([1, 1], [5.0, 1.0, 0.0], grid, angles, P)
    with pytest.raises(ValueError, match="no occupied cell"):
        likelihood_field_range_finder_model(
            [1, 1], [0.1, 0.1, 0.0], OccupancyGrid(np.zeros((4, 4), bool), 0.1), angles, P
        )
    with pytest.raises(ValueError, match="sensor_offset"):
        likelihood_field_range_finder_model(
            [1, 1], [0, 1, 0], grid, angles, P, sensor_offset=(1, 2, 3)
        )
    with pytest.raises(ValueError, match="non-negative"):
        likelihood_field_range_finder_model([-1, 1], [0, 1, 0], grid, angles, P)


def test_deck_prob_of_sigma_is_a_variance_slot(grid):
    """Errata B6: prob(dist, σ_hit) with Table 5.2's prob(a, b²) reads σ_hit as a variance."""
    from probrob.distributions import prob_normal_distribution

    d = 0.1
    book = P.z_hit * prob_normal_distribution(d, P.sigma_hit**2) + P.z_rand / P.max_range
    deck = P.z_hit * prob_normal_distribution(d, P.sigma_hit) + P.z_rand / P.max_range
    # The library's table at a cell whose distance is d equals the book's value ...
    table = likelihood_field_table(grid, P)[1:-1, 1:-1]
    dist = grid.distance_field
    i, j = np.argwhere(np.isclose(dist, d))[0]
    assert np.exp(table[i, j]) == pytest.approx(book, rel=1e-12)
    # ... and the deck's reading is a normal of std sqrt(0.1) = 0.32 m, not 0.1 m.
    assert deck / book < 0.6
