"""probrob.grid_localization: Table 8.1 against a brute-force Bayes filter, its limits, MCL.

The brute force is the book's double loop: for every pair of cells (k, i) one call of
``motion_model_odometry`` between their centres (line 3), then one call of the likelihood
field per cell (line 4). The library must agree with it to 1e-12; everything else here
(limits, invariants, the particle histogram, the Intel lab) checks the discretisation.
"""

from __future__ import annotations

import math
from functools import partial

import numpy as np
import pytest

from probrob.distributions import sample_normal_distribution
from probrob.grid_localization import (
    MotionKernel,
    PoseGrid,
    grid_localization,
    grid_prediction,
    motion_kernel,
)
from probrob.maps import OccupancyGrid, ray_cast
from probrob.motion import motion_model_odometry, odometry_deltas, sample_motion_model_odometry
from probrob.sensors import BeamModelParams, likelihood_field_range_finder_model

EXACT_NORMAL = partial(sample_normal_distribution, method="exact")  # the kernel's noise
# The odometry noise the Monte Carlo localization chapter fits to the Intel lab's steps of
# 0.2 m and more (probrob.fitting.fit_odometry_alpha, density="pose"), to 3 digits.
ALPHA_INTEL = (0.113, 0.0166, 0.00267, 0.00126)
PARAMS = BeamModelParams(0.85, 0.0, 0.05, 0.10, 0.1, 1.0, 8.0)


def _tiny() -> OccupancyGrid:
    """8 x 7 cells of 0.1 m: walls all round, a pillar and a short wall inside."""
    occ = np.zeros((7, 8), dtype=bool)
    occ[[0, -1], :] = True
    occ[:, [0, -1]] = True
    occ[2, 3] = True
    occ[4, 5:7] = True
    return OccupancyGrid(occ, 0.1, origin=(-0.3, 0.2))


TINY = PoseGrid(_tiny(), 0.1, 8)


def _room() -> OccupancyGrid:
    """A 6 m x 4 m room at 0.1 m with an inner wall and a box (no symmetry)."""
    occ = np.zeros((40, 60), dtype=bool)
    occ[[0, -1], :] = True
    occ[:, [0, -1]] = True
    occ[0:22, 25] = True
    occ[28:33, 40:48] = True
    return OccupancyGrid(occ, 0.1)


ROOM = _room()


def _random_belief(pose_grid, seed):
    b = np.zeros(pose_grid.shape)
    b[pose_grid.mask] = np.random.default_rng(seed).random(
        (int(pose_grid.mask.sum()), pose_grid.n_headings)
    )
    return b / b.sum()


def _tv(p, q):
    return 0.5 * float(np.abs(np.asarray(p) - np.asarray(q)).sum())


# ---------------------------------------------------------------------- Table 8.1, brute force
def _own_cell_mass(x_i, theta_k, u, alpha, res, d_theta, nodes=32):
    """The source's own cell at heading theta_k: the density integrated in polar coordinates
    about x_i over the whole cell (the rule for n_sigma = inf), nodes x nodes mid-points."""
    rot1, _, _ = odometry_deltas(u[0], u[1])
    d_phi = 2 * math.pi / nodes
    phi = x_i[2] + rot1 - math.pi + (np.arange(nodes) + 0.5) * d_phi
    edge = 0.5 * res / np.maximum(np.abs(np.cos(phi)), np.abs(np.sin(phi)))
    d_r = edge / nodes
    r = (np.arange(nodes) + 0.5) * d_r[:, None]
    pts = np.stack(
        [
            x_i[0] + r * np.cos(phi)[:, None],
            x_i[1] + r * np.sin(phi)[:, None],
            np.full(r.shape, theta_k),
        ],
        axis=-1,
    )
    p = motion_model_odometry(pts, u, x_i, alpha, density="pose")
    return float(np.sum(p * r * d_r[:, None]) * d_phi * d_theta)


def _brute_force_line3(belief, u, pose_grid, alpha):
    """pbar_k = sum_i p_i p(x_k | u, x_i) r^2 dtheta / Z_i, a Python loop over all pairs."""
    res, d_theta = pose_grid.resolution, pose_grid.heading_resolution
    ny, nx, n = pose_grid.shape
    centres = pose_grid.centres()
    volume = res * res * d_theta
    own = {  # translation invariant: one value per pair of headings
        (a, b): _own_cell_mass(
            np.array([0.0, 0.0, pose_grid.headings[a]]),
            pose_grid.headings[b],
            u,
            alpha,
            res,
            d_theta,
        )
        for a in range(n)
        for b in range(n)
    }

    def transition(x_k, x_i, same_cell, a, b):
        if same_cell:
            return own[a, b]
        return float(motion_model_odometry(x_k, u, x_i, alpha, density="pose")) * volume

    # Z_i: the sum over every offset that joins two cells of the grid (n_sigma = inf)
    z_sum = np.zeros(n)
    for a in range(n):
        x_i = np.array([0.0, 0.0, pose_grid.headings[a]])
        for dy in range(-(ny - 1), ny):
            for dx in range(-(nx - 1), nx):
                for b in range(n):
                    x_k = np.array([dx * res, dy * res, pose_grid.headings[b]])
                    z_sum[a] += transition(x_k, x_i, dy == 0 and dx == 0, a, b)
    states = [
        (i, j, k) for i in range(ny) for j in range(nx) for k in range(n) if pose_grid.mask[i, j]
    ]
    p_bar = np.zeros(pose_grid.shape)
    for i, j, b in states:  # target k
        for i2, j2, a in states:  # source i
            x_k, x_i = centres[i, j, b], centres[i2, j2, a]
            p_bar[i, j, b] += (
                belief[i2, j2, a] * transition(x_k, x_i, (i, j) == (i2, j2), a, b) / z_sum[a]
            )
    return p_bar


def _brute_force_line4(p_bar, z, pose_grid, angles, params, exponent):
    centres = pose_grid.centres()
    log_p = np.full(pose_grid.shape, -np.inf)
    for i, j in zip(*np.nonzero(pose_grid.mask), strict=True):
        for k in range(pose_grid.n_headings):
            log_q = likelihood_field_range_finder_model(
                z, centres[i, j, k], pose_grid.grid, angles, params, log=True
            )
            log_p[i, j, k] = np.log(p_bar[i, j, k]) + exponent * log_q
    p = np.exp(log_p - log_p.max())
    return p / p.sum()


@pytest.mark.parametrize(
    "u",
    [
        np.array([[1.0, 2.0, 0.3], [1.14, 2.07, 0.9]]),  # across cells, turning left
        np.array([[0.0, 0.0, 2.5], [-0.03, 0.01, 3.1]]),  # within the cell, across ±π
    ],
)
def test_table_8_1_equals_the_brute_force_bayes_filter(u):
    alpha = (0.2, 0.05, 0.1, 0.05)
    belief = _random_belief(TINY, 3)
    kernel = motion_kernel(TINY, u, alpha, n_sigma=np.inf)
    assert kernel.rule == "mid-point"
    p_bar = grid_prediction(belief, u, TINY, alpha, kernel=kernel)
    expected = _brute_force_line3(belief, u, TINY, alpha)
    assert np.abs(p_bar - expected).max() <= 1e-12
    assert 0.0 < p_bar.sum() < 1.0  # some probability lands on walls and off the grid

    angles = np.linspace(-np.pi / 2, np.pi / 2, 7)
    z = ray_cast(TINY.grid, [-0.05, 0.45, 0.2], angles, PARAMS.max_range) + 0.01
    out = grid_localization(belief, u, z, TINY, angles, alpha, PARAMS, exponent=0.5, kernel=kernel)
    assert np.abs(out - _brute_force_line4(expected, z, TINY, angles, PARAMS, 0.5)).max() <= 1e-12


def _dense(kernel, a, reach):
    """Block ``a`` of a kernel as an array (n_headings, 2 reach + 1, 2 reach + 1) of offsets."""
    blk = kernel.blocks[a]
    out = np.zeros((kernel.n_headings, 2 * reach + 1, 2 * reach + 1))
    rows = (blk.dy + reach)[:, None]
    cols = (blk.dx + reach)[None, :]
    for d, w in zip(blk.dtheta % kernel.n_headings, blk.weights, strict=True):
        out[d, rows, cols] = w
    return out


def test_the_window_holds_the_motion():
    """The 4σ window (plus a cell) against every offset: the same transitions up to the
    normalisation, and the window leaves out less than 3 · 2Φ(-4) = 1.9e-4 of them."""
    pose_grid = PoseGrid(ROOM, 0.2, 36)
    u = np.array([[0.0, 0.0, 0.0], [0.5, 0.3, 0.7]])  # 0.58 m, turning
    alpha = (0.3, 0.05, 0.01, 0.01)
    narrow = motion_kernel(pose_grid, u, alpha)
    wide = motion_kernel(pose_grid, u, alpha, n_sigma=np.inf)
    reach = max(wide.reach)
    for a in range(36):
        n_d, w_d = _dense(narrow, a, reach), _dense(wide, a, reach)
        window = n_d > 0
        assert 1.0 - w_d[window].sum() < 1.9e-4
        assert (w_d[window] > 0).all()
        # the own cell is integrated over the window's part of it: compare the others
        window[:, reach, reach] = False
        ratio = n_d[window] / w_d[window]
        np.testing.assert_allclose(ratio, ratio[0], rtol=1e-9)
        assert n_d[:, reach, reach].sum() < 1e-6  # 0.58 m away: the own cell holds ~nothing


# ---------------------------------------------------------------------- invariants
def _room_run(rule, steps=4):
    pose_grid = PoseGrid(ROOM, 0.2, 18)
    angles = np.linspace(-np.pi / 2, np.pi / 2, 9)
    poses = np.column_stack(
        [
            np.linspace(1.0, 2.2, steps + 1),
            np.linspace(2.5, 1.2, steps + 1),
            np.full(steps + 1, -0.8),
        ]
    )
    poses[2, 2] += 0.9  # a turn on the way
    belief = pose_grid.uniform()
    beliefs, kernels = [belief], []
    for t in range(steps):
        u = poses[t : t + 2]
        kernel = motion_kernel(pose_grid, u, (0.1, 0.02, 0.05, 0.02), rule=rule)
        z = ray_cast(ROOM, poses[t + 1], angles, PARAMS.max_range)
        belief = grid_localization(
            belief, u, z, pose_grid, angles, (0.1, 0.02, 0.05, 0.02), PARAMS, kernel=kernel
        )
        beliefs.append(belief)
        kernels.append(kernel)
    return pose_grid, poses, beliefs, kernels


@pytest.mark.parametrize("rule", ["mid-point", "quadrature"])
def test_beliefs_stay_distributions_on_the_state_space(rule):
    pose_grid, poses, beliefs, kernels = _room_run(rule)
    for kernel in kernels:
        assert kernel.rule == rule
        for blk in kernel.blocks:
            assert abs(blk.weights.sum() - 1.0) <= 1e-12
            assert blk.weights.min() >= 0.0
    for b in beliefs:
        assert abs(b.sum() - 1.0) <= 1e-12
        assert b.min() >= 0.0
        assert not b[~pose_grid.mask].any()
    # and the filter found the robot: the mode within a cell and a heading bin of the truth
    mode = pose_grid.mode(beliefs[-1])
    assert np.hypot(*(mode[:2] - poses[-1, :2])) <= 0.2 * math.sqrt(2)
    assert abs(math.remainder(mode[2] - poses[-1, 2], 2 * math.pi)) <= pose_grid.heading_resolution


# ---------------------------------------------------------------------- limits
def test_no_motion_keeps_the_belief():
    belief = _random_belief(TINY, 5)
    u = np.array([[1.0, 2.0, 0.3], [1.0, 2.0, 0.3]])  # no motion: every variance is 0
    kernel = motion_kernel(TINY, u, (0.5, 0.5, 0.5, 0.5))
    assert kernel.rule == "quadrature" and kernel.midpoint_sum is None
    assert np.array_equal(grid_prediction(belief, u, TINY, (0.5, 0.5, 0.5, 0.5)), belief)


def test_a_creeping_motion_with_small_noise_stays_in_its_cell():
    pose_grid = PoseGrid(ROOM, 0.2, 36)
    belief = _random_belief(pose_grid, 6)
    u = np.array([[0.0, 0.0, 0.0], [0.005, 0.001, 0.002]])  # 5 mm and 0.1°
    p_bar = grid_prediction(belief, u, pose_grid, (0.01, 0.01, 0.01, 0.01))
    assert motion_kernel(pose_grid, u, (0.01, 0.01, 0.01, 0.01)).rule == "mid-point"
    # what leaves a cell is what the walls take at its border, and a sliver of heading
    assert _tv(p_bar / p_bar.sum(), belief) < 0.01


@pytest.mark.parametrize("alpha", [(0.0, 0.0, 0.0, 0.0), (1e-4, 1e-4, 1e-4, 1e-4)])
def test_one_cell_east_moves_a_point_mass_one_cell_east(alpha):
    pose_grid = PoseGrid(ROOM, 0.2, 36)
    start = np.array([1.1, 1.3, 0.0])
    belief = pose_grid.point_mass(start)
    u = np.array([[5.0, -1.0, 0.0], [5.2, -1.0, 0.0]])  # 0.2 m straight ahead, heading 0
    p_bar = grid_prediction(belief, u, pose_grid, alpha)
    target = pose_grid.point_mass(start + [0.2, 0.0, 0.0])
    if alpha[0] == 0:
        assert np.array_equal(p_bar, target)  # no noise: the cell of the end pose, exactly
    else:
        assert p_bar[target == 1] > 0.99


@pytest.mark.parametrize("alpha", [(0.0, 0.0, 0.0, 0.0), (0.01, 0.01, 0.01, 0.01)])
def test_a_turn_on_the_spot_wraps_across_pi(alpha):
    pose_grid = PoseGrid(ROOM, 0.2, 36)
    d = pose_grid.heading_resolution
    start = np.array([1.1, 1.3, math.pi - d])  # the last bin
    u = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 2 * d]])  # two bins to the left
    p_bar = grid_prediction(pose_grid.point_mass(start), u, pose_grid, alpha)
    target = pose_grid.point_mass(start + [0.0, 0.0, 2 * d])  # bin 1, past ±π
    assert pose_grid.locate(start + [0.0, 0.0, 2 * d])[0][2] == 1
    i, j, _ = pose_grid.locate(start)[0]
    assert abs(p_bar[i, j].sum() - 1.0) <= 1e-12  # a turn on the spot stays in its cell
    if alpha[0] == 0:
        assert np.array_equal(p_bar, target)
    else:  # σ of the turn 0.035 rad against bins of ±0.087 rad: mostly bin 1, a little 0, 2
        assert p_bar[target == 1] > 0.95
        assert p_bar[i, j, [0, 1, 2]].sum() == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("alpha", [(0.0,) * 4, (1e-4,) * 4])  # quadrature, mid-point
def test_probability_carried_off_the_state_space_is_an_error(alpha):
    u = np.array([[0.0, 0.0, 0.0], [3.0, 0.0, 0.0]])  # 3 m: beyond the 0.8 m map
    with pytest.raises(ValueError, match="u carries all the probability off the state space"):
        grid_localization(
            TINY.uniform(), u, np.full(7, 1.0), TINY, np.linspace(-1, 1, 7), alpha, PARAMS
        )


def test_a_scan_that_rules_out_every_cell_keeps_the_prediction():
    params = BeamModelParams(1.0, 0.0, 0.0, 0.0, 0.01, 1.0, 100.0)  # z_rand = 0
    angles = np.linspace(-1, 1, 7)
    z = np.full(7, 50.0)  # every end point off the map: probability 0 everywhere
    u = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.2]])
    belief = _random_belief(TINY, 8)
    p_bar = grid_prediction(belief, u, TINY, (0.1,) * 4)
    out = grid_localization(belief, u, z, TINY, angles, (0.1,) * 4, params)
    np.testing.assert_allclose(out, p_bar / p_bar.sum(), rtol=1e-12, atol=0)


# ---------------------------------------------------------------------- against the sampler
def _belief_and_draws(pose_grid, n, rng):
    """A belief on three cells, and n poses drawn from it at the cells' centres."""
    belief = np.zeros(pose_grid.shape)
    for pose, w in [((0.05, 0.02, 0.3), 0.5), ((-0.3, 0.2, -2.0), 0.3), ((0.4, -0.5, 3.1), 0.2)]:
        (i, j, k), _ = pose_grid.locate(np.array(pose))
        belief[i, j, k] += w
    cell = rng.choice(belief.size, size=n, p=belief.ravel())
    return belief, pose_grid.centres().reshape(-1, 3)[cell]


def _prediction(pose_grid, belief, u, alpha, rule):
    kernel = motion_kernel(pose_grid, u, alpha, rule=rule)
    p_bar = grid_prediction(belief, u, pose_grid, alpha, kernel=kernel)
    return p_bar / p_bar.sum()  # nothing leaves the open map but what lands off its grid


def _sampling_tv(q, n, rng, repeats=5):
    """Mean and std of the TV between n draws from q and q itself."""
    tv = [_tv(rng.multinomial(n, q.ravel()) / n, q.ravel()) for _ in range(repeats)]
    return float(np.mean(tv)), float(np.std(tv))


OPEN = OccupancyGrid(np.zeros((80, 80), dtype=bool), 0.1, origin=(-4.0, -4.0))  # all free


def test_the_particle_histogram_converges_to_line_3_down_to_the_mid_point_floor():
    """Particles drawn at the cell centres of a belief (the sources of the mid-point rule)
    and moved by Table 5.6's sampler with normal noise: their histogram h_N tends to the
    cells' true probabilities q, line 3 predicts p. By the triangle inequality
    |TV(h_N, p) - TV(h_N, q)| <= TV(q, p), the floor: the mid-point rule's error. q is
    estimated by a fine Monte Carlo (10^6 particles), and TV(h_N, q) is the sampling error of
    N draws from it, whose mean and spread are read from 5 multinomial draws. The noise spans
    a few cells (σ_trans 0.16 m, σ_rot1 0.24 rad on 0.2 m x 10° cells), where the rule is
    good: a floor of about 0.05, which 10 cm x 5° cells cut by about 4 (second order), and
    where the quadrature rule does worse."""
    u = np.array([[0.0, 0.0, 0.0], [0.9, 0.4, 0.5]])  # 0.98 m, turning
    alpha = (0.3, 0.05, 0.02, 0.05)
    rng = np.random.default_rng(11)
    floors = {}
    for res, n_headings in [(0.2, 36), (0.1, 72)]:
        pose_grid = PoseGrid(OPEN, res, n_headings)
        belief, x = _belief_and_draws(pose_grid, 10**6, rng)
        p = _prediction(pose_grid, belief, u, alpha, "mid-point")
        q = pose_grid.histogram(
            sample_motion_model_odometry(u, x, alpha, sample=EXACT_NORMAL, rng=rng)
        )
        q_noise, _ = _sampling_tv(q, 10**6, rng)  # the fine Monte Carlo's own error
        floors[res] = math.sqrt(max(_tv(q, p) ** 2 - q_noise**2, 0.0))  # independent errors
        # the quadrature rule's 32 nodes per noise term leave gaps between so many cells
        assert _tv(q, _prediction(pose_grid, belief, u, alpha, "quadrature")) > _tv(q, p)
        if res == 0.2:
            assert 0.03 < floors[res] < 0.06
            tvs = []
            for n in (10**3, 10**4, 10**5):
                _, x_n = _belief_and_draws(pose_grid, n, rng)
                h = pose_grid.histogram(
                    sample_motion_model_odometry(u, x_n, alpha, sample=EXACT_NORMAL, rng=rng)
                )
                tvs.append(_tv(h, p))
                sampling, spread = _sampling_tv(q, n, rng)
                assert abs(tvs[-1] - sampling) <= _tv(q, p) + q_noise + 4 * spread, n
            assert tvs[0] > 2 * tvs[1] and tvs[1] > 1.5 * tvs[2]  # N^-1/2, then the floor
    assert floors[0.1] < floors[0.2] / 2.5


def test_narrow_noise_costs_the_mid_point_rule_what_quadrature_keeps():
    """With the noise fitted to the Intel lab (σ of a few cm and degrees) and a half-metre
    step, 20 cm x 10° cells are coarse for the mid-point rule: its prediction differs from
    the sampler's cell probabilities by about 0.6 in total variation (its normalisation sums,
    0.1 to 2.7, show it too). The quadrature rule stays within about 1 %."""
    u = np.array([[0.0, 0.0, 0.0], [0.45, 0.15, 0.4]])
    pose_grid = PoseGrid(OPEN, 0.2, 36)
    kernel = motion_kernel(pose_grid, u, ALPHA_INTEL)
    assert kernel.midpoint_sum.min() < 0.2 and kernel.midpoint_sum.max() > 2.0
    rng = np.random.default_rng(12)
    belief, x = _belief_and_draws(pose_grid, 10**6, rng)
    q = pose_grid.histogram(
        sample_motion_model_odometry(u, x, ALPHA_INTEL, sample=EXACT_NORMAL, rng=rng)
    )
    q_noise, _ = _sampling_tv(q, 10**6, rng)
    assert q_noise < 0.002
    assert _tv(q, _prediction(pose_grid, belief, u, ALPHA_INTEL, "mid-point")) > 0.4
    assert _tv(q, _prediction(pose_grid, belief, u, ALPHA_INTEL, "quadrature")) < 0.02


# ---------------------------------------------------------------------- API
def test_shapes_and_the_order_of_the_state_space():
    pg = TINY
    ny, nx, n = pg.shape
    assert (ny, nx, n) == (7, 8, 8) and pg.n_states == int(pg.mask.sum()) * 8
    full = pg.centres()
    assert full.shape == (7, 8, 8, 3)
    free = pg.centres(free_only=True)
    assert free.shape == (pg.n_states, 3)
    assert np.array_equal(full[pg.mask].reshape(-1, 3), free)
    # every centre lies in its own cell
    ijk, inside = pg.locate(full)
    assert ijk.shape == (7, 8, 8, 3) and inside.shape == (7, 8, 8)
    assert np.array_equal(inside, np.broadcast_to(pg.mask[..., None], inside.shape))
    assert np.array_equal(ijk[..., 0], np.broadcast_to(np.arange(7)[:, None, None], (7, 8, 8)))
    assert np.array_equal(ijk[..., 2], np.broadcast_to(np.arange(8), (7, 8, 8)))
    for shape in [(), (5,), (2, 3)]:
        assert pg.locate(np.zeros((*shape, 3)))[1].shape == shape
    b = pg.uniform()
    assert b.shape == pg.shape and abs(b.sum() - 1) < 1e-12
    assert pg.marginal_xy(b).shape == (7, 8)
    assert pg.mode(b).shape == (3,)
    x0, x1, y0, y1 = pg.extent
    assert (x1 - x0, y1 - y0) == pytest.approx((0.8, 0.7))
    kernel = motion_kernel(pg, np.array([[0, 0, 0], [0.1, 0, 0.1]]), (0.1,) * 4)
    assert isinstance(kernel, MotionKernel) and len(kernel.blocks) == 8
    assert kernel.nbytes > 0 and kernel.size > 0


def test_headings_wrap_into_their_bins():
    d = TINY.heading_resolution
    theta = np.array([0.0, math.pi, -math.pi, math.pi - 0.49 * d, 4 * math.pi + d, -d])
    bins = TINY.locate(np.column_stack([np.full(6, 0.05), np.full(6, 0.45), theta]))[0][:, 2]
    assert bins.tolist() == [4, 0, 0, 0, 5, 3]  # bin 4 is θ = 0


def test_the_histogram_leaves_out_particles_outside_the_state_space():
    pg = TINY
    centre = pg.centres(free_only=True)[0]
    wall = np.array([-0.25, 0.25, 0.0])  # a wall cell
    far = np.array([50.0, 50.0, 0.0])  # off the grid
    h = pg.histogram(np.stack([centre, centre, wall, far]), weights=[1.0, 2.0, 5.0, 5.0])
    assert h.sum() == pytest.approx(1.0)
    assert h[tuple(pg.locate(centre)[0])] == pytest.approx(1.0)
    with pytest.raises(ValueError, match="no particle"):
        pg.histogram(np.stack([wall, far]))


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda b: b[:, :, :4], r"belief must have the pose grid's shape"),
        (lambda b: b - 2 * b.max() * (b == b.max()), "belief must be non-negative"),
        (lambda b: 2 * b, "belief must sum to 1"),
        (lambda b: np.where(b == b.max(), np.nan, b), "belief must be finite"),
        (lambda b: b + (b == 0) / (b == 0).sum(), "outside the state space"),
    ],
)
def test_bad_beliefs_are_named(change, message):
    bad = change(TINY.uniform())
    u = np.array([[0, 0, 0], [0.1, 0, 0]])
    with pytest.raises(ValueError, match=message):
        grid_prediction(bad, u, TINY, (0.1,) * 4)
    with pytest.raises(ValueError, match=message):
        grid_localization(bad, u, np.ones(3), TINY, [-1, 0, 1], (0.1,) * 4, PARAMS)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"resolution": 0.0}, "resolution"),
        ({"resolution": np.nan}, "resolution"),
        ({"resolution": "0.2"}, "resolution"),
        ({"resolution": 1e-6}, "resolution"),  # 10^14 cells
        ({"resolution": 5.0}, "resolution"),  # no centre in a free cell
        ({"n_headings": 0}, "n_headings"),
        ({"n_headings": 2.5}, "n_headings"),
        ({"n_headings": True}, "n_headings"),
        ({"grid": np.zeros((3, 3))}, "grid"),
    ],
)
def test_bad_pose_grids_are_named(kwargs, message):
    with pytest.raises(ValueError, match=message):
        PoseGrid(**({"grid": TINY.grid} | kwargs))


def test_bad_arguments_are_named():
    b = TINY.uniform()
    u = np.array([[0, 0, 0], [0.1, 0, 0]])
    alpha = (0.1,) * 4
    z, angles = np.ones(3), np.array([-1.0, 0.0, 1.0])
    cases = [
        (lambda: grid_prediction(b, u[0], TINY, alpha), "u must be an odometry pair"),
        (lambda: grid_prediction(b, u, TINY, (0.1, -0.1, 0.1, 0.1)), "alpha"),
        (lambda: grid_prediction(b, u, TINY.grid, alpha), "pose_grid"),
        (lambda: grid_prediction(b, u, TINY, alpha, kernel="k"), "kernel must be"),
        (
            lambda: grid_prediction(b, u, TINY, alpha, kernel=motion_kernel(TINY, 2 * u, alpha)),
            "kernel was made for another u",
        ),
        (
            lambda: grid_prediction(
                b, u, TINY, alpha, kernel=motion_kernel(PoseGrid(TINY.grid, 0.1, 4), u, alpha)
            ),
            "kernel was made for a pose grid",
        ),
        (lambda: motion_kernel(TINY, u, alpha, n_sigma=0), "n_sigma"),
        (lambda: motion_kernel(TINY, u, alpha, n_sigma=np.nan), "n_sigma"),
        (lambda: motion_kernel(TINY, u, alpha, rule="midpoint"), "rule"),
        (lambda: motion_kernel(TINY, u, (1e5,) * 4), "u and alpha make a window"),
        (lambda: grid_localization(b, u, z[:2], TINY, angles, alpha, PARAMS), "z must hold"),
        (lambda: grid_localization(b, u, z, TINY, angles, alpha, PARAMS, exponent=0), "exponent"),
        (lambda: grid_localization(b, u, z, TINY, angles, alpha, "p"), "params"),
        (lambda: TINY.point_mass([50.0, 0.0, 0.0]), "does not lie in the state space"),
        (lambda: TINY.histogram(np.zeros(3)), "particles"),
        (lambda: TINY.histogram(np.zeros((2, 3)), weights=[1.0, -1.0]), "weights"),
        (lambda: TINY.centres(free_only=1), "free_only"),
    ]
    for call, message in cases:
        with pytest.raises(ValueError, match=message):
            call()


# ---------------------------------------------------------------------- the Intel lab
def _intel():
    from probrob.datasets import DatasetNotFoundError, load_intel_lab

    try:
        return load_intel_lab()
    except DatasetNotFoundError:
        return None


def test_global_localization_in_the_intel_lab(time_limit):
    """From a uniform belief over 20 cm x 20 cm x 10° cells (13,339 free (x, y) cells x 36),
    the log's real odometry and 60 of each scan's 180 beams, tempered by 3/60 as the
    chapter's MCL: from the fifth step on, the mode stays within 3 cells and 2 heading bins
    of the corrected pose."""
    data = _intel()
    if data is None:
        pytest.skip("Intel lab log absent")
    grid = OccupancyGrid.from_scans(
        data.poses, data.ranges, data.beam_angles, 0.1, max_range=data.max_range
    )
    pose_grid = PoseGrid(grid, 0.2, 36)
    # about the chapter's EM fit of the intrinsic parameters (z_max = 26 m)
    params = BeamModelParams(0.9033, 0.0266, 0.0214, 0.0487, 0.0832, 1.0, 26.0)
    z_all = np.where(data.no_return, params.max_range, data.ranges)
    beams = np.round(np.linspace(0, 179, 60)).astype(int)
    belief = pose_grid.uniform()
    with time_limit(60):
        for t in range(16):
            belief = grid_localization(
                belief,
                data.odometry[t],
                z_all[t + 1, beams],
                pose_grid,
                data.beam_angles[beams],
                ALPHA_INTEL,
                params,
                exponent=3 / 60,
            )
            if t + 1 >= 5:
                mode, truth = pose_grid.mode(belief), data.poses[t + 1]
                assert np.hypot(*(mode[:2] - truth[:2])) <= 3 * 0.2, t + 1
                assert abs(math.remainder(mode[2] - truth[2], 2 * math.pi)) <= 2 * math.pi / 18
