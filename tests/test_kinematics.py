"""Wheel kinematics (deck 002) and the CIR state function (deck 003): probrob.kinematics."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from probrob.kinematics import (
    arc_update,
    cir_pose_matrix,
    cir_radius_angle,
    cir_state_function,
    cir_state_jacobians,
    cir_step_transform,
    dead_reckon,
    diff_drive_odometry,
    tricycle_odometry,
)
from probrob.motion import velocity_motion

FLIP = np.array([1.0, 1.0, -1.0])  # report's clockwise heading <-> counter-clockwise heading
angles = st.floats(-np.pi, np.pi)
lengths = st.floats(-2.0, 2.0)


def rot(a):
    """The usual counter-clockwise rotation matrix R(a)."""
    return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])


# --------------------------------------------------------------------------- deck 002


def deck_exterior_kinematics(x_prev, ds, dtheta):
    """Deck 002, 'Dış Kinematik' typed literally: centre C, R = ΔS/Δθ, rotate about C."""
    x, y, th = x_prev
    with np.errstate(divide="ignore", invalid="ignore"):
        radius = np.float64(ds) / dtheta
        a = th - np.pi / 2
        cx, cy = x - radius * np.cos(a), y - radius * np.sin(a)
        return np.array(
            [cx + radius * np.cos(a + dtheta), cy + radius * np.sin(a + dtheta), th + dtheta]
        )


def deck_radius(ds_left, ds_right, d):
    """Deck 002: R = d (ΔS_R + ΔS_L) / (2 (ΔS_R − ΔS_L)), typed literally."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.float64(d) * (ds_right + ds_left) / (2.0 * (np.float64(ds_right) - ds_left))


@given(st.floats(-5.0, 5.0), st.floats(-3.0, 3.0).filter(lambda t: abs(t) > 1e-3))
def test_diff_drive_recovers_radius_and_turn_from_the_wheel_arcs(radius, dtheta):
    d = 0.35
    left, right = (radius - d / 2) * dtheta, (radius + d / 2) * dtheta  # deck's first lines
    ds, dth, r = diff_drive_odometry(left, right, d)
    np.testing.assert_allclose([ds, dth], [radius * dtheta, dtheta], rtol=1e-12, atol=1e-12)
    assert r == pytest.approx(radius, rel=1e-9, abs=1e-9)
    assert r == pytest.approx(deck_radius(left, right, d), rel=1e-9, abs=1e-9)


def test_diff_drive_straight_line_rest_and_rotation_in_place():
    assert diff_drive_odometry(0.4, 0.4, 0.5) == (0.4, 0.0, np.inf)
    assert diff_drive_odometry(-0.4, -0.4, 0.5) == (-0.4, 0.0, -np.inf)
    assert diff_drive_odometry(0.0, 0.0, 0.5) == (0.0, 0.0, np.inf)  # at rest: no turn
    assert diff_drive_odometry(-0.1, 0.1, 0.5) == (0.0, 0.4, 0.0)  # spin about the middle
    # The deck's formula divides by zero: NaN at rest, where the library gives +inf.
    assert np.isnan(deck_radius(0.0, 0.0, 0.5))
    # A turn too small to represent a finite radius overflows to the right infinity.
    assert diff_drive_odometry(1.0, 1.0 + 1e-300, 1e300) == (1.0, 0.0, np.inf)


def test_diff_drive_mirror_swaps_the_sign_of_the_turn():
    rng = np.random.default_rng(0)
    left, right = rng.uniform(-1, 1, (2, 50))
    a = np.array(diff_drive_odometry(left, right, 0.4))
    b = np.array(diff_drive_odometry(right, left, 0.4))
    np.testing.assert_allclose(b, a * np.array([1, -1, -1])[:, None], rtol=1e-14)


def test_diff_drive_arc_moves_each_wheel_by_its_own_arc_length():
    """Move the body with arc_update; each wheel's end point is where its own arc ends."""
    d, x0 = 0.5, np.array([0.3, -0.7, 2.5])
    for left, right in [(0.6, 1.0), (1.0, 0.6), (-0.3, 0.4), (0.2, 0.2)]:
        ds, dth, _ = diff_drive_odometry(left, right, d)
        x1 = arc_update(x0, ds, dth)
        for offset, arc in [(d / 2, left), (-d / 2, right)]:  # left wheel at +d/2 (y left)
            side = np.array([-np.sin(x0[2]), np.cos(x0[2])])
            start = x0[:2] + offset * side
            end = x1[:2] + offset * np.array([-np.sin(x1[2]), np.cos(x1[2])])
            # the wheel runs its own arc: the same exact arc update from the wheel's pose
            expected = arc_update([*start, x0[2]], arc, dth)
            np.testing.assert_allclose(end, expected[:2], atol=1e-12)


def test_tricycle_limits():
    assert tricycle_odometry(0.7, 0.0, 1.2) == (0.7, 0.0)
    ds, dth = tricycle_odometry(0.6, np.pi / 2, 1.2)
    assert abs(ds) < 1e-16 and dth == pytest.approx(0.5)
    ds, dth = tricycle_odometry(0.6, -np.pi / 2, 1.2)
    assert dth == pytest.approx(-0.5)


@given(st.floats(-1.4, 1.4).filter(lambda a: abs(a) > 1e-3), st.floats(0.01, 2.0))
def test_tricycle_front_wheel_moves_along_its_steering_direction(steer, travel):
    """The steered wheel ahead of the body travels exactly ΔF, starting along θ + α."""
    d, x0 = 0.9, np.array([1.0, 2.0, 0.4])
    ds, dth = tricycle_odometry(travel, steer, d)
    front = x0[:2] + d * np.array([np.cos(x0[2]), np.sin(x0[2])])
    x1 = arc_update(x0, ds, dth)
    front1 = x1[:2] + d * np.array([np.cos(x1[2]), np.sin(x1[2])])
    # the front wheel's own arc: from its pose (heading θ + α), length ΔF, same turn
    expected = arc_update([*front, x0[2] + steer], travel, dth)
    np.testing.assert_allclose(front1, expected[:2], atol=1e-12)
    # and the centre of rotation is on the rear axle, R = d / tan α from its middle
    assert ds / dth == pytest.approx(d / np.tan(steer), rel=1e-9)


def test_tricycle_equals_a_diff_drive_with_the_same_rear_axle():
    """The rear wheels (track w) of a tricycle roll like a differential drive's."""
    d, w = 1.1, 0.6
    steer = np.array([-1.2, -0.4, 0.3, 0.9])
    travel = np.array([0.5, 1.0, -0.7, 0.2])
    ds, dth = tricycle_odometry(travel, steer, d)
    radius = d / np.tan(steer)
    left, right = (radius - w / 2) * dth, (radius + w / 2) * dth
    ds2, dth2, r2 = diff_drive_odometry(left, right, w)
    np.testing.assert_allclose(ds2, ds, rtol=1e-12)
    np.testing.assert_allclose(dth2, dth, rtol=1e-12)
    np.testing.assert_allclose(r2, radius, rtol=1e-12)


def test_arc_update_is_the_decks_rotation_about_the_centre_and_velocity_motion():
    rng = np.random.default_rng(1)
    x0 = rng.uniform([-2, -2, -np.pi], [2, 2, np.pi], (200, 3))
    ds = rng.uniform(-2, 2, 200)
    dth = rng.uniform(-3, 3, 200)
    out = arc_update(x0, ds, dth)
    deck = np.array([deck_exterior_kinematics(*a) for a in zip(x0, ds, dth, strict=True)])
    np.testing.assert_allclose(out, deck, atol=1e-12)
    np.testing.assert_allclose(
        out, velocity_motion(x0, np.stack([ds / 0.1, dth / 0.1], -1), 0.1), atol=1e-12
    )
    # on the circle: distance to the deck's centre is |R| before and after
    radius = ds / dth
    centre = x0[:, :2] + radius[:, None] * np.stack([-np.sin(x0[:, 2]), np.cos(x0[:, 2])], -1)
    np.testing.assert_allclose(
        np.hypot(*(out[:, :2] - centre).T), np.abs(radius), rtol=1e-9, atol=1e-12
    )


def test_decks_centre_form_divides_by_zero_and_cancels_near_straight():
    x0 = np.array([3.0, -1.0, 0.6])
    straight = x0 + [np.cos(0.6), np.sin(0.6), 0.0]
    np.testing.assert_array_equal(arc_update(x0, 1.0, 0.0), straight)
    assert np.all(np.isnan(deck_exterior_kinematics(x0, 1.0, 0.0)[:2]))
    # Δθ = 1e-13: the true end is within 1e-13 m of the straight line's; the deck's formula
    # subtracts two numbers of size R = 1e13 m and misses by millimetres.
    deck = deck_exterior_kinematics(x0, 1.0, 1e-13)
    lib = arc_update(x0, 1.0, 1e-13)
    assert np.hypot(*(lib - straight)[:2]) < 1e-12
    assert np.hypot(*(deck - straight)[:2]) > 1e-4


@given(st.floats(-1e-6, 1e-6), st.floats(-2.0, 2.0), angles)
def test_arc_update_is_continuous_through_a_straight_line(dth, ds, th):
    x0 = np.array([0.5, -0.5, th])
    straight = arc_update(x0, ds, 0.0)
    # lateral offset of an arc is ΔS·Δθ/2 to first order
    assert np.abs(arc_update(x0, ds, dth) - straight).max() <= abs(ds * dth) / 2 + abs(dth) + 1e-15


@pytest.mark.parametrize(("method", "order"), [("euler", 1), ("midpoint", 2)])
def test_small_steps_converge_to_the_exact_arc_with_their_order(method, order):
    x0 = np.array([0.2, 0.1, 2.9])  # heading near π on purpose
    ds, dth = 1.5, 2.0
    exact = arc_update(x0, ds, dth)
    counts = np.array([4, 8, 16, 32, 64, 128, 256])
    errors = np.array(
        [
            np.hypot(
                *(
                    dead_reckon(x0, np.full(n, ds / n), np.full(n, dth / n), method=method)[-1]
                    - exact
                )[:2]
            )
            for n in counts
        ]
    )
    slope = np.polyfit(np.log(counts), np.log(errors), 1)[0]
    assert slope == pytest.approx(-order, abs=0.05)
    # the exact arcs chain to the exact arc at every step count
    for n in counts:
        end = dead_reckon(x0, np.full(n, ds / n), np.full(n, dth / n))[-1]
        np.testing.assert_allclose(end, exact, atol=1e-12)


def test_odometry_error_shrinks_with_dt_with_the_order_of_the_step_rule():
    """The Turkish lecture's claim, measured: wheel speeds that vary within each step."""
    from scipy.integrate import solve_ivp

    d, t_end = 0.5, 10.0

    def distance(t):  # ∫ v, v = 0.5 + 0.2 sin 0.7t
        return 0.5 * t + (0.2 / 0.7) * (1 - np.cos(0.7 * t))

    def heading(t):  # ∫ ω, ω = 0.6 sin 0.5t
        return 1.2 * (1 - np.cos(0.5 * t))

    truth = solve_ivp(
        lambda t, p: (
            (0.5 + 0.2 * np.sin(0.7 * t)) * np.array([np.cos(heading(t)), np.sin(heading(t))])
        ),
        (0.0, t_end),
        [0.0, 0.0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-12,
    ).y[:, -1]
    steps = t_end / np.array([40, 80, 160, 320, 640])
    for method, order in [("euler", 1), ("midpoint", 2), ("arc", 2)]:
        errors = []
        for dt in steps:
            t = np.linspace(0.0, t_end, round(t_end / dt) + 1)
            left, right = distance(t) - heading(t) * d / 2, distance(t) + heading(t) * d / 2
            ds, dth, _ = diff_drive_odometry(np.diff(left), np.diff(right), d)
            end = dead_reckon([0.0, 0.0, 0.0], ds, dth, method=method)[-1]
            errors.append(np.hypot(*(end[:2] - truth)))
            assert abs(end[2] - heading(t_end)) < 1e-12  # the heading telescopes: no Δt error
        slope = np.polyfit(np.log(steps), np.log(errors), 1)[0]
        assert slope == pytest.approx(order, abs=0.1), method


def test_dead_reckon_equals_repeated_arc_updates_and_broadcasts():
    rng = np.random.default_rng(2)
    ds, dth = rng.uniform(-0.3, 0.3, (2, 4, 50))
    x0 = rng.uniform(-1, 1, (4, 3))
    traj = dead_reckon(x0, ds, dth)
    assert traj.shape == (4, 51, 3)
    pose = x0.copy()
    for k in range(50):
        pose = arc_update(pose, ds[:, k], dth[:, k])
        np.testing.assert_allclose(traj[:, k + 1], pose, atol=1e-12)
    for method in ("euler", "midpoint"):
        one = dead_reckon(x0[0], ds[0, :1], dth[0, :1], method=method)
        assert one.shape == (2, 3)
    euler = dead_reckon(x0[0], ds[0, :1], dth[0, :1], method="euler")[1]
    th = x0[0, 2]
    np.testing.assert_allclose(
        euler, x0[0] + [ds[0, 0] * np.cos(th), ds[0, 0] * np.sin(th), dth[0, 0]], atol=1e-15
    )
    # one start pose for a batch of step sequences
    assert dead_reckon([0.0, 0.0, 0.0], ds, dth).shape == (4, 51, 3)


# --------------------------------------------------------------------------- deck 003


def deck_f(x_prev, u, ell):
    """Deck 003, the closed forms under eq. 8 typed literally (straight and turning)."""
    x, y, th = x_prev
    s_sx, s_dx = u
    alpha = (s_sx - s_dx) / ell
    if s_sx == s_dx:
        return np.array([x + s_sx * np.cos(th), y - s_sx * np.sin(th), th + alpha])
    r = ell * s_dx / (s_sx - s_dx)
    h = ell / 2 + r
    return np.array(
        [
            x - np.sin(th) * (h - np.cos(alpha) * h) + np.cos(th) * np.sin(alpha) * h,
            y - np.cos(th) * (h - np.cos(alpha) * h) - np.sin(alpha) * np.sin(th) * h,
            th + alpha,
        ]
    )


def random_cir_inputs(n, seed):
    rng = np.random.default_rng(seed)
    x0 = rng.uniform([-3, -3, -np.pi], [3, 3, np.pi], (n, 3))
    u = rng.uniform(-1, 1, (n, 2))
    return x0, u


def test_cir_pose_matrix_is_the_transposed_rotation():
    x = np.array([1.0, -2.0, 0.4])
    t = cir_pose_matrix(x)
    np.testing.assert_allclose(t[:2, :2], rot(0.4).T)
    np.testing.assert_allclose(t[:2, :2], rot(-0.4))  # i.e. the usual matrix of heading -θ
    np.testing.assert_array_equal(t[:, 2], [1.0, -2.0, 1.0])
    np.testing.assert_array_equal(t[2], [0.0, 0.0, 1.0])


def test_cir_state_function_is_the_printed_closed_form():
    x0, u = random_cir_inputs(300, 3)
    ell = 0.45
    f = cir_state_function(x0, u, ell)
    deck = np.array([deck_f(a, b, ell) for a, b in zip(x0, u, strict=True)])
    np.testing.assert_allclose(f, deck, atol=1e-10)
    for s in (0.7, -0.2, 0.0):  # the straight case, eq. 7
        np.testing.assert_allclose(
            cir_state_function(x0[0], [s, s], ell), deck_f(x0[0], (s, s), ell), atol=1e-15
        )


def test_cir_step_is_a_rigid_motion_consistent_with_the_heading():
    x0, u = random_cir_inputs(100, 4)
    ell = 0.3
    step = cir_step_transform(u, ell)
    np.testing.assert_allclose(np.linalg.det(step), 1.0, rtol=1e-12)
    np.testing.assert_allclose(step[:, 2], np.tile([0, 0, 1.0], (100, 1)), atol=1e-15)
    # eq. 8's third line θ + α is the heading of the product of eq. 3
    f = cir_state_function(x0, u, ell)
    np.testing.assert_allclose(cir_pose_matrix(f), cir_pose_matrix(x0) @ step, atol=1e-12)


def test_cir_wheels_travel_their_arcs_about_a_fixed_centre():
    """Eq. 4 checked from its meaning: the CIR stays put, each wheel sweeps its own arc."""
    x0, u = random_cir_inputs(100, 5)
    u = u[np.abs(u[:, 0] - u[:, 1]) > 1e-2]
    ell = 0.5
    r, alpha = cir_radius_angle(u, ell)
    before, after = (
        cir_pose_matrix(x0[: len(u)]),
        cir_pose_matrix(cir_state_function(x0[: len(u)], u, ell)),
    )
    cir = np.stack([np.zeros_like(r), -(r + ell / 2), np.ones_like(r)], -1)  # robot frame
    np.testing.assert_allclose(
        (before @ cir[..., None])[..., 0], (after @ cir[..., None])[..., 0], atol=1e-9
    )
    for wheel_y, arc in [(ell / 2, u[:, 0]), (-ell / 2, u[:, 1])]:  # left (+y), right (-y)
        radius = np.abs(wheel_y + r + ell / 2)  # wheel to CIR
        np.testing.assert_allclose(radius * np.abs(alpha), np.abs(arc), rtol=1e-9, atol=1e-12)


def test_cir_is_the_standard_model_with_a_clockwise_heading():
    x0, u = random_cir_inputs(1000, 6)
    ell = 0.4
    ds, dth_ccw = 0.5 * (u[:, 0] + u[:, 1]), (u[:, 1] - u[:, 0]) / ell
    f = cir_state_function(x0, u, ell)
    np.testing.assert_allclose(f, FLIP * arc_update(x0 * FLIP, ds, dth_ccw), atol=1e-10)
    dt = 0.2
    g = velocity_motion(x0 * FLIP, np.stack([ds / dt, dth_ccw / dt], -1), dt)
    np.testing.assert_allclose(f, FLIP * g, atol=1e-10)
    # and the wheel odometry of deck 002 gives the same (ΔS, Δθ)
    np.testing.assert_allclose(diff_drive_odometry(u[:, 0], u[:, 1], ell)[:2], [ds, dth_ccw])


def test_cir_read_with_a_counter_clockwise_heading_drives_the_wrong_way():
    """Feeding the report's f the usual heading: facing +y, a straight drive goes to -y."""
    facing_up = np.array([0.0, 0.0, np.pi / 2])
    end = cir_state_function(facing_up, [1.0, 1.0], 0.4)
    np.testing.assert_allclose(end[:2], [0.0, -1.0], atol=1e-15)
    np.testing.assert_allclose(arc_update(facing_up, 1.0, 0.0)[:2], [0.0, 1.0], atol=1e-15)
    # left wheel further: the report turns right (α > 0), i.e. θ grows clockwise
    assert cir_radius_angle([1.1, 0.9], 0.4)[1] > 0
    assert diff_drive_odometry(1.1, 0.9, 0.4)[1] < 0


@given(st.floats(-1e-7, 1e-7), lengths, angles)
def test_cir_straight_case_is_the_limit_of_the_turning_case(eps, s, th):
    x0 = np.array([0.2, 0.3, th])
    ell = 0.4
    straight = cir_state_function(x0, [s, s], ell)
    turning = cir_state_function(x0, [s + eps, s], ell)
    # α = ε/l, ΔS moves by ε/2 and the arc bends sideways by about ΔS·α/2; the rounding of
    # the printed product near a straight line adds ~1e-16·ΔS/α, below 1e-8 (see below)
    assert np.abs(turning - straight).max() <= abs(eps) * (1 + (1 + abs(s)) / ell) + 1e-8


def numeric_jacobian(fun, at, h=1e-6):
    at = np.asarray(at, float)
    cols = []
    for k in range(at.size):
        e = np.zeros_like(at)
        e[k] = h
        cols.append((fun(at + e) - fun(at - e)) / (2 * h))
    return np.stack(cols, axis=-1)


def standard_f(x0, u, ell):
    """The report's f through the convention map (tested equal to it above)."""
    ds, dth = 0.5 * (u[0] + u[1]), (u[1] - u[0]) / ell
    return FLIP * arc_update(x0 * FLIP, ds, dth)


@given(
    st.floats(-3.0, 3.0),
    st.floats(-1.0, 1.0),
    st.floats(-1.0, 1.0),
    st.sampled_from([None, 0.0, 1e-9, 1e-3]),
)
def test_cir_jacobians_match_finite_differences(th, s_sx, s_dx, nudge):
    x0 = np.array([0.5, -0.4, th])
    u = np.array([s_sx, s_dx]) if nudge is None else np.array([s_sx, s_sx + nudge])
    ell = 0.35
    F, W = cir_state_jacobians(x0, u, ell)
    np.testing.assert_allclose(F, numeric_jacobian(lambda x: standard_f(x, u, ell), x0), atol=1e-8)
    np.testing.assert_allclose(W, numeric_jacobian(lambda v: standard_f(x0, v, ell), u), atol=1e-7)
    if abs(u[0] - u[1]) > 0.05:  # the report's own product, where it has digits to spare
        np.testing.assert_allclose(
            F, numeric_jacobian(lambda x: cir_state_function(x, u, ell), x0), atol=1e-7
        )
        np.testing.assert_allclose(
            W, numeric_jacobian(lambda v: cir_state_function(x0, v, ell), u), atol=1e-7
        )


def test_cir_product_loses_digits_near_a_straight_line():
    """ρ(1 - cos α) with ρ = ΔS/α: rounding error ~1e-16·ΔS/α, largest for α near 1e-8."""
    x0, ell = np.array([0.0, 0.0, 0.3]), 0.4
    alphas = np.logspace(-15, -1, 57)
    u = np.stack([1.0 + 0.5 * ell * alphas, 1.0 - 0.5 * ell * alphas], -1)
    err = np.abs(cir_state_function(x0, u, ell) - standard_f(x0, u.T, ell)).max(axis=-1)
    assert err.max() < 1e-8  # harmless for the state itself...
    # ...but a finite difference with step 1e-6 turns it into an error of ~1e-5 in W
    worst = u[np.argmin(np.abs(alphas - 3e-6))]
    fd = numeric_jacobian(lambda v: cir_state_function(x0, v, ell), worst)
    assert np.abs(fd - cir_state_jacobians(x0, worst, ell)[1]).max() > 1e-7


def test_cir_jacobians_on_a_straight_line_are_exact():
    th, s, ell = 0.7, 0.8, 0.4
    F, W = cir_state_jacobians([0.0, 0.0, th], [s, s], ell)
    # f = (x + ΔS cos(θ + α/2) sinc(α/2), y - ΔS sin(θ + α/2) sinc(α/2), θ + α) at α = 0
    c, si = np.cos(th), np.sin(th)
    np.testing.assert_allclose(F, [[1, 0, -s * si], [0, 1, -s * c], [0, 0, 1]], atol=1e-15)
    dalpha = np.array([-0.5 * s * si, -0.5 * s * c, 1.0])  # ∂f/∂α at α = 0
    dds = np.array([c, -si, 0.0])
    expected = np.stack([dds / 2 + dalpha / ell, dds / 2 - dalpha / ell], -1)
    np.testing.assert_allclose(W, expected, atol=1e-15)


@pytest.mark.parametrize("shape", [(), (7,), (4, 5)])
def test_batches_equal_one_at_a_time(shape):
    rng = np.random.default_rng(8)
    x0 = rng.uniform(-1, 1, (*shape, 3))
    u = rng.uniform(-1, 1, (*shape, 2))
    f = cir_state_function(x0, u, 0.3)
    F, W = cir_state_jacobians(x0, u, 0.3)
    step = cir_step_transform(u, 0.3)
    arc = arc_update(x0, u[..., 0], u[..., 1])
    dd = np.array(diff_drive_odometry(u[..., 0], u[..., 1], 0.3))
    assert f.shape == arc.shape == (*shape, 3)
    assert F.shape == (*shape, 3, 3) and W.shape == (*shape, 3, 2) and step.shape == F.shape
    for idx in np.ndindex(shape):
        np.testing.assert_array_equal(f[idx], cir_state_function(x0[idx], u[idx], 0.3))
        np.testing.assert_array_equal(F[idx], cir_state_jacobians(x0[idx], u[idx], 0.3)[0])
        np.testing.assert_array_equal(W[idx], cir_state_jacobians(x0[idx], u[idx], 0.3)[1])
        np.testing.assert_array_equal(arc[idx], arc_update(x0[idx], *u[idx]))
        np.testing.assert_array_equal(dd[(slice(None), *idx)], diff_drive_odometry(*u[idx], 0.3))
    if shape == ():
        assert all(isinstance(a, float) for a in diff_drive_odometry(*u, 0.3))
        assert all(isinstance(a, float) for a in tricycle_odometry(*u, 0.3))
        assert all(isinstance(a, float) for a in cir_radius_angle(u, 0.3))


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: diff_drive_odometry(1.0, 1.0, 0.0), "wheelbase"),
        (lambda: diff_drive_odometry(1.0, 1.0, -0.3), "wheelbase"),
        (lambda: diff_drive_odometry(np.nan, 1.0, 0.3), "ds_left"),
        (lambda: diff_drive_odometry(1.0, "a", 0.3), "ds_right"),
        (lambda: diff_drive_odometry([1.0, 2.0], [1.0, 2.0, 3.0], 0.3), "ds_left"),
        (lambda: tricycle_odometry(1.0, np.inf, 0.3), "steering_angle"),
        (lambda: tricycle_odometry(1.0, 0.1, np.nan), "wheelbase"),
        (lambda: tricycle_odometry(np.nan, 0.1, 1.0), "d_front"),
        (lambda: arc_update([0.0, 0.0], 1.0, 0.1), "x_prev"),
        (lambda: arc_update([0.0, 0.0, np.nan], 1.0, 0.1), "x_prev"),
        (lambda: arc_update([0.0, 0.0, 0.0], np.nan, 0.1), "ds"),
        (lambda: arc_update(np.zeros((2, 3)), 1.0, [0.1, 0.2, 0.3]), "x_prev"),
        (lambda: dead_reckon([0.0, 0.0, 0.0], 1.0, 0.1), "ds"),
        (lambda: dead_reckon([0.0, 0.0, 0.0], [1.0], [0.1], method="rk4"), "method"),
        (lambda: dead_reckon(np.zeros((2, 3)), np.ones((3, 4)), np.ones((3, 4))), "x0"),
        (lambda: dead_reckon([0.0, 0.0, 0.0], [1.0, 1.0], [0.1, 0.1, 0.1]), "ds"),
        (lambda: cir_state_function([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], 0.3), "u"),
        (lambda: cir_state_function([0.0, 0.0, 0.0], [1.0, 1.0], 0.0), "wheelbase"),
        (lambda: cir_state_function([0.0, 0.0], [1.0, 1.0], 0.3), "x_prev"),
        (lambda: cir_state_jacobians([0.0, 0.0, 0.0], [1.0, np.nan], 0.3), "u"),
        (lambda: cir_step_transform([1.0, 0.5], -1.0), "wheelbase"),
        (lambda: cir_radius_angle([[1.0, 0.5]] * 3, [0.3, 0.4]), "wheelbase"),
        (lambda: cir_pose_matrix([0.0, 0.0, 0.0, 0.0]), "x"),
        (lambda: cir_state_function(np.zeros((2, 3)), np.ones((3, 2)), 0.3), "x_prev"),
        (lambda: cir_state_jacobians(np.zeros((2, 3)), np.ones((3, 2)), 0.3), "x_prev"),
        (lambda: dead_reckon([0.0, 0.0, 0.0], np.ones((2, 4)), np.ones((3, 4))), "ds"),
        # finite input whose result overflows float64: named, not inf or a RuntimeWarning
        (
            lambda: (
                arc_update([0.0, 0.0, 0.0], 1e308, 0.0) * 0 + arc_update([1e308, 0, 0], 1e308, 0.0)
            ),
            "ds",
        ),
        (lambda: tricycle_odometry(1e300, 0.5, 1e-10), "d_front|wheelbase"),
        (lambda: diff_drive_odometry(1.5e308, 1.5e308, 1.0), "ds_left|ds_right"),
        (lambda: cir_state_function([0.0, 0.0, 0.0], [1.0, 0.5], 1e-320), "wheelbase|u"),
        (lambda: dead_reckon([0.0, 0.0, 0.0], [1e308, 1e308], [0.0, 0.0]), "ds"),
    ],
)
def test_bad_input_raises_value_error_naming_the_argument(call, name):
    with pytest.raises(ValueError, match=name):
        call()


@pytest.mark.parametrize(
    "call",
    [
        lambda: diff_drive_odometry(1j, 1.0, 0.3),
        lambda: arc_update([0.0, 0.0, 1j], 1.0, 0.1),
        lambda: cir_state_function([0.0, 0.0, 0.0], [1.0, 1j], 0.3),
    ],
)
def test_complex_input_raises_type_error(call):
    with pytest.raises(TypeError, match="real"):
        call()
