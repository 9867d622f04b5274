"""The book's figure style, the Table 5.1 / Table 5.5 diagrams and the generic player."""

import re

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.colorbar import Colorbar

from probrob.angles import wrap_angle
from probrob.motion import apply_odometry_deltas, odometry_deltas, velocity_motion
from probrob.plotting import (
    BOOK_COLUMN_PX,
    BOOK_DPI,
    BOOK_FIGURE_WIDTH,
    BOOK_MIN_FONT_PX,
    DENSITY_XY_LABEL,
    book_style,
    plot_motion_model,
    plot_odometry_deltas,
    plot_velocity_geometry,
    use_book_style,
)
from probrob.widgets import alpha_player, parameter_player


@pytest.fixture(autouse=True)
def book_rc():
    with plt.rc_context():
        use_book_style()
        yield
    plt.close("all")


def texts(ax):
    return " ".join(t.get_text() for t in ax.texts)


# ------------------------------------------------------------------ the style


def test_book_style_fits_the_column_with_readable_text():
    from matplotlib.font_manager import FontProperties

    assert plt.rcParams["figure.dpi"] == BOOK_DPI
    width_px = plt.rcParams["figure.figsize"][0] * BOOK_DPI
    assert width_px <= BOOK_COLUMN_PX
    for key in ("xtick.labelsize", "ytick.labelsize", "legend.fontsize", "font.size"):
        points = FontProperties(size=plt.rcParams[key]).get_size_in_points()
        assert points * BOOK_DPI / 72 >= BOOK_MIN_FONT_PX, key
    assert book_style()["figure.dpi"] == BOOK_DPI
    assert BOOK_FIGURE_WIDTH * BOOK_DPI <= BOOK_COLUMN_PX


def test_a_default_figure_renders_no_wider_than_the_column(tmp_path):
    fig, ax = plt.subplots()
    plot_motion_model("velocity", [1.0, 0.5], [0, 0, 0], [0.05] * 6, grid=30, ax=ax)
    fig.savefig(tmp_path / "f.png")
    width = plt.imread(tmp_path / "f.png").shape[1]
    assert width == round(BOOK_FIGURE_WIDTH * BOOK_DPI) <= BOOK_COLUMN_PX


@pytest.mark.parametrize("orientation", [True, "horizontal"])
def test_density_images_get_a_colorbar_with_quantity_and_units(orientation):
    ax = plot_motion_model(
        "velocity", [1.0, 0.5], [0, 0, 0], [0.05] * 6, grid=30, colorbar=orientation
    )
    bars = [a for a in ax.figure.axes if a is not ax]
    assert len(bars) == 1
    label = bars[0].get_xlabel() if orientation == "horizontal" else bars[0].get_ylabel()
    assert label == DENSITY_XY_LABEL and "[1/m²]" in label
    assert isinstance(ax.collections[0].colorbar, Colorbar)


def test_no_colorbar_without_a_density_image():
    ax = plot_motion_model("velocity", [1.0, 0.5], [0, 0, 0], [0.05] * 6, show_density=False)
    assert len(ax.figure.axes) == 1


# ------------------------------------------------------------------ the diagrams


@pytest.mark.parametrize(("v", "w"), [(1.0, 0.8), (1.0, -0.8), (-0.7, 0.5)])
def test_velocity_geometry_draws_the_circle_of_the_arc(v, w):
    x_prev = np.array([0.4, -0.3, 2.5])
    x_t = velocity_motion(x_prev, [v, w], 1.0) + [0.0, 0.0, 0.2]  # final turn 0.2 rad
    ax = plot_velocity_geometry(x_prev, x_t, 1.0)
    r = v / w  # the signed radius of the arc that velocity_motion drove
    centre = (x_prev[0] - r * np.sin(x_prev[2]), x_prev[1] + r * np.cos(x_prev[2]))
    markers = [line for line in ax.lines if line.get_marker() == "+"]
    assert len(markers) == 1
    np.testing.assert_allclose(np.ravel(markers[0].get_data()), centre, atol=1e-9)
    label = texts(ax)
    assert f"$r^* = {abs(r):.2f}$ m" in label
    assert f"$\\Delta\\theta = {w:.2f}$ rad" in label
    assert "$\\hat\\gamma\\Delta t = 0.20$ rad" in label
    assert f"$\\hat v = {v:.2f}$ m/s" in ax.get_title()


def test_velocity_geometry_of_a_straight_line_has_no_centre():
    x_prev = np.array([0.0, 0.0, 0.3])
    ax = plot_velocity_geometry(x_prev, velocity_motion(x_prev, [1.0, 0.0], 1.0))
    assert not [line for line in ax.lines if line.get_marker() == "+"]
    assert "straight" in texts(ax)


def test_velocity_geometry_bad_input():
    with pytest.raises(ValueError, match="one pose"):
        plot_velocity_geometry(np.zeros((2, 3)), np.ones(3))
    with pytest.raises(ValueError, match="dt"):
        plot_velocity_geometry(np.zeros(3), np.ones(3), dt=0.0)


@pytest.mark.parametrize("heading", [0.4, 3.0, -3.1])
def test_odometry_diagram_labels_the_wrapped_deltas(heading):
    a = np.array([1.0, 2.0, heading])
    b = apply_odometry_deltas(a, 0.6, 1.3, -0.9)
    ax = plot_odometry_deltas(a, b)
    rot1, trans, rot2 = odometry_deltas(a, b)
    assert (rot1, trans, rot2) == pytest.approx((0.6, 1.3, -0.9))
    label = texts(ax)
    for name, value, unit in (("rot1", rot1, "rad"), ("trans", trans, "m"), ("rot2", rot2, "rad")):
        assert f"$\\delta_{{{name}}} = {value:.2f}$ {unit}" in label
    assert abs(wrap_angle(heading + rot1) - np.arctan2(b[1] - a[1], b[0] - a[0])) < 1e-9


# ------------------------------------------------------------------ the players


def test_parameter_player_fixes_the_axes_across_frames():
    rendered = []  # limits and title of every frame as it is rendered into a PNG

    def snapshot(event):
        ax = event.canvas.figure.axes[0]
        rendered.append((ax.get_xlim(), ax.get_ylim(), ax.get_title()))

    def draw(ax, value):
        ax.plot([0, value], [0, 2 * value], "o-")
        if not getattr(ax.figure, "_watched", False):
            ax.figure._watched = True
            ax.figure.canvas.mpl_connect("draw_event", snapshot)

    html = parameter_player(draw, [1.0, 2.0, 3.0], label="σ").data
    assert len(re.findall(r"data:image/png;base64,", html)) == 3
    assert {title for _, _, title in rendered} == {"σ = 1", "σ = 2", "σ = 3"}
    limits = {(x, y) for x, y, _ in rendered}
    assert len(limits) == 1  # every frame has the same axes
    (x0, x1), (y0, y1) = limits.pop()
    assert x0 <= 0 and x1 >= 3 and y0 <= 0 and y1 >= 6  # the union of all frames


def test_parameter_player_explicit_limits_and_accessibility():
    def draw(ax, value):
        ax.plot([0, value], [0, value])
        ax.set_title(f"my title {value}")

    html = parameter_player(draw, [0.5, 1.5], label="w", xlim=(-1, 2), ylim=(-1, 2)).data
    assert re.search(
        r'<img alt="Player: w swept over 2 frames, from 0.5 to 1.5" width="\d+" height="\d+" '
        r'style="display: block; '
        r'max-width: 100%; height: auto" id="_anim_img',
        html,
    )
    assert '<input aria-label="frame of the w sweep" id="_anim_slider' in html
    assert "http://" not in html and "https://" not in html


def test_parameter_player_bad_input():
    with pytest.raises(ValueError, match="values"):
        parameter_player(lambda ax, v: None, [], label="x")
    with pytest.raises(ValueError, match="draw"):
        parameter_player("not callable", [1.0], label="x")
    with pytest.raises(ValueError, match="label"):
        parameter_player(lambda ax, v: None, [1.0], label="")


def test_alpha_player_is_a_thin_case_with_fixed_axes_and_colorbars():
    html = alpha_player(
        "velocity", 2, [0.0, 0.2], alpha=[0.01] * 6, u_t=[1.0, 0.5], grid=20, n_samples=50
    ).data
    assert len(re.findall(r"data:image/png;base64,", html)) == 2
    assert 'alt="Player: the velocity model' in html and "α2" in html
