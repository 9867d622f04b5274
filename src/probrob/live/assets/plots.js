// probrob live widgets: the plot layers of the model kernels, on runtime.js. Inlined after
// runtime.js and maths.js into every widget whose kernel has a kind (all but mcl.js). A layer
// computes through its kernel and draws the kernel's numbers; the kernels hold only their
// table's computation (and a scene kernel its construction's drawing).
//
// kind "cloud" (the default): samples over a density image in the x-y plane. The kernel has
//   sample(p, z, n, out, draws)  fills out (Float64Array, n*3, rows x, y, theta) from the
//                          standardized draws z = draws[p.distribution] (Float64Array, k*n,
//                          row k = z[k*n .. k*n+n)); draws holds every embedded array by name
//   density(p, xs, ys, theta, out)  fills out (Float64Array, ys.length*xs.length, row-major,
//                          out[i*nx + j] at (xs[j], ys[i])) with the density at heading theta
//   markers(p) -> [{x, y, theta, color}, ...] (theta null: a square; color a palette name such
//                          as "fg" or "blue") and heading(p) -> the heading of the density, or
//                          instead end(p) -> the noise-free end pose of a motion from the origin
//                          at heading p.theta (markers: the start and the end, heading: the end's)
//   title(p), densityLabel(p) -> strings
//   panels: k (k > 1): k clouds of the same draws in one view and one grey scale, panel j at
//                          the parameters panel(p, j), titled title(panel(p, j)) (noise_forms.js);
//                          side by side, or stacked where a plot would be narrower than MIN_PLOT
// kind "curve": a function of one variable over a histogram of its samples (distribution.js):
//   sample fills n values, density one value per xs (ys is [0]), xRange(p) -> [x0, x1],
//   labels(p) -> {x, y}, title(p).
// kind "scene": a construction (cir.js, ekf.js): scene(p) -> {values: {name: number |
//   Float64Array}, points: [[x, y], ...]} (the view holds the points), drawScene(ctx, p, values,
//   plot) draws it clipped to the plot (plot: the maps sx, sy, box [left, top, S, S], theme),
//   legend(p, values, theme) -> its legend, lines [text, colour] (null: a gap), drawn right of
//   the plot, or below it in two columns split at the gap (legendRows: the longer one); title(p).
// p holds every slider and choice value by name and the kernel's constants. The test hook's
// state adds {n, nx, ny, markers, panels, scene, theta, view, xs, ys, particles, density}: the
// arrays base64 float64 (particles (panels*n, 3) or (n,) for a curve, density (panels*ny, nx)),
// scene the scene's values (a number as one element).

// numpy.percentile (linear) of the finite values; NaN if there are none.
function percentile(values, q) {
  const f = Float64Array.from(values).filter(Number.isFinite).sort();
  if (!f.length) return NaN;
  const pos = (q / 100) * (f.length - 1);
  const lo = Math.floor(pos);
  const hi = Math.min(lo + 1, f.length - 1);
  return f[lo] + (f[hi] - f[lo]) * (pos - lo);
}

// The arrays a layer fills and the test hook reads, and the draws decoded.
function plotData(config, panels, ny, perSample) {
  const draws = {};
  for (const [name, b64] of Object.entries(config.draws)) draws[name] = decodeFloat64(b64);
  return {
    draws,
    particles: new Float64Array(panels * config.n * perSample),
    density: new Float64Array(panels * config.grid * ny),
    xs: new Float64Array(config.grid),
    ys: new Float64Array(ny),
    hook(extra) {
      return Object.assign(
        {
          n: config.n,
          nx: config.grid,
          ny,
          markers: [],
          panels,
          scene: {},
          theta: 0,
          xs: encodeFloat64(this.xs),
          ys: encodeFloat64(this.ys),
          particles: encodeFloat64(this.particles),
          density: encodeFloat64(this.density),
        },
        extra,
      );
    },
  };
}

// The view [x0, x1, y0, y1] (square) for `box`: it only grows while the reader drags (so a
// growing α is seen to grow the cloud); refit ("fit view", "reset") fits it to `box` again.
function growView(view, box, refit) {
  if (refit || view === null) return box;
  if (view[0] <= box[0] && view[1] >= box[1] && view[2] <= box[2] && view[3] >= box[3]) return view;
  const lox = Math.min(view[0], box[0]);
  const hix = Math.max(view[1], box[1]);
  const loy = Math.min(view[2], box[2]);
  const hiy = Math.max(view[3], box[3]);
  const half = Math.max(hix - lox, hiy - loy) / 2;
  const cx = (lox + hix) / 2;
  const cy = (loy + hiy) / 2;
  return [cx - half, cx + half, cy - half, cy + half];
}

// the labels of a motion model's density choice ("xy", "pose", "book" of `table`)
function motionDensityLabel(p, table) {
  if (p.density === "xy") return "density over (x′, y′) [1/m²]";
  if (p.density === "pose") return "density at θ′ of the blue arrow [1/(m² rad)]";
  return table + " value at θ′ of the blue arrow";
}

const COLOUR_BAR = { right: 118, below: 58 };

layers.cloud = function ({ kernel, model, config }) {
  const n = config.n;
  const nx = config.grid;
  const ny = config.grid;
  const panels = kernel.panels || 1;
  const data = plotData(config, panels, ny, 3);
  const { particles, density, xs, ys } = data;
  const image = document.createElement("canvas");
  image.width = nx;
  image.height = ny;
  const imageCtx = image.getContext("2d");
  const pixels = imageCtx.createImageData(nx, ny);
  let view = null;
  let heading = 0;
  let grid = null;
  let width = config.width;
  const markersOf = (p) => {
    if (kernel.markers) return kernel.markers(p);
    const e = kernel.end(p);
    return [
      { x: 0, y: 0, theta: p.theta, color: "fg" }, // the start pose
      { x: e[0], y: e[1], theta: e[2], color: "blue" }, // the noise-free end pose
    ];
  };
  const headingOf = (p) => (kernel.heading ? kernel.heading(p) : kernel.end(p)[2]);
  const panelParams = (p) => Array.from({ length: panels }, (_, k) => (panels === 1 ? p : kernel.panel(p, k)));

  // The box of probrob.plotting.motion_extent: central 99 % of the cloud, both poses, padded.
  function fitBox(markers) {
    const px = new Float64Array(panels * n);
    const py = new Float64Array(panels * n);
    for (let i = 0; i < panels * n; i++) {
      px[i] = particles[3 * i];
      py[i] = particles[3 * i + 1];
    }
    const mx = markers.map((m) => m.x);
    const my = markers.map((m) => m.y);
    let lox = Math.min(percentile(px, 0.5), ...mx);
    let hix = Math.max(percentile(px, 99.5), ...mx);
    let loy = Math.min(percentile(py, 0.5), ...my);
    let hiy = Math.max(percentile(py, 99.5), ...my);
    if (!Number.isFinite(lox + hix + loy + hiy)) [lox, hix, loy, hiy] = [-1, 1, -1, 1];
    const cx = (lox + hix) / 2;
    const cy = (loy + hiy) / 2;
    const half = Math.max((Math.max(hix - lox, hiy - loy) / 2) * 1.3, 0.25);
    return [cx - half, cx + half, cy - half, cy + half];
  }

  // the density as an image from the background (zero) to the foreground colour (the 99.5th
  // percentile and above, as probrob.plotting.plot_density_xy): one scale for all panels
  function densityImage(theme, d0, vmax) {
    const bg = theme.rgb("bg");
    const fg = theme.rgb("fg");
    const px = pixels.data;
    for (let i = 0; i < ny; i++) {
      const row = (ny - 1 - i) * nx;
      for (let j = 0; j < nx; j++) {
        let v = density[d0 + i * nx + j];
        if (Number.isNaN(v)) v = 0;
        const t = Math.min(v / vmax, 1);
        const k = 4 * (row + j);
        for (let c = 0; c < 3; c++) px[k + c] = Math.round(bg[c] + (fg[c] - bg[c]) * t);
        px[k + 3] = 255;
      }
    }
    imageCtx.putImageData(pixels, 0, 0);
    return image;
  }

  function drawPanel(ctx, theme, state, panel, vmax) {
    const [x0, x1, y0, y1] = view;
    const box = grid.boxes[panel];
    const [left, top, S] = box;
    const sx = (x) => left + ((x - x0) / (x1 - x0)) * S;
    const sy = (y) => top + S - ((y - y0) / (y1 - y0)) * S;
    const p0 = panel * n * 3;
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(densityImage(theme, panel * nx * ny, vmax), left, top, S, S);
    ctx.save();
    ctx.beginPath();
    ctx.rect(left, top, S, S);
    ctx.clip();
    // one path for all dots: one fill call instead of n (the canvas's cost is per call)
    ctx.fillStyle = theme.alpha("red", 0.6);
    ctx.beginPath();
    for (let i = 0; i < n; i++) {
      ctx.rect(sx(particles[p0 + 3 * i]) - 1.2, sy(particles[p0 + 3 * i + 1]) - 1.2, 2.4, 2.4);
    }
    ctx.fill();
    const len = 0.04 * (x1 - x0);
    ctx.strokeStyle = theme.alpha("red", 0.8);
    ctx.lineWidth = 1;
    ctx.beginPath();
    for (let i = 0; i < Math.min(config.headings, n); i++) {
      const x = particles[p0 + 3 * i];
      const y = particles[p0 + 3 * i + 1];
      const th = particles[p0 + 3 * i + 2];
      ctx.moveTo(sx(x), sy(y));
      ctx.lineTo(sx(x + len * Math.cos(th)), sy(y + len * Math.sin(th)));
    }
    ctx.stroke();
    for (const m of state.markers) {
      const color = theme[m.color] || m.color;
      if (m.theta === null) {
        ctx.fillStyle = color;
        ctx.fillRect(sx(m.x) - 5, sy(m.y) - 5, 10, 10);
      } else {
        const L = 0.08 * (x1 - x0);
        const end = [sx(m.x + L * Math.cos(m.theta)), sy(m.y + L * Math.sin(m.theta))];
        arrow(ctx, sx(m.x), sy(m.y), end[0], end[1], color, 2, 9, 3.5);
      }
    }
    ctx.restore();
    const labels = { x: "x [m]", y: "y [m]", title: kernel.title(state.ps[panel]) };
    axes(ctx, theme, box, view, labels, { yLabels: panel % grid.cols === 0 });
  }

  // the colour bar: right of the plots, or below them on a narrow canvas
  function colourBar(ctx, theme, vmax, label) {
    const first = grid.boxes[0];
    const S = grid.S;
    const span = grid.cols * S + (grid.cols - 1) * GAP;
    const right = grid.beside;
    const x = right ? first[0] + span + 16 : first[0];
    const y = right ? first[1] : grid.below + 4;
    const grad = right
      ? ctx.createLinearGradient(0, y + S, 0, y)
      : ctx.createLinearGradient(x, 0, x + span, 0);
    grad.addColorStop(0, theme.bg);
    grad.addColorStop(1, theme.fg);
    ctx.fillStyle = grad;
    const [w, h] = right ? [14, S] : [span, 12];
    ctx.fillRect(x, y, w, h);
    ctx.strokeStyle = theme.fg;
    ctx.lineWidth = 1;
    ctx.strokeRect(x + 0.5, y + 0.5, w, h);
    ctx.fillStyle = theme.fg;
    ctx.font = "12px sans-serif";
    ctx.textAlign = right ? "left" : "center";
    ctx.textBaseline = right ? "middle" : "top";
    for (const t of niceTicks(0, vmax, 4)) {
      if (right) {
        const Y = y + S - (t / vmax) * S;
        ctx.fillRect(x + 14, Y, 4, 1);
        ctx.fillText(fmtTick(t), x + 20, Y);
      } else {
        const X = x + (t / vmax) * span;
        ctx.fillRect(X, y + 12, 1, 4);
        ctx.fillText(fmtTick(t), X, y + 17);
      }
    }
    ctx.save();
    if (right) {
      ctx.translate(width - 10, y + S / 2);
      ctx.rotate(-Math.PI / 2);
      ctx.textAlign = "center";
      fitText(ctx, label, 0, 0, S, 12);
    } else {
      fitText(ctx, label, x + span / 2, y + 33, span, 12);
    }
    ctx.restore();
  }

  return {
    layout(W) {
      width = W;
      grid = plotGrid(W, config, panels, COLOUR_BAR.right, COLOUR_BAR.below);
      return { height: grid.height, plots: grid.boxes };
    },
    compute(refit) {
      const p = model.params();
      const ps = panelParams(p);
      const z = data.draws[p.distribution || "normal"];
      for (let k = 0; k < panels; k++) {
        kernel.sample(ps[k], z, n, particles.subarray(3 * n * k, 3 * n * (k + 1)), data.draws);
      }
      const markers = markersOf(p);
      view = growView(view, fitBox(markers), refit);
      const dx = (view[1] - view[0]) / nx;
      const dy = (view[3] - view[2]) / ny;
      for (let j = 0; j < nx; j++) xs[j] = view[0] + (j + 0.5) * dx;
      for (let i = 0; i < ny; i++) ys[i] = view[2] + (i + 0.5) * dy;
      heading = headingOf(p);
      for (let k = 0; k < panels; k++) {
        kernel.density(ps[k], xs, ys, heading, density.subarray(nx * ny * k, nx * ny * (k + 1)));
      }
      return { p, ps, markers };
    },
    draw(ctx, state, theme) {
      let vmax = percentile(density, 99.5);
      if (!(vmax > 0)) vmax = 1;
      for (let panel = 0; panel < panels; panel++) drawPanel(ctx, theme, state, panel, vmax);
      colourBar(ctx, theme, vmax, kernel.densityLabel(state.p));
    },
    hook: () => data.hook({ markers: markersOf(model.params()), theta: heading, view: view.slice() }),
    extras: { draws: (name) => encodeFloat64(data.draws[name]) },
  };
};

layers.curve = function ({ kernel, model, config }) {
  const n = config.n;
  const nx = config.grid;
  const data = plotData(config, 1, 1, 1);
  const { particles, density, xs, ys } = data;
  let view = null;
  let box = null;
  return {
    fit: false, // the axis follows the parameters
    layout(W) {
      const h = Math.max(200, (W * config.height) / config.width - MARGIN.top - MARGIN.bottom);
      box = [MARGIN.left, MARGIN.top, W - MARGIN.left - MARGIN.right, h];
      return { height: MARGIN.top + h + MARGIN.bottom, plots: [box] };
    },
    compute() {
      const p = model.params();
      kernel.sample(p, data.draws[p.distribution || "normal"], n, particles, data.draws);
      view = [...kernel.xRange(p), 0, 0];
      const dx = (view[1] - view[0]) / nx;
      for (let j = 0; j < nx; j++) xs[j] = view[0] + (j + 0.5) * dx;
      kernel.density(p, xs, ys, null, density);
      return { p };
    },
    // a histogram of the samples (as a density) under the kernel's curve
    draw(ctx, state, theme) {
      const [x0, x1] = view;
      const bins = 40;
      const width = (x1 - x0) / bins;
      const hist = new Float64Array(bins);
      for (let i = 0; i < n; i++) {
        const k = Math.floor((particles[i] - x0) / width);
        if (k >= 0 && k < bins) hist[k] += 1 / (n * width);
      }
      let ymax = 0;
      for (const v of density) if (Number.isFinite(v)) ymax = Math.max(ymax, v);
      for (const v of hist) ymax = Math.max(ymax, v);
      ymax = ymax > 0 ? ymax * 1.08 : 1;
      const labels = Object.assign({ title: kernel.title(state.p) }, kernel.labels(state.p));
      const [sx, sy] = axes(ctx, theme, box, [x0, x1, 0, ymax], labels);
      ctx.fillStyle = theme.alpha("red", 0.35);
      for (let k = 0; k < bins; k++) {
        const top = sy(Math.min(hist[k], ymax));
        ctx.fillRect(sx(x0 + k * width), top, sx(x0 + (k + 1) * width) - sx(x0 + k * width), sy(0) - top);
      }
      const curve = Array.from(xs, (x, j) => [sx(x), sy(Math.min(Number.isFinite(density[j]) ? density[j] : ymax, ymax))]);
      polyline(ctx, curve, theme.blue, 2);
    },
    hook: () => data.hook({ view: view.slice() }),
    extras: { draws: (name) => encodeFloat64(data.draws[name]) },
  };
};

layers.scene = function ({ kernel, model, config }) {
  const data = plotData(config, 1, config.grid, 3);
  const rows = kernel.legendRows || 6; // the legend's longest column, in two columns below
  let values = {};
  let view = null;
  let grid = null;
  let width = config.width;
  return {
    layout(W) {
      width = W;
      grid = plotGrid(W, config, 1, 118, rows * 17 + 16);
      return { height: grid.height, plots: grid.boxes };
    },
    compute(refit) {
      const p = model.params();
      const out = kernel.scene(p);
      values = out.values;
      const px = out.points.map((q) => q[0]);
      const py = out.points.map((q) => q[1]);
      const cx = (Math.min(...px) + Math.max(...px)) / 2;
      const cy = (Math.min(...py) + Math.max(...py)) / 2;
      const half = Math.max(((Math.max(...px) - Math.min(...px)) / 2) * 1.15, ((Math.max(...py) - Math.min(...py)) / 2) * 1.15, 0.25);
      view = growView(view, [cx - half, cx + half, cy - half, cy + half], refit);
      return { p };
    },
    draw(ctx, state, theme) {
      const box = grid.boxes[0];
      const [left, top, S] = box;
      const [x0, x1, y0, y1] = view;
      const sx = (x) => left + ((x - x0) / (x1 - x0)) * S;
      const sy = (y) => top + S - ((y - y0) / (y1 - y0)) * S;
      const place = grid.beside
        ? { x: left + S + 10, y: top + 6, columns: 1, width: 0 }
        : { x: 16, y: grid.below + 6, columns: 2, width: (width - 16) / 2 };
      ctx.save();
      ctx.beginPath();
      ctx.rect(left, top, S, S);
      ctx.clip();
      kernel.drawScene(ctx, state.p, values, { sx, sy, box, theme });
      ctx.restore();
      legend(ctx, theme, place, kernel.legend(state.p, values, theme));
      axes(ctx, theme, box, view, { x: "x [m]", y: "y [m]", title: kernel.title(state.p) });
    },
    hook: () =>
      data.hook({
        view: view.slice(),
        scene: Object.fromEntries(
          Object.entries(values).map(([k, v]) => [k, encodeFloat64(typeof v === "number" ? Float64Array.of(v) : v)]),
        ),
      }),
  };
};
