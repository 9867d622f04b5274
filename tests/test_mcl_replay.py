"""probrob.mcl fed given random numbers: the keywords that replay the live particle filter's draws.

``low_variance_sampler(offset=)``, ``uniform_particles(uniforms=)`` and ``mcl(sample=,
resample_offset=)`` let a caller (tests/test_live_mcl.py) feed the library the random numbers a
page embeds. Here: each gives what the table says for those numbers, the same as the generator's
path when fed the generator's own numbers, and bad values raise naming the argument.
"""

from __future__ import annotations

import numpy as np
import pytest

from probrob import mcl as M
from probrob.distributions import sample_normal_distribution
from probrob.maps import OccupancyGrid
from probrob.sensors import BeamModelParams

OCC = np.zeros((20, 30), dtype=bool)
OCC[0, :] = OCC[-1, :] = OCC[:, 0] = OCC[:, -1] = True
OCC[8:12, 10:14] = True
FREE = ~OCC
FREE[1:4, 1:4] = False  # an unexplored corner
GRID = OccupancyGrid(OCC, 0.2, origin=(-1.0, 2.0), free=FREE)
PARAMS = BeamModelParams(0.8, 0.05, 0.05, 0.1, sigma_hit=0.2, lambda_short=0.5, max_range=8.0)
ANGLES = np.linspace(-np.pi / 2, np.pi / 2, 9)


def test_low_variance_offset_is_line_3s_random_number():
    w = np.array([0.1, 0.25, 0.05, 0.3, 0.3])
    for m in (5, 7, 12):
        for offset in (0.0, 0.3, 0.999999):
            got = M.low_variance_sampler(w, size=m, offset=offset)
            r = offset / m
            c = np.cumsum(w)
            want = [int(np.argmax(c >= r + k / m)) for k in range(m)]  # lines 6-9, one by one
            np.testing.assert_array_equal(got, want)
    # the generator's path is the same sampler with the generator's draw
    gen = np.random.default_rng(5)
    r = np.random.default_rng(5).uniform(0.0, 1.0 / 7)
    np.testing.assert_array_equal(
        M.low_variance_sampler(w, size=7, rng=gen), M.low_variance_sampler(w, size=7, offset=r * 7)
    )


@pytest.mark.parametrize("bad", [-0.1, 1.0, np.nan, [0.1, 0.2], "a"])
def test_low_variance_offset_bad(bad):
    with pytest.raises(ValueError, match="offset"):
        M.low_variance_sampler([0.5, 0.5], offset=bad)


def test_uniform_particles_from_given_uniforms():
    n = 500
    u = np.random.default_rng(0).random((n, 4))
    x = M.uniform_particles(GRID, n, uniforms=u)
    cells = np.flatnonzero(GRID.free)
    pick = cells[np.floor(u[:, 0] * cells.size).astype(int)]
    i, j = np.divmod(pick, GRID.shape[1])
    np.testing.assert_allclose(x[:, 0], -1.0 + (j + u[:, 1]) * 0.2, rtol=0, atol=1e-12)
    np.testing.assert_allclose(x[:, 1], 2.0 + (i + u[:, 2]) * 0.2, rtol=0, atol=1e-12)
    np.testing.assert_allclose(x[:, 2], -np.pi + 2 * np.pi * u[:, 3], rtol=0, atol=1e-15)
    # every particle in a free cell (the unexplored corner and the walls never)
    ij = GRID.world_to_cell(x[:, :2])
    assert GRID.free[ij[:, 0], ij[:, 1]].all()
    # the extremes: u = 0 is the first free cell's corner, u -> 1 the last free cell
    edge = M.uniform_particles(GRID, 2, uniforms=[[0, 0, 0, 0], [1 - 1e-12] * 4])
    assert tuple(GRID.world_to_cell(edge[:, :2])[0]) == divmod(cells[0], GRID.shape[1])
    assert tuple(GRID.world_to_cell(edge[:, :2])[1]) == divmod(cells[-1], GRID.shape[1])
    assert edge[0, 2] == -np.pi and edge[1, 2] < np.pi


@pytest.mark.parametrize(
    "bad", [np.zeros((3, 4)), np.zeros((5, 3)), np.full((5, 4), 1.0), np.full((5, 4), np.nan)]
)
def test_uniform_particles_bad_uniforms(bad):
    with pytest.raises(ValueError, match="uniforms"):
        M.uniform_particles(GRID, 5, uniforms=bad)


def _odometry_pair():
    return np.array([[1.0, 3.0, 0.2], [1.6, 3.3, 0.5]])


def test_mcl_with_given_draws_is_table_8_2_on_them():
    n = 300
    x0 = M.uniform_particles(GRID, n, rng=1)
    z = np.full(ANGLES.size, 2.5)
    z[3] = PARAMS.max_range  # a max-range reading
    normals = sample_normal_distribution(1.0, size=(3, n), rng=2)
    rows = iter(normals)

    def sample(b2, size=None, rng=None):
        return np.sqrt(b2) * next(rows)

    alpha = [0.05, 0.01, 0.02, 0.005]
    got = M.mcl(
        x0, _odometry_pair(), z, GRID, ANGLES, alpha, PARAMS, sample=sample, resample_offset=0.4
    )
    # the same step written out from the models
    from probrob.motion import sample_motion_model_odometry

    rows2 = iter(normals)
    x_bar = sample_motion_model_odometry(
        _odometry_pair(),
        x0,
        alpha,
        sample=lambda b2, size=None, rng=None: np.sqrt(b2) * next(rows2),
    )
    lw = M.measurement_log_weights(x_bar, z, GRID, ANGLES, PARAMS)
    w = np.exp(lw - lw[np.isfinite(lw)].max())
    np.testing.assert_array_equal(got, x_bar[M.low_variance_sampler(w, offset=0.4)])
    # the default sampler is the book's sum of twelve uniforms: the same generator, the same step
    a = M.mcl(x0, _odometry_pair(), z, GRID, ANGLES, alpha, PARAMS, rng=7)
    b = M.mcl(
        x0,
        _odometry_pair(),
        z,
        GRID,
        ANGLES,
        alpha,
        PARAMS,
        rng=7,
        sample=sample_normal_distribution,
    )
    np.testing.assert_array_equal(a, b)


def test_mcl_bad_replay_arguments():
    x0 = M.uniform_particles(GRID, 10, rng=1)
    z = np.full(ANGLES.size, 2.5)
    args = (x0, _odometry_pair(), z, GRID, ANGLES, [0.05] * 4, PARAMS)
    with pytest.raises(ValueError, match="sample"):
        M.mcl(*args, sample=3)
    with pytest.raises(ValueError, match="offset"):
        M.mcl(*args, resample_offset=1.5)
