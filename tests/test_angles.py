import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from probrob.angles import angle_diff, circular_mean, wrap_angle

finite_angles = st.floats(-1e6, 1e6, allow_nan=False)


@given(finite_angles)
def test_wrap_is_in_half_open_interval_and_equivalent(theta):
    w = wrap_angle(theta)
    assert -np.pi <= w < np.pi
    # Same direction: the difference is a whole number of turns.
    turns = (theta - w) / (2 * np.pi)
    assert abs(turns - round(turns)) < 1e-9 * max(1.0, abs(turns))


def test_wrap_leaves_angles_in_range_untouched():
    inside = np.array([np.nextafter(np.pi, 0), -np.pi, 0.1, -3.0, 1e-300])
    np.testing.assert_array_equal(wrap_angle(inside), inside)


def test_wrap_boundaries():
    assert wrap_angle(np.pi) == -np.pi
    assert wrap_angle(-np.pi) == -np.pi
    assert wrap_angle(0.0) == 0.0
    assert wrap_angle(3 * np.pi) == -np.pi
    assert -1e-15 < wrap_angle(-1e-17) <= 0.0  # a tiny negative angle stays near 0, not π


def test_scalar_in_scalar_out_and_shapes():
    assert isinstance(wrap_angle(1.0), float)
    for shape in [(7,), (4, 5)]:
        theta = np.linspace(-10, 10, int(np.prod(shape))).reshape(shape)
        assert wrap_angle(theta).shape == shape
        assert angle_diff(theta, 0.3).shape == shape


@given(finite_angles, finite_angles)
def test_angle_diff_takes_the_short_way(a, b):
    d = angle_diff(a, b)
    assert -np.pi <= d < np.pi
    assert np.isclose(np.cos(b + d), np.cos(a), atol=1e-6)
    assert np.isclose(np.sin(b + d), np.sin(a), atol=1e-6)


def test_angle_diff_across_pi():
    assert angle_diff(-np.pi + 0.01, np.pi - 0.01) == pytest.approx(0.02)
    assert angle_diff(np.pi - 0.01, -np.pi + 0.01) == pytest.approx(-0.02)


def test_circular_mean_across_pi():
    m = circular_mean([np.pi - 0.1, -np.pi + 0.1, np.pi - 0.05, -np.pi + 0.05])
    assert abs(angle_diff(m, np.pi)) < 1e-12
    assert circular_mean([0.1, 0.3], weights=[3.0, 1.0]) == pytest.approx(
        np.arctan2(3 * np.sin(0.1) + np.sin(0.3), 3 * np.cos(0.1) + np.cos(0.3))
    )
    rows = np.array([[0.1, 0.2, 0.3], [3.0, -3.0, np.pi]])
    assert circular_mean(rows, axis=1).shape == (2,)


def test_circular_mean_rejects_bad_weights():
    with pytest.raises(ValueError, match="weights"):
        circular_mean([0.0, 1.0], weights=[1.0, -1.0])
