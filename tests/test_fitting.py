"""Tests of probrob.fitting: maximum-likelihood α, dead reckoning, windows of a recording.

The fits are checked statistically: pose pairs are sampled from the model with known α
(exact normal noise, fixed seeds) and every fitted α_i must lie within 4 of its own
asymptotic standard errors of the truth (|z| < 4; for six parameters the chance of a
false alarm is about 4e-4). The standard errors themselves are checked for calibration
over repeated fits.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

from probrob.angles import angle_diff
from probrob.distributions import sample_normal_distribution
from probrob.fitting import (
    MotionWindows,
    fit_odometry_alpha,
    fit_velocity_alpha,
    frame_errors,
    integrate_commands,
    interpolate_poses,
    motion_windows,
    odometry_log_likelihood,
    velocity_log_likelihood,
)
from probrob.motion import (
    motion_model_odometry,
    motion_model_velocity,
    odometry_deltas,
    sample_motion_model_odometry,
    sample_motion_model_velocity,
    velocity_motion,
)

EXACT = functools.partial(sample_normal_distribution, method="exact")
Z_MAX = 4.0

VELOCITY_ALPHA = {
    "variance": np.array([0.05, 0.002, 0.5, 0.1, 0.02, 0.01]),
    "std": np.array([0.1, 0.01, 0.5, 0.2, 0.1, 0.05]),
}
ODOMETRY_ALPHA = {
    "variance": np.array([0.05, 0.01, 0.02, 0.01]),
    "std": np.array([0.1, 0.05, 0.1, 0.05]),
}


def velocity_data(noise, alpha, n, rng, v=(0.02, 0.1), w=(-0.4, 0.4), dt=1.0):
    """Commands like MRCLAM's, random start poses, end poses sampled from Table 5.3."""
    u = np.stack([rng.uniform(*v, n), rng.uniform(*w, n)], axis=-1)
    x_prev = np.stack([rng.normal(size=n), rng.normal(size=n), rng.uniform(-np.pi, np.pi, n)], -1)
    x_t = sample_motion_model_velocity(u, x_prev, dt, alpha, noise=noise, sample=EXACT, rng=rng)
    return x_t, u, x_prev


def odometry_data(noise, alpha, n, rng):
    """Odometry arcs of 0.2-1 m (negative sampled translations have < 3e-7 chance)."""
    u = np.stack([rng.uniform(0.2, 1.0, n), rng.uniform(-0.4, 0.4, n)], axis=-1)
    odo = np.zeros((n, 2, 3))
    odo[:, 0, 2] = rng.uniform(-np.pi, np.pi, n)
    odo[:, 1] = velocity_motion(odo[:, 0], u, 1.0)
    x_prev = np.stack([rng.normal(size=n), rng.normal(size=n), rng.uniform(-np.pi, np.pi, n)], -1)
    x_t = sample_motion_model_odometry(odo, x_prev, alpha, noise=noise, sample=EXACT, rng=rng)
    return x_t, odo, x_prev


# --------------------------------------------------------------------------- velocity fits


@pytest.mark.parametrize("noise", ["variance", "std"])
def test_velocity_fit_recovers_known_alpha(noise):
    rng = np.random.default_rng(11)
    alpha = VELOCITY_ALPHA[noise]
    x_t, u, x_prev = velocity_data(noise, alpha, 3000, rng)
    fit = fit_velocity_alpha(x_t, u, x_prev, 1.0, noise=noise)
    assert fit.success, fit.message
    assert not fit.at_bound.any()
    z = (fit.alpha - alpha) / fit.stderr
    assert np.all(np.abs(z) < Z_MAX), z
    # The errors are real: with 3000 pairs each α is known to a few per cent.
    assert np.all(fit.stderr / alpha < 0.1)
    assert fit.nit >= 1 and fit.nfev >= fit.nit
    assert fit.n_pairs == 3000 and fit.model == "velocity" and fit.noise == noise


@pytest.mark.parametrize("noise", ["variance", "std"])
def test_velocity_book_and_pose_fits_coincide(noise):
    """The Jacobian noise -> pose does not depend on α: same maximiser, shifted ℓ."""
    rng = np.random.default_rng(12)
    x_t, u, x_prev = velocity_data(noise, VELOCITY_ALPHA[noise], 1000, rng)
    book = fit_velocity_alpha(x_t, u, x_prev, 1.0, noise=noise, density="book")
    pose = fit_velocity_alpha(x_t, u, x_prev, 1.0, noise=noise, density="pose")
    # The same maximiser up to the optimiser's tolerance: a thousandth of a standard error.
    assert np.all(np.abs(pose.alpha - book.alpha) < 1e-3 * pose.stderr)
    np.testing.assert_allclose(pose.alpha, book.alpha, rtol=1e-4)
    shifts = [
        velocity_log_likelihood(x_t, u, x_prev, 1.0, a, noise=noise, density="pose")
        - velocity_log_likelihood(x_t, u, x_prev, 1.0, a, noise=noise, density="book")
        for a in (book.alpha, 3 * book.alpha, book.alpha[::-1])
    ]
    np.testing.assert_allclose(shifts[1], shifts[0], rtol=0, atol=1e-9)
    np.testing.assert_allclose(shifts[2], shifts[0], rtol=0, atol=1e-9)
    assert pose.log_likelihood - book.log_likelihood == pytest.approx(np.sum(shifts[0]))


def test_velocity_fit_is_the_maximum():
    """No α nearby (each coordinate ±1 %) has a higher log-likelihood."""
    rng = np.random.default_rng(13)
    x_t, u, x_prev = velocity_data("variance", VELOCITY_ALPHA["variance"], 500, rng)
    fit = fit_velocity_alpha(x_t, u, x_prev, 1.0)
    best = np.sum(velocity_log_likelihood(x_t, u, x_prev, 1.0, fit.alpha))
    assert best == pytest.approx(fit.log_likelihood)
    for i in range(6):
        for factor in (0.99, 1.01):
            alpha = fit.alpha.copy()
            alpha[i] *= factor
            assert np.sum(velocity_log_likelihood(x_t, u, x_prev, 1.0, alpha)) < best


@pytest.mark.slow
def test_velocity_standard_errors_are_calibrated():
    """Over 30 independent data sets the z-scores of α̂ have unit spread."""
    alpha = VELOCITY_ALPHA["variance"]
    z = []
    for seed in range(30):
        rng = np.random.default_rng(1000 + seed)
        x_t, u, x_prev = velocity_data("variance", alpha, 300, rng)
        fit = fit_velocity_alpha(x_t, u, x_prev, 1.0)
        z.append((fit.alpha - alpha) / fit.stderr)
    z = np.array(z)
    # 180 z-scores: their RMS has a standard error of about 0.05 if they are N(0, 1).
    rms = np.sqrt(np.mean(z**2))
    assert 0.8 < rms < 1.2, rms
    assert abs(z.mean()) < 0.3


# --------------------------------------------------------------------------- odometry fits


@pytest.mark.parametrize("noise", ["variance", "std"])
def test_odometry_pose_fit_recovers_known_alpha(noise):
    rng = np.random.default_rng(21)
    alpha = ODOMETRY_ALPHA[noise]
    x_t, odo, x_prev = odometry_data(noise, alpha, 3000, rng)
    fit = fit_odometry_alpha(x_t, odo, x_prev, noise=noise, density="pose")
    assert fit.success, fit.message
    z = (fit.alpha - alpha) / fit.stderr
    assert np.all(np.abs(z) < Z_MAX), z
    assert fit.model == "odometry" and fit.density == "pose"


def test_odometry_book_fit_misses_alpha_where_the_tables_disagree():
    """Errata O3: the printed Table 5.5 maximised over α lands away from the truth."""
    rng = np.random.default_rng(22)
    alpha = ODOMETRY_ALPHA["std"]
    x_t, odo, x_prev = odometry_data("std", alpha, 3000, rng)
    book = fit_odometry_alpha(x_t, odo, x_prev, noise="std", density="book")
    pose = fit_odometry_alpha(x_t, odo, x_prev, noise="std", density="pose")
    z_book = (book.alpha - alpha) / book.stderr
    assert np.max(np.abs(z_book)) > 2 * Z_MAX, z_book
    assert np.max(np.abs((pose.alpha - alpha) / pose.stderr)) < Z_MAX


def test_odometry_book_fit_is_consistent_for_small_noise():
    """For small α the variances at δ and at δ̂ agree to first order: both fits find α."""
    rng = np.random.default_rng(23)
    alpha = np.array([0.002, 0.001, 0.002, 0.001])
    x_t, odo, x_prev = odometry_data("variance", alpha, 3000, rng)
    for density in ("book", "pose"):
        fit = fit_odometry_alpha(x_t, odo, x_prev, density=density)
        z = (fit.alpha - alpha) / fit.stderr
        assert np.all(np.abs(z) < Z_MAX), (density, z)


def test_log_likelihoods_are_the_logs_of_the_motion_densities():
    rng = np.random.default_rng(24)
    x_t, u, x_prev = velocity_data("std", VELOCITY_ALPHA["std"], 50, rng)
    for density in ("book", "pose"):
        np.testing.assert_allclose(
            velocity_log_likelihood(
                x_t, u, x_prev, 1.0, VELOCITY_ALPHA["std"], noise="std", density=density
            ),
            np.log(
                motion_model_velocity(
                    x_t, u, x_prev, 1.0, VELOCITY_ALPHA["std"], noise="std", density=density
                )
            ),
            rtol=1e-12,
        )
    x_t, odo, x_prev = odometry_data("variance", ODOMETRY_ALPHA["variance"], 50, rng)
    for density in ("book", "pose"):
        np.testing.assert_allclose(
            odometry_log_likelihood(x_t, odo, x_prev, ODOMETRY_ALPHA["variance"], density=density),
            np.log(
                motion_model_odometry(
                    x_t, odo, x_prev, ODOMETRY_ALPHA["variance"], density=density
                )
            ),
            rtol=1e-12,
        )


def test_fit_survives_far_outliers():
    """A pose pair metres off the model has a log density of about -1e6, not -inf (log
    space): the fit still converges, and the outlier widens the fitted noise."""
    rng = np.random.default_rng(29)
    alpha = VELOCITY_ALPHA["variance"]
    x_t, u, x_prev = velocity_data("variance", alpha, 1000, rng)
    clean = fit_velocity_alpha(x_t, u, x_prev, 1.0)
    x_t[7, :2] += [0.0, 2.0]  # two metres to the side
    assert np.isfinite(velocity_log_likelihood(x_t[7], u[7], x_prev[7], 1.0, alpha))
    fit = fit_velocity_alpha(x_t, u, x_prev, 1.0)
    assert fit.success and np.isfinite(fit.log_likelihood)
    assert np.any(fit.alpha > 2 * clean.alpha)


def test_alpha0_is_a_starting_point_not_the_answer():
    rng = np.random.default_rng(25)
    alpha = VELOCITY_ALPHA["variance"]
    x_t, u, x_prev = velocity_data("variance", alpha, 1000, rng)
    default = fit_velocity_alpha(x_t, u, x_prev, 1.0)
    started = fit_velocity_alpha(x_t, u, x_prev, 1.0, alpha0=np.full(6, 3.0))
    np.testing.assert_allclose(started.alpha, default.alpha, rtol=1e-3)


# --------------------------------------------------------------------------- fit: bad input


def test_fit_rejects_pairs_no_alpha_can_explain():
    rng = np.random.default_rng(26)
    x_t, u, x_prev = velocity_data("variance", VELOCITY_ALPHA["variance"], 20, rng)
    u[3] = 0.0  # a stopped robot: the model is a point mass at x_prev
    with pytest.raises(ValueError, match=r"1 of 20 pose pairs .* index 3"):
        fit_velocity_alpha(x_t, u, x_prev, 1.0)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        (dict(noise="sd"), "noise"),
        (dict(density="xy"), "density"),
        (dict(alpha_bounds=(0.0, 1.0)), "alpha_bounds"),
        (dict(alpha_bounds=(1.0, 0.1)), "alpha_bounds"),
        (dict(alpha0=np.ones(4)), "alpha0"),
        (dict(alpha0=-np.ones(6)), "alpha0"),
    ],
)
def test_velocity_fit_bad_keywords(kwargs, match):
    rng = np.random.default_rng(27)
    x_t, u, x_prev = velocity_data("variance", VELOCITY_ALPHA["variance"], 20, rng)
    with pytest.raises(ValueError, match=match):
        fit_velocity_alpha(x_t, u, x_prev, 1.0, **kwargs)


def test_fit_bad_arrays():
    rng = np.random.default_rng(28)
    x_t, u, x_prev = velocity_data("variance", VELOCITY_ALPHA["variance"], 20, rng)
    with pytest.raises(ValueError, match="u_t"):
        fit_velocity_alpha(x_t, u[:10], x_prev, 1.0)
    with pytest.raises(ValueError, match="x_t and x_prev"):
        fit_velocity_alpha(x_t[:10], u, x_prev, 1.0)
    with pytest.raises(ValueError, match="x_t and x_prev"):
        fit_velocity_alpha(x_t[0], u[0], x_prev[0], 1.0)
    with pytest.raises(ValueError, match="dt"):
        fit_velocity_alpha(x_t, u, x_prev, 0.0)
    bad = x_t.copy()
    bad[2, 1] = np.nan
    with pytest.raises(ValueError, match="x_t"):
        fit_velocity_alpha(bad, u, x_prev, 1.0)
    odo = np.zeros((20, 2, 3))
    with pytest.raises(ValueError, match="u_t"):
        fit_odometry_alpha(x_t, odo[:, :, :2], x_prev)
    with pytest.raises(ValueError, match="pose pairs"):
        fit_odometry_alpha(x_t, odo, x_prev, density="pose")  # no odometry motion at all


# --------------------------------------------------------------------------- recordings


def test_integrate_commands_with_one_command_is_one_arc():
    """Constant (v, ω) over irregular stamps: the exact arc, however it is cut."""
    rng = np.random.default_rng(31)
    t = np.cumsum(rng.uniform(0.005, 0.3, 400))
    u = np.tile([0.3, -0.7], (t.size, 1))
    x0 = np.array([1.0, -2.0, 3.0])
    poses = integrate_commands(t, u, x0)
    for k in (1, 57, t.size - 1):
        np.testing.assert_allclose(
            poses[k], velocity_motion(x0, u[0], t[k] - t[0]), rtol=0, atol=1e-10
        )


def test_integrate_commands_matches_a_step_by_step_loop():
    rng = np.random.default_rng(32)
    t = np.cumsum(rng.uniform(0.01, 0.1, 300))
    u = np.stack([rng.uniform(0, 0.1, t.size), rng.uniform(-0.4, 0.4, t.size)], axis=-1)
    u[::7, 1] = 0.0  # exactly straight steps too
    x0 = np.array([0.5, 0.2, np.pi - 0.01])
    loop = [x0]
    for i in range(t.size - 1):
        loop.append(velocity_motion(loop[-1], u[i], t[i + 1] - t[i]))
    np.testing.assert_allclose(integrate_commands(t, u, x0), np.array(loop), rtol=0, atol=1e-12)


def test_integrate_commands_between_stamps_takes_the_partial_arc():
    t = np.array([0.0, 1.0, 2.0])
    u = np.array([[1.0, 0.0], [1.0, np.pi / 2], [9.0, 9.0]])
    x0 = np.zeros(3)
    out = integrate_commands(t, u, x0, t_out=[0.5, 1.0, 2.0])
    np.testing.assert_allclose(out[0], [0.5, 0.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(out[1], [1.0, 0.0, 0.0], atol=1e-15)
    r = 1.0 / (np.pi / 2)  # a quarter circle of radius 2/π to the left
    np.testing.assert_allclose(out[2], [1.0 + r, r, np.pi / 2], atol=1e-14)


def test_integrate_commands_bad_input():
    t = np.array([0.0, 1.0, 2.0])
    u = np.zeros((3, 2))
    with pytest.raises(ValueError, match="t must be strictly increasing"):
        integrate_commands([0.0, 1.0, 1.0], u, np.zeros(3))
    with pytest.raises(ValueError, match="u must have shape"):
        integrate_commands(t, u[:2], np.zeros(3))
    with pytest.raises(ValueError, match="x0"):
        integrate_commands(t, u, np.zeros((2, 3)))
    with pytest.raises(ValueError, match="t_out"):
        integrate_commands(t, u, np.zeros(3), t_out=[2.5])


def test_interpolate_poses_takes_the_short_way_across_pi():
    t = np.array([0.0, 1.0])
    poses = np.array([[0.0, 0.0, np.pi - 0.1], [1.0, 2.0, -np.pi + 0.1]])
    mid = interpolate_poses(t, poses, 0.5)
    np.testing.assert_allclose(mid[:2], [0.5, 1.0])
    assert abs(angle_diff(mid[2], np.pi)) < 1e-12
    np.testing.assert_allclose(interpolate_poses(t, poses, t)[:, 2], poses[:, 2], atol=1e-12)
    with pytest.raises(ValueError, match="t_out"):
        interpolate_poses(t, poses, [-0.1])
    with pytest.raises(ValueError, match="poses"):
        interpolate_poses(t, poses[:, :2], [0.5])


def synthetic_recording(rng, duration=60.0):
    """Commands held between irregular stamps, and their exact dead reckoning as truth."""
    t = np.cumsum(rng.uniform(0.01, 0.05, int(duration / 0.03)))
    u = np.stack([rng.uniform(0, 0.1, t.size), rng.uniform(-0.4, 0.4, t.size)], axis=-1)
    truth_t = np.linspace(t[0] - 1.0, t[-1] + 1.0, 20_000)  # 3 ms apart
    inside = (truth_t >= t[0]) & (truth_t <= t[-1])
    truth = np.zeros((truth_t.size, 3))
    truth[inside] = integrate_commands(t, u, [0.3, 0.4, 0.5], truth_t[inside])
    return t, u, truth_t, truth, inside


def test_motion_windows_average_the_held_commands_exactly():
    rng = np.random.default_rng(33)
    t, u, truth_t, truth, _ = synthetic_recording(rng)
    win = motion_windows(t, u, truth_t, truth, 2.0, stride=0.7)
    assert isinstance(win, MotionWindows) and win.dt == 2.0
    np.testing.assert_allclose(np.diff(win.t0), 0.7)
    assert win.t0[0] == t[0] and win.t0[-1] + 2.0 <= t[-1]
    # Brute force: the held commands sampled on a fine grid.
    for k in (0, len(win) // 2, len(win) - 1):
        fine = np.linspace(win.t0[k], win.t0[k] + 2.0, 200_001)[:-1] + 1e-5
        held = u[np.searchsorted(t, fine, side="right") - 1]
        np.testing.assert_allclose(win.u[k], held.mean(axis=0), atol=1e-4)
        np.testing.assert_array_equal(win.u_min[k], held.min(axis=0))
        np.testing.assert_array_equal(win.u_max[k], held.max(axis=0))
    assert len(win.select(win.u[:, 0] > 0.05)) == int(np.sum(win.u[:, 0] > 0.05))


def test_motion_windows_odometry_moves_like_the_truth_when_the_truth_is_dead_reckoned():
    rng = np.random.default_rng(34)
    t, u, truth_t, truth, inside = synthetic_recording(rng)
    # Truth only where it was dead-reckoned: the windows must stay inside.
    win = motion_windows(t, u, truth_t[inside], truth[inside], 1.0)
    odo = np.array(odometry_deltas(win.odometry[:, 0], win.odometry[:, 1]))
    true = np.array(odometry_deltas(win.x_prev, win.x_t))
    # The truth is interpolated linearly between 3 ms stamps, across command changes of
    # |Δω| <= 0.8 rad/s: heading errors below 0.8 * 0.003 / 4 = 6e-4 rad.
    np.testing.assert_allclose(odo[1], true[1], atol=2e-3)
    np.testing.assert_allclose(angle_diff(odo[0], true[0]), 0.0, atol=0.05)
    np.testing.assert_allclose(angle_diff(odo[0] + odo[2], true[0] + true[2]), 0.0, atol=1e-3)


def test_motion_windows_bad_input():
    rng = np.random.default_rng(35)
    t, u, truth_t, truth, _ = synthetic_recording(rng, duration=5.0)
    with pytest.raises(ValueError, match="dt"):
        motion_windows(t, u, truth_t, truth, 100.0)
    with pytest.raises(ValueError, match="stride"):
        motion_windows(t, u, truth_t, truth, 1.0, stride=-1.0)
    with pytest.raises(ValueError, match="truth must have shape"):
        motion_windows(t, u, truth_t, truth[:-1], 1.0)
    with pytest.raises(ValueError, match="command_t"):
        motion_windows(t[::-1], u, truth_t, truth, 1.0)


def test_frame_errors_undo_a_known_offset():
    """A pose moved by (a, c, e) in the reference frame reads back (a, c, e)."""
    rng = np.random.default_rng(36)
    ref = np.stack([rng.normal(size=50), rng.normal(size=50), rng.uniform(-np.pi, np.pi, 50)], -1)
    err = np.stack([rng.normal(size=50), rng.normal(size=50), rng.uniform(-3, 3, 50)], -1)
    c, s = np.cos(ref[:, 2]), np.sin(ref[:, 2])
    poses = np.stack(
        [
            ref[:, 0] + c * err[:, 0] - s * err[:, 1],
            ref[:, 1] + s * err[:, 0] + c * err[:, 1],
            ref[:, 2] + err[:, 2] + 2 * np.pi,  # a full turn more: the same heading
        ],
        axis=-1,
    )
    np.testing.assert_allclose(frame_errors(ref, poses), err, atol=1e-12)
    assert frame_errors(ref[0], poses).shape == (50, 3)
    with pytest.raises(ValueError, match="reference"):
        frame_errors(ref[:, :2], poses)
