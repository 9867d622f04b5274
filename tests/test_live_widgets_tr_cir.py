"""Live widgets of the Turkish lecture's noise forms and of the CIR report's step (issue 17).

``velocity_noise_forms_live`` / ``odometry_noise_forms_live`` draw the velocity and odometry
kernels (``velocity.js``, ``odometry.js``, unchanged) twice side by side, ``noise="std"`` at the
sliders' α and ``noise="variance"`` at α² (or the same α); ``cir_step_live`` computes the CIR
report's step (``cir.js``). As ``tests/test_live_widgets.py``, the tests open the widgets in
headless Chromium, set parameters through the test hook and hold the JavaScript equal to
:mod:`probrob.motion` and :mod:`probrob.kinematics` to a relative 1e-9, value by value, on named
settings (straight line, rotation in place, headings and turns near ±π) and on seeded random
ones. Without Chromium they are skipped, unless ``PROBROB_REQUIRE_BROWSER=1`` makes that a
failure.
"""

from __future__ import annotations

import base64
import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

from probrob.distributions import prob_normal_distribution, prob_triangular_distribution
from probrob.kinematics import (
    cir_pose_matrix,
    cir_radius_angle,
    cir_state_function,
    cir_step_transform,
)
from probrob.live import standard_draws
from probrob.motion import (
    apply_odometry_deltas,
    motion_model_odometry,
    motion_model_velocity,
    sample_motion_model_odometry,
    sample_motion_model_velocity,
)
from probrob.widgets import (
    cir_step_live,
    odometry_noise_forms_live,
    velocity_noise_forms_live,
)

ROOT = Path(__file__).resolve().parent.parent
PROB = {"normal": prob_normal_distribution, "triangular": prob_triangular_distribution}
RTOL = 1e-9
N, GRID, SEED = 1000, 70, 0  # the widgets' defaults
PI = np.pi

_spec = importlib.util.spec_from_file_location(
    "probrob_test_live_widgets", ROOT / "tests" / "test_live_widgets.py"
)
_base = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_base)  # the HTML survey and the browser fixture of the first widgets
browser = _base.browser
_replay, _hypotheses, _assert_parity = _base._replay, _base._hypotheses, _base._assert_parity

MAKERS = [velocity_noise_forms_live, odometry_noise_forms_live, cir_step_live]


# ------------------------------------------------------------------------------ the HTML


@pytest.mark.parametrize("make", MAKERS)
def test_widget_is_one_small_self_contained_accessible_block(make):
    widget = make()
    config = _base._config(widget)
    html = widget._repr_html_()
    assert len(html.encode()) <= 200_000, f"{len(html.encode())} bytes"
    assert "http:" not in html and "https:" not in html and "//cdn" not in html
    _base._assert_one_block(widget, config, min_parameters=4)


def test_one_implementation_per_model():
    """The forms widgets inline the motion kernels' own files, not a second copy of them."""
    from probrob.live.core import inlined

    for make, base in [
        (velocity_noise_forms_live, "velocity"),
        (odometry_noise_forms_live, "odometry"),
    ]:
        html = make().html
        assert (
            html.count(inlined(f"{base}.js")) == 1 and html.count(inlined("noise_forms.js")) == 1
        )
        assert html.count(f"kernels.{base} = {{") == 1


def test_widget_bad_input():
    with pytest.raises(ValueError, match="pairing"):
        velocity_noise_forms_live(pairing="sqrt")
    with pytest.raises(ValueError, match="alpha"):
        odometry_noise_forms_live(alpha=[0.1] * 6)
    with pytest.raises(ValueError, match="s_dx"):
        cir_step_live(s_dx=2.0)
    with pytest.raises(ValueError, match="wheelbase"):
        cir_step_live(wheelbase=0.0)
    with pytest.raises(ValueError, match="requires"):
        _base.live_widget(
            "velocity_forms", [], title="t", caption="c", aria_label="a", requires=("nope",)
        )


# ------------------------------------------------------------------------------ the browser


@pytest.fixture(scope="module")
def page(browser, tmp_path_factory):
    """A page with the velocity forms (index 0), the odometry forms (1) and the CIR (2) widget."""
    cdp, b = browser
    widgets = [
        velocity_noise_forms_live(n_particles=N, grid=GRID, rng=SEED),
        odometry_noise_forms_live(n_particles=N, grid=GRID, rng=SEED),
        cir_step_live(),
    ]
    path = tmp_path_factory.mktemp("live_tr_cir") / "widgets.html"
    body = "\n".join(w.html for w in widgets)
    path.write_text(f"<!doctype html><meta charset='utf-8'><body>{body}</body>", "utf-8")
    tab = cdp.Tab.open(b, path.as_uri())
    tab.configs = [_base._config(w) for w in widgets]
    yield tab
    assert tab.exceptions() == []
    tab.close()


def _floats(b64: str) -> np.ndarray:
    return np.frombuffer(base64.b64decode(b64), "<f8")


def _set(page, index: int, values: dict) -> dict:
    """Reset the widget, apply ``values`` through its hook, and decode its state by panel."""
    state = page.js(
        f"(() => {{ const w = probrobLive.widgets[{index}];"
        f" w.set(w.defaults(), true); return w.set({json.dumps(values)}, true); }})()"
    )
    for key in ("xs", "ys", "particles", "density"):
        state[key] = _floats(state[key])
    k = state["panels"]
    state["particles"] = state["particles"].reshape(k, state["n"], 3)
    state["density"] = state["density"].reshape(k, state["ny"], state["nx"])
    state["scene"] = {name: _floats(v) for name, v in state["scene"].items()}
    return state


def _forms(p, count):
    """The two panels' (noise, α): std at the sliders' α, variance at α² or the same α."""
    alpha = np.array([p[f"a{k}"] for k in range(1, count + 1)])
    return [("std", alpha), ("variance", alpha**2 if p["pairing"] == "squared" else alpha)]


def _velocity_reference(state):
    p = state["values"]
    u, x_prev = [p["v"], p["w"]], [0.0, 0.0, p["theta"]]
    out = []
    for noise, alpha in _forms(p, 6):
        z = standard_draws(N, SEED)[p["distribution"]]
        samples = sample_motion_model_velocity(
            u, x_prev, p["dt"], alpha, sample=_replay(z), noise=noise, size=N
        )
        density = motion_model_velocity(
            _hypotheses(state, p["density"]),
            u,
            x_prev,
            p["dt"],
            alpha,
            prob=PROB[p["distribution"]],
            noise=noise,
            density=p["density"],
        )
        out.append((samples, density))
    return out


def _odometry_reference(state):
    p = state["values"]
    origin = np.zeros(3)
    u = np.stack([origin, apply_odometry_deltas(origin, p["rot1"], p["trans"], p["rot2"])])
    x_prev = [0.0, 0.0, p["theta"]]
    out = []
    for noise, alpha in _forms(p, 4):
        z = standard_draws(N, SEED)[p["distribution"]]
        samples = sample_motion_model_odometry(
            u, x_prev, alpha, sample=_replay(z), noise=noise, size=N
        )
        density = motion_model_odometry(
            _hypotheses(state, p["density"]),
            u,
            x_prev,
            alpha,
            prob=PROB[p["distribution"]],
            noise=noise,
            density=p["density"],
        )
        out.append((samples, density))
    return out


def _assert_forms(state, reference, what):
    for k, (samples, density) in enumerate(reference):
        form = ("std", "variance")[k]
        _assert_parity(state["particles"][k], samples, f"{what}, {form}: particles")
        _assert_parity(state["density"][k], density, f"{what}, {form}: density")


VELOCITY_ALPHA = dict(a1=0.11, a2=0.07, a3=0.09, a4=0.13, a5=0.05, a6=0.03)
VELOCITY_SETTINGS = {
    "the widget as shipped (α², normal, xy)": {},
    "distinct α": VELOCITY_ALPHA,
    "same α, triangular, pose density": dict(
        VELOCITY_ALPHA, pairing="same", distribution="triangular", density="pose"
    ),
    "straight line (ω = 0): one term per sum, the forms coincide": dict(VELOCITY_ALPHA, w=0),
    "turning on the spot (v = 0), book value": dict(VELOCITY_ALPHA, v=0, w=1.5, density="book"),
    "start heading near π, reversing right turn": dict(
        VELOCITY_ALPHA, theta=3.14, v=-1.2, w=-1.4, dt=1.7
    ),
    "start heading near -π, large α": dict(theta=-3.14, a1=0.5, a2=0.5, a3=0.4, a4=0.3),
}


@pytest.mark.parametrize("name", list(VELOCITY_SETTINGS))
def test_velocity_forms_widget_computes_what_probrob_computes(page, name):
    state = _set(page, 0, VELOCITY_SETTINGS[name])
    reference = _velocity_reference(state)
    _assert_forms(state, reference, name)
    (std, _), (var, _) = reference
    assert std[:, :2].std(axis=0).min() > 1e-3  # not vacuous: two clouds
    p = state["values"]
    if p["pairing"] == "squared" and (p["v"] == 0 or p["w"] == 0):
        # one term per sum: α|m| as a std is √(α²m²) as a variance, the same noise
        np.testing.assert_allclose(std, var, rtol=1e-12, atol=1e-12)
    elif p["pairing"] == "squared":
        assert np.ptp(std[:, 0]) > np.ptp(var[:, 0])  # a sum of two terms: the std form wider


ODOMETRY_ALPHA = dict(a1=0.21, a2=0.08, a3=0.17, a4=0.12)
ODOMETRY_SETTINGS = {
    "the widget as shipped (α², normal, xy)": {},
    "distinct α, triangular": dict(ODOMETRY_ALPHA, distribution="triangular"),
    "same α, pose density": dict(ODOMETRY_ALPHA, pairing="same", density="pose"),
    "rotation in place (δtrans = 0)": dict(ODOMETRY_ALPHA, trans=0, rot1=0.5, rot2=0.3),
    "straight ahead (δrot1 = δrot2 = 0), book value": dict(
        ODOMETRY_ALPHA, rot1=0, rot2=0, density="book"
    ),
    "rotations and heading near ±π": dict(
        ODOMETRY_ALPHA, theta=3.13, rot1=3.1, trans=0.8, rot2=-3.12, density="pose"
    ),
    "first turn near -π, book value": dict(
        ODOMETRY_ALPHA, theta=-3.1, rot1=-3.14, rot2=1.0, density="book"
    ),
}


@pytest.mark.parametrize("name", list(ODOMETRY_SETTINGS))
def test_odometry_forms_widget_computes_what_probrob_computes(page, name):
    state = _set(page, 1, ODOMETRY_SETTINGS[name])
    reference = _odometry_reference(state)
    _assert_forms(state, reference, name)
    (std, dens_std), _ = reference
    assert std[:, :2].std(axis=0).max() > 1e-3  # a cloud; a line when δtrans = 0 (no δrot1 noise)
    if state["values"]["trans"] > 0:
        assert np.nanmax(dens_std) > 0


def _cir_reference(state):
    """probrob.kinematics for the widget's step: r, α, T, the end pose, the CIR, the paths."""
    p = state["values"]
    u, ell, x0 = np.array([p["ssx"], p["sdx"]]), p["l"], np.array([0.0, 0.0, p["theta"]])
    r, alpha = cir_radius_angle(u, ell)
    frac = np.linspace(0.0, 1.0, 61)
    mid = cir_state_function(x0, frac[:, None] * u, ell)  # as the chapter's draw_step traces it
    frames = cir_pose_matrix(mid)
    cir = (
        (cir_pose_matrix(x0) @ [0.0, -(r + ell / 2), 1.0])[:2]
        if np.isfinite(r)
        else np.full(2, np.nan)
    )
    return {
        "r": np.array([r]),
        "alpha": np.array([alpha]),
        "rho": np.array([r + ell / 2]),
        "step": cir_step_transform(u, ell).ravel(),
        "pose": cir_state_function(x0, u, ell),
        "cir": cir,
        "frac": frac,
        "mid": mid.ravel(),
        "left": (frames @ [0.0, ell / 2, 1.0])[:, :2].ravel(),
        "right": (frames @ [0.0, -ell / 2, 1.0])[:, :2].ravel(),
    }


def _assert_cir(state, what):
    ref = _cir_reference(state)
    js = state["scene"]
    assert set(js) == set(ref), what
    for name, py in ref.items():
        _assert_parity(js[name], py, f"{what}: {name}")
    return ref


L = 0.4
CIR_SETTINGS = {
    "the widget as shipped (a right turn)": {},
    "straight line (s_sx = s_dx)": dict(ssx=0.7, sdx=0.7),
    "straight backwards": dict(ssx=-0.8, sdx=-0.8),
    "rotation in place (s_dx = -s_sx)": dict(ssx=0.45, sdx=-0.45, theta=0.7),
    "pivot on the right wheel (s_dx = 0)": dict(ssx=0.6, sdx=0.0),
    "left turn, CIR on the left": dict(ssx=0.3, sdx=0.9, l=0.55),
    "half a turn right (α = π)": dict(ssx=PI * L, sdx=0.0, l=L),
    "half a turn left (α = -π), start heading near -π": dict(
        ssx=0.1, sdx=0.1 + PI * L, l=L, theta=-3.14
    ),
    "start heading near π, reversing": dict(ssx=-0.9, sdx=-0.4, theta=3.14, l=0.25),
    "almost straight (s_sx - s_dx = 1e-6)": dict(ssx=0.5 + 1e-6, sdx=0.5),
}


@pytest.mark.parametrize("name", list(CIR_SETTINGS))
def test_cir_widget_computes_what_probrob_computes(page, name):
    state = _set(page, 2, CIR_SETTINGS[name])
    ref = _assert_cir(state, name)
    p = state["values"]
    if p["ssx"] == p["sdx"]:  # eq. 7: a translation, no CIR
        assert np.isinf(ref["r"][0]) and np.isnan(state["scene"]["cir"]).all()
        np.testing.assert_allclose(
            ref["pose"][:2], p["ssx"] * np.array([np.cos(p["theta"]), -np.sin(p["theta"])])
        )
    else:  # both wheels and the axle's middle keep their distance to the CIR
        for path in ("left", "right"):
            d = np.hypot(*(ref[path].reshape(-1, 2) - ref["cir"]).T)
            assert np.ptp(d) < 1e-9 * max(1, d.max()), f"{name}: {path} on a circle"
    if p["sdx"] == -p["ssx"]:  # the spin: the CIR is the middle of the axle
        assert abs(ref["rho"][0]) < 1e-12
        np.testing.assert_allclose(ref["pose"][:2], 0, atol=1e-12)


@pytest.mark.parametrize("index", [0, 1, 2])
def test_widgets_compute_what_probrob_computes_anywhere_on_the_sliders(page, index):
    """8 seeded random settings per widget: every slider uniform on its range (and at an end
    with probability 1/5), every choice uniform."""
    rng = np.random.default_rng(200 + index)
    config = page.js(f"probrobLive.widgets[{index}].config()")
    for trial in range(8):
        values = {}
        for s in config["sliders"]:
            u = rng.random()
            end = rng.random() < 0.2
            values[s["name"]] = float(
                (s["min"] if u < 0.5 else s["max"])
                if end
                else s["min"] + u * (s["max"] - s["min"])
            )
        for c in config["choices"]:
            values[c["name"]] = str(rng.choice(c["options"]))
        state = _set(page, index, values)
        what = f"widget {index}, trial {trial}, {values}"
        if index == 2:
            _assert_cir(state, what)
        else:
            reference = (_velocity_reference, _odometry_reference)[index](state)
            _assert_forms(state, reference, what)


@pytest.mark.parametrize("index,param", [(0, "a1"), (1, "a1"), (2, "sdx"), (2, "l")])
def test_keyboard_moves_a_slider_and_redraws(page, index, param):
    page.js(f"probrobLive.widgets[{index}].set(probrobLive.widgets[{index}].defaults(), true)")
    before = page.js(_base.JS_CANVAS_HASH % index)
    root = f"document.querySelectorAll('.probrob-live')[{index}]"
    value = page.js(f"probrobLive.widgets[{index}].values().{param}")
    step = page.js(f"Number({root}.querySelector('input[type=range][data-param={param}]').step)")
    page.js(f"{root}.querySelector('input[type=range][data-param={param}]').focus()")
    for _ in range(10):
        page.key("ArrowRight", "ArrowRight", 39)
    page.js("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    values = page.js(f"probrobLive.widgets[{index}].values()")
    assert values[param] == pytest.approx(value + 10 * step)
    shown = page.js(f"{root}.querySelector('input[type=number][data-param={param}]').value")
    assert float(shown) == pytest.approx(values[param])
    assert page.js(_base.JS_CANVAS_HASH % index) != before


def test_keyboard_reaches_the_straight_line(page):
    """From s_dx = 0.3 thirty steps of 0.01 reach s_dx = s_sx = 0.6: eq. 7's straight line."""
    page.js("probrobLive.widgets[2].set(probrobLive.widgets[2].defaults(), true)")
    page.js(
        "document.querySelectorAll('.probrob-live')[2].querySelector('input[type=range][data-param=sdx]').focus()"
    )
    for _ in range(30):
        page.key("ArrowRight", "ArrowRight", 39)
    page.js("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    state = page.js("probrobLive.widgets[2].state()")
    assert state["values"]["sdx"] == state["values"]["ssx"] == 0.6
    assert np.isinf(_floats(state["scene"]["r"])[0])


def test_widgets_update_within_the_budget(page):
    """The browser check's budget (16 ms median per update), here with a margin for a busy CI."""
    for index in range(3):
        bench = page.js(f"probrobLive.widgets[{index}].bench(30)", timeout=120)
        assert bench["total"]["median"] < 4 * 16.0, (index, bench)


def test_controls_and_dark_mode(page):
    _base.assert_controls_built_from_the_spec(page, page.configs)
    try:
        dark = page.js(_base.JS_MODE % json.dumps("dark"))
    finally:
        page.js(_base.JS_MODE % "null")
    for w in dark:
        assert w["mode"] == "dark" and _base._luminance(w["corner"]) < 60
    assert "white arrow" in dark[0]["caption"] and "white: after" in dark[2]["caption"]


def test_two_panels_stack_on_a_phone(page):
    """The Turkish lecture's two noise forms: side by side on a desktop column (each plot at
    least 250 CSS px), one above the other on a phone instead of two plots of 69 px; the CIR
    step's legend moves below its plot there."""
    narrow, wide = _base.plots_on_phone_and_desktop(page)
    _base.assert_plots_fit(narrow + wide)
    for k in (0, 1):
        (x0, y0, w0, _), (x1, y1, w1, _) = narrow[k]["plots"]
        assert x0 == x1 and y1 > y0 + w0 and w0 == w1  # stacked, as wide as each other
        (x0, y0, w0, _), (x1, y1, _, _) = wide[k]["plots"]
        assert y0 == y1 and x1 > x0 + w0  # side by side
    assert narrow[2]["css"][1] > narrow[2]["css"][0] + 100  # the CIR's legend below its plot
