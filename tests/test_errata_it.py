"""The errata of the CIR report (IT, deck ``003``): every number the entries C1 and C2 of
``book/errata.md`` state, asserted at the precision the page prints it."""

from pathlib import Path

import numpy as np
import pytest

from probrob.kinematics import (
    arc_update,
    cir_pose_matrix,
    cir_radius_angle,
    cir_state_function,
    cir_state_jacobians,
    diff_drive_odometry,
)
from probrob.motion import velocity_motion

FLIP = np.array([1.0, 1.0, -1.0])  # the map M
L = 0.4
ERRATA = (Path(__file__).parent.parent / "book" / "errata.md").read_text(encoding="utf-8")
SEED = Path(__file__).parent.parent.parent / "shared" / "seeds" / "003_bdbc41154fb08229.txt"


def _entry(tag):
    start = ERRATA.index(f"(errata-{tag})=")
    end = ERRATA.find("\n(errata-", start + 1)
    return " ".join(ERRATA[start:end].split())  # one line: the page's wrapping does not matter


def _rot(t):
    return np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])


def test_c1_the_report_matrix_is_the_transposed_rotation():
    """Eq. 2 is R(θ)ᵀ = R(−θ): the usual matrix of the pose (x, y, −θ); α > 0 turns right."""
    pose = np.array([1.0, -2.0, 0.4])
    T = cir_pose_matrix(pose)
    np.testing.assert_allclose(T[:2, :2], _rot(0.4).T)
    np.testing.assert_allclose(T[:2, :2], _rot(-0.4))
    assert cir_radius_angle([1.1, 0.9], L)[1] > 0 > diff_drive_odometry(1.1, 0.9, L)[1]


def test_c1_f_is_the_standard_model_under_the_map_m():
    """f(x, u) = M arc_update(Mx, ΔS, −α), and velocity_motion alike, to 1e-12 over 1000."""
    rng = np.random.default_rng(6)
    x0 = rng.uniform([-3, -3, -np.pi], [3, 3, np.pi], (1000, 3))
    u = rng.uniform(-1, 1, (1000, 2))
    ds = 0.5 * (u[:, 0] + u[:, 1])
    _, alpha = cir_radius_angle(u, L)
    f = cir_state_function(x0, u, L)
    assert np.abs(f - FLIP * arc_update(x0 * FLIP, ds, -alpha)).max() < 1e-12
    dt = 0.1
    g = velocity_motion(x0 * FLIP, np.stack([ds / dt, -alpha / dt], -1), dt)
    assert np.abs(f - FLIP * g).max() < 1e-12
    assert "$10^{-12}$ over 1000 random poses" in _entry("c1")


def test_c1_a_book_pose_facing_up_is_driven_down():
    facing_up = np.array([0.0, 0.0, np.pi / 2])
    np.testing.assert_allclose(
        cir_state_function(facing_up, [1.0, 1.0], L)[:2], [0, -1], atol=1e-15
    )
    np.testing.assert_allclose(arc_update(facing_up, 1.0, 0.0)[:2], [0, 1], atol=1e-15)
    assert "drives the robot 1 m to $-y$" in _entry("c1")


def _rounding():
    x0 = np.array([0.0, 0.0, 0.3])
    alphas = np.logspace(-15, -1, 57)
    u = np.stack([1.0 + 0.5 * L * alphas, 1.0 - 0.5 * L * alphas], -1)
    ds, dphi, _ = diff_drive_odometry(u[:, 0], u[:, 1], L)
    err = np.abs(cir_state_function(x0, u, L) - FLIP * arc_update(x0 * FLIP, ds, dphi))
    return x0, alphas, err.max(axis=-1)


def test_c2_rounding_of_the_printed_product():
    """Below ε ΔS/α + 1e-14 m (machine ε) where cos α < 1; largest, 4.8e-9 m, at α = 1e-8 (ΔS = 1 m)."""
    _, alphas, err = _rounding()
    assert alphas.size == 57 and alphas[0] == 1e-15 and np.isclose(alphas[-1], 0.1)
    turning = np.cos(alphas) < 1
    eps = np.finfo(float).eps
    assert f"{eps:.1e}" == "2.2e-16"
    assert np.all(err[turning] < eps / alphas[turning] + 1e-14)
    assert np.all(np.cos(alphas[: int(np.argmax(err))]) == 1.0)
    peak = int(np.argmax(err))
    assert f"{err[peak]:.1e}" == "4.8e-09" and f"{alphas[peak]:.0e}" == "1e-08"
    assert "$4.8\\cdot10^{-9}$ m, at $\\alpha = 10^{-8}$" in _entry("c2")
    assert "57 turns $\\alpha$ from $10^{-15}$ to $10^{-1}$" in _entry("c2")


def test_c2_finite_differences_through_it_lose_four_digits():
    """Step 1e-6, 3e-6 rad from a straight line: W wrong in its fifth significant digit."""
    x0 = np.array([0.0, 0.0, 0.3])
    u = np.array([1.0 + 0.5 * L * 3e-6, 1.0 - 0.5 * L * 3e-6])
    h = 1e-6
    fd = np.stack(
        [
            (cir_state_function(x0, u + h * e, L) - cir_state_function(x0, u - h * e, L)) / (2 * h)
            for e in np.eye(2)
        ],
        -1,
    )
    W = cir_state_jacobians(x0, u, L)[1]
    relative = np.abs(fd - W).max() / np.abs(W).max()
    assert 1e-5 <= relative < 1e-4
    assert "fifth significant digit" in _entry("c2")


def test_the_entries_quote_the_report():
    """Each formula an entry gives as the deck's is in the deck's text, character for
    character (skipped where the course decks are not beside the checkout)."""
    if not SEED.exists():
        pytest.skip("the source decks are not beside the checkout")
    deck = SEED.read_text(encoding="utf-8")
    quotes = [
        r"\begin{bmatrix} \cos \theta_t & \sin \theta_t & x_t \\ -\sin \theta_t & \cos \theta_t & y_t \\ 0 & 0 & 1 \end{bmatrix}",
        r"\begin{bmatrix} \cos \alpha & \sin \alpha & 0 \\ -\sin \alpha & \cos \alpha & 0 \\ 0 & 0 & 1 \end{bmatrix}",
        r"\alpha := \frac{s_{sx} - s_{dx}}{l}",
        r"y_{t-1} - s_{sx} \sin \theta_{t-1}",
        r"\underline{T}_{R_{t-1}}^{R_t}$  in funzione del CIR",
        r"\underline{T}_{R_t}^{R_w}",
        r"r := \frac{l s_{dx}}{s_{sx} - s_{dx}}",
        "l'equazione di stato che sarà impiegata nello sviluppo del filtro di Kalman",
    ]
    entries = _entry("c1") + _entry("c2")
    for quote in quotes:
        assert quote in deck, quote
        assert " ".join(quote.split()) in entries, quote
