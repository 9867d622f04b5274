"""Regression tests for the bugs the property suite found when the kinematics, sensor, map,
filter, simulation, fitting and dataset modules joined it (tests/test_api_properties.py).

Each test is one call that misbehaved before the fix (the comment says how).
"""

import warnings

import numpy as np
import pytest

from probrob import evaluation, fitting, localization, maps, motion, sensors, simulation

LANDMARKS = np.array([[2.0, 1.0, 0.0], [-1.0, 3.0, 1.0]])


def _raises(exc, names, func, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(exc) as info:
            func(*args, **kwargs)
    assert type(info.value) is exc
    for name in names:
        assert name in str(info.value), (name, str(info.value))


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        (dict(T=-1), "T"),  # was numpy's "negative dimensions are not allowed"
        (dict(T=2.5), "T"),  # was silently truncated to 2
        (dict(v=None), "v"),  # was a TypeError from float()
        (dict(v=np.nan), "v"),  # was a NaN command
        (dict(radius=0.0), "radius"),  # was ZeroDivisionError
        (dict(wiggle=np.inf), "wiggle"),  # was a RuntimeWarning and NaN commands
        (dict(wiggle=0.3, period=0.0), "period"),  # was a RuntimeWarning and NaN
    ],
)
def test_loop_controls_validates_its_arguments(kwargs, name):
    _raises(ValueError, [name], simulation.loop_controls, **{"T": 5, "dt": 1.0, **kwargs})


def test_loop_controls_still_drives_circles_and_straight_lines():
    u = simulation.loop_controls(4, 0.5, v=0.5, radius=2.0)
    np.testing.assert_array_equal(u, np.tile([0.5, 0.25], (4, 1)))
    straight = simulation.loop_controls(4, 0.5, radius=np.inf, wiggle=0.0)
    assert np.all(straight[:, 1] == 0.0)
    assert simulation.loop_controls(0, 1.0, wiggle=0.3).shape == (0, 2)


@pytest.mark.parametrize("rng", ["abc", -1, 1.5, np.random.RandomState(0)])
def test_simulation_rng_is_validated(rng):
    # was numpy's "SeedSequence expects int or sequence of ints" (a TypeError)
    _raises(ValueError, ["rng"], simulation.random_landmarks, 3, (0, 1, 0, 1), rng=rng)
    controls = simulation.loop_controls(3, 0.5)
    _raises(ValueError, ["rng"], simulation.simulate_run, np.zeros(3), controls, 0.5,
            LANDMARKS, [0.01] * 4, (0.1, 0.05, 0.0), rng=rng)  # fmt: skip


def test_landmark_counts_are_not_truncated():
    _raises(ValueError, ["nx"], simulation.grid_landmarks, 2.5, 2, 1.0)  # was 2 columns
    _raises(ValueError, ["ny"], simulation.grid_landmarks, 2, True, 1.0)
    _raises(ValueError, ["n"], simulation.random_landmarks, 2.5, (0, 1, 0, 1))
    _raises(ValueError, ["min_distance"], simulation.random_landmarks, 2, (0, 1, 0, 1),
            min_distance=-1.0)  # fmt: skip


def test_chi2_quantile_names_its_arguments():
    _raises(ValueError, ["p"], evaluation.chi2_quantile, None, 2)  # was a TypeError
    _raises(ValueError, ["p"], evaluation.chi2_quantile, [0.5, 0.9], 2)
    _raises(TypeError, ["p"], evaluation.chi2_quantile, 0.5j, 2)
    _raises(ValueError, ["dof"], evaluation.chi2_quantile, 0.5, True)  # was dof = 1
    assert evaluation.chi2_quantile(0.95, 2) == pytest.approx(5.991464547107979)


def test_covariance_ellipse_checks_mu_and_n():
    S = np.diag([0.1, 0.2, 0.05])
    _raises(ValueError, ["mu"], evaluation.covariance_ellipse, np.zeros((4, 4)), S)
    _raises(ValueError, ["n"], evaluation.covariance_ellipse, np.zeros(3), S, n=2.5)
    _raises(ValueError, ["p"], evaluation.covariance_ellipse, np.zeros(3), S, p=None)
    assert evaluation.covariance_ellipse(np.zeros(2), S[:2, :2], n=8).shape == (9, 2)


def test_ukf_weights_n_is_an_integer():
    _raises(ValueError, ["n"], localization.ukf_weights, 2.5)  # was 2n + 1 = 6 weights
    _raises(ValueError, ["n"], localization.ukf_weights, True)


def test_run_filter_names_its_own_arguments():
    sim = simulation.simulate_run(np.zeros(3), simulation.loop_controls(3, 0.5), 0.5,
                                  LANDMARKS, [0.01] * 4, (0.1, 0.05, 0.0), rng=0)  # fmt: skip
    args = (np.eye(3) * 0.01, LANDMARKS, [0.01] * 4, (0.1, 0.05, 0.1))
    # the start pose was reported as "mu"
    with pytest.raises(ValueError, match=r"^mu0 "):
        localization.run_filter(sim.steps, [np.nan, 0, 0], *args)
    _raises(ValueError, ["steps"], localization.run_filter, None, np.zeros(3), *args)
    _raises(
        ValueError,
        ["signatures"],
        localization.run_filter,
        sim.steps,
        np.zeros(3),
        *args,
        signatures="no",
    )  # fmt: skip  (was truthy: signatures used)


def test_step_lengths_of_the_wrong_length_are_named():
    u = np.array([[1.0, 0.1], [1.0, 0.0]])
    # was numpy's "operands could not be broadcast together with remapped shapes"
    _raises(ValueError, ["dt"], localization.ekf_predict_segment, np.zeros(3), np.eye(3), u,
            [1.0, 1.0, 1.0], [0.01] * 4)  # fmt: skip
    poses = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.1], [2.0, 0.1, 0.1]])
    _raises(ValueError, ["dt"], fitting.fit_motion_noise, u, [1.0] * 3, poses, window=1.0)


@pytest.mark.parametrize(
    "func", [sensors.beam_mixture, sensors.beam_model_components]
)  # fmt: skip
def test_beam_models_check_the_log_flag(func):
    params = sensors.BeamModelParams(0.7, 0.1, 0.1, 0.1, 0.2, 0.5, 6.0)
    _raises(ValueError, ["log"], func, 2.0, 3.0, params, log="no")  # was truthy: log output


def test_beam_range_finder_model_names_x():
    occ = np.zeros((4, 4), dtype=bool)
    occ[0] = True
    grid = maps.OccupancyGrid(occ, 1.0)
    params = sensors.BeamModelParams(0.7, 0.1, 0.1, 0.1, 0.2, 0.5, 6.0)
    # was "poses must be finite": the name of ray_cast's argument
    with pytest.raises(ValueError, match=r"^x "):
        sensors.beam_range_finder_model([2.0], [np.nan, 2, 0], grid, [0.0], params)
    _raises(ValueError, ["log"], sensors.beam_range_finder_model, [2.0], [2, 2, 0], grid,
            [0.0], params, log=1)  # fmt: skip


def test_log_beam_mixture_with_a_zero_weight_does_not_warn():
    # z = z* = 0 with only the max-range component: p_short's log is +inf there and its
    # weight's log -inf; the sum warned "invalid value encountered in add"
    params = sensors.BeamModelParams(0.0, 0.0, 1.0, 0.0, 1e-3, 10.0, 6.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert sensors.beam_mixture(0.0, 0.0, params, log=True) == -np.inf
        assert sensors.beam_mixture(0.0, 0.0, params) == 0.0


def test_filter_and_fit_errors_name_the_callers_arguments():
    # an S that double precision cannot form was reported against "S" only (Table 7.3)
    sim = simulation.simulate_run(np.zeros(3), simulation.loop_controls(8, 0.5), 0.5,
                                  LANDMARKS, [0.01] * 4, (0.1, 0.05, 0.0), rng=3)  # fmt: skip
    with pytest.raises(ValueError, match=r"^S \(the innovation covariance, from Sigma and sig"):
        localization.run_filter(sim.steps, np.zeros(3), 1e4 * np.eye(3), LANDMARKS, [0.0] * 4,
                                (1e-3,) * 3, method="ekf_ml")  # fmt: skip
    x_prev = np.zeros((3, 3))
    u = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.2]])
    x_t = motion.velocity_motion(x_prev, u, 1.0) + 0.01
    # a zero command's point mass: the message named no argument
    with pytest.raises(ValueError, match=r"^x_t, u_t, x_prev: 1 of 3 pose pairs"):
        fitting.fit_velocity_alpha(x_t, u, x_prev, 1.0)


def test_range_finder_batches_that_do_not_broadcast_are_named():
    occ = np.zeros((4, 4), dtype=bool)
    occ[0] = True
    grid = maps.OccupancyGrid(occ, 1.0)
    params = sensors.BeamModelParams(0.7, 0.1, 0.1, 0.1, 0.2, 0.5, 6.0)
    z, x = np.ones((5, 1)), np.tile([2.0, 2.0, 0.0], (3, 1))
    # was numpy's "operands could not be broadcast together with shapes (5,1) (3,1)"
    for model in (sensors.beam_range_finder_model, sensors.likelihood_field_range_finder_model):
        _raises(ValueError, ["z (5,)", "x (3,)"], model, z, x, grid, [0.0], params)


@pytest.mark.parametrize("method", ["hybrid", "dda", "march"])
def test_ray_cast_with_a_subnormal_heading(method):
    # θ = 2.2e-313: sin θ is subnormal and 1/sin θ overflowed (a RuntimeWarning); found by
    # the thorough profile through beam_range_finder_model at a pose on the map's corner
    occ = np.zeros((4, 6), dtype=bool)
    occ[:, -1] = True
    grid = maps.OccupancyGrid(occ, 0.5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        z = maps.ray_cast(grid, [0.0, 0.0, 2.22507386e-313], [0.0, np.pi / 2], 6.0, method=method)
        z_axis = maps.ray_cast(grid, [0.0, 0.0, 0.0], [0.0, np.pi / 2], 6.0, method=method)
    np.testing.assert_allclose(z, z_axis, atol=1e-12)


def test_beam_mixture_with_a_subnormal_expected_range():
    # z* = 5e-324: the short component's 1/(1 - exp(-λ z*)) divided by zero (a RuntimeWarning)
    params = sensors.BeamModelParams(0.7, 0.1, 0.1, 0.1, 0.2, 0.5, 6.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert sensors.beam_mixture(0.0, 5e-324, params) == np.inf  # as at z* = 0
        assert np.isfinite(sensors.beam_mixture(1.0, 5e-324, params))
