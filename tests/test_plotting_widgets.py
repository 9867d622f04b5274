import re

import matplotlib.pyplot as plt
import numpy as np
import pytest

from probrob.distributions import prob_triangular_distribution, sample_triangular_distribution
from probrob.motion import apply_odometry_deltas, velocity_motion
from probrob.plotting import (
    DISTRIBUTIONS,
    motion_extent,
    motion_samples,
    plot_distribution,
    plot_motion_model,
)
from probrob.widgets import alpha_player, odometry_model_explorer, velocity_model_explorer

ODOMETRY = np.stack([np.zeros(3), apply_odometry_deltas(np.zeros(3), 0.4, 1.0, -0.3)])


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


def test_plot_distribution_draws_density_over_histogram():
    x = sample_triangular_distribution(0.5, size=1000, rng=0)
    ax = plot_distribution(prob_triangular_distribution, 0.5, samples=x, label="tri")
    assert len(ax.patches) == 60 and len(ax.lines) == 1
    a, p = ax.lines[0].get_data()
    np.testing.assert_allclose(p, prob_triangular_distribution(a, 0.5))
    assert ax.get_ylabel() == "density $p(a)$"


@pytest.mark.parametrize("model", ["velocity", "odometry"])
@pytest.mark.parametrize("distribution", list(DISTRIBUTIONS))
def test_plot_motion_model(model, distribution):
    u = [1.0, 0.5] if model == "velocity" else ODOMETRY
    alpha = [0.05] * (6 if model == "velocity" else 4)
    ax = plot_motion_model(model, u, [0.0, 0.0, 0.0], alpha, distribution=distribution, grid=40)
    assert ax.get_xlabel() == "$x$ [m]" and ax.get_ylabel() == "$y$ [m]"
    assert len(ax.collections) == 2  # density mesh and sample scatter
    assert ax.collections[1].get_offsets().shape == (500, 2)


def test_motion_samples_are_seeded_and_end_is_noise_free():
    a, end = motion_samples("velocity", [1.0, 0.5], [0, 0, 0], [0.05] * 6, n=50, rng=3)
    b, _ = motion_samples("velocity", [1.0, 0.5], [0, 0, 0], [0.05] * 6, n=50, rng=3)
    np.testing.assert_array_equal(a, b)
    np.testing.assert_allclose(end, velocity_motion([0, 0, 0], [1.0, 0.5], 1.0))


def test_motion_extent_holds_the_included_points():
    x0, x1, y0, y1 = motion_extent(np.ones((10, 3)), include=[[0.0, 0.0, 0.0]])
    assert x0 < 0 < 1 < x1 and y0 < 0 < 1 < y1
    assert x1 - x0 == pytest.approx(y1 - y0)


def test_plotting_bad_input():
    with pytest.raises(ValueError, match="model"):
        plot_motion_model("ackermann", [1, 0], [0, 0, 0], [0.1] * 6)
    with pytest.raises(ValueError, match="distribution"):
        plot_motion_model("velocity", [1, 0], [0, 0, 0], [0.1] * 6, distribution="cauchy")
    with pytest.raises(ValueError, match="b2"):
        plot_distribution(prob_triangular_distribution, -1.0)


def test_alpha_player_is_a_self_contained_html_player():
    html = alpha_player(
        "odometry", 3, [0.0, 0.1, 0.2], alpha=[0.05, 0.005, 0.05, 0.005], u_t=ODOMETRY, grid=30
    ).data
    frames = re.findall(r"data:image/png;base64,", html)
    assert len(frames) == 3
    assert "<script" in html
    assert "http://" not in html and "https://" not in html  # nothing fetched from a network


def test_alpha_player_bad_input():
    with pytest.raises(ValueError, match="index"):
        alpha_player("velocity", 7, [0.1], alpha=[0.1] * 6, u_t=[1, 0])
    with pytest.raises(ValueError, match="values"):
        alpha_player("velocity", 1, [], alpha=[0.1] * 6, u_t=[1, 0])


def test_explorers_build_sliders_for_every_alpha():
    vel = velocity_model_explorer()
    odo = odometry_model_explorer()
    vel_names = [c.description for c in vel.children[0].children[0].children]
    odo_names = [c.description for c in odo.children[0].children[0].children]
    assert vel_names == ["α1", "α2", "α3", "α4", "α5", "α6"]
    assert odo_names == ["α1", "α2", "α3", "α4"]
    assert all(not c.continuous_update for c in vel.children[0].children[0].children)


@pytest.mark.parametrize(
    ("model", "u", "alpha"),
    [
        ("velocity", [0.0, 0.0], [0.0] * 6),  # at rest, no noise: every sample on the start
        ("velocity", [0.0, 0.0], [0.1] * 6),  # at rest: zero variances, a point mass
        ("velocity", [0.0, 2.0], [0.1] * 6),  # rotation in place
        ("velocity", [1.0, 0.0], [0.0] * 6),  # straight, noise-free
        ("odometry", np.zeros((2, 3)), [0.5] * 4),  # odometry reports no motion
        ("odometry", np.array([[0, 0, 0], [0, 0, 1.0]]), [0.5] * 4),  # spin in place
    ],
)
def test_degenerate_settings_draw_without_warnings(model, u, alpha):
    # pytest turns every warning into an error (pyproject): a NaN or a division by zero fails
    ax = plot_motion_model(model, u, [0.0, 0.0, 0.0], alpha, grid=40, n_headings=10)
    assert np.all(np.isfinite(ax.collections[1].get_offsets()))
