"""probrob.mcl: Tables 4.4, 8.2, 8.3 and 8.4, checked against their definitions."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.stats import chi2, norm

from probrob import mcl as M
from probrob.angles import wrap_angle
from probrob.maps import OccupancyGrid, ray_cast
from probrob.motion import sample_motion_model_odometry
from probrob.sensors import BeamModelParams

PARAMS = BeamModelParams(0.85, 0.0, 0.05, 0.10, 0.1, 1.0, 8.0)
ALPHA = [0.02, 0.005, 0.02, 0.005]


# ---------------------------------------------------------------------- a synthetic world
def _room() -> OccupancyGrid:
    """A 10 m x 6 m room at 0.1 m, with walls that break its symmetry."""
    occ = np.zeros((60, 100), dtype=bool)
    occ[[0, -1], :] = True
    occ[:, [0, -1]] = True
    occ[0:35, 30] = True  # a wall from the bottom
    occ[25:60, 65] = True  # a wall from the top
    occ[45:50, 10:20] = True  # a box
    occ[8:12, 80:92] = True  # another box
    return OccupancyGrid(occ, 0.1)


ROOM = _room()
ANGLES = np.linspace(-np.pi / 2, np.pi / 2, 19)


def _scan(pose, max_range=PARAMS.max_range):
    return ray_cast(ROOM, pose, ANGLES, max_range, method="dda")


def _path(n):
    """A path through the room: poses and the odometry pairs between them."""
    t = np.linspace(0.0, 1.0, n + 1)
    x = 1.5 + 1.0 * t
    y = 4.5 - 3.0 * t
    th = np.full_like(t, -np.pi / 2 + 0.3)
    poses = np.column_stack([x, y, th])
    return poses, np.stack([poses[:-1], poses[1:]], axis=1)


# ---------------------------------------------------------------------- Table 4.4
@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.floats(0.0, 10.0, allow_subnormal=False), min_size=1, max_size=40).filter(
        lambda w: sum(w) > 1e-3
    ),
    st.integers(0, 2**32 - 1),
)
def test_low_variance_counts_are_floor_or_ceil_of_m_times_w(w, seed):
    w = np.asarray(w)
    idx = M.low_variance_sampler(w, rng=seed)
    counts = np.bincount(idx, minlength=w.size)
    expected = w.size * w / w.sum()
    assert idx.shape == (w.size,)
    assert np.all(counts >= np.floor(expected - 1e-9)) and np.all(
        counts <= np.ceil(expected + 1e-9)
    )
    assert np.all(counts[w == 0] == 0)


@pytest.mark.parametrize("offset", [0.0, 0.5, float(np.nextafter(1.0, 0.0))])
@pytest.mark.parametrize(
    "w", [[0.0, 0.0, 1.0], [0.5, 0.5], [0.125] * 8 + [0.0], [0.0, 0.25, 0.0, 0.75, 0.0]]
)
def test_low_variance_edges_of_the_offset(w, offset):
    # issue 23, item 3: offset 0 drew zero-weight particles ([0, 0, 1] -> [0, 2, 2]) and
    # broke the floor/ceil rule ([.5, .5] -> [0, 0]); an offset just below 1 drew index N.
    # Dyadic weights: the cumulative sums are exact, so the rule holds without round-off.
    w = np.array(w)
    for m in (len(w), 8, 16):
        counts = np.bincount(M.low_variance_sampler(w, m, offset=offset), minlength=len(w))
        assert np.all(counts[w == 0] == 0)
        assert np.all((counts == np.floor(m * w)) | (counts == np.ceil(m * w)))


def test_low_variance_through_mcl_keeps_no_off_map_particle():
    poses, u = _path(1)
    x = np.tile(poses[0], (10, 1))
    x[:3, 0] = -50.0  # off the map: weight zero
    out = M.mcl(x, u[0], _scan(poses[1]), ROOM, ANGLES, [0.0] * 4, PARAMS, resample_offset=0.0)
    assert ROOM.contains(out[:, :2]).all()


def test_low_variance_size_other_than_n():
    idx = M.low_variance_sampler([0.5, 0.25, 0.25], size=8, rng=0)
    assert np.array_equal(np.bincount(idx, minlength=3), [4, 2, 2])


def test_low_variance_is_unbiased_over_seeds():
    w = np.array([0.07, 0.33, 0.01, 0.29, 0.3])
    n_seeds = 4000
    counts = np.array(
        [np.bincount(M.low_variance_sampler(w, rng=s), minlength=5) for s in range(n_seeds)]
    )
    mean = counts.mean(axis=0)
    # each count is floor(Nw) or ceil(Nw): a Bernoulli on top of floor, variance <= 1/4
    assert np.all(np.abs(mean - 5 * w) < 4 * 0.5 / math.sqrt(n_seeds))


def test_low_variance_has_lower_variance_than_multinomial():
    rng = np.random.default_rng(7)
    w = rng.random(200)
    w /= w.sum()
    lv = np.array(
        [np.bincount(M.low_variance_sampler(w, rng=s), minlength=200) for s in range(300)]
    )
    mn = rng.multinomial(200, w, size=300)
    assert lv.var(axis=0).sum() < 0.5 * mn.var(axis=0).sum()


@pytest.mark.parametrize(
    ("weights", "message"),
    [
        ([0.5, -0.1, 0.6], "non-negative"),
        ([0.5, np.nan], "NaN"),
        ([0.0, 0.0], "all zero"),
        ([1.0, np.inf], "finite"),
        ([[0.5, 0.5]], r"shape \(N,\)"),
        ([], r"shape \(N,\)"),
    ],
)
def test_low_variance_rejects_bad_weights(weights, message):
    with pytest.raises(ValueError, match=message):
        M.low_variance_sampler(weights)


def test_low_variance_rejects_bad_size():
    with pytest.raises(ValueError, match="size"):
        M.low_variance_sampler([1.0], size=0)
    with pytest.raises(ValueError, match="size"):
        M.low_variance_sampler([1.0], size=2.5)


def test_effective_sample_size():
    assert M.effective_sample_size(np.ones(10)) == pytest.approx(10.0)
    assert M.effective_sample_size([0, 0, 1.0]) == pytest.approx(1.0)
    lw = np.log([0.2, 0.3, 0.5])
    assert M.effective_sample_size(lw, log=True) == pytest.approx(1 / (0.04 + 0.09 + 0.25))
    assert M.effective_sample_size(np.array([-np.inf, 0.0]), log=True) == pytest.approx(1.0)
    with pytest.raises(ValueError, match="log"):
        M.effective_sample_size([1.0], log="yes")


# ---------------------------------------------------------------------- uniform particles
def test_uniform_particles_lie_in_free_cells_with_uniform_headings():
    x = M.uniform_particles(ROOM, 20000, rng=1)
    assert x.shape == (20000, 3)
    ij = ROOM.world_to_cell(x[:, :2])
    assert not ROOM.occupied[ij[:, 0], ij[:, 1]].any()
    assert np.all((x[:, 2] >= -np.pi) & (x[:, 2] < np.pi))
    # every free cell equally likely: the share left of the first wall matches its free area
    free = ~ROOM.occupied
    share = free[:, :30].sum() / free.sum()
    assert abs(np.mean(x[:, 0] < 3.0) - share) < 4 * math.sqrt(share * (1 - share) / 20000)


def test_uniform_particles_free_mask_and_errors():
    mask = np.zeros(ROOM.shape, dtype=bool)
    mask[30, 50] = True
    x = M.uniform_particles(ROOM, 50, rng=0, free=mask)
    assert np.all(ROOM.world_to_cell(x[:, :2]) == [30, 50])
    with pytest.raises(ValueError, match="free"):
        M.uniform_particles(ROOM, 5, free=np.zeros(ROOM.shape, dtype=bool))
    with pytest.raises(ValueError, match="free"):
        M.uniform_particles(ROOM, 5, free=np.ones((3, 3), dtype=bool))
    with pytest.raises(ValueError, match="n"):
        M.uniform_particles(ROOM, 0)


# ---------------------------------------------------------------------- Table 8.4, line 17
@pytest.mark.parametrize("k", [2, 3, 10, 100, 5000])
@pytest.mark.parametrize(("epsilon", "delta"), [(0.05, 0.01), (0.1, 0.05), (0.02, 0.001)])
def test_kld_sample_size_equals_the_formula(k, epsilon, delta):
    z = norm.ppf(1 - delta)
    a = 2 / (9 * (k - 1))
    formula = (k - 1) / (2 * epsilon) * (1 - a + math.sqrt(a) * z) ** 3
    assert M.kld_sample_size(k, epsilon, delta) == math.ceil(formula)
    # the Wilson-Hilferty approximation of the chi-square quantile (Fox 2003)
    if k >= 10:
        exact = chi2.ppf(1 - delta, k - 1) / (2 * epsilon)
        assert abs(formula / exact - 1) < 0.01


def test_kld_sample_size_errors():
    with pytest.raises(ValueError, match="k"):
        M.kld_sample_size(1)
    with pytest.raises(ValueError, match="epsilon"):
        M.kld_sample_size(10, epsilon=0.0)
    with pytest.raises(ValueError, match="delta"):
        M.kld_sample_size(10, delta=1.0)


# ---------------------------------------------------------------------- the measurement step
def test_off_map_particles_get_weight_zero_not_an_exception():
    pose = np.array([5.0, 3.0, 0.3])
    x = np.array([pose, [-5.0, 3.0, 0.0], [5.0, 100.0, 0.0], [5.0, 3.0, 0.0]])
    lw = M.measurement_log_weights(x, _scan(pose), ROOM, ANGLES, PARAMS)
    assert np.isneginf(lw[1]) and np.isneginf(lw[2])
    assert np.isfinite(lw[[0, 3]]).all() and lw[0] > lw[3]
    for sensor in ("likelihood_field", "beam"):
        lw = M.measurement_log_weights(x, _scan(pose), ROOM, ANGLES, PARAMS, sensor=sensor)
        assert np.isneginf(lw[1]) and lw[0] == lw.max()


def test_exponent_tempers_the_log_likelihood():
    pose = np.array([5.0, 3.0, 0.3])
    x = pose + np.random.default_rng(0).normal(0, 0.2, (20, 3))
    full = M.measurement_log_weights(x, _scan(pose), ROOM, ANGLES, PARAMS)
    half = M.measurement_log_weights(x, _scan(pose), ROOM, ANGLES, PARAMS, exponent=0.5)
    np.testing.assert_allclose(half, 0.5 * full)


def test_mcl_drops_particles_that_leave_the_map():
    poses, u = _path(1)
    x = np.vstack([np.tile(poses[0], (50, 1)), np.tile([0.05, 3.0, np.pi], (50, 1))])
    out = M.mcl(x, u[0], _scan(poses[1]), ROOM, ANGLES, [0, 0, 0, 0], PARAMS, rng=0)
    assert out.shape == (100, 3) and ROOM.contains(out[:, :2]).all()


def test_mcl_keeps_the_moved_particles_when_every_weight_is_zero():
    poses, u = _path(1)
    x = np.tile([-30.0, 3.0, 0.0], (10, 1)) + np.arange(10)[:, None] * [0.0, 0.1, 0.0]
    out = M.mcl(x, u[0], _scan(poses[1]), ROOM, ANGLES, [0, 0, 0, 0], PARAMS, rng=0)
    moved = sample_motion_model_odometry(u[0], x, [0, 0, 0, 0])
    np.testing.assert_allclose(out, moved)  # equal weights: each particle once, in order


def test_odometry_frame_is_irrelevant():
    """Table 5.6 uses only the relative motion: an odometry frame rotated and shifted
    against the map's gives the same particles."""
    poses, u = _path(3)
    x0 = poses[0] + np.random.default_rng(2).normal(0, 0.1, (500, 3))
    phi, shift = 2.1, np.array([40.0, -17.0])
    c, s = math.cos(phi), math.sin(phi)
    u_rot = u.copy()
    u_rot[..., :2] = u[..., :2] @ np.array([[c, s], [-s, c]]) + shift
    u_rot[..., 2] = wrap_angle(u[..., 2] + phi)
    a = M.mcl(x0, u[1], _scan(poses[2]), ROOM, ANGLES, ALPHA, PARAMS, rng=5)
    b = M.mcl(x0, u_rot[1], _scan(poses[2]), ROOM, ANGLES, ALPHA, PARAMS, rng=5)
    np.testing.assert_allclose(a, b, atol=1e-9)


@pytest.mark.parametrize("method", ["mcl", "augmented", "kld"])
def test_seeded_global_localization_converges_on_a_synthetic_map(method):
    poses, u = _path(25)
    scans = np.array([_scan(p) for p in poses[1:]])
    x0 = M.uniform_particles(ROOM, 6000, rng=11)
    options = dict(exponent=0.5)
    if method == "kld":
        options.update(n_max=6000, n_min=300)
    run = M.run_mcl(x0, u, scans, ROOM, ANGLES, ALPHA, PARAMS, method=method, rng=3, **options)
    err = np.hypot(*(run.estimates[:, :2] - poses[:, :2]).T)
    head = np.abs(wrap_angle(run.estimates[:, 2] - poses[:, 2]))
    assert err[0] > 1.0, "the uniform start is not already localized"
    assert np.all(err[-5:] < 0.25), err
    assert np.all(head[-5:] < 0.15), head
    if method == "kld":
        assert run.n_particles[-1] < run.n_particles[0] / 3


# ---------------------------------------------------------------------- Table 8.3
def _augmented_step(w_slow, w_fast, seed=0):
    """One step with no motion noise, so every particle not injected is a moved input particle."""
    poses, u = _path(1)
    x0 = poses[0] + np.random.default_rng(seed).normal(0, 0.05, (400, 3))
    out, ws, wf = M.augmented_mcl(
        x0, u[0], _scan(poses[1]), ROOM, ANGLES, [0, 0, 0, 0], PARAMS, w_slow, w_fast, rng=seed
    )
    moved = sample_motion_model_odometry(u[0], x0, [0, 0, 0, 0])  # noise-free: deterministic
    is_moved = np.isclose(out[:, None, :], moved[None, :, :], atol=1e-9).all(axis=2).any(axis=1)
    return out, ws, wf, int((~is_moved).sum())


def test_augmented_mcl_injects_only_when_w_fast_below_w_slow():
    _, ws, wf, injected = _augmented_step(0.0, 0.0)
    assert wf > ws > 0 and injected == 0
    _, ws, wf, injected = _augmented_step(ws, wf)
    assert wf > ws and injected == 0
    # a sudden drop of the likelihood: the fast average falls below the slow one
    _, ws, wf, injected = _augmented_step(1e30, 1e20)
    assert wf < ws
    expected = 400 * (1 - wf / ws)
    assert injected > 0 and abs(injected - expected) < 5 * math.sqrt(expected + 1)


def test_augmented_mcl_injects_about_half_when_w_fast_is_half_of_w_slow():
    poses, u = _path(1)
    x0 = poses[0] + np.random.default_rng(1).normal(0, 0.05, (400, 3))
    z = _scan(poses[1])
    x_bar = sample_motion_model_odometry(u[0], x0, [0, 0, 0, 0])
    w_avg = np.exp(M.measurement_log_weights(x_bar, z, ROOM, ANGLES, PARAMS)).mean()
    # choose the inputs so that after the update w_fast / w_slow = 1/2 exactly
    a_s, a_f = 0.01, 0.1
    ws_new = 4.0 * w_avg
    ws_old = (ws_new - a_s * w_avg) / (1 - a_s)
    wf_old = (0.5 * ws_new - a_f * w_avg) / (1 - a_f)
    counts = []
    for seed in range(20):
        out, ws, wf = M.augmented_mcl(
            x0,
            u[0],
            z,
            ROOM,
            ANGLES,
            [0, 0, 0, 0],
            PARAMS,
            ws_old,
            wf_old,
            alpha_slow=a_s,
            alpha_fast=a_f,
            rng=seed,
        )
        assert wf / ws == pytest.approx(0.5)
        moved = np.isclose(out[:, None, :], x_bar[None, :, :], atol=1e-9).all(axis=2).any(axis=1)
        counts.append(int((~moved).sum()))
    mean = np.mean(counts)  # binomial(400, 1/2): mean 200, sd 10 per step, 2.2 over 20 steps
    assert abs(mean - 200) < 10


def test_augmented_mcl_starts_afresh_when_every_weight_is_zero():
    poses, u = _path(1)
    x0 = np.tile([-30.0, 3.0, 0.0], (300, 1))
    out, ws, wf = M.augmented_mcl(
        x0, u[0], _scan(poses[1]), ROOM, ANGLES, ALPHA, PARAMS, 0.0, 0.0, rng=0
    )
    assert ws == 0.0 and wf == 0.0
    ij = ROOM.world_to_cell(out[:, :2])
    assert ROOM.free[ij[:, 0], ij[:, 1]].all() and out[:, 0].std() > 1.0


def test_augmented_mcl_running_averages_follow_table_8_3():
    poses, u = _path(1)
    x0 = np.tile(poses[0], (100, 1))
    z = _scan(poses[1])
    x_bar = sample_motion_model_odometry(u[0], x0, [0, 0, 0, 0])
    w_avg = np.exp(M.measurement_log_weights(x_bar, z, ROOM, ANGLES, PARAMS)).mean()
    _, ws, wf = M.augmented_mcl(
        x0,
        u[0],
        z,
        ROOM,
        ANGLES,
        [0, 0, 0, 0],
        PARAMS,
        2.0,
        3.0,
        alpha_slow=0.01,
        alpha_fast=0.2,
        rng=0,
    )
    assert ws == pytest.approx(2.0 + 0.01 * (w_avg - 2.0), rel=1e-9)
    assert wf == pytest.approx(3.0 + 0.2 * (w_avg - 3.0), rel=1e-9)


def test_augmented_mcl_bad_averages():
    poses, u = _path(1)
    args = (np.tile(poses[0], (5, 1)), u[0], _scan(poses[1]), ROOM, ANGLES, ALPHA, PARAMS)
    with pytest.raises(ValueError, match="w_slow"):
        M.augmented_mcl(*args, -1.0, 0.0)
    with pytest.raises(ValueError, match="w_fast"):
        M.augmented_mcl(*args, 0.0, np.nan)
    with pytest.raises(ValueError, match="alpha_slow < alpha_fast"):
        M.augmented_mcl(*args, 0.0, 0.0, alpha_slow=0.5, alpha_fast=0.1)


# ---------------------------------------------------------------------- Table 8.4
def test_kld_particle_count_follows_the_bound():
    poses, u = _path(2)
    bins = np.array([0.5, 0.5, np.pi / 18])
    x, w = M.uniform_particles(ROOM, 5000, rng=4), None
    for t in range(2):
        x, w = M.kld_sampling_mcl(
            x,
            u[t],
            _scan(poses[t + 1]),
            ROOM,
            ANGLES,
            ALPHA,
            PARAMS,
            weights=w,
            exponent=0.3,
            rng=t,
            n_min=50,
            n_max=20000,
        )
        assert w.shape == (len(x),) and w.sum() == pytest.approx(1.0)
        k = M.occupied_bins(x, bins)
        # counted independently of the library's bin labels
        pose = np.column_stack([x[:, :2], wrap_angle(x[:, 2])])
        assert k == len(np.unique(np.floor(pose / bins), axis=0))
        assert 50 <= len(x) <= 20000
        assert len(x) >= min(20000, M.kld_sample_size(k)) if k >= 2 else len(x) == 50
        # Table 8.4's loop stops at the first M with M >= M_chi(k of the first M): one
        # particle fewer and the bound of its own bins is not met yet
        if 50 < len(x) < 20000:
            k_before = M.occupied_bins(x[:-1], bins)
            assert len(x) - 1 < max(50, M.kld_sample_size(max(k_before, 2)))


def _flat_step(n, m_max, seed):
    """One KLD step from n particles at one pose, with flat weights (issue 23's reproducer)."""
    poses, u = _path(1)
    x = np.tile(poses[0], (n, 1))
    return M.kld_sampling_mcl(
        x,
        u[0],
        _scan(poses[1]),
        ROOM,
        ANGLES,
        [2.0] * 4,
        PARAMS,
        exponent=1e-4,
        n_min=50,
        n_max=m_max,
        rng=seed,
    )


def test_kld_draws_a_fresh_motion_sample_for_every_new_particle():
    # Table 8.4, line 9: each new particle is its own motion sample, so the set holds as many
    # distinct poses as particles, however few the previous set had (the library's former
    # order, resampling copies of the N moved particles, held at most N distinct poses)
    for m_max in (200, 2000, 8000):
        x, _ = _flat_step(50, m_max, seed=1)
        assert len(x) == m_max  # the flat, wide noise spreads the set: the cap is reached
        assert len(np.unique(x, axis=0)) == len(x)


def test_kld_weights_are_the_new_samples_likelihoods():
    poses, u = _path(1)
    x0 = M.uniform_particles(ROOM, 3000, rng=2)
    x, w = M.kld_sampling_mcl(
        x0, u[0], _scan(poses[1]), ROOM, ANGLES, ALPHA, PARAMS, exponent=0.3, rng=5
    )
    lw = M.measurement_log_weights(x, _scan(poses[1]), ROOM, ANGLES, PARAMS, exponent=0.3)
    np.testing.assert_allclose(w, np.exp(lw - lw.max()) / np.exp(lw - lw.max()).sum())


def test_kld_draws_from_the_previous_weights():
    # all weight on one particle: every new particle is a motion sample from it
    poses, u = _path(1)
    x0 = M.uniform_particles(ROOM, 400, rng=3)
    w0 = np.zeros(400)
    w0[17] = 1.0
    x, _ = M.kld_sampling_mcl(
        x0, u[0], _scan(poses[1]), ROOM, ANGLES, [0.0] * 4, PARAMS, weights=w0, rng=0
    )
    expected = sample_motion_model_odometry(u[0], x0[17], [0.0] * 4, rng=0)
    np.testing.assert_allclose(x, np.broadcast_to(expected, x.shape), atol=1e-12)
    with pytest.raises(ValueError, match="weights must have shape"):
        M.kld_sampling_mcl(x0, u[0], _scan(poses[1]), ROOM, ANGLES, ALPHA, PARAMS, weights=w0[:-1])


def test_kld_respects_n_max_and_checks_its_arguments():
    poses, u = _path(1)
    args = (M.uniform_particles(ROOM, 2000, rng=0), u[0], _scan(poses[1]), ROOM, ANGLES)
    x, w = M.kld_sampling_mcl(*args, ALPHA, PARAMS, exponent=0.01, n_max=700, rng=0)
    assert len(x) == len(w) == 700
    with pytest.raises(ValueError, match="n_min <= n_max"):
        M.kld_sampling_mcl(*args, ALPHA, PARAMS, n_min=10, n_max=5)
    with pytest.raises(ValueError, match="bin_size"):
        M.kld_sampling_mcl(*args, ALPHA, PARAMS, bin_size=(0.5, 0.0, 0.1))


def test_kld_sample_size_is_at_least_one_and_delta_below_one_half():
    # issue 23, item 23: delta = 0.99 gave 0 particles and 0.9999 gave -9
    for delta in (0.5, 0.99, 0.9999):
        with pytest.raises(ValueError, match="delta"):
            M.kld_sample_size(2, 0.05, delta)
    assert all(M.kld_sample_size(k, 0.05, 0.49) >= 1 for k in (2, 3, 10))
    with pytest.raises(ValueError, match="epsilon"):
        M.kld_sample_size(2, 5e-324)  # was OverflowError


def test_binning_refuses_what_it_cannot_bin():
    # issue 23, item 22: int64 bin codes wrapped silently (two particles 1 m apart, 1 bin)
    with pytest.raises(ValueError, match="particles"):
        M.occupied_bins([[1e12, 0, 0], [1e12 + 1, 0, 0]], (1e-7, 1, 1))
    assert M.occupied_bins([[1e6, 0, 0], [1e6 + 1, 0, 0]], (0.5, 1, 1)) == 2


# ---------------------------------------------------------------------- estimates and input
def test_estimate_pose_is_not_fooled_by_a_mode_split_across_bin_corners():
    rng = np.random.default_rng(3)
    wide = np.c_[1.0 + rng.normal(0, 0.15, (600, 2)), np.zeros(600)]  # 60 %, on a corner
    compact = np.c_[5.25 + rng.normal(0, 0.02, (400, 2)), np.zeros(400)]  # 40 %, in one bin
    est = M.estimate_pose(np.vstack([wide, compact]), radius=0.5)
    np.testing.assert_allclose(est.pose[:2], [1.0, 1.0], atol=0.03)
    assert est.fraction == pytest.approx(0.6, abs=0.01)


def test_occupied_bins_wraps_headings_and_checks_bin_size():
    x = np.array(
        [[0.1, 0.1, np.pi - 0.01], [0.1, 0.1, -np.pi + 0.01], [0.1, 0.1, 3 * np.pi - 0.01]]
    )
    assert M.occupied_bins(x) == 2  # π - 0.01 and 3π - 0.01 are one heading
    with pytest.raises(ValueError, match="bin_size"):
        M.occupied_bins(x, bin_size=(0.5, 0.5))


def test_estimate_pose_picks_the_heavier_mode_of_a_bimodal_set():
    rng = np.random.default_rng(0)
    a = np.array([2.0, 2.0, 3.1]) + rng.normal(0, 0.05, (600, 3))
    b = np.array([7.0, 4.0, -1.0]) + rng.normal(0, 0.05, (400, 3))
    est = M.estimate_pose(np.vstack([a, b]))
    np.testing.assert_allclose(est.pose[:2], [2.0, 2.0], atol=0.02)
    assert abs(wrap_angle(est.pose[2] - 3.1)) < 0.02  # the circular mean across ±π
    assert est.fraction == pytest.approx(0.6)
    w = np.r_[np.full(600, 0.1), np.full(400, 1.0)]
    np.testing.assert_allclose(M.estimate_pose(np.vstack([a, b]), w).pose[:2], [7, 4], atol=0.02)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (dict(particles=np.zeros((0, 3))), "particles"),
        (dict(particles=np.zeros((4, 2))), "particles"),
        (dict(u=np.zeros((3,))), "u must be an odometry pair"),
        (dict(z=np.ones(3)), "one range per beam"),
        (dict(z=-np.ones(19)), "non-negative"),
        (dict(alpha=[0.1, -0.1, 0, 0]), "alpha"),
        (dict(params="beam"), "BeamModelParams"),
        (dict(sensor="lidar"), "sensor"),
        (dict(exponent=2.0), "exponent"),
        (dict(grid=np.zeros((3, 3))), "grid"),
    ],
)
def test_mcl_bad_input_names_the_argument(change, message):
    poses, u = _path(1)
    args = dict(
        particles=np.tile(poses[0], (5, 1)),
        u=u[0],
        z=_scan(poses[1]),
        grid=ROOM,
        beam_angles=ANGLES,
        alpha=ALPHA,
        params=PARAMS,
    )
    args.update(change)
    extra = {k: args.pop(k) for k in ("sensor", "exponent") if k in args}
    with pytest.raises(ValueError, match=message):
        M.mcl(*args.values(), **extra)


def test_run_mcl_collects_and_can_kidnap():
    poses, u = _path(6)
    scans = np.array([_scan(p) for p in poses[1:]])
    x0 = poses[0] + np.random.default_rng(0).normal(0, 0.05, (300, 3))
    seen = []

    def kidnap(t, x):
        seen.append(t)
        return np.tile([8.0, 1.5, 0.0], (len(x), 1)) if t == 3 else None

    run = M.run_mcl(
        x0,
        u,
        scans,
        ROOM,
        ANGLES,
        ALPHA,
        PARAMS,
        method="augmented",
        keep=(0, 3),
        rng=0,
        on_step=kidnap,
    )
    assert seen == [1, 2, 3, 4, 5, 6]
    assert run.estimates.shape == (7, 3) and run.seconds.shape == (6,)
    assert set(run.snapshots) == {0, 3}
    np.testing.assert_allclose(run.estimates[3], [8.0, 1.5, 0.0])
    assert np.all(run.w_fast[1:] > 0)
    with pytest.raises(ValueError, match="method"):
        M.run_mcl(x0, u, scans, ROOM, ANGLES, ALPHA, PARAMS, method="ekf")
    with pytest.raises(ValueError, match="scans"):
        M.run_mcl(x0, u, scans[:3], ROOM, ANGLES, ALPHA, PARAMS)


def test_an_infinite_density_takes_all_the_weight():
    # the beam model's short-reading point mass: a reading of 0 where the map's range is 0
    w = M._normalise_log(np.array([-np.inf, 0.0, np.inf, -3.0, np.inf]))
    np.testing.assert_array_equal(w, [0.0, 0.0, 0.5, 0.0, 0.5])


# ---------------------------------------------------------------------- selective resampling
def test_selective_mcl_carries_the_weights_until_n_eff_falls():
    poses, u = _path(1)
    x0 = poses[0] + np.random.default_rng(0).normal(0, [0.3, 0.3, 0.1], (400, 3))
    w0 = np.random.default_rng(1).uniform(0.5, 1.0, 400)
    z = _scan(poses[1])
    zero = [0.0] * 4  # no motion noise: the moved particles are known
    x, w = M.selective_mcl(x0, w0, u[0], z, ROOM, ANGLES, zero, PARAMS, threshold=0.0, rng=3)
    moved = sample_motion_model_odometry(u[0], x0, zero, rng=0)
    np.testing.assert_allclose(x, moved, atol=1e-12)
    lw = M.measurement_log_weights(moved, z, ROOM, ANGLES, PARAMS)
    expected = w0 * np.exp(lw - lw.max())
    np.testing.assert_allclose(w, expected / expected.sum(), rtol=1e-9)
    # threshold 1: any unequal weights resample, and the set comes out equally weighted
    x1, w1 = M.selective_mcl(x0, w0, u[0], z, ROOM, ANGLES, zero, PARAMS, threshold=1.0, rng=3)
    np.testing.assert_array_equal(w1, np.full(400, 1 / 400))
    assert len(np.unique(x1, axis=0)) < 400  # copies: a resampling
    # between: it resamples exactly when N_eff < threshold * M
    n_eff = 1 / np.sum((expected / expected.sum()) ** 2)
    for thr in (0.9 * n_eff / 400, 1.1 * n_eff / 400):
        _, wt = M.selective_mcl(x0, w0, u[0], z, ROOM, ANGLES, zero, PARAMS, threshold=thr)
        assert np.all(wt == wt[0]) == (n_eff < thr * 400)


def test_selective_mcl_in_a_run_resamples_on_some_steps_only():
    poses, u = _path(12)
    z = np.array([_scan(p) for p in poses[1:]])
    x0 = poses[0] + np.random.default_rng(2).normal(0, [0.05, 0.05, 0.02], (300, 3))
    run = M.run_mcl(
        x0,
        u,
        z,
        ROOM,
        ANGLES,
        ALPHA,
        PARAMS,
        method="selective",
        exponent=0.2,
        threshold=0.5,
        rng=4,
    )
    assert 0 < run.resampled.sum() < len(u)
    assert np.all(M.run_mcl(x0, u, z, ROOM, ANGLES, ALPHA, PARAMS, rng=4).resampled)
    err = np.hypot(*(run.estimates[:, :2] - poses[:, :2]).T)
    assert err.max() < 0.3
    with pytest.raises(ValueError, match="threshold"):
        M.selective_mcl(x0, None, u[0], z[0], ROOM, ANGLES, ALPHA, PARAMS, threshold=1.5)
    with pytest.raises(ValueError, match="weights must have shape"):
        M.selective_mcl(x0, np.ones(3), u[0], z[0], ROOM, ANGLES, ALPHA, PARAMS)


def test_low_variance_refuses_a_size_it_cannot_count():
    # was a RuntimeWarning (an invalid cast) for size=10**20
    with pytest.raises(ValueError, match="size must be at most"):
        M.low_variance_sampler([0.5, 0.5], size=10**20)
