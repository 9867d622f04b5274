"""Live widgets (probrob.live): the HTML block, and its JavaScript held equal to probrob.

The JavaScript kernels are a second implementation of Tables 5.1, 5.3, 5.5 and 5.6. The parity
tests open the widgets in headless Chromium (the DevTools-pipe driver of ``.ci/cdp.py``), set
parameters through the widgets' test hook, read back the particles and the density grid, and
compare them with :mod:`probrob.motion` fed the same standardized draws: to a relative 1e-9,
value by value. Without Chromium they are skipped with a message, unless
``PROBROB_REQUIRE_BROWSER=1`` (CI) makes that a failure.
"""

from __future__ import annotations

import base64
import importlib.util
import json
import os
import re
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

from probrob.distributions import (
    prob_normal_distribution,
    prob_triangular_distribution,
    sample_normal_distribution,
)
from probrob.live import LiveWidget, landmark_draws, standard_draws
from probrob.motion import (
    apply_odometry_deltas,
    motion_model_odometry,
    motion_model_velocity,
    sample_motion_model_odometry,
    sample_motion_model_velocity,
)
from probrob.sensors import (
    BeamModelParams,
    beam_mixture,
    landmark_model_known_correspondence,
    sample_landmark_model_known_correspondence,
)
from probrob.widgets import (
    beam_model_live,
    distribution_live,
    landmark_model_live,
    live_widget,
    odometry_model_live,
    velocity_model_live,
)

ROOT = Path(__file__).resolve().parent.parent
PROB = {"normal": prob_normal_distribution, "triangular": prob_triangular_distribution}
RTOL = 1e-9
N, GRID, SEED = 2000, 100, 0


# ------------------------------------------------------------------------------ the HTML


class _Survey(HTMLParser):
    def __init__(self):
        super().__init__()
        self.labels: set[str] = set()
        self.controls: list[dict] = []
        self.canvases: list[dict] = []
        self.fetching: list[tuple[str, str]] = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "label" and a.get("for"):
            self.labels.add(a["for"])
        if tag in ("input", "select"):
            self.controls.append(a)
        if tag == "canvas":
            self.canvases.append(a)
        for key in ("src", "href", "srcset", "data"):
            if key in a:
                self.fetching.append((tag, key))


def _config(widget: LiveWidget) -> dict:
    match = re.search(r"const config = (\{.*?\});\n", widget.html)
    return json.loads(match.group(1))


@pytest.mark.parametrize(
    "make",
    [
        velocity_model_live,
        odometry_model_live,
        landmark_model_live,
        distribution_live,
        beam_model_live,
    ],
)
def test_widget_is_one_small_self_contained_accessible_block(make):
    widget = make()
    config = _config(widget)
    html = widget._repr_html_()
    assert len(html.encode()) <= 200_000, f"{len(html.encode())} bytes"
    assert "http:" not in html and "https:" not in html and "//cdn" not in html
    _assert_one_block(widget, config, min_parameters=2)
    assert re.fullmatch(r"<probrob live widget: \w+ model, \d+ kB of HTML>", repr(widget))


def _assert_one_block(widget, config, min_parameters):
    """One block that loads nothing, with a labelled canvas and a spec of labelled parameters
    (the runtime builds the controls from it: ``test_controls_are_built_from_the_spec``)."""
    survey = _Survey()
    survey.feed(widget.html)
    assert survey.fetching == []  # no src/href: nothing loaded from anywhere
    assert survey.controls == []  # the controls are the runtime's, from the spec
    parameters = config["sliders"] + config["choices"]
    assert len(parameters) >= min_parameters
    assert all(p["label"] for p in parameters)
    assert len(survey.canvases) == 1 and survey.canvases[0].get("aria-label")
    assert "<script>" in widget.html and "mountLiveWidget" in widget.html


def test_widget_embeds_the_seeded_standardized_draws():
    config = _config(velocity_model_live(n_particles=N, rng=SEED))
    draws = standard_draws(N, SEED)
    assert set(config["draws"]) == set(draws) == {"normal", "triangular"}
    for name, z in draws.items():
        embedded = np.frombuffer(base64.b64decode(config["draws"][name]), "<f8").reshape(3, N)
        np.testing.assert_array_equal(embedded, z)
        # ε = b·z has variance b² only if z has variance 1 (both samplers are exact in it)
        assert abs(z.var() - 1) < 0.05 and abs(z.mean()) < 0.05
    assert np.all(np.abs(draws["normal"]) <= 6) and np.all(np.abs(draws["triangular"]) <= 6**0.5)
    # seeded: the same draws every time, other draws for another seed
    np.testing.assert_array_equal(standard_draws(N, SEED)["normal"], draws["normal"])
    assert not np.array_equal(standard_draws(N, SEED + 1)["normal"], draws["normal"])


def test_widget_bad_input():
    with pytest.raises(ValueError, match="alpha"):
        velocity_model_live(alpha=[0.1] * 4)
    with pytest.raises(ValueError, match="alpha"):
        odometry_model_live(alpha=[0.1, -0.1, 0.1, 0.1])
    with pytest.raises(ValueError, match="w"):
        velocity_model_live(w=5.0)
    with pytest.raises(ValueError, match="trans"):
        odometry_model_live(trans=-1.0)
    with pytest.raises(ValueError, match="distribution"):
        velocity_model_live(distribution="cauchy")
    with pytest.raises(ValueError, match="density"):
        odometry_model_live(density="joint")
    with pytest.raises(ValueError, match="n_particles"):
        velocity_model_live(n_particles=0)
    with pytest.raises(ValueError, match="kernel"):
        live_widget("ackermann", [], title="t", caption="c", aria_label="a")
    with pytest.raises(ValueError, match="n"):
        standard_draws(-3)
    with pytest.raises(ValueError, match="sigmas"):
        landmark_model_live(sigmas=[0.1, 0.1])
    with pytest.raises(ValueError, match="draws"):
        live_widget(
            "velocity", [], title="t", caption="c", aria_label="a", draws={"normal": np.ones(3)}
        )


# ------------------------------------------------------------------------------ the browser


def _load_cdp():
    spec = importlib.util.spec_from_file_location("probrob_ci_cdp", ROOT / ".ci" / "cdp.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def browser():
    cdp = _load_cdp()
    try:
        executable = cdp.find_chromium(None)
    except cdp.CheckError:
        message = (
            "Chromium not found: the live widgets' JavaScript-vs-probrob parity tests need it "
            "(apt-get install chromium); CI installs it and runs them"
        )
        if os.environ.get("PROBROB_REQUIRE_BROWSER") == "1":
            pytest.fail(message)
        pytest.skip(message)
    b = cdp.Browser(executable, timeout=60)
    try:
        yield cdp, b
    finally:
        b.close()


@pytest.fixture(scope="module")
def page(browser, tmp_path_factory):
    """A page with a velocity (index 0), an odometry (1), a landmark (2), a Table 5.2 (3) and
    a beam model (4) widget."""
    cdp, b = browser
    widgets = [
        velocity_model_live(n_particles=N, grid=GRID, rng=SEED),
        odometry_model_live(n_particles=N, grid=GRID, rng=SEED),
        landmark_model_live(n_particles=N, grid=GRID, rng=SEED),
        distribution_live(n_particles=N, grid=200, rng=SEED),
        beam_model_live(),
    ]
    path = tmp_path_factory.mktemp("live") / "widgets.html"
    body = "\n".join(w.html for w in widgets)
    path.write_text(f"<!doctype html><meta charset='utf-8'><body>{body}</body>", "utf-8")
    tab = cdp.Tab.open(b, path.as_uri())
    tab.configs = [_config(w) for w in widgets]
    yield tab
    assert tab.exceptions() == []
    tab.close()


def _floats(b64: str) -> np.ndarray:
    return np.frombuffer(base64.b64decode(b64), "<f8")


def _set(page, index: int, values: dict) -> dict:
    """Reset the widget, apply ``values`` through its hook, and decode its state."""
    state = page.js(
        f"(() => {{ const w = probrobLive.widgets[{index}];"
        f" w.set(w.defaults(), true); return w.set({json.dumps(values)}, true); }})()"
    )
    for key in ("xs", "ys", "particles", "density"):
        state[key] = _floats(state[key])
    if state["n"]:
        state["particles"] = state["particles"].reshape(state["n"], -1).squeeze()
    state["density"] = state["density"].reshape(state["ny"], state["nx"])
    if state["ny"] == 1:  # a curve: one value per xs
        state["density"] = state["density"][0]
    return state


def _replay(z: np.ndarray):
    """A Table 5.4 sampler that returns sqrt(b2) times the next row of ``z``, as the widget."""
    rows = iter(z)

    def sample(b2, size=None, rng=None):
        row = next(rows)
        assert size == row.shape
        return np.sqrt(b2) * row

    return sample


def _hypotheses(state, mode):
    xy = np.stack(np.meshgrid(state["xs"], state["ys"]), axis=-1)
    if mode == "xy":
        return xy
    return np.concatenate([xy, np.full((*xy.shape[:-1], 1), state["theta"])], axis=-1)


def _assert_parity(js, py, what):
    assert js.shape == py.shape, what
    np.testing.assert_allclose(js, py, rtol=RTOL, atol=0, err_msg=what)


# Six different α (and four), so that a swap of any two in a kernel changes its output.
VELOCITY_ALPHA = dict(a1=0.031, a2=0.012, a3=0.023, a4=0.008, a5=0.017, a6=0.005)
ODOMETRY_ALPHA = dict(a1=0.06, a2=0.004, a3=0.045, a4=0.009)

VELOCITY_SETTINGS = {
    "the widget as shipped (normal, variance, xy)": {},
    "distinct α (normal, variance, xy)": VELOCITY_ALPHA,
    "straight line (ω = 0), std form, pose density": dict(
        w=0, noise="std", density="pose", a1=0.1, a2=0.05, a3=0.02, a4=0.05, a5=0.02, a6=0.01
    ),
    "some α = 0, book value": dict(a1=0.05, a2=0, a3=0.03, a4=0, a5=0, a6=0.02, density="book"),
    "all α = 0 (point mass)": dict(a1=0, a2=0, a3=0, a4=0, a5=0, a6=0),
    "triangular, start heading near π, right turn": dict(
        VELOCITY_ALPHA,
        theta=3.14,
        v=0.8,
        w=-1.2,
        dt=1.5,
        distribution="triangular",
        density="pose",
    ),
    "triangular, reversing, std form, book value": dict(
        VELOCITY_ALPHA,
        v=-1.5,
        w=0.5,
        distribution="triangular",
        density="book",
        noise="std",
        theta=-3.1,
    ),
}


def _velocity_reference(state):
    """probrob's samples and density for the widget's state, fed the widget's draws."""
    p = state["values"]
    alpha = [p[f"a{k}"] for k in range(1, 7)]
    u, x_prev = [p["v"], p["w"]], [0.0, 0.0, p["theta"]]
    z = standard_draws(N, SEED)[p["distribution"]]
    samples = sample_motion_model_velocity(
        u, x_prev, p["dt"], alpha, sample=_replay(z), noise=p["noise"], size=N
    )
    density = motion_model_velocity(
        _hypotheses(state, p["density"]),
        u,
        x_prev,
        p["dt"],
        alpha,
        prob=PROB[p["distribution"]],
        noise=p["noise"],
        density=p["density"],
    )
    return samples, density


@pytest.mark.parametrize("name", list(VELOCITY_SETTINGS))
def test_velocity_widget_computes_what_probrob_computes(page, name):
    state = _set(page, 0, VELOCITY_SETTINGS[name])
    samples, density = _velocity_reference(state)
    _assert_parity(state["particles"], samples, f"{name}: particles")
    _assert_parity(state["density"], density, f"{name}: density")
    if any(state["values"][f"a{k}"] for k in range(1, 7)):  # not vacuous: a cloud, a density
        assert samples[:, :2].std(axis=0).min() > 1e-3
        assert np.isfinite(density).any() and np.nanmax(density) > 0
    else:
        assert np.ptp(samples, axis=0).max() < 1e-12


ODOMETRY_SETTINGS = {
    "the widget as shipped (normal, variance, xy)": {},
    "distinct α (normal, variance, xy)": ODOMETRY_ALPHA,
    "std form, triangular, pose density": dict(
        ODOMETRY_ALPHA, noise="std", distribution="triangular", density="pose"
    ),
    "some α = 0, book value": dict(a1=0.07, a2=0, a3=0.03, a4=0, density="book"),
    "all α = 0 (point mass)": dict(a1=0, a2=0, a3=0, a4=0),
    "rotations and heading near ±π, pose density": dict(
        ODOMETRY_ALPHA, theta=3.13, rot1=3.1, trans=0.8, rot2=-3.12, density="pose"
    ),
    "first turn near -π, triangular, book value": dict(
        ODOMETRY_ALPHA, theta=-3.1, rot1=-3.14, rot2=1.0, distribution="triangular", density="book"
    ),
    "rotation in place (δtrans = 0)": dict(ODOMETRY_ALPHA, trans=0, rot1=0.5, rot2=0.3, theta=0.3),
}


def _odometry_reference(state):
    p = state["values"]
    alpha = [p[f"a{k}"] for k in range(1, 5)]
    origin = np.zeros(3)
    u = np.stack([origin, apply_odometry_deltas(origin, p["rot1"], p["trans"], p["rot2"])])
    x_prev = [0.0, 0.0, p["theta"]]
    z = standard_draws(N, SEED)[p["distribution"]]
    samples = sample_motion_model_odometry(
        u, x_prev, alpha, sample=_replay(z), noise=p["noise"], size=N
    )
    density = motion_model_odometry(
        _hypotheses(state, p["density"]),
        u,
        x_prev,
        alpha,
        prob=PROB[p["distribution"]],
        noise=p["noise"],
        density=p["density"],
    )
    return samples, density


@pytest.mark.parametrize("name", list(ODOMETRY_SETTINGS))
def test_odometry_widget_computes_what_probrob_computes(page, name):
    state = _set(page, 1, ODOMETRY_SETTINGS[name])
    samples, density = _odometry_reference(state)
    _assert_parity(state["particles"], samples, f"{name}: particles")
    _assert_parity(state["density"], density, f"{name}: density")
    p = state["values"]
    alpha = [p[f"a{k}"] for k in range(1, 5)]
    if any(alpha):
        assert samples[:, :2].std(axis=0).min() > 1e-3
    else:
        assert np.ptp(samples, axis=0).max() < 1e-12
    if any(alpha) and p["trans"] > 0:
        assert np.isfinite(density).any() and np.nanmax(density) > 0
    # (with δtrans = 0 the δrot1 noise has variance α1·0² + α2·0² = 0: every sample lies on
    # the line through the start along θ + δrot1, a line mass that no grid point hits)


LANDMARK_SETTINGS = {
    "the widget as shipped": {},
    "bearing and heading near ±π": dict(phi=3.1, theta=-3.1, r=1.5),
    "wide bearing noise, signature off the landmark's": dict(sphi=0.8, sr=0.3, r=1.0, s=1.3),
    "σ_s = 0 with the landmark's signature (point mass matched)": dict(ss=0, s=1.0),
    "σ_r = 0 (poses on an exact circle)": dict(sr=0),
}


def _landmark_reference(state):
    p = state["values"]
    f, m = [p["r"], p["phi"], p["s"]], [[0.0, 0.0, 1.0]]
    sigmas = [p["sr"], p["sphi"], p["ss"]]
    g = np.random.default_rng(SEED)  # the order of landmark_draws: normals, then γ̂
    z = sample_normal_distribution(1.0, size=(3, N), rng=g)
    poses = sample_landmark_model_known_correspondence(
        f, 0, m, sigmas, size=N, rng=g, sample=_replay(z[:2])
    )
    q = landmark_model_known_correspondence(f, 0, _hypotheses(state, "pose"), m, sigmas)
    return poses, q


@pytest.mark.parametrize("name", list(LANDMARK_SETTINGS))
def test_landmark_widget_computes_what_probrob_computes(page, name):
    state = _set(page, 2, LANDMARK_SETTINGS[name])
    poses, q = _landmark_reference(state)
    _assert_parity(state["particles"], poses, f"{name}: poses")
    _assert_parity(state["density"], q, f"{name}: likelihood")
    sr = state["values"]["sr"]
    assert np.ptp(np.hypot(poses[:, 0], poses[:, 1])) > 0.05 or sr == 0
    if sr > 0:
        assert np.nanmax(q) > 0


def _distribution_reference(state):
    p = state["values"]
    z = standard_draws(N, SEED)[p["distribution"]][0]
    return np.sqrt(p["b2"]) * z, PROB[p["distribution"]](state["xs"], p["b2"])


@pytest.mark.parametrize(
    "values",
    [
        dict(b2=1.0),
        dict(b2=0.5, distribution="triangular"),
        dict(b2=0.01),
        dict(b2=4.0, distribution="triangular"),
    ],
)
def test_distribution_widget_computes_what_probrob_computes(page, values):
    """The curve layer (kind "curve", as a beam model's p(z | z*) would use) against Table 5.2."""
    state = _set(page, 3, values)
    samples, density = _distribution_reference(state)
    b = np.sqrt(values["b2"])
    np.testing.assert_allclose(state["xs"][[0, -1]], [-4.5 * b, 4.5 * b], rtol=0.02)
    assert state["density"].shape == state["xs"].shape == (200,)
    _assert_parity(state["particles"], samples, f"{values}: samples")
    _assert_parity(state["density"], density, f"{values}: density")
    # not vacuous: the curve holds the density's mass (midpoint rule over ±4.5 b)
    assert density.sum() * (state["xs"][1] - state["xs"][0]) == pytest.approx(1, abs=0.01)


def _beam_reference(state):
    p = state["values"]
    total = p["whit"] + p["wshort"] + p["wmax"] + p["wrand"]  # the widget's order of sums
    weights = (
        [p[k] / total for k in ("whit", "wshort", "wmax", "wrand")] if total > 0 else [0, 0, 0, 1]
    )
    params = BeamModelParams(*weights, p["sigma"], p["lambda"], 10.0)
    return np.empty(0), beam_mixture(state["xs"], p["zstar"], params)


@pytest.mark.parametrize(
    "values",
    [
        dict(),
        dict(zstar=0.3, sigma=0.5),  # p_hit's normaliser (the mass below 0 is cut)
        dict(zstar=9.8, sigma=0.4, wshort=0.6),  # ... and beyond z_max
        dict(zstar=0.0),  # z* = 0: p_short is a point mass at 0 (no grid point hits it)
        dict(wshort=0.0, wrand=0.0, whit=0.3, wmax=0.2),  # weights normalised by their sum
    ],
)
def test_beam_widget_computes_what_probrob_computes(page, values):
    state = _set(page, 4, values)
    _, density = _beam_reference(state)
    assert state["density"].shape == (400,) and state["n"] == 0
    _assert_parity(state["density"], density, f"{values}: p(z | z*)")
    assert np.isfinite(density).all() and density.max() > 0.1


REFERENCES = {
    0: _velocity_reference,
    1: _odometry_reference,
    2: _landmark_reference,
    3: _distribution_reference,
    4: _beam_reference,
}


@pytest.mark.parametrize("index", [0, 1, 2, 3, 4])
def test_widgets_compute_what_probrob_computes_anywhere_on_the_sliders(page, index):
    """12 seeded random settings per widget: every slider uniform on its range (and at an
    end with probability 1/5), every choice uniform."""
    rng = np.random.default_rng(100 + index)
    config = page.js(f"probrobLive.widgets[{index}].config()")
    for trial in range(12):
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
        samples, density = REFERENCES[index](state)
        what = f"widget {index}, trial {trial}, {values}"
        _assert_parity(state["particles"], samples, f"{what}: particles")
        _assert_parity(state["density"], density, f"{what}: density")


@pytest.mark.parametrize("index", [0, 1, 2])
def test_widget_decodes_the_draws_python_embedded(page, index):
    draws = landmark_draws(N, SEED) if index == 2 else standard_draws(N, SEED)
    for name, z in draws.items():
        js = _floats(page.js(f"probrobLive.widgets[{index}].draws({json.dumps(name)})"))
        np.testing.assert_array_equal(js, z.ravel())


JS_CANVAS_HASH = """
(() => {
  const s = document.querySelectorAll(".probrob-live canvas")[%d].toDataURL();
  let h = 0;
  for (let i = 0; i < s.length; i++) h = (h * 31 + s.charCodeAt(i)) | 0;
  return h;
})()
"""


@pytest.mark.parametrize("index", [0, 1])
def test_keyboard_moves_a_slider_and_redraws(page, index):
    """A reader's arrow key on a slider changes its value, its number box and the plot."""
    page.js(f"probrobLive.widgets[{index}].set(probrobLive.widgets[{index}].defaults(), true)")
    before = page.js(JS_CANVAS_HASH % index)
    root = f"document.querySelectorAll('.probrob-live')[{index}]"
    a1 = page.js(f"probrobLive.widgets[{index}].values().a1")
    page.js(f"{root}.querySelector('input[type=range][data-param=a1]').focus()")
    for _ in range(20):
        page.key("ArrowRight", "ArrowRight", 39)
    # the redraw runs on the next animation frame
    page.js("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    values = page.js(f"probrobLive.widgets[{index}].values()")
    assert values["a1"] == pytest.approx(a1 + 20 * 0.001)
    shown = page.js(f"{root}.querySelector('input[type=number][data-param=a1]').value")
    assert float(shown) == pytest.approx(values["a1"])
    assert page.js(JS_CANVAS_HASH % index) != before


JS_CONTROLS = """
(async () => {
  const root = document.querySelectorAll(".probrob-live")[0];
  const w = probrobLive.widgets[0];
  const frames = () => new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)));
  const out = {};
  const number = root.querySelector("input[type=number][data-param=w]");
  number.value = "-0.5";
  number.dispatchEvent(new Event("change"));
  await frames();
  out.typed = [w.values().w, Number(root.querySelector("input[type=range][data-param=w]").value)];
  number.value = "7";  // beyond the slider: clamped to its maximum
  number.dispatchEvent(new Event("change"));
  await frames();
  out.clamped = [w.values().w, Number(number.value)];
  const menu = root.querySelector("select[data-param=distribution]");
  menu.value = "triangular";
  menu.dispatchEvent(new Event("change"));
  await frames();
  out.chosen = w.values().distribution;
  root.querySelector("[data-action=reset]").click();
  out.reset = JSON.stringify(w.values()) === JSON.stringify(w.defaults());
  out.shown = [number.value, menu.value];
  return out;
})()
"""


def test_number_box_menu_and_reset(page):
    out = page.js(JS_CONTROLS)
    assert out["typed"] == [-0.5, -0.5]
    assert out["clamped"] == [2.0, 2.0]
    assert out["chosen"] == "triangular"
    assert out["reset"] and out["shown"] == ["0.8", "normal"]


# ------------------------------------------------------------------ the runtime: controls, mode, width

JS_CONTROLS_SURVEY = """
Array.from(document.querySelectorAll(".probrob-live")).map((el, k) => {
  const controls = Array.from(el.querySelectorAll(".pl-controls input, .pl-controls select"));
  const labelled = (c) => (c.labels && c.labels.length > 0) || !!c.getAttribute("aria-label");
  return {
    ranges: el.querySelectorAll("input[type=range]").length,
    numbers: el.querySelectorAll("input[type=number]").length,
    selects: Array.from(el.querySelectorAll("select")).map((s) => [s.dataset.param,
      Array.from(s.options).map((o) => [o.value, o.textContent]),
      s.value === probrobLive.widgets[k].values()[s.dataset.param]]),
    labels: Array.from(el.querySelectorAll("label")).map((l) => l.textContent),
    unlabelled: controls.filter((c) => !labelled(c)).map((c) => c.id),
    ids: controls.map((c) => c.id),
    buttons: Array.from(el.querySelectorAll("button")).map((b) => [b.dataset.action, b.hidden]),
    status: el.querySelector(".pl-status[aria-live=polite]") !== null,
  };
})
"""


def assert_controls_built_from_the_spec(page, configs):
    """Every widget's controls, as the runtime built them from its spec: a range slider and a
    number box per slider, a menu per choice (its options and their texts), each labelled, ids
    unique on the page, and the spec's buttons."""
    survey = page.js(JS_CONTROLS_SURVEY)
    assert len(survey) == len(configs)
    ids = [i for w in survey for i in w["ids"]]
    assert len(ids) == len(set(ids))
    for w, config in zip(survey, configs, strict=True):
        assert w["ranges"] == w["numbers"] == len(config["sliders"])
        expected = [[c["name"], c["options"], True] for c in config["choices"]]  # value shown
        assert w["selects"] == expected
        assert w["labels"] == [p["label"] for p in config["sliders"] + config["choices"]]
        assert w["unlabelled"] == []
        assert [a for a, _ in w["buttons"]] == [a for a, _ in config["buttons"]]
        assert w["status"] == bool(config.get("status"))
    return survey


def test_controls_are_built_from_the_spec(page):
    survey = assert_controls_built_from_the_spec(page, page.configs)
    # "fit view" is hidden where the axis follows the parameters (the curves)
    assert [dict(w["buttons"])["fit"] for w in survey] == [False, False, False, True, True]


JS_MODE = """
(async (mode) => {
  const frames = () => new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)));
  if (mode === null) delete document.documentElement.dataset.theme;
  else document.documentElement.dataset.theme = mode;
  await frames();
  return Array.from(document.querySelectorAll(".probrob-live")).map((el, k) => {
    const c = el.querySelector("canvas");
    const px = c.getContext("2d").getImageData(1, 1, 1, 1).data;
    return {mode: probrobLive.widgets[k].state().mode, dark: el.classList.contains("pl-dark"),
            corner: Array.from(px.slice(0, 3)), block: getComputedStyle(el).backgroundColor,
            caption: el.querySelector(".pl-caption").innerText};
  });
})(%s)
"""


def _luminance(rgb):
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]


def test_widgets_follow_the_pages_colour_mode(page):
    """The book's theme sets <html data-theme>: the canvases redraw on the mode's background
    (no recomputation), the block takes the mode's colours, and a caption's colour words
    follow (a white start arrow on a dark page is not called black)."""
    try:
        dark = page.js(JS_MODE % json.dumps("dark"))
        light = page.js(JS_MODE % json.dumps("light"))
        default = page.js(JS_MODE % "null")
    finally:
        page.js(JS_MODE % "null")
    for d, lt, df in zip(dark, light, default, strict=True):
        assert d["mode"] == "dark" and d["dark"] and _luminance(d["corner"]) < 60
        assert lt["mode"] == "light" and not lt["dark"] and _luminance(lt["corner"]) > 240
        assert df == lt  # no mode on the page: light
        assert d["block"] != lt["block"]
    assert (
        "black arrow" in light[0]["caption"] and "darker is more probable" in light[0]["caption"]
    )
    assert "white arrow" in dark[0]["caption"] and "lighter is more probable" in dark[0]["caption"]
    assert "black" not in dark[0]["caption"] and "lighter" not in light[0]["caption"]


def test_jupyterlab_dark_theme(page):
    """JupyterLab marks its theme on <body data-jp-theme-light>."""
    try:
        page.js("document.body.dataset.jpThemeLight = 'false'")
        page.js("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
        assert page.js("probrobLive.widgets.map((w) => w.state().mode)") == ["dark"] * 5
    finally:
        page.js("delete document.body.dataset.jpThemeLight")
    page.js("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    assert page.js("probrobLive.widgets.map((w) => w.state().mode)") == ["light"] * 5


JS_PLOTS = """
(async (width) => {
  document.body.style.width = width ? width + "px" : "";
  await new Promise(r => setTimeout(r, 50));
  await new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)));
  return Array.from(document.querySelectorAll(".probrob-live")).map((el, k) => {
    const c = el.querySelector("canvas");
    const r = c.getBoundingClientRect();
    return {plots: probrobLive.widgets[k].state().plots, data: JSON.parse(c.dataset.plots),
            css: [r.width, r.height], bitmap: [c.width, c.height], dpr: devicePixelRatio};
  });
})(%s)
"""


def assert_plots_fit(widgets, min_plot=250):
    """Every plot at least ``min_plot`` CSS px wide; the bitmap is the CSS size times the DPR,
    at the displayed aspect ratio; data-plots tells the plots' sizes."""
    for w in widgets:
        assert min(p[2] for p in w["plots"]) >= min_plot, w
        assert [[round(p[2], 1), round(p[3], 1)] for p in w["plots"]] == w["data"]
        css_w, css_h = w["css"]
        assert (
            abs(w["bitmap"][0] - css_w * w["dpr"]) <= 1
            and abs(w["bitmap"][1] - css_h * w["dpr"]) <= 1
        )
        assert max(p[0] + p[2] for p in w["plots"]) <= css_w + 0.5


def phone(page, on):
    """A phone's viewport (390 x 844 CSS px at device pixel ratio 3), or the tab's own again."""
    if on:
        metrics = {"width": 390, "height": 844, "deviceScaleFactor": 3, "mobile": True}
        page.send("Emulation.setDeviceMetricsOverride", metrics)
    else:
        page.send("Emulation.clearDeviceMetricsOverride")


def plots_on_phone_and_desktop(page):
    """The plots of every widget in the book's column on a phone (358 CSS px, DPR 3) and on
    a desktop (623 px): ``(narrow, wide)``, each as :data:`JS_PLOTS` returns them; the page is
    left as it was."""
    try:
        phone(page, True)
        narrow = page.js(JS_PLOTS % json.dumps(358))
        phone(page, False)
        wide = page.js(JS_PLOTS % json.dumps(623))
    finally:
        phone(page, False)
        page.js(JS_PLOTS % "null")
    return narrow, wide


def test_plots_are_never_narrower_than_250_css_px(page):
    """In the book's column on a phone (358 CSS px of a 390-px viewport, device pixel ratio 3)
    and on a desktop (623 px), no plot is narrower than 250 CSS px: on the phone the colour bar
    moves below the plot, and the canvas gets taller instead of the plot narrower."""
    try:
        phone(page, True)
        narrow = page.js(JS_PLOTS % json.dumps(358))
        assert_plots_fit(narrow)
        assert all(w["dpr"] == 3 for w in narrow)
        phone(page, False)
        assert_plots_fit(page.js(JS_PLOTS % json.dumps(623)))
    finally:
        phone(page, False)
        page.js(JS_PLOTS % "null")


def test_the_browser_check_reports_a_canvas_off_the_pages_mode_and_a_narrow_plot():
    """The browser check's two rules for live widget canvases (on the layout survey it makes in
    every view; the built book's run is ``make browser-check``): a light background on a dark
    page (or a dark one on a light page), and a plot narrower than 250 CSS px."""
    import sys

    sys.path.insert(0, str(ROOT / ".ci"))
    try:
        bc = importlib.import_module("browser_check")
    finally:
        sys.path.remove(str(ROOT / ".ci"))

    def classes(canvas, view):
        f = bc.Findings(view)
        bc.check_canvas_page(canvas, view, f, canvas["id"])
        return [c for c, _ in f.items]

    dark, phone = bc.View(1280, "dark"), bc.View(390, "light")
    ok = {"id": "w", "bg": [28, 31, 36], "plots": [[266, 266], [266, 266]]}
    assert classes(ok, dark) == []
    assert classes(ok | {"bg": [255, 255, 255]}, dark) == ["canvas-background"]
    assert classes(ok, phone) == ["canvas-background"]  # a dark canvas on a light page
    light = ok | {"bg": [255, 255, 255]}
    assert classes(light, phone) == []
    assert classes(light | {"plots": [[266, 266], [69, 69]]}, phone) == ["plot-width"]
    assert classes(light | {"plots": "unreadable"}, phone) == ["plot-width"]
    assert classes({"id": "a canvas that is no widget's", "bg": None, "plots": None}, dark) == []
    assert {
        ("canvas-background", "probrob-live-planted"),
        ("plot-width", "probrob-live-planted"),
    } <= set(bc.PLANTED)
