// The live particle filter's layer (probrob.live.mcl.particle_filter_live): the map, the
// particles, the reference and the estimate, the particle count per step, with step, play,
// "to start" and kidnap buttons, over the runs of mcl_filter.js (Tables 8.2-8.4, held equal to
// probrob.mcl by tests/test_live_mcl.py); the test hook adds field() (the distance field), and
// its bench times filter steps as "play" runs them.

function particleFilter({ model, config, api }) {
  const T = config.steps;
  const { h, w, resolution: res } = config.map;
  const [ox, oy] = config.map.origin;
  const xMax = ox + w * res;
  const yMax = oy + h * res;
  const runs = filterRuns(config, model);
  const { ensure, error } = runs;
  const { codes, dist, truth } = runs.data;
  const METHODS = { mcl: "MCL", augmented: "augmented MCL", kld: "KLD-sampling" };

  // ---- the picture --------------------------------------------------------------------------
  const M = { left: 56, top: 30, right: 12, bottom: 42 };
  const STRIP = 64; // CSS px: the height of the particle count's plot below the map
  let box = null;
  let strip = null;
  let mapImage = null;
  // the map in the mode's colours: free the background, occupied the foreground, unexplored
  // between them (as the plot's surroundings)
  function paintMap(theme) {
    if (mapImage && mapImage.mode === theme.mode) return mapImage;
    const bg = theme.rgb("bg");
    const fg = theme.rgb("fg");
    const grey = [0.15, 0, 1].map((t) => bg.map((b, c) => Math.round(b + (fg[c] - b) * t)));
    const canvas = document.createElement("canvas");
    canvas.width = w;
    canvas.height = h;
    const mctx = canvas.getContext("2d");
    const img = mctx.createImageData(w, h);
    for (let i = 0; i < h; i++) {
      const row = h - 1 - i; // row 0 of the grid is the lowest y: the image's last row
      for (let j = 0; j < w; j++) {
        const k = 4 * (row * w + j);
        img.data.set(grey[codes[i * w + j]], k);
        img.data[k + 3] = 255;
      }
    }
    mctx.putImageData(img, 0, 0);
    mapImage = { mode: theme.mode, canvas, unexplored: "rgb(" + grey[0].join(", ") + ")" };
    return mapImage;
  }
  // the data box in view: the whole map or a 12 m square around the reference pose, at equal
  // scales in x and y, centred in the plot box
  function viewBox(t) {
    const [, , PW, PH] = box;
    const half = 6;
    const [x0, x1, y0, y1] =
      model.get("view") === "robot"
        ? [truth[3 * t] - half, truth[3 * t] + half, truth[3 * t + 1] - half, truth[3 * t + 1] + half]
        : [ox, xMax, oy, yMax];
    const scale = Math.min(PW / (x1 - x0), PH / (y1 - y0));
    const cx = (x0 + x1) / 2;
    const cy = (y0 + y1) / 2;
    return { scale, lim: [cx - PW / 2 / scale, cx + PW / 2 / scale, cy - PH / 2 / scale, cy + PH / 2 / scale] };
  }
  function draw(ctx, { t, est }, theme) {
    const run = runs.current();
    const step = run.steps[t];
    const n = step.n;
    const x = step.x;
    const [left, top, PW, PH] = box;
    const v = viewBox(t);
    const sx = (a) => left + (a - v.lim[0]) * v.scale;
    const sy = (b) => top + PH - (b - v.lim[2]) * v.scale;
    const map = paintMap(theme);
    ctx.save();
    ctx.beginPath();
    ctx.rect(left, top, PW, PH);
    ctx.clip();
    ctx.fillStyle = map.unexplored;
    ctx.fillRect(left, top, PW, PH);
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(map.canvas, sx(ox), sy(yMax), w * res * v.scale, h * res * v.scale);
    // the reference path and pose
    const path = Array.from({ length: T + 1 }, (_, k) => [sx(truth[3 * k]), sy(truth[3 * k + 1])]);
    polyline(ctx, path, theme.alpha("green", 0.7), 1.2);
    // particles: one path, one fill
    ctx.fillStyle = theme.alpha("red", 0.55);
    ctx.beginPath();
    const dot = 2.2;
    for (let i = 0; i < n; i++) ctx.rect(sx(x[3 * i]) - dot / 2, sy(x[3 * i + 1]) - dot / 2, dot, dot);
    ctx.fill();
    ctx.strokeStyle = theme.green;
    ctx.lineWidth = 2.5;
    ctx.beginPath();
    ctx.arc(sx(truth[3 * t]), sy(truth[3 * t + 1]), 8, 0, TWO_PI);
    ctx.stroke();
    // the estimate: an arrow 24 px long
    const [ex, ey, eth] = est.pose;
    arrow(ctx, sx(ex), sy(ey), sx(ex) + 24 * Math.cos(eth), sy(ey) - 24 * Math.sin(eth), theme.blue, 2.5, 9, 3.5);
    ctx.restore();
    let title = METHODS[run.p.method] + ", " + (run.p.sensor === "beam" ? "beam model" : "likelihood field") +
      ", step " + t + " of " + T + ": " + n + " particles, " + run.p.beams + " beams";
    if (run.p.method === "augmented") title += ", w_fast/w_slow " + ratio(step);
    axes(ctx, theme, box, v.lim, { x: "x [m]", y: "y [m]", title }, { ticks: 6 });
    drawCounts(ctx, theme, t);
    api.controls.status.textContent = describe(t, est);
  }
  function ratio(step) {
    return step.wSlow > 0 ? (step.wFast / step.wSlow).toPrecision(4) : "— (w_slow = 0)";
  }
  // the particles per step (augmented MCL: and the random ones), steps 0 .. t
  function drawCounts(ctx, theme, t) {
    const run = runs.current();
    const counts = run.steps.slice(0, t + 1).map((s) => s.n);
    const top = Math.max(...counts, 100);
    const lim = [0, T, 0, top * 1.15];
    const [sx, sy] = [(a) => strip[0] + (a / T) * strip[2], (b) => strip[1] + strip[3] - (b / lim[3]) * strip[3]];
    polyline(ctx, counts.map((c, k) => [sx(k), sy(c)]), theme.blue, 1.5);
    let what = "particles per step (KLD-sampling: as many as the bound asks)";
    if (run.p.method === "augmented") {
      const random = run.steps.slice(1, t + 1).map((s, k) => [sx(k + 1), sy(s.random)]);
      polyline(ctx, random, theme.red, 1.5);
      what = "particles per step (blue) and random ones (red, Table 8.3)";
    } else if (run.p.method === "mcl") {
      what = "particles per step (fixed in MCL)";
    }
    if (run.p.kidnap > 0) {
      ctx.fillStyle = theme.fg;
      ctx.fillRect(sx(run.p.kidnap), strip[1], 1, strip[3]);
    }
    axes(ctx, theme, strip, lim, { x: "step t", y: "particles", title: what }, { ticks: 4 });
  }
  function describe(t, est) {
    const run = runs.current();
    const [pos, head] = error(est, t);
    const step = run.steps[t];
    let text =
      "Step " + t + " of " + T + ": the estimate is " + (100 * pos).toFixed(1) + " cm and " +
      ((head * 180) / Math.PI).toFixed(1) + "° from the reference pose; its cluster holds " +
      (100 * est.fraction).toFixed(0) + " % of the " + step.n + " particles (" + METHODS[run.p.method] +
      ", " + (run.p.sensor === "beam" ? "beam model" : "likelihood field") + ", " + run.p.beams +
      " beams, " + (model.get("start") === "global" ? "global start" : "known start") +
      (run.p.kidnap > 0 ? ", kidnapped after step " + run.p.kidnap : "") + ").";
    if (run.p.method === "augmented") {
      text += " w_slow = " + step.wSlow.toExponential(3) + ", w_fast = " + step.wFast.toExponential(3) +
        ", w_fast/w_slow = " + ratio(step) + ": " + step.random + " random particles at this step" +
        (step.overflow ? " (w_avg overflows: use fewer beams or an exponent < 1)" : "") + ".";
    } else if (run.p.method === "kld") {
      text += " KLD-sampling: " + step.n + " particles" + (t > 0 ? " over " + step.bins + " occupied bins" : "") +
        " (ε " + run.p.eps + ", δ " + run.p.delta + ").";
    }
    return text;
  }

  // ---- step, play, to start -----------------------------------------------------------------
  let timer = null;
  const button = () => api.controls.buttons.play;
  function pause() {
    if (timer !== null) clearInterval(timer);
    timer = null;
    button().textContent = "play";
    button().setAttribute("aria-pressed", "false");
  }
  function goTo(t) {
    model.set("t", t);
    api.controls.show("t");
    api.update();
  }
  function advance() {
    if (model.get("t") >= T) pause();
    else goTo(model.get("t") + 1);
  }
  const actions = {
    step() {
      pause();
      advance();
    },
    play() {
      if (timer !== null) {
        pause();
        return;
      }
      if (model.get("t") >= T) model.set("t", 0);
      button().textContent = "pause";
      button().setAttribute("aria-pressed", "true");
      timer = setInterval(advance, 100);
    },
    start() {
      pause();
      goTo(0);
    },
    // kidnap the robot after the step shown (step 1 at the start): the kidnap slider holds it
    kidnap() {
      pause();
      const t = Math.max(1, Math.round(model.get("t")));
      model.set("kidnap", t);
      api.controls.show("kidnap");
      goTo(t);
    },
  };

  return {
    layout(W) {
      const H = (W * config.height) / config.width;
      const below = M.top + STRIP + M.bottom;
      box = [M.left, M.top, W - M.left - M.right, H - M.top - M.bottom - below];
      strip = [M.left, H - M.bottom - STRIP, W - M.left - M.right, STRIP];
      return { height: H, plots: [box, strip] };
    },
    compute() {
      const t = Math.round(model.get("t"));
      return { t, est: ensure(t) };
    },
    draw,
    // the step t shown: X_t (size, 3), the log-weights of its step's particles before resampling
    // (MCL, augmented: n,; KLD-sampling: those of X_t; none at t = 0), KLD-sampling's weights of
    // X_t, augmented MCL's w_slow, w_fast and random particles, the estimate, its error
    hook() {
      const t = Math.round(model.get("t"));
      const est = ensure(t);
      const run = runs.current();
      const step = run.steps[t];
      return {
        t,
        n: run.p.n,
        size: step.n,
        beams: Array.from(run.p.sel),
        particles: encodeFloat64(step.x),
        logW: t > 0 ? encodeFloat64(step.logW) : null,
        weights: step.w ? encodeFloat64(step.w) : null,
        wSlow: step.wSlow,
        wFast: step.wFast,
        random: step.random,
        estimate: est.pose,
        fraction: est.fraction,
        error: error(est, t),
        status: api.controls.status.textContent,
      };
    },
    stop: pause,
    actions,
    // time `count` filter steps (after 10 untimed ones) at the current parameters, as "play"
    // runs them: one step of the filter and its estimate (compute), the redraw (draw)
    bench(count) {
      pause();
      const saved = model.values();
      runs.reset();
      goTo(0);
      const out = api.timeRuns(count, () => {
        if (model.get("t") >= T) {
          runs.reset(); // start the run again: every timed update is one new step
          goTo(0);
        }
        goTo(model.get("t") + 1);
      });
      model.restore(saved);
      for (const name of Object.keys(saved)) api.controls.show(name);
      api.update();
      return out;
    },
    extras: { field: () => encodeFloat64(dist) },
  };
}

kernels.mcl = { render: particleFilter };
