"""The live EKF step of Trabalho 5 (issue 17): ``ekf_step_live`` and its kernel ``ekf.js``.

The page computes one step of Table 7.2 itself (the velocity model's prediction and one
range-bearing feature's correction) and draws the 95 % ellipses of the prior, the prediction
and the posterior. As ``tests/test_live_widgets.py``, these tests open the widget in headless
Chromium, set its sliders through the test hook and hold every number the page computes
(G, V, M, μ̄, Σ̄, ẑ, H, z, S, K, ν, μ, Σ, log p(z) and the three ellipses) equal to
:func:`probrob.localization.ekf_localization_known_correspondences`,
:func:`probrob.motion.velocity_motion_jacobians`, :mod:`probrob.sensors` and
:func:`probrob.evaluation.covariance_ellipse`, to 1e-9 relative to each array's largest entry,
on named settings (ω = 0 and ω → 0, headings and bearings across ±π, a landmark next to the
robot, sliders at their ends) and on seeded random ones; ``test_the_comparison_is_sharp`` shows
that a kernel with α1 and α2 (or σ_r and σ_φ) swapped, or an unwrapped innovation, would fail
them. Without Chromium they are skipped, unless ``PROBROB_REQUIRE_BROWSER=1`` makes that a
failure.
"""

from __future__ import annotations

import base64
import importlib.util
import json
import math
from pathlib import Path

import numpy as np
import pytest

from probrob.angles import wrap_angle
from probrob.evaluation import chi2_quantile, covariance_ellipse
from probrob.localization import ekf_localization_known_correspondences
from probrob.motion import velocity_motion_jacobians
from probrob.sensors import landmark_measurement, landmark_measurement_jacobian
from probrob.widgets import ekf_step_live

ROOT = Path(__file__).resolve().parent.parent
RTOL = 1e-9
DT, P = 1.0, 0.95  # the widget's defaults
PI = math.pi

_spec = importlib.util.spec_from_file_location(
    "probrob_test_live_widgets_t5_base", ROOT / "tests" / "test_live_widgets.py"
)
_base = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_base)  # the HTML survey and the browser fixture of the first widgets
browser = _base.browser

#: The largest error of each compared quantity over every setting the tests ran (relative to
#: the quantity's largest entry), printed by ``test_parity_summary`` (``-s``).
MAX_ERROR: dict[str, float] = {}


# ------------------------------------------------------------------------------ the HTML


def test_widget_is_one_small_self_contained_accessible_block():
    widget = ekf_step_live()
    config = _base._config(widget)
    html = widget._repr_html_()
    assert len(html.encode()) <= 200_000, f"{len(html.encode())} bytes"
    assert "http:" not in html and "https:" not in html and "//cdn" not in html
    _base._assert_one_block(widget, config, min_parameters=18)
    assert len(config["sliders"]) == 18 and config["choices"] == []
    assert config["constants"] == {"dt": DT, "p": P} and config["n"] == 0


def test_widget_bad_input():
    with pytest.raises(ValueError, match="alpha"):
        ekf_step_live(alpha=[0.1] * 6)
    with pytest.raises(ValueError, match=r"sigmas\[0\]"):
        ekf_step_live(sigmas=(0.0, 0.05))
    with pytest.raises(ValueError, match=r"mu\[2\]"):
        ekf_step_live(mu=(0.0, 0.0, 4.0))
    with pytest.raises(ValueError, match="landmark"):
        ekf_step_live(landmark=(1.0, 2.0, 3.0))
    with pytest.raises(ValueError, match="dt"):
        ekf_step_live(dt=0.0)
    with pytest.raises(ValueError, match="p must"):
        ekf_step_live(p=1.0)


# ------------------------------------------------------------------------------ the browser


@pytest.fixture(scope="module")
def page(browser, tmp_path_factory):
    cdp, b = browser
    path = tmp_path_factory.mktemp("live_t5") / "ekf.html"
    body = ekf_step_live().html
    path.write_text(f"<!doctype html><meta charset='utf-8'><body>{body}</body>", "utf-8")
    tab = cdp.Tab.open(b, path.as_uri())
    tab.configs = [_base._config(ekf_step_live())]
    yield tab
    assert tab.exceptions() == []
    tab.close()


def _floats(b64: str) -> np.ndarray:
    return np.frombuffer(base64.b64decode(b64), "<f8")


def _set(page, values: dict) -> dict:
    """Reset the widget, apply ``values`` through its hook; its values and its scene's arrays."""
    state = page.js(
        "(() => { const w = probrobLive.widgets[0];"
        f" w.set(w.defaults(), true); return w.set({json.dumps(values)}, true); }})()"
    )
    return state["values"], {name: _floats(v) for name, v in state["scene"].items()}


def _reference(p, fault=None):
    """The library's step for the widget's values ``p`` (``fault``: a planted mistake)."""
    alpha = np.array([p["a1"], p["a2"], p["a3"], p["a4"]])
    sr, sphi = p["sr"], p["sphi"]
    if fault == "α1 <-> α2":
        alpha = alpha[[1, 0, 2, 3]]
    if fault == "α3 <-> α4":
        alpha = alpha[[0, 1, 3, 2]]
    if fault == "σ_r <-> σ_φ":
        sr, sphi = sphi, sr
    mu_prev = np.array([p["x0"], p["y0"], p["th0"]])
    Sigma_prev = np.diag(np.square([p["sx"], p["sy"], p["sth"]]))
    u = np.array([p["v"], p["w"]])
    m = np.array([[p["mx"], p["my"], 0.0]])
    sigmas = np.array([sr, sphi, 1.0])  # σ_s unused: the feature is (r, φ)
    mu_bar, Sigma_bar, _ = ekf_localization_known_correspondences(
        mu_prev, Sigma_prev, u, np.zeros((0, 2)), [], m, DT, alpha, sigmas
    )
    G, V = velocity_motion_jacobians(mu_prev, u, DT)
    M = np.diag(
        [alpha[0] * u[0] ** 2 + alpha[1] * u[1] ** 2, alpha[2] * u[0] ** 2 + alpha[3] * u[1] ** 2]
    )
    radius = math.sqrt(chi2_quantile(P, 2))
    ref = {
        "muPrev": mu_prev,
        "SigmaPrev": Sigma_prev.ravel(),
        "G": G.ravel(),
        "V": V.ravel(),
        "M": M.ravel(),
        "muBar": mu_bar,
        "SigmaBar": Sigma_bar.ravel(),
        "radius": np.array([radius]),
    }
    if np.hypot(*(m[0, :2] - mu_bar[:2])) == 0:  # no bearing: the page skips the update
        mu, Sigma = mu_bar, Sigma_bar
        ref.update(updated=np.array([0.0]), logp=np.array([0.0]))
    else:
        zhat = landmark_measurement(mu_bar, m[0, :2])
        H = landmark_measurement_jacobian(mu_bar, m[0, :2])
        S = H @ Sigma_bar @ H.T + np.diag([sr**2, sphi**2])
        K = Sigma_bar @ H.T @ np.linalg.inv(S)
        z = np.array([max(0.0, zhat[0] + p["dr"]), float(wrap_angle(zhat[1] + p["dphi"]))])
        nu = np.array([z[0] - zhat[0], float(wrap_angle(z[1] - zhat[1]))])
        mu, Sigma, logp = ekf_localization_known_correspondences(
            mu_prev, Sigma_prev, u, z[None], [0], m, DT, alpha, sigmas, log=True
        )
        if fault == "innovation not wrapped":  # the deck's line 16 (erratum F4)
            mu = mu_bar + K @ (z - zhat)
            mu[2] = wrap_angle(mu[2])
        ref.update(
            updated=np.array([1.0]),
            zhat=zhat,
            H=H.ravel(),
            z=z,
            S=S.ravel(),
            K=K.ravel(),
            nu=nu,
            logp=np.array([logp]),
        )
    ref.update(mu=mu, Sigma=Sigma.ravel())
    for key, (mean, cov) in {
        "Prior": (mu_prev, Sigma_prev),
        "Bar": (mu_bar, Sigma_bar),
        "Post": (mu, Sigma),
    }.items():
        ref[f"ellipse{key}"] = covariance_ellipse(mean, cov, P, 60)
        ref[f"eig{key}"] = np.linalg.eigh(cov[:2, :2])[0]
    return ref


def _error(js, py):
    """max |js - py| over the largest |py| (1 if py is all zero); angles wrapped."""
    js, py = np.asarray(js, float).ravel(), np.asarray(py, float).ravel()
    assert js.shape == py.shape
    return float(np.max(np.abs(js - py)) / (np.max(np.abs(py)) or 1.0))


def _ellipse_error(js, py, eig):
    """The page's ellipse against covariance_ellipse's, as a set of points: eigh fixes each
    axis only up to its sign, which maps the angles linspace(0, 2π, 61) onto themselves, so
    every page point must be one of the library's (a bijection); for a near circle (axes
    within 1e-6), whose axes are not determined, each point must lie on the library's ellipse."""
    js, py = js.reshape(-1, 2), py.reshape(-1, 2)
    assert js.shape == py.shape == (61, 2)
    scale = np.max(np.abs(py))
    assert np.abs(js[0] - js[-1]).max() <= RTOL * scale  # closed
    if eig[1] - eig[0] > 1e-6 * eig[1]:
        d = np.hypot(*(js[:-1, None, :] - py[None, :-1, :]).T).T  # (60 page, 60 library)
        nearest = d.argmin(axis=1)
        assert sorted(nearest) == list(range(60)), "not a permutation of the library's points"
        return float(d.min(axis=1).max() / scale)
    centre = py[:-1].mean(axis=0)
    radius = np.hypot(*(py[:-1] - centre).T).mean()
    return float(np.abs(np.hypot(*(js - centre).T) - radius).max() / scale)


def _compare(js, ref, what):
    assert set(js) == set(ref) | ({"zhat", "H", "z", "S", "K", "nu"} - set(ref)), what
    errors = {}
    for name, py in ref.items():
        if name.startswith("ellipse"):
            errors[name] = _ellipse_error(js[name], py, ref["eig" + name[7:]])
        elif name in ("muBar", "mu", "muPrev"):  # a heading at ±π may come back as ∓π
            d = js[name] - py
            d[2] = wrap_angle(d[2])
            errors[name] = _error(py + d, py)
        else:
            errors[name] = _error(js[name], py)
    if ref["updated"][0] == 0:
        assert all(np.isnan(js[k]).all() for k in ("zhat", "H", "z", "S", "K", "nu")), what
    for name, err in errors.items():
        MAX_ERROR[name] = max(MAX_ERROR.get(name, 0.0), err)
    bad = {k: e for k, e in errors.items() if not e <= RTOL}
    assert not bad, f"{what}: {bad}"
    return errors


SETTINGS = {
    "the widget as shipped": {},
    "straight line (ω = 0)": dict(w=0.0),
    "ω → 0 (1e-9: sinc and its series)": dict(w=1e-9),
    "ω → 0 (-1e-4)": dict(w=-1e-4, v=1.7),
    "ω Δt / 2 just above the series' 0.1": dict(w=0.25),
    "turning on the spot (v = 0)": dict(v=0.0, w=1.5),
    "reversing left turn": dict(v=-1.3, w=0.9, th0=-2.0),
    "start heading near π, the predicted heading past π": dict(th0=3.14, v=0.8, w=0.9),
    "start heading near -π, turning right past -π": dict(th0=-3.14, v=1.2, w=-0.7, mx=-4.0),
    "bearing across ±π: the landmark right behind, measured across the cut": dict(
        v=0.0, w=0.0, mx=-3.0, my=0.01, dphi=0.05
    ),
    "bearing across ±π the other way": dict(v=0.0, w=0.0, mx=-3.0, my=-0.01, dphi=-0.05),
    "bearing across ±π after a turn past π": dict(
        th0=3.0, v=0.5, w=0.6, mx=2.2, my=1.4, dphi=-0.1
    ),
    "distinct α, σ at their smallest": dict(
        a1=0.11, a2=0.03, a3=0.07, a4=0.19, sr=0.01, sphi=0.005, sx=0.01, sy=0.01, sth=0.01
    ),
    "all α = 0: Σ̄ = G Σ Gᵀ": dict(a1=0.0, a2=0.0, a3=0.0, a4=0.0),
    "a round prior (σx = σy)": dict(sx=0.3, sy=0.3),
    "landmark 5 cm from the prediction": dict(v=0.0, w=0.0, mx=0.05, my=0.0),
    "negative measured range clamped at 0": dict(v=0.0, w=0.0, mx=0.3, my=0.0, dr=-1.0),
    "every slider at its top": dict(
        x0=3.0, y0=3.0, th0=3.14, sx=1.0, sy=1.0, sth=1.0, v=2.0, w=2.0, a1=0.5, a2=0.5,
        a3=0.5, a4=0.5, mx=5.0, my=5.0, sr=1.0, sphi=0.5, dr=1.0, dphi=0.5,
    ),
    "every slider at its bottom": dict(
        x0=-3.0, y0=-3.0, th0=-3.14, sx=0.01, sy=0.01, sth=0.01, v=-2.0, w=-2.0, a1=0.0,
        a2=0.0, a3=0.0, a4=0.0, mx=-5.0, my=-5.0, sr=0.01, sphi=0.005, dr=-1.0, dphi=-0.5,
    ),
}  # fmt: skip


@pytest.mark.parametrize("name", list(SETTINGS))
def test_widget_computes_what_probrob_computes(page, name):
    p, js = _set(page, SETTINGS[name])
    ref = _reference(p)
    _compare(js, ref, name)
    if ref["updated"][0]:
        # not vacuous: the measurement corrects the prediction and shrinks its ellipse
        assert np.linalg.det(ref["Sigma"].reshape(3, 3)) < np.linalg.det(
            ref["SigmaBar"].reshape(3, 3)
        )


def test_the_named_settings_reach_the_cases_they_name(page):
    """ω = 0 and ω → 0 agree; the ±π settings really put ẑ and z on both sides of the cut."""
    _, straight = _set(page, SETTINGS["straight line (ω = 0)"])
    _, almost = _set(page, SETTINGS["ω → 0 (1e-9: sinc and its series)"])
    assert _error(almost["SigmaBar"], straight["SigmaBar"]) < 1e-8
    assert _error(almost["V"], straight["V"]) < 1e-8
    crossings = 0
    for name in [n for n in SETTINGS if "across ±π" in n]:
        p, js = _set(page, SETTINGS[name])
        zhat, z, nu = js["zhat"][1], js["z"][1], js["nu"][1]
        assert abs(zhat) > PI - 0.6 and np.sign(z) != np.sign(zhat), name
        assert abs(nu) < 0.5 < abs(z - zhat), name  # the raw difference is nearly 2π
        crossings += 1
    assert crossings == 3
    p, js = _set(page, SETTINGS["start heading near π, the predicted heading past π"])
    assert p["th0"] + p["w"] * DT > PI and js["muBar"][2] < 0  # wrapped once
    p, js = _set(page, SETTINGS["negative measured range clamped at 0"])
    assert js["z"][0] == 0.0


@pytest.mark.parametrize("trial", range(40))
def test_widget_computes_what_probrob_computes_anywhere_on_the_sliders(page, trial):
    """40 seeded random settings: every slider uniform on its range (at an end with
    probability 1/5)."""
    rng = np.random.default_rng([5, trial])
    config = page.js("probrobLive.widgets[0].config()")
    values = {}
    for s in config["sliders"]:
        u = rng.random()
        end = rng.random() < 0.2
        values[s["name"]] = float(
            (s["min"] if u < 0.5 else s["max"]) if end else s["min"] + u * (s["max"] - s["min"])
        )
    p, js = _set(page, values)
    _compare(js, _reference(p), f"trial {trial}: {values}")


def test_the_comparison_is_sharp(page):
    """Each planted mistake in the reference breaks the parity by far more than its tolerance:
    a kernel with α1 and α2 or α3 and α4 swapped, σ_r and σ_φ swapped, or the deck's unwrapped
    innovation, would fail the tests above."""
    distinct = dict(a1=0.11, a2=0.03, a3=0.07, a4=0.19, v=1.3, w=0.6, sr=0.2, sphi=0.05)
    p, js = _set(page, distinct)
    _compare(js, _reference(p), "distinct values")
    for fault in ("α1 <-> α2", "α3 <-> α4", "σ_r <-> σ_φ"):
        ref = _reference(p, fault)
        worst = max(_error(js[k], ref[k]) for k in ("SigmaBar", "mu", "Sigma"))
        assert worst > 1e3 * RTOL, fault
        with pytest.raises(AssertionError):
            _compare(js, ref, fault)
    p, js = _set(
        page, SETTINGS["bearing across ±π: the landmark right behind, measured across the cut"]
    )
    ref = _reference(p, "innovation not wrapped")
    assert _error(js["mu"], ref["mu"]) > 1e3 * RTOL
    with pytest.raises(AssertionError):
        _compare(js, ref, "innovation not wrapped")


def test_keyboard_moves_a_slider_and_redraws(page):
    page.js("probrobLive.widgets[0].set(probrobLive.widgets[0].defaults(), true)")
    for param in ("sphi", "x0", "dphi"):
        before = page.js(_base.JS_CANVAS_HASH % 0)
        root = "document.querySelectorAll('.probrob-live')[0]"
        value = page.js(f"probrobLive.widgets[0].values().{param}")
        step = page.js(
            f"Number({root}.querySelector('input[type=range][data-param={param}]').step)"
        )
        page.js(f"{root}.querySelector('input[type=range][data-param={param}]').focus()")
        for _ in range(5):
            page.key("ArrowRight", "ArrowRight", 39)
        page.js("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
        values = page.js("probrobLive.widgets[0].values()")
        assert values[param] == pytest.approx(value + 5 * step)
        shown = page.js(f"{root}.querySelector('input[type=number][data-param={param}]').value")
        assert float(shown) == pytest.approx(values[param])
        assert page.js(_base.JS_CANVAS_HASH % 0) != before, param


def test_widget_updates_within_the_budget(page):
    """The browser check's budget (16 ms median per update), here with a margin for a busy CI."""
    bench = page.js("probrobLive.widgets[0].bench(100)", timeout=120)
    MAX_ERROR["bench median ms"] = bench["total"]["median"]
    MAX_ERROR["bench p90 ms"] = bench["total"]["p90"]
    assert bench["total"]["median"] < 4 * 16.0, bench


def test_parity_summary():
    """Prints the largest error of every compared array over the tests above (run with -s)."""
    if not MAX_ERROR:
        pytest.skip("no browser test ran")
    print("\nekf_step_live, largest error over all settings:")
    for name, err in sorted(MAX_ERROR.items()):
        print(f"  {name:16s} {err:.3g}")
    assert max(e for k, e in MAX_ERROR.items() if "ms" not in k) <= RTOL


def test_controls_mode_and_width(page):
    """The controls built from the spec; the dark mode; the legend below the plot on a phone
    (the plot keeps 250 CSS px and more), beside it on a desktop."""
    _base.assert_controls_built_from_the_spec(page, page.configs)
    try:
        dark = page.js(_base.JS_MODE % json.dumps("dark"))[0]
        assert dark["mode"] == "dark" and _base._luminance(dark["corner"]) < 60
        assert "white square" in dark["caption"]
    finally:
        page.js(_base.JS_MODE % "null")
    narrow, wide = _base.plots_on_phone_and_desktop(page)
    _base.assert_plots_fit(narrow + wide)
    # the legend: below the plot (a taller canvas) on the phone, beside it on the desktop
    (_, _, w, _), (css_w, css_h) = narrow[0]["plots"][0], narrow[0]["css"]
    assert css_h > css_w + 100 and w > 0.75 * css_w
    (x, _, w, _), (css_w, _) = wide[0]["plots"][0], wide[0]["css"]
    assert css_w - (x + w) > 100
