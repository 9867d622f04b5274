"""Regression tests for issue 15 ("ray_cast must never hang, and the last silent wrong answers go").

Each test failed (or hung) before its fix. Items 2, 4, 5, 8 and the filters' ``log`` flags
(item 6) live in ``probrob.localization`` and are tested with it.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from probrob import maps, sensors

PI = np.pi


# ------------------------------------------------------------- item 1: ray_cast hangs
# Beams along the axes, and a hair off them: cos(π/2) = 6e-17 is the direction's x
# component of a beam "straight up", so a pose on a grid line runs along it.
AXIS_ANGLES = [0.0, PI / 2, -PI / 2, PI, -PI, 1e-17, -1e-17, PI / 2 + 1e-16, np.nextafter(PI, 0)]
STRIPES = np.arange(100).reshape(10, 10) % 10 == 0  # column 0 occupied: the issue's map


@pytest.mark.parametrize("method", ["hybrid", "dda", "march"])
def test_the_issue_example_returns(method, time_limit):
    # hung for ever with the default method; "dda" returned 4.0
    grid = maps.OccupancyGrid(STRIPES, 1.0)
    with time_limit(20):
        z = maps.ray_cast(grid, [5.0, 5.0, 0.0], [-PI], 4.0, method=method)
    assert z[0] == 4.0


def test_the_beam_model_on_the_issue_example_returns(time_limit):
    grid = maps.OccupancyGrid(STRIPES, 1.0)
    params = sensors.BeamModelParams(0.7, 0.1, 0.1, 0.1, 0.2, 0.5, 4.0)
    with time_limit(20):
        q = sensors.beam_range_finder_model([4.0], [5.0, 5.0, 0.0], grid, [-PI], params, log=True)
    q_dda = sensors.beam_range_finder_model(
        [4.0], [5.0, 5.0, 0.0], grid, [-PI], params, log=True, method="dda"
    )
    assert q == q_dda


def test_a_pose_a_few_ulps_off_a_grid_line_follows_the_plain_traversal():
    # x = 4.35 on a grid with origin 0.35 is 3.9999999999999996 cells: just left of the line
    # x = 4, which the beam (θ = π/2 + 1e-17) crosses only after 8.7 cells. The hybrid
    # traversal floored a jump's landing point onto the line and ran up the next column:
    # 11.5 m (the obstacle at row 17) instead of 8.5 m (row 14).
    occ = np.zeros((20, 10), dtype=bool)
    occ[14, 3] = occ[17, 4] = True
    grid = maps.OccupancyGrid(occ, 1.0, (0.35, 0.35))
    for method in ("dda", "hybrid"):
        assert maps.ray_cast(grid, [4.35, 5.85, PI / 2], [1e-17], 30.0, method=method)[0] == 8.5


def test_a_heading_of_1e_307_on_a_large_grid_leaks_no_overflow():
    # sin(1e-307) = 1e-307: the hybrid traversal's row * (1 / dy) overflowed (a RuntimeWarning)
    occ = np.zeros((400, 400), dtype=bool)
    occ[:, -1] = occ[-1, :] = True
    grid = maps.OccupancyGrid(occ, 0.05)
    poses = [[0.0, 0.0, 1e-307], [0.0, 0.0, -1e-307], [0.0, 19.5, 1e-306]]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        z = {m: maps.ray_cast(grid, poses, [0.0, PI / 2], 30.0, method=m) for m in maps._METHODS}
    np.testing.assert_array_equal(z["hybrid"], z["dda"])
    # θ = -1e-307 from the corner: the ray runs just below the map's edge, leaving it at once
    assert z["dda"][1, 0] == 30.0 and z["dda"][0, 0] == pytest.approx(19.95)


@st.composite
def grid_aligned_case(draw):
    """A random grid and poses on its grid lines and corners (and cell centres), θ and beams
    along the axes or a hair off them."""
    h, w = draw(st.integers(1, 12)), draw(st.integers(1, 12))
    density = draw(st.sampled_from([0.0, 0.1, 0.3, 0.6]))
    seed = draw(st.integers(0, 2**32 - 1))
    occ = np.random.default_rng(seed).random((h, w)) < density
    res = draw(st.sampled_from([1.0, 0.5, 0.25, 0.1, 0.05, 0.3]))
    origin = draw(st.sampled_from([0.0, -1.0, 0.35, -7.3]))
    half_cells = st.tuples(st.integers(0, 2 * w - 1), st.integers(0, 2 * h - 1))
    cells = draw(st.lists(half_cells, min_size=1, max_size=8))
    xy = origin + np.array(cells, dtype=float) * 0.5 * res
    theta = draw(st.lists(st.sampled_from(AXIS_ANGLES), min_size=len(cells), max_size=len(cells)))
    beams = draw(st.lists(st.sampled_from(AXIS_ANGLES), min_size=1, max_size=6))
    max_range = draw(st.sampled_from([0.5, 3.0, 100.0]))
    return maps.OccupancyGrid(occ, res, (origin, origin)), np.c_[xy, theta], beams, max_range


@settings(max_examples=300, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(case=grid_aligned_case())
def test_hybrid_equals_dda_on_grid_lines_and_corners(case, time_limit):
    grid, poses, beams, max_range = case
    inside = grid.contains(poses[:, :2])
    poses = poses[inside]
    if not poses.size:
        return
    t_max = max_range / grid.resolution
    bounds = maps._step_bounds(grid.shape, t_max)
    with time_limit(20):
        z_dda, steps_dda = maps._cast(grid, poses, np.array(beams), max_range, "dda")
        z_hyb, steps_hyb = maps._cast(grid, poses, np.array(beams), max_range, "hybrid")
        _, steps_march = maps._cast(grid, poses, np.array(beams), max_range, "march")
    np.testing.assert_allclose(z_hyb, z_dda, rtol=0, atol=1e-9)
    for steps in (steps_dda, steps_hyb, steps_march):
        for stage, n in steps.items():
            assert n <= bounds[stage], (stage, n, bounds[stage])
    # the beam model on top of each method: the same likelihoods
    params = sensors.BeamModelParams(0.7, 0.1, 0.1, 0.1, 0.2, 0.5, max_range)
    z = np.full((len(poses), len(beams)), 0.4 * max_range)
    with time_limit(20):
        q = {
            m: sensors.beam_range_finder_model(z, poses, grid, beams, params, log=True, method=m)
            for m in ("hybrid", "dda")
        }
    np.testing.assert_allclose(q["hybrid"], q["dda"], rtol=1e-12)


@pytest.mark.parametrize(
    "method, stage", [("dda", "dda"), ("hybrid", "hybrid"), ("march", "march")]
)
def test_a_traversal_past_its_step_bound_raises_instead_of_looping(method, stage, monkeypatch):
    # The bounds are the proof of termination: with a bound too small for the map, the loop
    # stops with RuntimeError rather than running on.
    occ = np.zeros((10, 40), dtype=bool)
    occ[6, :] = True  # a wall along the beam: no jump is long enough, every cell is a step
    grid = maps.OccupancyGrid(occ, 1.0)
    real = maps._step_bounds

    def tiny(shape, t_max):
        bounds = real(shape, t_max)
        bounds[stage] = 2
        return bounds

    monkeypatch.setattr(maps, "_step_bounds", tiny)
    with pytest.raises(RuntimeError, match=f"{stage}.*bound of 2 steps"):
        maps.ray_cast(grid, [0.5, 5.5, 0.0], [0.0], 39.0, method=method)


# ------------------------------------------------- item 3: a falsy check result is "not yet"
@pytest.mark.parametrize(
    "result",
    [0, 0.0, np.array([False]), np.False_, np.array([True, False]), np.array([], bool), 1],
    ids=["0", "0.0", "array-False", "numpy-False", "array-mixed", "empty-array", "1"],
)
def test_verdict_calls_a_falsy_or_odd_test_result_not_yet(result):
    from probrob.exercises import verdict

    line = verdict("E", 3.0, test=lambda a: result)
    assert line.startswith("E: not yet — "), line


def test_verdict_of_the_issue_example():
    from probrob.exercises import verdict

    assert verdict("E", 3.0, test=lambda a: np.isclose(a, 4.0)).startswith("E: not yet")
    assert verdict("E", 4.0, test=lambda a: np.isclose(a, 4.0)) == "E: correct"
    assert verdict("E", [4.0, 4.0], test=lambda a: np.isclose(a, 4.0)) == "E: correct"


@pytest.mark.parametrize("answer", ["4", np.array([4.0 + 1j]), True])
def test_verdict_compares_numbers_only(answer):
    # "4" was read as 4.0 and np.array([4+1j]) lost its imaginary part (a ComplexWarning):
    # both were "correct"
    from probrob.exercises import verdict

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        line = verdict("E", answer, 4.0 if answer is not True else 1.0)
    # issue 23, item 4: the message says what the answer is (a string, a complex, a bool)
    what = {str: "a string", np.ndarray: "a complex number", bool: "a bool"}[type(answer)]
    assert line.startswith(f"E: not yet — expected a {'real ' * (what[2:] == 'complex number')}")
    assert f"got {what}" in line, line


# ----------------------------------------------------------- item 7: OccupancyGrid.from_scans
def test_from_scans_with_every_reading_at_max_range_is_all_free():
    # was numpy's "zero-size array to reduction operation maximum which has no identity"
    poses = [[0.0, 0.0, 0.0], [1.0, 0.5, 1.0]]
    grid = maps.OccupancyGrid.from_scans(
        poses, np.full((2, 3), 8.0), [-0.5, 0.0, 0.5], 0.1, max_range=8.0
    )
    assert not grid.occupied.any()
    assert grid.contains(np.array(poses)[:, :2]).all()


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"margin": -1.0}, "margin"),
        ({"margin": np.nan}, "margin"),
        ({"margin": [1.0, 2.0]}, "margin"),
        ({"margin": "1"}, "margin"),
        ({"p_free": [0.1, 0.2]}, "p_free"),
        ({"p_occupied": [0.7, 0.8]}, "p_occupied"),
    ],
)
def test_from_scans_checks_margin_and_the_inverse_sensor_model(kwargs, name):
    # margin was not checked at all; an array p_free raised numpy's "truth value of an array"
    with pytest.raises(ValueError, match=name):
        maps.OccupancyGrid.from_scans(
            [[0.0, 0.0, 0.0]], [[1.0, 2.0]], [0.0, 0.5], 0.1, max_range=8.0, **kwargs
        )


def test_from_scans_counts_in_small_integers():
    # A 200 m x 200 m extent at 5 cm is 16 million cells: the counts were int64 (and their
    # log-odds float64), 32 bytes per cell, so 700 m x 700 m needed 4.5 GB; now one byte per
    # count (two scans of one beam) and the boolean grids: 6 bytes.
    import tracemalloc

    tracemalloc.start()
    try:
        grid = maps.OccupancyGrid.from_scans(
            [[0.0, 0.0, 0.0], [200.0, 200.0, 0.0]], [[1.0], [1.0]], [0.0], 0.05, max_range=10.0
        )
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert grid.occupied.size > 1.6e7
    assert peak < 7 * grid.occupied.size, peak / grid.occupied.size


def test_from_scans_too_large_says_what_it_needs():
    # 100 km x 100 km at 5 cm: 4e12 cells; was numpy's bare MemoryError from bincount
    with pytest.raises(MemoryError, match=r"2e\+06 x 2e\+06 cells at resolution 0.05 m.*GiB"):
        maps.OccupancyGrid.from_scans(
            [[0.0, 0.0, 0.0], [1e5, 1e5, 0.0]], [[1.0], [1.0]], [0.0], 0.05, max_range=10.0
        )


def test_from_scans_with_end_points_beyond_float64_names_its_arguments():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match="overflows float64"):
            maps.OccupancyGrid.from_scans(
                [[1e308, 0.0, 0.0]], [[1e308]], [0.0], 0.05, max_range=1.7e308
            )


# -------------------------------------------- item 9: what a user's callable returns is checked
X_PREV = np.zeros((4, 3))
X_T = np.tile([0.1, 0.0, 0.0], (4, 1))
ALPHA6 = [0.1] * 6


def seven_values(a, b2):
    return np.ones(7)


def nan_sampler(b2, size=None, rng=None):
    return np.full(size, np.nan)


def test_a_prob_of_the_wrong_shape_is_an_error_naming_it():
    # returned shape (7,) on 4 hypotheses
    from probrob import motion

    with pytest.raises(ValueError, match=r"prob \(seven_values\) returned shape \(7,\)"):
        motion.motion_model_velocity(X_T, [1.0, 0.0], X_PREV, 0.1, ALPHA6, prob=seven_values)
    with pytest.raises(ValueError, match=r"prob \(seven_values\) returned shape \(7,\)"):
        motion.motion_model_odometry(
            X_T, [[0, 0, 0], [0.1, 0, 0]], X_PREV, [0.1] * 4, prob=seven_values
        )


@pytest.mark.parametrize("model", ["velocity", "odometry", "landmark"])
def test_a_sampler_returning_nan_is_named_not_alpha(model):
    # the NaN reached the overflow check, which blamed the most extreme argument, α
    from probrob import motion

    with pytest.raises(ValueError, match=r"sample \(nan_sampler\) returned nan") as info:
        if model == "velocity":
            motion.sample_motion_model_velocity(
                [1.0, 0.0], X_PREV, 0.1, ALPHA6, sample=nan_sampler
            )
        elif model == "odometry":
            motion.sample_motion_model_odometry(
                [[0, 0, 0], [1, 0, 0]], X_PREV, [0.1] * 4, sample=nan_sampler
            )
        else:
            sensors.sample_landmark_model_known_correspondence(
                [1.0, 0.2, 0.0], 0, [[2.0, 1.0, 0.0]], [0.1, 0.1, 0.1], sample=nan_sampler, size=3
            )
    assert "alpha" not in str(info.value)


def test_plot_distribution_checks_what_prob_returns():
    import matplotlib.pyplot as plt

    from probrob import plotting

    try:
        with pytest.raises(ValueError, match=r"prob \(seven_values\) returned shape \(7,\)"):
            plotting.plot_distribution(seven_values, 1.0)
    finally:
        plt.close("all")


# ------------------------------------- item 10: simulate_run, random_landmarks use the checks
def _simulate(**kwargs):
    from probrob import simulation

    m = simulation.grid_landmarks(2, 2, 3.0)
    controls = simulation.loop_controls(5, 0.1)
    return simulation.simulate_run(
        [0, 0, 0], controls, 0.1, m, [0.01] * 4, [0.1, 0.01, 0.0], rng=0, **kwargs
    )


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"max_range": [1.0, 2.0]}, "max_range"),  # was float()'s TypeError
        ({"max_range": "a"}, "max_range"),  # was "could not convert string to float"
        ({"max_range": None}, "max_range"),
        ({"fov": [1.0, 2.0]}, "fov"),
        ({"fov": None}, "fov"),
    ],
)
def test_simulate_run_checks_max_range_and_fov(kwargs, name):
    with pytest.raises(ValueError, match=name):
        _simulate(**kwargs)


def test_simulate_run_still_takes_an_infinite_max_range():
    # not a regression test: the guard that the checks above keep max_range = inf legal
    assert _simulate(max_range=np.inf).steps[0].z.shape == (4, 3)
    with pytest.raises(ValueError, match="max_range"):
        _simulate(max_range=np.nan)


def test_random_landmarks_checks_min_distance():
    # float() of an array raised "only length-1 arrays can be converted" (a TypeError)
    from probrob import simulation

    with pytest.raises(ValueError, match="min_distance"):
        simulation.random_landmarks(3, (0, 10, 0, 10), min_distance=[1.0, 2.0], rng=0)


def test_the_simulator_and_the_plots_share_one_exact_normal_sampler():
    from probrob import distributions, plotting, simulation

    assert plotting.DISTRIBUTIONS["normal (exact)"][1] is distributions._sample_exact_normal
    assert simulation._sample_exact_normal is distributions._sample_exact_normal


# ----------------------------------------- item 6 (outside localization): bool flags checked
def _plotting_call(name, value):
    from probrob import plotting

    pose_a, pose_b = [0.0, 0.0, 0.0], [1.0, 0.5, 0.3]
    if name == "hat":
        return plotting.plot_odometry_deltas(pose_a, pose_b, hat=value)
    if name == "colorbar":
        return plotting.plot_density_xy([0.0, 1.0], [0.0, 1.0], np.ones((2, 2)), colorbar=value)
    if name == "orientation":
        return plotting.plot_density_xy(
            [0.0, 1.0], [0.0, 1.0], np.ones((2, 2)), colorbar=True, orientation=value
        )
    if name in ("show_density", "motion colorbar"):
        key = "show_density" if name == "show_density" else "colorbar"
        return plotting.plot_motion_model(
            "velocity", [1.0, 0.5], pose_a, [0.1] * 6, n_samples=10, grid=4, **{key: value}
        )
    if name == "arrow odometry":
        return plotting.plot_odometry_deltas(pose_a, pose_b, arrow=value)
    if name == "arrow velocity":
        return plotting.plot_velocity_geometry(pose_a, pose_b, 1.0, arrow=value)
    raise AssertionError(name)


@pytest.mark.parametrize(
    "name, value, match",
    [
        ("hat", "False", "hat"),  # the string "False" is truthy: it drew the hat labels
        ("colorbar", "no", "colorbar"),
        ("show_density", "False", "show_density"),
        ("motion colorbar", "sideways", "colorbar"),
        ("arrow odometry", [1.0, 2.0], "arrow"),  # float() of an array: a TypeError
        ("arrow velocity", -1.0, "arrow"),  # a negative arrow was drawn backwards
    ],
)
def test_plot_flags_and_arrows_are_checked(name, value, match):
    import matplotlib.pyplot as plt

    before = plt.get_fignums()
    try:
        with pytest.raises(ValueError, match=match):
            _plotting_call(name, value)
        if name.startswith("arrow") or name == "hat":
            assert plt.get_fignums() == before  # the check comes before the figure
    finally:
        plt.close("all")


def test_parameter_player_and_em_check_their_flags():
    from probrob import widgets

    with pytest.raises(ValueError, match="fixed_axes"):
        widgets.parameter_player(lambda ax, v: None, [1.0, 2.0], label="v", fixed_axes="no")
    with pytest.raises(ValueError, match="full_output"):
        sensors.learn_intrinsic_parameters([1.0, 2.0], [1.0, 2.0], 5.0, full_output="yes")


def test_live_widget_constants_must_be_numbers():
    from probrob import live

    with pytest.raises(ValueError, match=r"constants\['zmax'\] must be a number"):
        live.live_widget(
            "beam",
            [live.Slider("a", "a", 0.1, 0.0, 1.0, 0.1)],
            title="t",
            caption="c",
            aria_label="l",
            constants={"zmax": [1, 2]},
        )


# ------------------------------------------------------------------ the sweep: leaked warnings
def test_em_on_short_readings_all_at_zero_leaks_no_overflow():
    # The MLE of λ_short is infinite there: the bracket search of _fit_lambda doubled log λ
    # until exp overflowed (355 steps, "overflow encountered in expm1"); now it stops at the
    # documented bound 1e9 / z_max.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        p = sensors.learn_intrinsic_parameters(np.zeros(200), np.full(200, 5.0), 10.0)
    assert p.lambda_short == pytest.approx(1e9 / 10.0)
    assert p.z_short == pytest.approx(1.0)


@pytest.mark.parametrize("z", [[0.0], [0.0, 1e-300]])
def test_em_on_a_reading_at_z_equal_z_star_equal_0(z):
    # z = z* = 0 is p_short's point mass (+inf): its responsibilities were 0/0 ("invalid value
    # encountered in divide") and, with a weight gone to 0, log 0 + inf = NaN
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        p, info = sensors.learn_intrinsic_parameters(z, 0.0, 10.0, max_iter=5, full_output=True)
    assert info.responsibilities[0].tolist() == [0.0, 1.0, 0.0, 0.0]
    assert np.isfinite(p.weights).all()


def test_marching_an_empty_map_to_a_huge_range_leaks_no_warning():
    # t jumped to max_range / resolution = 1e300 cells; its cell index overflowed int64
    grid = maps.OccupancyGrid(np.zeros((3, 4), dtype=bool), 1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        z = maps.ray_cast(grid, [1.5, 1.5, 0.3], [0.0, 1.0], 1e300, method="march")
    np.testing.assert_array_equal(z, [1e300, 1e300])


# ------------------------------------- the sweep: messages that named the wrong thing
def test_the_beam_model_names_x_for_a_pose_off_the_map():
    # the check ran inside ray_cast, whose argument is "poses": "poses: 1 pose(s) lie outside"
    grid = maps.OccupancyGrid(np.zeros((4, 4), dtype=bool), 1.0)
    params = sensors.BeamModelParams(0.7, 0.1, 0.1, 0.1, 0.2, 0.5, 6.0)
    with pytest.raises(
        ValueError, match=r"^x: 1 pose\(s\) lie outside the map \(extent \(0.0, 4.0"
    ):
        sensors.beam_range_finder_model([1.0], [9.0, 1.0, 0.0], grid, [0.0], params)


def test_messages_show_numbers_not_numpy_reprs():
    # numpy 2 scalars printed as "np.float64(-1.0)" in the messages
    from probrob import distributions, widgets

    with pytest.raises(ValueError, match=r"got min -1\.0$"):
        distributions.sample_normal_distribution(np.array([1.0, -1.0]))
    with pytest.raises(ValueError, match=r"got min -1\.0$"):
        sensors.beam_mixture(
            np.array([-1.0]), 1.0, sensors.BeamModelParams(0.7, 0.1, 0.1, 0.1, 0.2, 0.5, 6.0)
        )
    with pytest.raises(ValueError, match=r"got 0\.6$"):
        widgets.velocity_model_explorer(alpha=np.array([0.6, 0.1, 0.1, 0.1, 0.1, 0.1]))


def test_grid_landmarks_spacing_of_the_wrong_shape_names_it():
    # was numpy's "operands could not be broadcast together with remapped shapes"
    from probrob import simulation

    with pytest.raises(ValueError, match="spacing must be one value or"):
        simulation.grid_landmarks(2, 2, [1.0, 2.0, 3.0])


# ------------------------- the sweep: an approximation whose error its docstring understated
def test_sinc_derivative_is_as_accurate_as_its_docstring_says():
    # The docstring said the closed form "loses at most two digits" at |h| >= 0.1: it loses
    # 2.5 (3.9e-14 relative at h = 0.1); it now says so. Checked against the exact series in
    # rational arithmetic.
    from fractions import Fraction
    from math import factorial

    from probrob.motion import _sinc_derivative

    def exact(h):
        big_h = Fraction(h)
        return sum(
            (-1) ** k * Fraction(2 * k, factorial(2 * k + 1)) * big_h ** (2 * k - 1)
            for k in range(1, 16)
        )

    worst_series = worst_closed = 0.0
    for h in np.linspace(1e-6, 0.3, 601):
        h = float(h)
        err = abs(float((Fraction(float(_sinc_derivative(h))) - exact(h)) / exact(h)))
        if h < 0.1:
            worst_series = max(worst_series, err)
        else:
            worst_closed = max(worst_closed, err)
    assert worst_series < 1e-15
    doc = " ".join(_sinc_derivative.__doc__.split())
    assert "costs at most 2.5 digits" in doc and r"below :math:`5 \cdot 10^{-14}`" in doc
    assert 1e-14 < worst_closed < 5e-14  # more than two digits lost, less than 2.5
