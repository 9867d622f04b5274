"""Errata of the Turkish lecture (deck 002, tag TR): each number an entry of book/errata.md
states is computed here from the slide's formula as printed, next to the library's."""

import numpy as np
import pytest

from probrob.distributions import prob_normal_distribution, sample_normal_distribution
from probrob.kinematics import arc_update
from probrob.motion import (
    _invert_velocity,
    apply_odometry_deltas,
    motion_model_odometry,
    odometry_deltas,
    velocity_motion,
)

START = np.zeros(3)


# --------------------------------------------------------------- the slides, as printed


def slide_sample(b, size, rng):
    """sample(b) = 1/2 Σ_{i=1}^{12} rand(-b, b)."""
    return 0.5 * rng.uniform(-b, b, (size, 12)).sum(axis=1)


def slide_prob(a, b):
    """prob(a, b) = exp(-a²/2b²) / (√(2π) b)."""
    return np.exp(-(a**2) / (2 * b**2)) / (np.sqrt(2 * np.pi) * b)


def slide_centre_corrected(start, end):
    """The circle centre with μ of the slide and the sign of V6 corrected (Table 5.1)."""
    (x, y, th), (xp, yp) = start, end[:2]
    mu = 0.5 * ((x - xp) * np.cos(th) + (y - yp) * np.sin(th))
    mu /= (y - yp) * np.cos(th) - (x - xp) * np.sin(th)
    return np.array([(x + xp) / 2 - mu * (yp - y), (y + yp) / 2 + mu * (xp - x)])


def slide_delta_theta(start, end, centre):
    """Δθ = tan⁻¹((ȳ' - y_c)/(x̄' - x_c)) - tan⁻¹((ȳ - y_c)/(x̄ - x_c))."""
    with np.errstate(divide="ignore"):
        return np.arctan((end[1] - centre[1]) / (end[0] - centre[0])) - np.arctan(
            (start[1] - centre[1]) / (start[0] - centre[0])
        )


def slide_exterior(pose, ds, dtheta):
    """R = ΔS/Δθ, α = θ - π/2, x = C_x + R cos α, ..., x' = C_x + R cos(α + Δθ)."""
    x, y, th = pose
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.float64(ds) / dtheta
        a = th - np.pi / 2
        cx, cy = x - r * np.cos(a), y - r * np.sin(a)
        return np.array([cx + r * np.cos(a + dtheta), cy + r * np.sin(a + dtheta)])


# --------------------------------------------------------------------------- D2


def test_D2_the_slides_sampler_and_density_read_a_variance_of_004_as_sigma_004():
    """D2: with α1 v² = 0.04, sample(b) of the slide has σ 0.04; probrob's has σ 0.2."""
    rng = np.random.default_rng(0)
    variance = 0.04 * 1.0**2
    deck = slide_sample(variance, 200_000, rng)
    ours = sample_normal_distribution(variance, size=200_000, rng=rng)
    assert deck.std() == pytest.approx(0.04, rel=0.01)
    assert ours.std() == pytest.approx(0.2, rel=0.01)
    # the density likewise: prob(a, 0.04) of the slide is the normal of σ 0.04
    a = np.linspace(-0.5, 0.5, 11)
    sigma_004 = np.exp(-(a**2) / (2 * 0.04**2)) / (np.sqrt(2 * np.pi) * 0.04)
    np.testing.assert_allclose(slide_prob(a, variance), sigma_004, rtol=1e-12)
    np.testing.assert_allclose(
        prob_normal_distribution(a, variance), slide_prob(a, 0.2), rtol=1e-12
    )


# --------------------------------------------------------------------------- V1, V2


def test_V1_the_slides_unsigned_r_gives_minus_130_for_a_right_turn_probrob_plus_130():
    """V1 (TR): end pose (1, -0.7, -1.22): r = √(...) ≥ 0 and v̂ = Δθ·r/Δt give -1.30 m/s."""
    end = np.array([1.0, -0.7, -1.22])
    centre = slide_centre_corrected(START, end)
    r = np.sqrt((end[0] - centre[0]) ** 2 + (end[1] - centre[1]) ** 2)
    dth = slide_delta_theta(START, end, centre)
    v_slide = dth * r / 1.0
    v_ours, w_ours, _, _ = _invert_velocity(end, START, 1.0)
    assert round(float(v_slide), 2) == -1.30
    assert round(float(v_ours), 2) == 1.30
    assert dth == pytest.approx(w_ours, rel=1e-9)  # Δθ is right here: only the sign of v̂ is not
    # the signed radius (a² + b²)/(2b) with (a, b) = (1, -0.7) is the library's v̂/ω̂
    assert float(v_ours / w_ours) == pytest.approx((1 + 0.49) / (2 * -0.7), rel=1e-12)


def test_V2_the_slides_arctan_of_ratios_loses_the_quadrant():
    """V2 (TR): from θ = 2 rad, a left turn of 1.5 rad comes out as 1.5 - π."""
    start = np.array([0.0, 0.0, 2.0])
    end = velocity_motion(start, (1.5, 1.5), 1.0)
    centre = slide_centre_corrected(start, end)
    assert slide_delta_theta(start, end, centre) == pytest.approx(1.5 - np.pi, abs=1e-9)
    assert _invert_velocity(end, start, 1.0)[1] == pytest.approx(1.5, abs=1e-12)


# ------------------------------------------------------------------------ O5, O6


def test_O5_the_slides_delta_rot1_of_a_rotation_in_place_is_arctan_of_0_over_0():
    with np.errstate(invalid="ignore"):
        assert np.isnan(np.arctan(np.float64(0.0) / 0.0) - 1.2)
    assert odometry_deltas([1.0, 2.0, 1.2], [1.0, 2.0, 1.7]) == (0.0, 0.0, pytest.approx(0.5))


@pytest.mark.parametrize("noise", ["std", "variance"])
def test_O6_the_slides_closed_form_is_the_samplers_density_times_delta_trans_hat(noise):
    """O6 (TR): prob(δ - δ̂, b(δ)) with the variances at the odometry's δ is a density over
    (δ̂rot1, δ̂trans, δ̂rot2); over poses the sampler's density divides it by δ̂trans."""
    alpha = np.array([0.2, 0.1, 0.2, 0.1])
    xbar_prev = np.array([2.0, 1.0, 1.2])
    u = np.stack([xbar_prev, apply_odometry_deltas(xbar_prev, 0.6, 1.0, -0.4)])
    x_prev = np.array([0.5, -0.3, 0.4])
    rng = np.random.default_rng(3)
    x_t = apply_odometry_deltas(
        x_prev, *(np.array([0.6, 1.0, -0.4])[:, None] + rng.normal(0, 0.15, (3, 40)))
    )
    rot1, trans, rot2 = odometry_deltas(u[0], u[1])
    r1h, th, r2h = odometry_deltas(x_prev, x_t)
    a1, a2, a3, a4 = alpha
    if noise == "std":  # the first slide: the sums are standard deviations, as prob reads them
        b = (
            a1 * abs(rot1) + a2 * trans,
            a3 * trans + a4 * (abs(rot1) + abs(rot2)),
            a1 * abs(rot2) + a2 * trans,
        )
    else:  # the "veya" slide, with the variance read as a variance (erratum D2 corrected)
        b = (
            np.sqrt(a1 * rot1**2 + a2 * trans**2),
            np.sqrt(a3 * trans**2 + a4 * (rot1**2 + rot2**2)),
            np.sqrt(a1 * rot2**2 + a2 * trans**2),
        )
    slide = (
        slide_prob(rot1 - r1h, b[0]) * slide_prob(trans - th, b[1]) * slide_prob(rot2 - r2h, b[2])
    )
    pose = motion_model_odometry(x_t, u, x_prev, alpha, noise=noise, density="pose")
    book = motion_model_odometry(x_t, u, x_prev, alpha, noise=noise, density="book")
    np.testing.assert_allclose(slide, pose * th, rtol=1e-10)
    assert np.max(np.abs(slide / book - 1)) > 0.05  # not Table 5.5, whose variances are at δ̂


# --------------------------------------------------------------------------- W2


def test_W2_the_slides_centre_form_misses_by_the_printed_amounts():
    """W2: a 1 m step from (3, -1, 0.6): off by 7.5e-8 m, 1.1 mm and 0.25 m at Δθ = 1e-9,
    1e-13 and 1e-15; NaN at Δθ = 0. The chord form is exact to rounding."""
    pose = np.array([3.0, -1.0, 0.6])
    misses = {
        dth: np.hypot(*(slide_exterior(pose, 1.0, dth) - arc_update(pose, 1.0, dth)[:2]))
        for dth in (1e-9, 1e-13, 1e-15)
    }
    assert f"{misses[1e-9]:.1e}" == "7.5e-08"
    assert f"{misses[1e-13] * 1e3:.1f}" == "1.1"
    assert f"{misses[1e-15]:.2f}" == "0.25"
    assert np.all(np.isnan(slide_exterior(pose, 1.0, 0.0)))
    straight = pose[:2] + [np.cos(0.6), np.sin(0.6)]
    assert np.hypot(*(arc_update(pose, 1.0, 1e-15)[:2] - straight)) < 1e-15


# ------------------------------------------------------------------ the page itself


def test_every_test_a_TR_entry_names_exists():
    """Each `file.py::test_name` (or `::test_name` after it) in an entry tagged TR exists."""
    import re
    from pathlib import Path

    root = Path(__file__).parent
    page = (root.parent / "book" / "errata.md").read_text(encoding="utf-8")
    entries = [e.split("\n## ")[0] for e in page.split("\n### ")[1:]]
    entries = [e for e in entries if "TR" in e.splitlines()[0]]
    assert len(entries) >= 14
    for entry in entries:
        current = None
        for file, name in re.findall(r"`(test_\w+\.py)?::(\w+)", entry):
            current = file or current
            assert current, entry.splitlines()[0]
            assert f"def {name}(" in (root / current).read_text(encoding="utf-8"), (current, name)


def test_the_entries_quote_the_lecture():
    """Each formula and slide title an entry tagged TR gives as the lecture's is in the
    lecture's text (deck 002), character for character up to spaces, and in the entry
    (skipped where the decks are not beside the checkout)."""
    import re
    from pathlib import Path

    root = Path(__file__).parent.parent
    seed = root.parent / "shared" / "seeds" / "002_9887d60ab62234ff.txt"
    if not seed.exists():
        pytest.skip("the source decks are not beside the checkout")
    deck = re.sub(r"\s+", "", seed.read_text(encoding="utf-8"))
    page = (root / "book" / "errata.md").read_text(encoding="utf-8")

    def entry(tag):
        start = page.index(f"(errata-{tag})=")
        end = min(
            e for e in (page.find("\n(errata-", start + 1), page.find("\n## ", start)) if e > 0
        )
        return page[start:end]

    quotes = {
        "d2": [
            r"\hat{\nu} = \nu + \text{sample}(\alpha_1 \cdot \nu^2 + \alpha_2 \cdot \omega^2)",
            r"prob(\nu - \hat{\nu}, \alpha_1 \cdot \nu^2 + \alpha_2 \cdot \omega^2)",
            r"sample(b) = \frac{1}{2} \sum_{i=1}^{12} rand(-b, b)",
            r"prob(a, b) = \frac{1}{\sqrt{2\pi}b} e^{-\frac{a^2}{2b^2}}",
        ],
        "v1": [
            r"\sqrt{(\bar{x}' - x_c)^2 + (\bar{y}' - y_c)^2}",
            r"\sqrt{(\bar{x} - x_c)^2 + (\bar{y} - y_c)^2}",
            r"\hat{v} = \frac{\Delta\theta \cdot r}{\Delta t}",
        ],
        "v2": [
            r"\Delta\theta = \tan^{-1} \left( \frac{\bar{y}' - y_c}{\bar{x}' - x_c} \right) - \tan^{-1} \left( \frac{\bar{y} - y_c}{\bar{x} - x_c} \right)"
        ],
        "v3": [r"\hat{\gamma} = \frac{\bar{\theta}' - \bar{\theta}}{\Delta t} - \omega"],
        "v4": [r"\hat{\gamma} = \frac{\bar{\theta}' - \bar{\theta}}{\Delta t} - \omega"],
        "v5": [
            r"\mu = \frac{1}{2} \frac{(\bar{x} - \bar{x}') \cos \theta + (\bar{y} - \bar{y}') \sin \theta}{(\bar{y} - \bar{y}') \cos \theta - (\bar{x} - \bar{x}') \sin \theta}",
            r"x' = \bar{x} - \frac{\hat{v}}{\hat{\omega}} \sin \bar{\theta} + \frac{\hat{v}}{\hat{\omega}} \sin (\bar{\theta} + \hat{\omega} \cdot \Delta t)",
        ],
        "v6": [
            r"x_c = \frac{\bar{x} + \bar{x}'}{2} - \mu (\bar{y}' - \bar{y})",
            r"y_c = \frac{\bar{y} + \bar{y}'}{2} - \mu (\bar{x}' - \bar{x})",
        ],
        "o1": [
            r"\delta_{rot_1} = \tan^{-1} \left( \frac{\bar{y}' - \bar{y}}{\bar{x}' - \bar{x}} \right) - \bar{\theta}",
            r"\delta_{rot_2} = \bar{\theta}' - \bar{\theta} - \delta_{rot_1}",
            r"\delta_{rot_1} - \hat{\delta}_{rot_1}",
            r"\delta_{rot_2} - \hat{\delta}_{rot_2}",
        ],
        "o2": [
            r"x' = x + \hat{\delta}_{trans} \cdot \cos \left( \bar{\theta} + \hat{\delta}_{rot_1} \right)"
        ],
        "o4": [
            r"\delta_{rot_1} = \tan^{-1} \left( \frac{\bar{y}' - \bar{y}}{\bar{x}' - \bar{x}} \right) - \bar{\theta}"
        ],
        "o6": [
            "Odometri Modeli - Kapalı Form",
            r"p(x', y', \theta') =",
            r"prob \left( \delta_{rot_1} - \hat{\delta}_{rot_1}, \alpha_1 \cdot |\delta_{rot_1}| + \alpha_2 \cdot \delta_{trans} \right)",
            r"prob \left( \delta_{trans} - \hat{\delta}_{trans}, \alpha_3 \cdot \delta_{trans} + \alpha_4 \cdot (|\delta_{rot_1}| + |\delta_{rot_2}|) \right)",
            r"prob \left( \delta_{rot_2} - \hat{\delta}_{rot_2}, \alpha_1 \cdot |\delta_{rot_2}| + \alpha_2 \cdot \delta_{trans} \right)",
            r"\alpha_1 \cdot \delta_{rot_1}^2 + \alpha_2 \cdot \delta_{trans}^2",
        ],
        "w1": [
            "Odometri - Diferansiyel Sürüşlü Robot",
            r"R = \frac{d (\Delta S_R + \Delta S_L)}{2 (\Delta S_R - \Delta S_L)}",
        ],
        "w2": [
            "Dış Kinematik",
            r"R = \frac{\Delta S}{\Delta \theta}",
            r"\alpha = \theta - \frac{\pi}{2}",
            r"x = C_x + R \cos \alpha",
            r"y = C_y + R \sin \alpha",
            r"x' = C_x + R \cos (\alpha + \Delta \theta)",
            r"y' = C_y + R \sin (\alpha + \Delta \theta)",
        ],
    }
    tagged = {
        m[1].lower() for m in re.finditer(r"\(errata-(\w+)\)=\n### \w+ — [^\n]*\bTR\b", page)
    }
    assert tagged - {"o3", "o5"} == set(quotes), "every TR entry that quotes the lecture is here"
    for tag, formulas in quotes.items():
        text = re.sub(r"\s+", "", entry(tag))
        for formula in formulas:
            squeezed = re.sub(r"\s+", "", formula)
            assert squeezed in deck, (tag, formula)
            assert squeezed in text, (tag, formula)


def test_the_quote_check_can_fail():
    """The W1 quote as the page once typed it, with thin spaces, is not the lecture's text."""
    import re
    from pathlib import Path

    seed = Path(__file__).parent.parent.parent / "shared" / "seeds" / "002_9887d60ab62234ff.txt"
    if not seed.exists():
        pytest.skip("the source decks are not beside the checkout")
    deck = re.sub(r"\s+", "", seed.read_text(encoding="utf-8"))
    typed = r"R = \frac{d\,(\Delta S_R + \Delta S_L)}{2\,(\Delta S_R - \Delta S_L)}"
    assert re.sub(r"\s+", "", typed) not in deck
