"""The errata of deck "Trabalho 3" (T3, deck ``000``): every number the entries D1, V1–V3,
V5, O1, O3 and O5 of ``book/errata.md`` state, asserted at the precision the page prints
it, and each formula an entry quotes from the deck found in the deck's text."""

import math
import re
from functools import partial
from pathlib import Path

import numpy as np
import pytest

from probrob.angles import wrap_angle
from probrob.distributions import prob_normal_distribution, sample_normal_distribution
from probrob.motion import (
    apply_odometry_deltas,
    motion_model_odometry,
    motion_model_velocity,
    odometry_deltas,
    sample_motion_model_odometry,
    velocity_motion,
)

ROOT = Path(__file__).parent.parent
ERRATA = (ROOT / "book" / "errata.md").read_text(encoding="utf-8")
SEED = ROOT.parent / "shared" / "seeds" / "000_ba1b8a73033d86a9.txt"
EXACT = partial(sample_normal_distribution, method="exact")


def entry(tag):
    """The entry's text on one line (the page's wrapping does not matter)."""
    start = ERRATA.index(f"(errata-{tag})=")
    end = ERRATA.find("\n(errata-", start + 1)
    end = min(e for e in (end, ERRATA.find("\n## ", start)) if e > 0)
    return " ".join(ERRATA[start:end].split())


def deck_table_5_1(x_t, u_t, x_prev, dt, alpha):
    """T3's *Modelo Baseado em Velocidade*, typed as printed: (p, v̂, Δθ, γ̂)."""
    x, y, th = np.moveaxis(np.asarray(x_prev, float), -1, 0)
    xp, yp, thp = np.moveaxis(np.asarray(x_t, float), -1, 0)
    v, w = u_t
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = (
            0.5
            * ((x - xp) * np.cos(th) + (y - yp) * np.sin(th))
            / ((y - yp) * np.cos(th) - (x - xp) * np.sin(th))
        )
        xs = (x + xp) / 2 + mu * (y - yp)
        ys = (y + yp) / 2 + mu * (xp - x)
        rs = np.sqrt((x - xs) ** 2 + (y - ys) ** 2)
        dtheta = np.arctan2(yp - ys, xp - xs) - np.arctan2(y - ys, x - xs)
        v_hat, w_hat = dtheta / dt * rs, dtheta / dt
        gamma = (thp - th) / dt - w_hat
        a1, a2, a3, a4, a5, a6 = alpha
        p = (
            prob_normal_distribution(v - v_hat, a1 * v**2 + a2 * w**2)
            * prob_normal_distribution(w - w_hat, a3 * v**2 + a4 * w**2)
            * prob_normal_distribution(gamma, a5 * v**2 + a6 * w**2)
        )
    return p, v_hat, dtheta, gamma


ALPHA = np.array([0.02, 0.02, 0.02, 0.02, 0.01, 0.01])
START = np.zeros(3)


def test_d1_twelve_uniforms_halved_have_variance_b2():
    b = 0.7
    uniform_var = (2 * b) ** 2 / 12  # a uniform on (-b, b)
    assert np.isclose(uniform_var, b**2 / 3)
    assert [n for n in range(1, 40) if np.isclose(n * uniform_var / 4, b**2)] == [12]
    x = sample_normal_distribution(b**2, size=200_000, rng=1)
    assert np.all(np.abs(x) <= 6 * b)  # bounded at ±6b
    assert abs(x.var() / b**2 - 1) < 0.02
    assert "uniform on $(-b, b)$ has variance $b^2/3$; only twelve of them" in entry("d1")
    assert "bounded at $\\pm 6b$" in entry("d1")


def test_v1_the_deck_gives_minus_v_on_a_right_turn():
    u = [1.0, -0.8]
    x_t = velocity_motion(START, u, 1.0)
    p_deck, v_hat, _, _ = deck_table_5_1(x_t, u, START, 1.0, ALPHA)
    assert v_hat == pytest.approx(-u[0], rel=1e-12)  # v̂ = −v
    ours = motion_model_velocity(x_t, u, START, 1.0, ALPHA)
    assert p_deck < 1e-20 * ours  # "almost zero" at the pose it actually reaches
    left = [1.0, 0.8]  # and right where the deck is right
    x_left = velocity_motion(START, left, 1.0)
    p_left = deck_table_5_1(x_left, left, START, 1.0, ALPHA)[0]
    assert p_left == pytest.approx(motion_model_velocity(x_left, left, START, 1.0, ALPHA))
    assert (
        "gets $\\hat v = -v$, and the density of the pose it actually reaches is almost zero"
        in (entry("v1"))
    )


def _rotate(pose, phi):
    x, y, th = np.moveaxis(np.asarray(pose, float), -1, 0)
    c, s = np.cos(phi), np.sin(phi)
    return np.stack([c * x - s * y, s * x + c * y, wrap_angle(th + phi)], axis=-1)


def test_v2_v3_the_deck_collapses_where_an_angle_jumps():
    """The chapter's figure: 721 rotations of one scene; the deck collapses exactly where
    line 6's Δθ or line 9's θ' − θ crosses ±π, probrob does not move."""
    x_prev = np.array([0.4, -0.2, 0.3])
    x_t = velocity_motion(x_prev, [1.05, 0.75], 1.0) + [0.0, 0.0, 0.02]
    u = [1.0, 0.8]
    phis = np.linspace(-np.pi, np.pi, 721)
    ours = motion_model_velocity(_rotate(x_t, phis), u, _rotate(x_prev, phis), 1.0, ALPHA)
    p, _, dtheta, _ = deck_table_5_1(_rotate(x_t, phis), u, _rotate(x_prev, phis), 1.0, ALPHA)
    assert np.ptp(ours) < 1e-12 * ours.mean()
    turn = _rotate(x_t, phis)[:, 2] - _rotate(x_prev, phis)[:, 2]
    jumps = (np.abs(dtheta - wrap_angle(dtheta)) > 1) | (np.abs(turn - wrap_angle(turn)) > 1)
    assert jumps.any() and not jumps.all()
    assert np.array_equal(p < 1e-6 * ours, jumps)
    assert "both versions of Table 5.1 for 721 rotations of the scene" in entry("v2")
    # V3: θ' and θ' + 2π are the same heading; the deck's γ̂ differs by 2π/Δt
    x_hyp = velocity_motion(START, [1.0, 0.5], 1.0) + [0.0, 0.0, 0.05]
    g, g2 = (
        deck_table_5_1(x, [1.0, 0.5], START, 1.0, ALPHA)[3]
        for x in (x_hyp, x_hyp + [0, 0, 2 * np.pi])
    )
    assert g2 - g == pytest.approx(2 * np.pi)


def test_v5_the_deck_divides_by_zero_on_a_straight_line():
    x, y, th = START
    xp, yp = 1.0, 0.0  # on the heading line
    denominator = (y - yp) * np.cos(th) - (x - xp) * np.sin(th)
    assert denominator == 0  # μ = ·/0
    v_hat, w_hat = 1.0, 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.float64(v_hat) / np.float64(w_hat)
        x_sampled = x - ratio * np.sin(th) + ratio * np.sin(th + w_hat * 1.0)
    assert np.isnan(x_sampled)  # the sampler's v̂/ω̂ at ω̂ = 0
    assert np.isfinite(motion_model_velocity([xp, yp, 0.0], [1.0, 0.01], START, 1.0, ALPHA))
    assert velocity_motion(START, [v_hat, w_hat], 1.0)[0] == 1.0


def test_o1_the_deck_turns_almost_a_full_circle_near_pi():
    xbar, xbar2 = np.array([0.0, 0.0, 3.1]), np.array([-1.0, -0.1, 2.9])
    deck_rot1 = np.arctan2(xbar2[1] - xbar[1], xbar2[0] - xbar[0]) - xbar[2]
    rot1, _, _ = odometry_deltas(xbar, xbar2)
    assert f"{deck_rot1:.2f}" == "-6.14" and f"{rot1:.2f}" == "0.14"
    assert abs(deck_rot1 + 2 * np.pi) < 0.15  # ≈ −2π
    assert f"{abs(deck_rot1) / abs(rot1):.0f}" == "43"  # √α1 |δrot1| grows in proportion
    text = entry("o1")
    assert (
        "from $\\bar\\theta = 3.1$ a step to $(-1, -0.1)$ gives $-6.14$ rad for a turn of 0.14 rad"
        in text
    )
    assert "43 times too large" in text


def test_o5_no_translation_no_direction():
    xbar = np.array([0.3, 0.7, 1.1])
    turned = xbar + [0.0, 0.0, 0.4]
    assert np.arctan2(0.0, 0.0) - xbar[2] == -xbar[2]  # the deck's δrot1 = −θ̄
    rot1, trans, rot2 = odometry_deltas(xbar, turned)
    assert (rot1, trans) == (0.0, 0.0) and rot2 == pytest.approx(0.4)
    assert "make $\\delta_{rot1} = -\\bar\\theta$" in entry("o5")


def _odometry(rot1, trans, rot2, start=(0.3, 0.7, -0.4)):
    start = np.array(start)
    return np.stack([start, apply_odometry_deltas(start, rot1, trans, rot2)])


def test_o3_the_printed_table_integrates_to_its_numbers(grid3):
    text = entry("o3")
    x0 = np.array([1.0, -0.5, 2.0])
    u = _odometry(0.3, 1.0, -0.2)
    alpha = np.array([0.2, 0.1, 0.2, 0.1])
    assert (
        "with $\\alpha = (0.2, 0.1, 0.2, 0.1)$, odometry $(\\delta_{rot1}, \\delta_{trans}, \\delta_{rot2}) = (0.3, 1, -0.2)$ and start pose $(1, -0.5, 2)$"
        in text
    )

    def masses(grid):
        trans_hat = np.hypot(grid.points[..., 0] - x0[0], grid.points[..., 1] - x0[1])
        book = motion_model_odometry(grid.points, u, x0, alpha)
        pose = motion_model_odometry(grid.points, u, x0, alpha, density="pose")
        return grid.integrate(book / trans_hat), grid.integrate(pose)

    samples = sample_motion_model_odometry(u, x0, alpha, sample=EXACT, size=50_000, rng=5)
    grid = grid3.around(samples, 96)
    box = re.search(
        r"integrates to about ([\d.]+) over the box \$x' \\in \[(-?[\d.]+), (-?[\d.]+)\]\$ m, "
        r"\$y' \\in \[(-?[\d.]+), (-?[\d.]+)\]\$ m, \$\\theta' \\in \[(-?[\d.]+), (-?[\d.]+)\]\$ rad",
        text,
    ).groups()
    book, pose = masses(grid)
    assert f"{book:.2f}" == box[0]
    assert [f"{v:.2f}" for v in (grid.lo[0], grid.hi[0], grid.lo[1], grid.hi[1])] == list(box[1:5])
    assert [f"{v:.2f}" for v in (grid.lo[2], grid.hi[2])] == list(box[5:7])
    assert "50 000 samples, padded by 15 % per side; $96^3$ midpoint cells" in text
    (pose_text,) = re.search(
        r"the sampler's density integrates to ([\d.]+) on the same grid", text
    ).groups()
    assert f"{pose:.2f}" == pose_text
    missing, negative, sigma = re.search(
        r"of the missing ([\d.]+) %, ([\d.]+) % is the chance of a negative sampled translation, "
        r"\$P\(\\hat\\delta_{trans} < 0\) = \\Phi\(-1/([\d.]+)\)\$",
        text,
    ).groups()
    assert f"{100 * (1 - pose):.1f}" == missing
    s = math.sqrt(alpha[2] * 1.0**2 + alpha[3] * (0.3**2 + 0.2**2))
    assert f"{s:.2f}" == sigma
    p_negative = 0.5 * (1 + math.erf(-1 / s / math.sqrt(2)))
    assert f"{100 * p_negative:.1f}" == negative
    books = re.search(r"cells\) it is ([\d.]+), ([\d.]+) and ([\d.]+), because", text).groups()
    poses = re.search(
        r"the sampler's density gives ([\d.]+), ([\d.]+) and ([\d.]+) on the same grids", text
    ).groups()
    assert "half-width 1 m, 3 m and 10 m" in text and "$80^3$, $80^3$ and $128^3$ cells" in text
    end = apply_odometry_deltas(x0, 0.3, 1.0, -0.2)
    for h, n, book_text, pose_text in zip((1, 3, 10), (80, 80, 128), books, poses, strict=True):
        b, p = masses(grid3(end - [h, h, np.pi], end + [h, h, np.pi], n))
        assert (f"{b:.2f}", f"{p:.2f}") == (book_text, pose_text), h


def test_the_entries_quote_the_deck():
    """Each formula a T3 entry gives as the deck's is in the deck's text, character for
    character up to spaces (skipped where the decks are not beside the checkout)."""
    if not SEED.exists():
        pytest.skip("the source decks are not beside the checkout")
    deck = " ".join(SEED.read_text(encoding="utf-8").split())
    deck = re.sub(r"<sup>1</sup>/<sub>2</sub>", "½", deck)
    quotes = {
        "d1": ["return ½ ∑ rand(-b,b)"],
        "v1": [
            r"r^* = \sqrt{(x - x^*)^2 + (y - y^*)^2}",
            r"\hat{v} = \frac{\Delta \theta}{\Delta t} r^*",
        ],
        "v2": [
            r"\Delta\theta = \text{atan2}(y' - y^*, x' - x^*) - \text{atan2}(y - y^*, x - x^*)"
        ],
        "v3": [r"\hat{\gamma} = \frac{\theta' - \theta}{\Delta t} - \hat{\omega}"],
        "v5": [
            r"\mu = \frac{1}{2} \frac{(x - x')\cos\theta + (y - y')\sin\theta}{(y - y')\cos\theta - (x - x')\sin\theta}",
            r"x' = x - \frac{\hat{v}}{\hat{\omega}} \sin \theta + \frac{\hat{v}}{\hat{\omega}} \sin(\theta + \hat{\omega} \Delta t)",
        ],
        "o1": [
            r"\delta_{\text{rot}1} = \text{atan2}(\bar{y}' - \bar{y}, \bar{x}' - \bar{x}) - \bar{\theta}",
            r"\delta_{\text{rot}2} = \bar{\theta}' - \bar{\theta} - \delta_{\text{rot}1}",
        ],
        "o3": [
            r"p_1 = \mathbf{prob}(\delta_{\text{rot}1} - \hat{\delta}_{\text{rot}1}, \alpha_1 \hat{\delta}_{\text{rot}1}^2 + \alpha_2 \hat{\delta}_{\text{trans}}^2)",
            r"\hat{\delta}_{\text{rot1}} = \delta_{\text{rot1}} - \text{sample}(\alpha_1 \delta_{\text{rot1}}^2 + \alpha_2 \delta_{\text{trans}}^2)",
        ],
        "o5": [
            r"\delta_{\text{rot}1} = \text{atan2}(\bar{y}' - \bar{y}, \bar{x}' - \bar{x}) - \bar{\theta}"
        ],
    }
    for tag, formulas in quotes.items():
        text = entry(tag)
        assert "T3" in text.split("**Correct")[0].split("**Library")[0]  # who printed it
        for formula in formulas:
            assert formula in deck, (tag, formula)
            assert formula.replace(" ", "") in text.replace(" ", ""), (tag, formula)
