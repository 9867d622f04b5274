"""Regression tests for issue 23 (the library's reliability sweep).

Each test failed before its fix; the item number is the issue's. Items 4 and 11 (the exercise
checks) are tested in ``tests/test_exercises.py`` and ``tests/test_exercise_digits.py``, the
Turkish exercises of item 19 in ``tests/test_exercises_turkish.py``, the JavaScript mirror of
``estimate_pose`` (item 2) in ``tests/test_live_mcl.py``, the property classes (item 29) in
``tests/test_api_properties.py``.
"""

from __future__ import annotations

import numpy as np
import pytest

from probrob import mcl as M
from probrob.angles import circular_mean, wrap_angle
from probrob.maps import OccupancyGrid

PI = np.pi


# ------------------------------------------------------- item 2: estimate_pose in (x, y, θ)
def test_opposite_headings_are_not_averaged_into_one_no_particle_has():
    # 50 particles at θ = 0 and 50 at θ = π, 5 cm apart: the mean heading was π/2
    x = np.r_[np.zeros((50, 3)), np.tile([0.05, 0.0, PI], (50, 1))]
    est = M.estimate_pose(x)
    assert min(abs(wrap_angle(est.pose[2])), abs(wrap_angle(est.pose[2] - PI))) < 1e-12
    assert est.fraction == pytest.approx(0.5)
    assert est.pose[0] == pytest.approx(0.0, abs=1e-15) or est.pose[0] == pytest.approx(0.05)
    # weighted: the heavier heading wins
    w = np.r_[np.full(50, 1.0), np.full(50, 1.2)]
    est = M.estimate_pose(x, w)
    assert abs(wrap_angle(est.pose[2] - PI)) < 1e-12 and est.fraction == pytest.approx(60 / 110)


def test_a_cloud_across_the_heading_cut_is_one_cluster():
    rng = np.random.default_rng(2)
    x = np.c_[rng.normal(0, 0.1, (500, 2)), PI + rng.normal(0, 0.1, 500)]
    est = M.estimate_pose(x)
    assert est.fraction > 0.99 and abs(wrap_angle(est.pose[2] - PI)) < 0.02


def test_the_cluster_spans_less_than_half_a_turn():
    # headings spread over the whole circle: the estimate is one sector's, never a mean of
    # headings half a turn apart
    rng = np.random.default_rng(5)
    x = np.c_[rng.normal(0, 0.05, (2000, 2)), rng.uniform(-PI, PI, 2000)]
    est = M.estimate_pose(x, heading_bins=12)
    near = np.abs(wrap_angle(x[:, 2] - est.pose[2])) <= 2 * (2 * PI / 12)
    assert est.fraction == pytest.approx(near.mean(), abs=0.02) and est.fraction < 0.45
    with pytest.raises(ValueError, match="heading_bins"):
        M.estimate_pose(x, heading_bins=8)
    with pytest.raises(ValueError, match="heading_bins"):
        M.estimate_pose(x, heading_bins=12.0)


# --------------------------------------- item 22: binning that overflowed or divided by zero
def test_estimate_pose_far_from_the_origin_picks_the_heaviest_mode():
    x = [[1e11, 1e11, 0]] * 5 + [[-1e11, -1e11, 1]] * 2 + [[-1e11, 1e11, 2]]
    est = M.estimate_pose(x)  # was the 2-particle mode, fraction 0.25 (int64 codes wrapped)
    np.testing.assert_array_equal(est.pose, [1e11, 1e11, 0.0])
    assert est.fraction == pytest.approx(5 / 8)


@pytest.mark.parametrize(
    ("particles", "radius"),
    [
        ([[1.0, 2.0, 0.0]] * 2 + [[1.0 + 5e-12, 2.0, 0.0]], 1e-13),
        ([[1e12, -1e12, 0.0]] * 2 + [[1e12 + 5.0, -1e12, 0.1]], 0.5),
    ],
)
def test_estimate_pose_tiny_radius_or_far_particles_no_zero_division(particles, radius):
    # the bins were clipped at 2**40: every particle in one bin, the cluster around their
    # mean held none of them, and np.average raised ZeroDivisionError (run_mcl crashed)
    est = M.estimate_pose(particles, radius=radius)
    assert est.fraction == pytest.approx(2 / 3)
    np.testing.assert_array_equal(est.pose[:2], particles[0][:2])


def test_estimate_pose_refuses_what_it_cannot_bin_naming_radius():
    with pytest.raises(ValueError, match=r"particles.*radius"):
        M.estimate_pose([[1e3, 0.0, 0.0]] * 2, radius=1e-13)
    with pytest.raises(ValueError, match=r"particles.*radius"):
        M.estimate_pose([[1e300, 0.0, 0.0]] * 2)


def test_world_to_cell_refuses_instead_of_wrapping():
    grid = OccupancyGrid(np.zeros((4, 4), bool), 0.5)
    with pytest.raises(ValueError, match="xy"):
        grid.world_to_cell([1e20, 0.5])  # was cell (1, -9223372036854775808)
    with pytest.raises(ValueError, match=r"xy = \[0\.0, -1e\+300\]"):
        grid.world_to_cell([[1.0, 1.0], [0.0, -1e300]])
    assert grid.world_to_cell([1e10, 0.5]).tolist() == [1, 20_000_000_000]


# ------------------------------------------------------- item 24: effective sample size
@pytest.mark.parametrize(
    ("weights", "log", "n_eff"),
    [
        ([1e17, 1e17], True, 2.0),  # was 0.5: log-sum-exp lost the log 2
        ([-1e17, -1e17, -1e17], True, 3.0),
        ([1e308, 1e308, 1e308], False, 3.0),  # the sum overflowed (a RuntimeWarning)
        ([5e-324] * 4, False, 4.0),
        ([0.0, -np.inf, 0.0], True, 2.0),
        ([1.0, 1.0, 1.0, 5.0], False, 64 / 28),
    ],
)
def test_effective_sample_size_at_any_scale(weights, log, n_eff):
    assert M.effective_sample_size(weights, log=log) == pytest.approx(n_eff, rel=1e-15)


def test_effective_sample_size_lies_in_one_to_n():
    rng = np.random.default_rng(24)
    for scale in (1e-300, 1.0, 1e300):
        for _ in range(20):
            w = rng.exponential(size=rng.integers(1, 50)) ** rng.uniform(1, 30)
            w = w / w.max() * scale
            assert 1.0 <= M.effective_sample_size(w) <= w.size
            log_w = rng.normal(0, 1, w.size) * rng.uniform(1, 1e6) + np.log(scale)
            assert 1.0 <= M.effective_sample_size(log_w, log=True) <= w.size


# ------------------------------------------------------- item 25: circular mean
@pytest.mark.parametrize("weight", [1e308, 5e-324, 1e-320, 1.0])
def test_circular_mean_is_blind_to_the_weights_scale(weight):
    # 1e308: 0.0 with a RuntimeWarning (the sums overflowed); 5e-324: 0.0 (they underflowed)
    assert circular_mean([0.1, 0.2], [weight, weight]) == pytest.approx(0.15, abs=1e-15)


def test_circular_mean_of_near_opposite_angles_is_their_bisector_as_documented():
    # np.pi lies 1.2e-16 below a half turn: the mean of 0 and np.pi is π/2 (the docstring said 0)
    assert circular_mean([0.0, PI]) == PI / 2
    assert circular_mean([PI / 2, -PI / 2]) == 0.0
    doc = " ".join(circular_mean.__doc__.split())
    assert "the mean of 0 and ``np.pi`` is their bisector, π/2" in doc
    assert "0 is returned" not in doc


def test_circular_mean_with_no_direction_raises():
    with pytest.raises(ValueError, match="undefined"):
        circular_mean([0.3, 0.3], [0.0, 0.0])
    # a resultant exactly (0, 0) in floating point: cos(a + π) rounds to exactly -cos(a)
    a = 0.12292057180858407
    theta = np.array([a, -a, a + PI, -(a + PI)])
    assert np.sum(np.cos(theta)) == 0.0 and np.sum(np.sin(theta)) == 0.0
    with pytest.raises(ValueError, match="undefined"):
        circular_mean(theta)  # was 0.0, a direction that nothing points to


# ------------------------------------------------------- item 26: read_carmen_log
def _carmen(tmp_path, extra=(), name="log.txt", n=3):
    import gzip

    scans = [
        f"FLASER {n} {' '.join(['1.5'] * (n - 1))} 30 {k} 0 0 {k} 0 0 {k}.0 host {k}.0"
        for k in range(3)
    ]
    text = "\n".join([*extra, *scans]) + "\n"
    path = tmp_path / name
    if name.endswith(".gz"):
        with gzip.open(path, "wt") as fh:
            fh.write(text)
    else:
        path.write_text(text)
    return path


def test_carmen_one_beam_flaser_names_its_line(tmp_path):
    from probrob.datasets import read_carmen_log

    path = tmp_path / "one.log"
    path.write_text("FLASER 1 2.5 0 0 0 0 0 0 1.0 host 1.0\n")
    with pytest.raises(ValueError, match="line 1: FLASER has 1 beam"):  # ZeroDivisionError
        read_carmen_log(path, max_range=30.0)


def test_carmen_truncated_gzip_is_a_valueerror_naming_the_file(tmp_path):
    from probrob.datasets import read_carmen_log

    good = _carmen(tmp_path, name="log.gz", n=181)
    cut = tmp_path / "cut.log.gz"
    cut.write_bytes(good.read_bytes()[:-20])
    with pytest.raises(ValueError, match=r"path: .*cut\.log\.gz.*\(EOFError"):  # a bare EOFError
        read_carmen_log(cut)
    assert read_carmen_log(good).ranges.shape == (3, 181)


@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "ten"])
def test_carmen_laser_offset_must_be_a_finite_number(tmp_path, value):
    from probrob.datasets import read_carmen_log

    path = _carmen(tmp_path, [f"PARAM robot_frontlaser_offset {value}"])
    # nan was read as a NaN offset silently; "ten" raised float()'s bare ValueError
    with pytest.raises(ValueError, match="line 1: PARAM robot_frontlaser_offset must be"):
        read_carmen_log(path)
    ok = _carmen(tmp_path, ["PARAM robot_frontlaser_offset 0.25", "PARAM robot_name pioneer"])
    assert read_carmen_log(ok).laser_offset == 0.25


@pytest.mark.parametrize(
    ("max_range", "error"),
    [
        ([5], ValueError),  # float() TypeError, naming nothing
        (np.array([5.0, 6.0]), ValueError),
        (5 + 0j, TypeError),
        (True, ValueError),  # was read as 1.0
        ("30", ValueError),
        (float("nan"), ValueError),
        (-1.0, ValueError),
    ],
)
def test_carmen_max_range_is_one_positive_real_number(tmp_path, max_range, error):
    from probrob.datasets import read_carmen_log

    with pytest.raises(error, match="max_range"):
        read_carmen_log(_carmen(tmp_path), max_range=max_range)
    for ok in (30, 30.0, np.float64(30.0), np.int64(30), np.array(30.0)):
        assert read_carmen_log(_carmen(tmp_path), max_range=ok).max_range == 30.0


# ------------------------------------------ item 27: overflow and batch shapes named, not NaN
def test_nees_overflow_names_the_argument():
    from probrob.evaluation import nees

    # was NaN (with a RuntimeWarning)
    with pytest.raises(ValueError, match=r"x_true = .* out of range: the error x_true - mu"):
        nees([1e308, 0, 0], [-1e308, 0, 0], np.eye(3))
    with pytest.raises(ValueError, match=r"(?s)Sigma = .* out of range: the NEES overflows"):
        nees([1.0, 0, 0], [0.0, 0, 0], 1e-320 * np.eye(3))
    # headings far apart, or their difference overflowing, are still wrapped exactly
    assert nees([0, 0, 1e308], [0, 0, -1e308], np.eye(3)) == pytest.approx(
        float(wrap_angle(wrap_angle(1e308) - wrap_angle(-1e308))) ** 2
    )


def test_frame_errors_overflow_names_the_argument():
    from probrob.fitting import frame_errors

    with pytest.raises(ValueError, match=r"reference = .* the frame error overflows"):
        frame_errors([1e308, 0, 0], [-1e308, 0, 0])  # was [inf, nan, 0]
    np.testing.assert_allclose(frame_errors([1e300, 0, 0], [1e300, 1, 0]), [0, 1, 0])


@pytest.mark.parametrize(
    ("call", "names"),
    [
        ("nees(np.zeros((2, 3)), np.zeros((3, 3)), np.eye(3))", ["x_true (2,)", "mu (3,)"]),
        ("nees(np.zeros((2, 3)), np.zeros(3), np.tile(np.eye(3), (3, 1, 1)))", ["Sigma (3,)"]),
        ("frame_errors(np.zeros((2, 3)), np.zeros((3, 3)))", ["reference (2,)", "poses (3,)"]),
        ("beam_mixture([1.0, 2.0], [1.0, 2.0, 3.0], PARAMS)", ["z (2,)", "z_star (3,)"]),
        ("beam_model_components([1.0, 2.0], [1.0, 2.0, 3.0], PARAMS)", ["z (2,)", "z_star (3,)"]),
        (
            "learn_intrinsic_parameters([1.0, 2.0], [1.0, 2.0, 3.0], 10.0)",
            ["z (2,)", "z_star (3,)"],
        ),
    ],
)
def test_batch_mismatches_name_the_arguments(call, names):
    from probrob.evaluation import nees
    from probrob.fitting import frame_errors
    from probrob.sensors import (
        BeamModelParams,
        beam_mixture,
        beam_model_components,
        learn_intrinsic_parameters,
    )

    scope = {
        "np": np,
        "nees": nees,
        "frame_errors": frame_errors,
        "beam_mixture": beam_mixture,
        "beam_model_components": beam_model_components,
        "learn_intrinsic_parameters": learn_intrinsic_parameters,
        "PARAMS": BeamModelParams(0.7, 0.1, 0.1, 0.1, 0.2, 0.5, 10.0),
    }
    # was numpy's "operands could not be broadcast together", naming no argument
    with pytest.raises(ValueError, match="batch shapes of the arguments do not broadcast") as e:
        eval(call, scope)
    assert all(n in str(e.value) for n in names), str(e.value)


# ------------------------------------------------------------------ item 28: smaller ones
def _filter(steps, **kw):
    from probrob.localization import run_filter
    from probrob.simulation import grid_landmarks

    m = grid_landmarks(2, 2, 3.0)
    return run_filter(steps, np.zeros(3), 0.01 * np.eye(3), m, [0.01] * 4, [0.1, 0.1, 0.1], **kw)


def _step(**change):
    from probrob.simulation import Step

    fields = dict(t=0.1, dt=0.1, u=np.array([1.0, 0.0]), z=np.zeros((0, 3)), c=np.zeros(0, int))
    return Step(**{**fields, **change})


class _NoT:
    dt, u, z, c = 0.1, np.array([1.0, 0.0]), np.zeros((0, 3)), np.zeros(0, int)


@pytest.mark.parametrize(
    ("steps", "message"),
    [
        ([], "steps is empty"),  # "cannot reshape array of size 0 into shape (0,newaxis)"
        ([_NoT()], r"steps\[0\] must have the attributes t, dt, u, z and c .* without t"),
        ([_step(), _step(t=np.nan)], r"steps\[1\]\.t must be finite"),  # was accepted
        ([_step(u=np.array([1.0, 0.0, 3.0]))], r"steps\[0\]\.u must be \(v, omega\)"),
        ([_step(u=["1", "0"])], r"steps\[0\]\.u must be numeric"),  # was read as (1, 0)
        ([_step(t=[0.1])], r"steps\[0\]\.t must be one number"),  # "setting an array element"
        ([_step(dt=np.array([0.1, 0.2]))], r"steps\[0\]\.dt must be one number"),
        ([_step(z=None)], r"steps\[0\]\.z must be the step's features"),  # TypeError
        ({"a": 1}, "steps must be a sequence of steps"),  # AttributeError on 'str'
        ("abc", "steps must be a sequence of steps"),
    ],
)
def test_run_filter_names_the_bad_step(steps, message):
    with pytest.raises(ValueError, match=message):
        _filter(steps)


def test_run_filter_still_runs_good_steps():
    run = _filter([_step(), _step(t=0.2, u=[1, 0], dt=np.float32(0.1))])
    assert run.mu.shape == (2, 3) and np.all(np.isfinite(run.mu))


@pytest.mark.parametrize("kw", [{"beta": [2.0]}, {"kappa": [0.0]}, {"beta": np.array([2.0])}])
def test_ukf_parameters_must_be_numbers(kw):
    from probrob.localization import ukf_weights

    name = next(iter(kw))
    with pytest.raises(ValueError, match=f"{name} must be a number, got shape"):  # TypeError
        ukf_weights(5, **kw)
    with pytest.raises(ValueError, match=f"{name} must be a number"):
        _filter([_step()], method="ukf", **kw)
    assert ukf_weights(5, **{name: np.float64(1.0)})[0] > 0


def test_chi2_quantile_refuses_a_dof_beyond_float():
    from probrob.evaluation import chi2_quantile

    with pytest.raises(ValueError, match=r"dof must be at most 2\*\*53"):
        chi2_quantile(0.5, 10**400)  # OverflowError: int too large to convert to float
    assert chi2_quantile(0.5, 2**53) == pytest.approx(2.0**53, rel=1e-12)


def test_loop_controls_at_the_smallest_period_and_radius():
    from probrob.simulation import loop_controls

    u = loop_controls(4, 0.5, wiggle=0.1, period=5e-324)  # was NaN: the phase overflowed
    np.testing.assert_array_equal(u[:, 1], 0.5 / 4.0)  # t is a whole number of periods
    with pytest.raises(ValueError, match=r"radius = 5e-324 is out of range"):  # ω = inf
        loop_controls(4, 0.5, radius=5e-324)
    # an ordinary wiggle is unchanged
    t = 0.5 * np.arange(40)
    np.testing.assert_allclose(
        loop_controls(40, 0.5, wiggle=0.2)[:, 1],
        0.5 / 4.0 + 0.2 * np.sin(2 * np.pi * t / 5.0),
        rtol=0,
        atol=1e-15,
    )


def test_simulate_run_keeps_its_own_read_only_arrays():
    from probrob.simulation import grid_landmarks, loop_controls, simulate_run

    controls, m = loop_controls(5, 0.5), grid_landmarks(2, 2, 3.0)
    run = simulate_run(np.zeros(3), controls, 0.5, m, [0.01] * 4, [0.1, 0.05, 0.1], rng=1)
    assert not np.shares_memory(run.commanded, controls)  # were the caller's, writable
    assert not np.shares_memory(run.landmarks, m)
    for name in ("t", "poses", "commanded", "odometry", "landmarks"):
        with pytest.raises(ValueError, match="read-only"):
            getattr(run, name)[0] = 0.0
    controls[0] = 99.0
    assert run.commanded[0, 0] == 0.5


def test_grid_landmarks_peaks_at_its_result():
    import tracemalloc

    from probrob.simulation import grid_landmarks

    tracemalloc.start()
    try:
        m = grid_landmarks(400, 300, (1.0, 2.0), origin=(5.0, -1.0))
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 1.1 * m.nbytes  # was 2.5 times: meshgrid, ravel and two column_stacks
    gx, gy = np.meshgrid(5.0 + np.arange(400), -1.0 + 2.0 * np.arange(300))
    np.testing.assert_array_equal(
        m, np.column_stack([gx.ravel(), gy.ravel(), np.arange(m.shape[0])])
    )
    assert grid_landmarks(2, 1, 1.0, signatures=[7, 8])[:, 2].tolist() == [7.0, 8.0]
