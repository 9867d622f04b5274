"""The live widgets' core: the spec of a widget, its HTML block and the encoders of its data.

Holds :class:`Slider`, :class:`Choice` (the parameters a widget offers), :class:`LiveWidget`,
:func:`live_widget` (any model kernel's widget from its spec), :func:`render` (the one HTML
block of every widget: the runtime, the kernel files and the spec) and the base64 encoders.
Does not hold a model or a widget of a table (the family modules of :mod:`probrob.live`) nor
any JavaScript (``assets/``).
"""

from __future__ import annotations

import base64
import html
import itertools
import json
import re
from dataclasses import dataclass
from importlib import resources

import numpy as np

from .. import _validation as check

__all__ = ["Choice", "LiveWidget", "Slider", "live_widget", "render"]

ASSETS = "assets"
#: The runtime, inlined into every widget first: the model, controls, canvas, mode and test
#: hook, and its drawing helpers.
RUNTIME = ("runtime.js", "draw.js")
_COUNTER = itertools.count(1)
#: The buttons of a model widget: (action, text).
MODEL_BUTTONS = (("reset", "reset"), ("fit", "fit view"))


def asset(name: str) -> str:
    """The text of ``assets/<name>`` (a kernel file, the runtime or its stylesheet)."""
    return resources.files(__package__).joinpath(ASSETS, name).read_text(encoding="utf-8")


def inlined(name: str) -> str:
    """``assets/<name>`` as a widget carries it: after a line naming the file, its lines without
    indentation, blank lines and comments (whole-line ``//`` in JavaScript, ``/* */`` in CSS;
    the files keep them for their readers)."""
    text = asset(name)
    if name.endswith(".css"):
        text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    lines = (line.strip() for line in text.splitlines())
    code = [line for line in lines if line and not line.startswith("//")]
    return "\n".join([f"/* probrob/live/{ASSETS}/{name} */", *code])


@dataclass(frozen=True)
class Slider:
    """A numeric parameter: a range slider and a number box, ``lo <= value <= hi``.

    ``snap``: the page rounds the value to a multiple of ``step`` (a count, a step index).
    """

    name: str
    label: str
    value: float
    lo: float
    hi: float
    step: float
    snap: bool = False


@dataclass(frozen=True)
class Choice:
    """A parameter with a few named values: a ``<select>`` of ``(value, text)`` options."""

    name: str
    label: str
    options: tuple[tuple[str, str], ...]
    value: str


def slider(name, label, value, lo, hi, step, *, what=None) -> Slider:
    """A :class:`Slider` whose start ``value`` is checked against ``[lo, hi]`` (named ``what``)."""
    return Slider(name, label, check.in_range(value, what or name, lo, hi), lo, hi, step)


def alpha_sliders(alpha, count) -> list[Slider]:
    r"""The sliders of :math:`\alpha_1 \ldots \alpha_{count}`, each in [0, 0.5]."""
    alpha = check.alphas(alpha, "alpha", count)
    if np.any(alpha > 0.5):
        raise ValueError(f"alpha must lie in [0, 0.5] (the sliders' range), got {alpha.tolist()}")
    return [
        Slider(f"a{k + 1}", f"α{k + 1}", float(alpha[k]), 0.0, 0.5, 0.001) for k in range(count)
    ]


class LiveWidget:
    """A live widget: display it (its ``_repr_html_``) or read its ``html``."""

    def __init__(self, html_text: str, kernel: str):
        self.html = html_text
        self.kernel = kernel

    def _repr_html_(self) -> str:
        return self.html

    def __repr__(self) -> str:
        return (
            f"<probrob live widget: {self.kernel} model, {len(self.html) / 1000:.0f} kB of HTML>"
        )


def b64(arr, dtype: str = "<f8") -> str:
    """``arr`` as base64 of its little-endian bytes in ``dtype`` (float64 unless said)."""
    return base64.b64encode(np.ascontiguousarray(arr, dtype=dtype).tobytes()).decode("ascii")


def spec(sliders, choices) -> dict:
    """The controls' part of a widget's config: what the runtime builds the controls from."""
    for s in sliders:
        if not (s.lo <= s.value <= s.hi and s.step > 0):
            raise ValueError(f"{s.name} must lie in [{s.lo}, {s.hi}], got {s.value!r}")
    for c in choices:
        if c.value not in [v for v, _ in c.options]:
            raise ValueError(
                f"{c.name} must be one of {[v for v, _ in c.options]}, got {c.value!r}"
            )
    return {
        "sliders": [
            {"name": s.name, "label": s.label, "value": float(s.value), "min": float(s.lo)}
            | {"max": float(s.hi), "step": float(s.step)}
            | ({"snap": True} if s.snap else {})
            for s in sliders
        ],
        "choices": [
            {"name": c.name, "label": c.label, "value": c.value, "options": list(c.options)}
            for c in choices
        ],
    }


# A caption's words that name a colour of the mode: {light-mode word|dark-mode word}
_MODE_WORDS = re.compile(r"\{([^{}|]*)\|([^{}|]*)\}")


def _caption(text: str) -> str:
    return _MODE_WORDS.sub(
        r'<span class="pl-light-only">\1</span><span class="pl-dark-only">\2</span>',
        html.escape(text),
    )


def render(
    kernel: str,
    config: dict,
    *,
    title: str,
    caption: str,
    aria_label: str,
    scripts: tuple[str, ...],
    budgets: dict[str, int] | None = None,
) -> LiveWidget:
    """Return the HTML block of a widget: its canvas, the runtime, ``scripts`` and ``config``.

    Parameters
    ----------
    kernel : str
        The kernel's name (``kernels.<kernel>`` of its file).
    config : dict
        The spec the runtime mounts: ``kernel``, ``width``, ``height`` (the canvas's largest
        width and its aspect ratio, CSS px), ``sliders``, ``choices`` (:func:`spec`),
        ``buttons``, ``constants`` and what the kernel reads.
    title, caption, aria_label : str
        A heading, a sentence below the plot (``{light word|dark word}`` names a colour that
        follows the page's mode) and the canvas's accessible name.
    scripts : tuple of str
        The asset files inlined after the runtime (:data:`RUNTIME`), in order (the kernel's
        file last).
    budgets : dict, optional
        ``data-*`` attributes of the block (``size-budget``, ``update-budget``) that the
        browser check holds the widget to.
    """
    wid = f"probrob-live-{kernel}-{next(_COUNTER)}"
    config_js = json.dumps(config, ensure_ascii=True).replace("</", "<\\/")
    code = "\n".join(inlined(name) for name in (*RUNTIME, *scripts))
    data = "".join(f' data-{k}="{v}"' for k, v in (budgets or {}).items())
    e = html.escape
    return LiveWidget(
        f"""<div class="probrob-live" id="{wid}" role="group" aria-label="{e(title)}"{data}>
<style>{inlined("runtime.css")}</style>
<div class="pl-title"><strong>{e(title)}</strong> (live: runs in this page, no kernel)</div>
<div class="pl-body">
<canvas width="{config["width"]}" height="{config["height"]}" role="img" aria-label="{e(aria_label)}">{e(aria_label)}</canvas>
<div class="pl-controls"></div>
</div>
<p class="pl-caption">{_caption(caption)}</p>
<script>
(function () {{
"use strict";
{code}
const config = {config_js};
// the script's own block (also when a front end runs it before the block is in the document,
// as JupyterLab does), else the block with this id
const script = document.currentScript;
const root = (script && script.closest(".probrob-live")) || document.getElementById("{wid}");
mountLiveWidget(root, config, kernels[config.kernel]);
}})();
</script>
</div>""",
        kernel,
    )


def _constant(value, key) -> float:
    """One finite number for ``constants[key]`` (an array is an error, not float()'s TypeError)."""
    arr = check.finite(value, f"constants[{key!r}]")
    if arr.ndim != 0:
        raise ValueError(f"constants[{key!r}] must be a number, got shape {arr.shape}")
    return float(arr)


def _kernel_files(kernel, requires) -> tuple[str, ...]:
    """The files a model kernel needs after the runtime: the maths, the layers, ``requires``."""
    try:
        asset(f"{kernel}.js")
    except (FileNotFoundError, OSError) as exc:
        raise ValueError(f"kernel must name a file {ASSETS}/<kernel>.js, got {kernel!r}") from exc
    try:
        files = tuple(f"{name}.js" for name in requires)
        for name in files:
            asset(name)
    except (FileNotFoundError, OSError, TypeError) as exc:
        raise ValueError(f"requires must name files {ASSETS}/<name>.js, got {requires!r}") from exc
    return ("maths.js", "plots.js", *files, f"{kernel}.js")


def _checked_draws(draws, n_particles, rng) -> dict[str, np.ndarray]:
    from .distributions import standard_draws

    if draws is None:
        if n_particles < 1:
            raise ValueError(f"n_particles must be >= 1 with the default draws, got {n_particles}")
        draws = standard_draws(n_particles, rng)
    draws = {k: check.finite(v, f"draws[{k!r}]") for k, v in draws.items()}
    for k, v in draws.items():
        if v.ndim != 2 or v.shape[1] != n_particles:
            raise ValueError(f"draws[{k!r}] must have shape (k, {n_particles}), got {v.shape}")
    return draws


def live_widget(
    kernel: str,
    sliders,
    choices=(),
    *,
    title: str,
    caption: str,
    aria_label: str,
    draws: dict[str, np.ndarray] | None = None,
    constants: dict[str, float] | None = None,
    n_particles: int = 2000,
    grid: int = 100,
    headings: int = 60,
    rng=0,
    width: int = 600,
    height: int = 500,
    requires: tuple[str, ...] = (),
) -> LiveWidget:
    """Return a live widget of the model whose JavaScript kernel is ``assets/<kernel>.js``.

    The generic mechanism: a widget of a table (e.g. :func:`probrob.live.motion.velocity_model_live`)
    only chooses the kernel, the sliders and the choices.

    Parameters
    ----------
    kernel : str
        Name of the kernel file (without ``.js``) and of the entry it adds to ``kernels``.
    sliders : sequence of Slider
    choices : sequence of Choice
        A choice named ``distribution`` picks the draws and the density of Table 5.2 (its
        values must be keys of ``draws``); without one, the ``"normal"`` draws are used.
    title, caption, aria_label : str
        A heading above the widget, a sentence below the plot saying what it shows (a
        ``{light word|dark word}`` pair names a colour that follows the page's mode), and the
        canvas's accessible name.
    draws : dict of ndarray (k, n), optional
        Draws by name (``n = n_particles``): the kernel's ``sample`` gets the one named by the
        ``distribution`` choice and all of them; default
        :func:`probrob.live.distributions.standard_draws` ``(n_particles, rng)``. A kernel that
        draws no samples takes ``{}`` and ``n_particles=0``.
    constants : dict of float, optional
        Fixed parameters the kernel reads like slider values (e.g. a landmark's position).
    n_particles, grid, headings : int
        Particles, density grid points per axis, and how many particles show a heading.
    rng : None, int or numpy.random.Generator
        Seed of the default draws.
    width, height : int
        The canvas's largest width and its aspect ratio, in CSS pixels (on a narrow page the
        runtime stacks the plots and makes the canvas taller).
    requires : sequence of str
        Further kernel files (without ``.js``) inlined before the kernel's own, in this order:
        a kernel built on others (e.g. ``velocity_forms`` on ``velocity`` and ``noise_forms``).

    Returns
    -------
    widget : LiveWidget
    """
    files = _kernel_files(kernel, requires)
    n_particles = check.count(n_particles, "n_particles", 0)
    grid = check.count(grid, "grid", 2)
    headings = check.count(headings, "headings", 0)
    draws = _checked_draws(draws, n_particles, rng)
    constants = {k: _constant(v, k) for k, v in (constants or {}).items()}
    names = [s.name for s in sliders] + [c.name for c in choices] + list(constants)
    if len(set(names)) != len(names):
        raise ValueError(f"parameter names must be unique, got {names}")
    controls = spec(sliders, choices)
    families = [v for c in choices if c.name == "distribution" for v, _ in c.options]
    if draws and not set(families or ["normal"]) <= set(draws):
        raise ValueError(f"every distribution needs its draws, have {sorted(draws)}")
    config = {
        "kernel": kernel,
        "n": int(n_particles),
        "grid": int(grid),
        "headings": int(headings),
        "width": check.count(width, "width", 1),
        "height": check.count(height, "height", 1),
        **controls,
        "buttons": MODEL_BUTTONS,
        "constants": constants,
        "draws": {k: b64(v) for k, v in draws.items()},
    }
    return render(
        kernel, config, title=title, caption=caption, aria_label=aria_label, scripts=files
    )
