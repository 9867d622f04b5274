// probrob live widgets: the runtime, one copy inlined into every widget's HTML by
// probrob.live.core, with its drawing helpers (draw.js), before maths.js, the plot layers
// (plots.js) and the widget's kernel files. It holds what every widget shares and no model: the
// parameters and the controls built from the Python spec, the canvas (its size,
// devicePixelRatio, resize), the redraw scheduling and its timing, the colours of the page's
// mode (light or dark), axes, arrows and text (draw.js), and the test hook. No network, no
// library, no build step.
//
// The contract, after anywidget's front-end modules (render({ model, el })): a kernel file
// assigns kernels.<name> an object. A model kernel (velocity.js, ...) is drawn by a plot layer
// of plots.js chosen by its kind ("cloud", "curve" or "scene"); a kernel with its own picture
// (mcl.js) has render({ model, el, config, api }), which returns a layer. A layer has
//   layout(W)            -> {height, plots: [[x, y, w, h], ...]}: for a canvas W CSS px wide,
//                           its height and its plot boxes (CSS px; the browser check reads
//                           their widths from the canvas's data-plots)
//   compute(refit)       -> state: the numbers of the model's current parameters (timed as
//                           "compute"; refit: fit the view to them)
//   draw(ctx, state, theme)  the picture (timed as "draw"), ctx in CSS pixels on the page's
//                           background; theme: the palette of the page's mode
//   hook(state)          -> what the test hook's state() adds to {values, timings, mode, plots}
// and optionally actions {name: fn} (its buttons), stop() (before set and reset),
// bench(count) (default: one slider moved per update), extras {name: fn} (more hook functions)
// and fit: false (no "fit view" button).
//
// The model (anywidget's model: get and set by name) holds every slider and choice value; set
// clamps a slider to its range (and snaps it to its step if its spec says snap) and refuses an
// unknown name or option. The test hook: window.probrobLive.widgets, in page order, each with
// values(), defaults(), config(), set(changes, refit), state(), bench(count) and the layer's
// extras (documented in probrob.live).

const kernels = {};
const layers = {}; // the plot layers of plots.js, by kind
const TWO_PI = 2 * Math.PI;
const MIN_PLOT = 250; // CSS px: a plot narrower than this is stacked or moved, not shrunk
const MARGIN = { left: 62, top: 34, right: 16, bottom: 48 }; // around a plot: axes, title
const GAP = 14; // between plots side by side (they share the y axis)

// ---- base64 <-> typed arrays ------------------------------------------------------------
function decodeBytes(b64) {
  const bin = atob(b64);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
  return bytes;
}
function decodeTyped(b64, Type) {
  const bytes = decodeBytes(b64);
  return new Type(bytes.buffer, 0, bytes.length / Type.BYTES_PER_ELEMENT);
}
function decodeFloat64(b64) {
  return decodeTyped(b64, Float64Array);
}
function encodeFloat64(arr) {
  const bytes = new Uint8Array(arr.buffer, arr.byteOffset, arr.byteLength);
  let s = "";
  for (let i = 0; i < bytes.length; i += 0x8000) {
    s += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
  }
  return btoa(s);
}

// ---- the model: the parameters by name --------------------------------------------------
function createModel(config) {
  const values = {};
  const defaults = {};
  const sliders = {};
  const options = {};
  for (const s of config.sliders) {
    defaults[s.name] = s.value;
    sliders[s.name] = s;
  }
  for (const c of config.choices) {
    defaults[c.name] = c.value;
    options[c.name] = c.options.map((o) => o[0]);
  }
  Object.assign(values, defaults);
  return {
    get: (name) => values[name],
    set(name, raw) {
      if (name in options) {
        if (!options[name].includes(raw)) {
          throw new Error("probrob live widget: no option " + raw + " for " + name);
        }
        values[name] = raw;
        return;
      }
      const s = sliders[name];
      if (!s) throw new Error("probrob live widget: no parameter " + name);
      let v = Number(raw);
      if (!Number.isFinite(v)) return;
      if (s.snap) v = Math.round(v / s.step) * s.step;
      values[name] = Math.min(Math.max(v, s.min), s.max);
    },
    values: () => Object.assign({}, values),
    defaults: () => Object.assign({}, defaults),
    restore: (saved) => Object.assign(values, saved),
    // every value, and the kernel's fixed constants, by name
    params: () => Object.assign({}, config.constants, values),
  };
}

// ---- the controls, built from the spec into the block's .pl-controls --------------------
function element(tag, attrs, text) {
  const el = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) el.setAttribute(k, String(v));
  if (text !== undefined) el.textContent = text;
  return el;
}
// A range slider and a number box per slider (one label), a menu per choice, the buttons and
// a status line; returns show(name) (the model's value into its controls) and the elements.
function buildControls(root, config, model, onInput, actions) {
  const box = root.querySelector(".pl-controls");
  const inputs = {};
  const selects = {};
  const rows = element("div", { class: "pl-sliders" });
  for (const s of config.sliders) {
    const id = root.id + "-" + s.name;
    const attrs = { min: s.min, max: s.max, step: s.step, value: s.value, "data-param": s.name };
    const range = element("input", Object.assign({ type: "range", id }, attrs));
    const number = element(
      "input",
      Object.assign({ type: "number", id: id + "-n", "aria-label": s.label + ", value" }, attrs),
    );
    const row = element("div", { class: "pl-row" });
    row.append(element("label", { for: id }, s.label), range, number);
    rows.append(row);
    inputs[s.name] = { range, number };
  }
  box.append(rows);
  for (const c of config.choices) {
    const id = root.id + "-" + c.name;
    const select = element("select", { id, "data-param": c.name });
    for (const [v, text] of c.options) select.append(element("option", { value: v }, text));
    select.value = c.value;
    const row = element("div", { class: "pl-choice" });
    row.append(element("label", { for: id }, c.label), select);
    box.append(row);
    selects[c.name] = select;
  }
  const buttons = {};
  for (const [action, text] of config.buttons) {
    const attrs = { type: "button", "data-action": action };
    if (action === "play") attrs["aria-pressed"] = "false";
    buttons[action] = element("button", attrs, text);
    buttons[action].addEventListener("click", () => actions[action]());
    box.append(buttons[action]);
  }
  const status = config.status ? element("p", { class: "pl-status", "aria-live": "polite" }) : null;
  if (status) box.append(status);
  function show(name) {
    if (name in inputs) {
      inputs[name].range.value = String(model.get(name));
      inputs[name].number.value = String(model.get(name));
    } else {
      selects[name].value = model.get(name);
    }
  }
  for (const [name, { range, number }] of Object.entries(inputs)) {
    range.addEventListener("input", () => {
      model.set(name, range.value);
      number.value = range.value;
      onInput();
    });
    number.addEventListener("change", () => {
      model.set(name, number.value);
      show(name);
      onInput();
    });
  }
  for (const [name, select] of Object.entries(selects)) {
    select.addEventListener("change", () => {
      model.set(name, select.value);
      onInput();
    });
  }
  return { show, buttons, status };
}

// ---- the page's colour mode and its palette ---------------------------------------------
const PALETTES = {
  light: {
    bg: "#ffffff", fg: "#000000", muted: "#8c8c8c", blue: "#1f77b4", red: "#d62728",
    green: "#2ca02c", orange: "#e0650b",
  },
  dark: {
    bg: "#1c1f24", fg: "#e6e6e6", muted: "#9c9c9c", blue: "#5aa7e0", red: "#ff6b66",
    green: "#5ccf5c", orange: "#ff9f4a",
  },
};
function hexRgb(hex) {
  return [1, 3, 5].map((k) => parseInt(hex.slice(k, k + 2), 16));
}
// The palette of a mode, with rgb(name) (three numbers) and alpha(name, a) (a CSS colour).
function themeOf(mode) {
  const colours = PALETTES[mode];
  return Object.assign({ mode }, colours, {
    rgb: (name) => hexRgb(colours[name]),
    alpha: (name, a) => "rgba(" + hexRgb(colours[name]).join(", ") + ", " + a + ")",
  });
}
// The page says its mode: the book (pydata-sphinx-theme: <html data-theme>), JupyterLab
// (<body data-jp-theme-light>), VS Code (<body class="vscode-dark">); else the luminance of the
// first opaque background around the widget; else light.
function pageMode(root) {
  const html = document.documentElement.dataset.theme;
  if (html === "dark" || html === "light") return html;
  const body = document.body;
  const jp = body && body.dataset.jpThemeLight;
  if (jp === "false" || jp === "true") return jp === "false" ? "dark" : "light";
  if (body && body.classList.contains("vscode-dark")) return "dark";
  for (let el = root.parentElement; el; el = el.parentElement) {
    const m = getComputedStyle(el).backgroundColor.match(/[\d.]+/g);
    if (m && (m.length < 4 || Number(m[3]) > 0.5)) {
      const [r, g, b] = m.map(Number);
      return 0.2126 * r + 0.7152 * g + 0.0722 * b < 110 ? "dark" : "light";
    }
  }
  return "light";
}
// Calls onChange(mode) when the page switches its mode (the book's and JupyterLab's toggles).
function watchMode(root, onChange) {
  let mode = pageMode(root);
  const check = () => {
    const now = pageMode(root);
    if (now !== mode) {
      mode = now;
      onChange(now);
    }
  };
  const observer = new MutationObserver(check);
  observer.observe(document.documentElement, { attributes: true, attributeFilter: ["data-theme"] });
  if (document.body) {
    observer.observe(document.body, { attributes: true, attributeFilter: ["data-jp-theme-light", "class"] });
  }
  return mode;
}

// ---- the canvas -------------------------------------------------------------------------
// The canvas is as wide as its box allows, at most config.width CSS px; the layer's layout(W)
// gives its height (the aspect ratio is set, no inline height), and its bitmap is that size
// times devicePixelRatio. Before layout (a hidden or detached block) config.width is used.
// Returns {W, H, dpr, geometry}.
function sizeCanvas(canvas, config, layout) {
  canvas.style.maxWidth = config.width + "px";
  const dpr = window.devicePixelRatio || 1;
  const shown = canvas.getBoundingClientRect().width;
  const W = shown > 0 ? shown : config.width;
  const geometry = layout(W);
  const H = geometry.height;
  canvas.style.aspectRatio = W + " / " + H;
  const bw = Math.max(1, Math.round(W * dpr));
  const bh = Math.max(1, Math.round(H * dpr));
  if (canvas.width !== bw) canvas.width = bw;
  if (canvas.height !== bh) canvas.height = bh;
  const round = (x) => Math.round(x * 10) / 10;
  canvas.dataset.plots = JSON.stringify(geometry.plots.map((b) => [round(b[2]), round(b[3])]));
  return { W, H, dpr, geometry };
}
// Calls redraw() (on the next animation frame) when the canvas's displayed width or the
// devicePixelRatio changes: a rotated phone, a resized window, a zoom.
function watchCanvasSize(canvas, redraw) {
  let shown = [canvas.getBoundingClientRect().width, window.devicePixelRatio || 1];
  let queued = false;
  const check = () => {
    const now = [canvas.getBoundingClientRect().width, window.devicePixelRatio || 1];
    if (now[0] > 0 && (Math.abs(now[0] - shown[0]) > 0.5 || now[1] !== shown[1]) && !queued) {
      shown = now;
      queued = true;
      requestAnimationFrame(() => {
        queued = false;
        redraw();
      });
    }
  };
  if (typeof ResizeObserver !== "undefined") new ResizeObserver(check).observe(canvas);
  window.addEventListener("resize", check);
}
// Plots of side S (square) in a canvas W CSS px wide: `panels` of them side by side with
// `side` px right of them (a colour bar, a legend) at the canvas's configured aspect ratio;
// where that leaves a plot narrower than MIN_PLOT, the side part goes below (`below` px) and
// the panels stack. Returns {S, cols, beside, boxes: [[x, y, S, S], ...], below: y, height}.
function plotGrid(W, config, panels, side, below) {
  const fit = (cols, right) => (W - MARGIN.left - right - (cols - 1) * GAP) / cols;
  const H0 = (W * config.height) / config.width;
  let cols = panels;
  let S = Math.min(fit(cols, side), H0 - MARGIN.top - MARGIN.bottom);
  const beside = S >= MIN_PLOT;
  if (!beside) {
    S = fit(cols, MARGIN.right);
    if (S < MIN_PLOT) {
      cols = 1;
      S = fit(1, MARGIN.right);
    }
    S = Math.max(1, Math.min(S, config.height - MARGIN.top - MARGIN.bottom));
  }
  const rows = Math.ceil(panels / cols);
  const step = S + MARGIN.bottom + MARGIN.top;
  const boxes = [];
  for (let k = 0; k < panels; k++) {
    boxes.push([MARGIN.left + (k % cols) * (S + GAP), MARGIN.top + Math.floor(k / cols) * step, S, S]);
  }
  const bottom = MARGIN.top + (rows - 1) * step + S + MARGIN.bottom;
  return { S, cols, beside, boxes, below: bottom, height: beside ? H0 : bottom + below };
}

// ---- mounting: model, controls, canvas, mode, updates, test hook -------------------------
function mountLiveWidget(root, config, kernel) {
  const model = createModel(config);
  const canvas = root.querySelector("canvas");
  const ctx = canvas.getContext("2d");
  const timings = { compute: 0, draw: 0, total: 0 };
  let size = null;
  let last = null;
  let pending = false;
  const api = { model, config, timings, update, schedule, timeRuns };
  const layer = kernel.render
    ? kernel.render({ model, el: root, config, api })
    : layers[kernel.kind || "cloud"]({ kernel, model, config });
  let theme = themeOf(watchMode(root, (mode) => setMode(mode)));
  function setMode(mode) {
    theme = themeOf(mode);
    root.classList.toggle("pl-dark", mode === "dark");
    if (last !== null) paint();
  }
  setMode(theme.mode);
  function paint() {
    ctx.setTransform(size.dpr, 0, 0, size.dpr, 0, 0);
    ctx.fillStyle = theme.bg;
    ctx.fillRect(0, 0, size.W, size.H);
    layer.draw(ctx, last, theme);
  }
  function update(refit) {
    const t0 = performance.now();
    last = layer.compute(Boolean(refit));
    const t1 = performance.now();
    paint();
    const t2 = performance.now();
    timings.compute = t1 - t0;
    timings.draw = t2 - t1;
    timings.total = t2 - t0;
  }
  function schedule() {
    if (pending) return;
    pending = true;
    requestAnimationFrame(() => {
      pending = false;
      update(false);
    });
  }
  // `count` timed runs of run(k) (after `warmup` untimed ones that let the JIT compile):
  // {count, compute, draw, total}, each {median, p90, max} in milliseconds
  function timeRuns(count, run, warmup = 10) {
    const times = { compute: [], draw: [], total: [] };
    for (let k = 0; k < warmup + count; k++) {
      run(k);
      if (k < warmup) continue;
      for (const key of Object.keys(times)) times[key].push(timings[key]);
    }
    const out = { count };
    for (const [key, t] of Object.entries(times)) {
      t.sort((a, b) => a - b);
      const at = (q) => t[Math.min(count - 1, Math.floor(q * count))];
      out[key] = { median: at(0.5), p90: at(0.9), max: t[count - 1] };
    }
    return out;
  }
  const stop = () => layer.stop && layer.stop();
  const actions = Object.assign(
    {
      reset() {
        stop();
        model.restore(model.defaults());
        for (const name of Object.keys(model.defaults())) controls.show(name);
        update(true);
      },
      fit: () => update(true),
    },
    layer.actions,
  );
  const controls = buildControls(root, config, model, schedule, actions);
  api.controls = controls;
  if (controls.buttons.fit && layer.fit === false) controls.buttons.fit.hidden = true;
  size = sizeCanvas(canvas, config, layer.layout);
  // a new displayed size: a new layout and bitmap, the same state drawn again
  watchCanvasSize(canvas, () => {
    size = sizeCanvas(canvas, config, layer.layout);
    if (last !== null) paint();
  });

  // ---- the test hook ------------------------------------------------------------------
  const handle = Object.assign(
    {
      id: root.id,
      kernel: config.kernel,
      values: model.values,
      defaults: model.defaults,
      config: () => ({
        sliders: config.sliders,
        choices: config.choices.map((c) => ({ name: c.name, options: c.options.map((o) => o[0]) })),
      }),
      set(changes, refit) {
        stop();
        for (const [name, v] of Object.entries(changes)) model.set(name, v);
        for (const name of Object.keys(changes)) controls.show(name);
        update(refit);
        return handle.state();
      },
      state: () =>
        Object.assign({ values: model.values() }, layer.hook(last), {
          timings: Object.assign({}, timings),
          mode: theme.mode,
          plots: size.geometry.plots,
        }),
      bench(count) {
        if (layer.bench) return layer.bench(count);
        const saved = model.values();
        const out = timeRuns(count, (k) => {
          const s = config.sliders[k % config.sliders.length];
          model.set(s.name, s.min + ((k * 0.618034) % 1) * (s.max - s.min));
          update(false);
        });
        model.restore(saved);
        update(true);
        return out;
      },
    },
    layer.extras,
  );
  window.probrobLive = window.probrobLive || { widgets: [] };
  window.probrobLive.widgets.push(handle);
  update(true);
  root.setAttribute("data-ready", "true");
  return handle;
}
