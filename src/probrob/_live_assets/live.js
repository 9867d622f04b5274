// probrob live widget, generic part: controls, view box, drawing, timing and the test hook.
// Inlined into every widget's HTML by probrob/_live.py together with one model kernel file,
// which adds its kernel to `kernels` (see velocity.js). No network, no library, no build step.
//
// A kernel is an object with
//   markers(p)          -> [{x, y, theta, color}, ...]: poses drawn as arrows (theta null: a
//                          square, e.g. a landmark); the view always holds them
//   heading(p)          -> the hypothesis heading of densities over (x, y) at a fixed heading
//   sample(p, z, n, out, draws)  fills out (Float64Array, n*3, rows x, y, theta) from the
//                          standardized draws z = draws[p.distribution] (Float64Array, k*n,
//                          row k = z[k*n .. k*n+n)); draws holds every embedded array by name
//   density(p, xs, ys, theta, out)  fills out (Float64Array, ys.length*xs.length, row-major,
//                          out[i*nx + j] at (xs[j], ys[i])) with the density; theta = heading(p)
//   title(p)            -> string above the plot
//   densityLabel(p)     -> string beside the colour bar
// A kernel with kind: "curve" draws a function of one variable instead (a sensor model such as
// the beam model's p(z | z*)): sample fills n values (a histogram is drawn of them), density
// fills one value per xs (ys is [0]), xRange(p) -> [x0, x1] replaces markers and heading, and
// labels(p) -> {x, y} names the axes (see distribution.js).
// where p holds every slider and choice value by name, plus p.logProb(a, b2), the log of the
// zero-mean density of Table 5.2 chosen by p.distribution (default "normal").
// A kernel with panels: k (k > 1) draws k clouds side by side in one view (the same draws, the
// same grey scale): panel j is the kernel at the parameters panel(p, j), titled title(panel(p, j))
// (see noise_forms.js). The test hook's particles are then (k*n, 3), panel after panel, and its
// density (k*ny, nx).
// A kernel with kind: "scene" draws a construction instead of a cloud (no samples, no density;
// see cir.js): scene(p) -> {values: {name: number | Float64Array}, points: [[x, y], ...]} (the
// view holds the points), drawScene(ctx, p, values, sx, sy, box) draws it (box: the plot's
// {left, top, size} and the canvas's right edge, in CSS pixels; the kernel clips what may leave
// the plot, and may put a legend right of it), title(p) above it. The test hook's state then
// has scene: every value as base64 float64 (a number as one element).

const kernels = {};

const TWO_PI = 2 * Math.PI;
const SQRT6 = Math.sqrt(6);

// numpy's round (half to even) and probrob.angles.wrap_angle, operation for operation: the
// fast route below |θ| = 40, the exact remainder (fmod, JavaScript's %) above.
function roundHalfEven(x) {
  let r = Math.round(x);
  if (r - x === 0.5 && r % 2 !== 0) r -= 1;
  return r;
}
function wrapAngle(t) {
  let r;
  if (Math.abs(t) < 40) {
    r = t - roundHalfEven(t * (1 / TWO_PI)) * TWO_PI;
  } else {
    r = t % TWO_PI;
  }
  if (r >= Math.PI) r -= TWO_PI;
  if (r < -Math.PI) r += TWO_PI;
  return r;
}
// probrob.angles._diff: exact also when a - b overflows
function angleDiff(a, b) {
  let d = a - b;
  if (!Number.isFinite(d)) d = wrapAngle(a) - wrapAngle(b);
  return wrapAngle(d);
}
function sinc(h) {
  return h !== 0 ? Math.sin(h) / h : 1;
}

// Table 5.2 in log space, as probrob.distributions computes it (the linear density is its exp);
// a zero variance is a point mass: +inf at a == 0, -inf elsewhere.
const HALF_LOG_2PI = 0.5 * Math.log(2 * Math.PI);
const LOG_PROB = {
  normal(a, b2) {
    if (!(b2 > 0)) return a === 0 ? Infinity : -Infinity;
    const b = Math.sqrt(b2);
    let z = a / b;
    z = z * z;
    z *= -0.5;
    z -= Math.log(b) + HALF_LOG_2PI;
    return z;
  },
  triangular(a, b2) {
    if (!(b2 > 0)) return a === 0 ? Infinity : -Infinity;
    const width = SQRT6 * Math.sqrt(b2); // half-width of the triangle
    const t = Math.min(Math.abs(a) / width, 1);
    let out = Math.log1p(-t); // -inf at and beyond the edge
    out -= Math.log(width);
    return out;
  },
};

// probrob.motion._log_product: the sum of the log factors, -inf if any is -inf (off a point
// mass, also against a matched point mass's +inf).
function logProduct(l0, l1, l2) {
  let total = l0 + l1;
  if (l2 !== undefined) total += l2;
  if (l0 === -Infinity || l1 === -Infinity || l2 === -Infinity) return -Infinity;
  return total;
}
// probrob.motion._minus_log_jacobian: a zero density over a zero Jacobian stays zero
function minusLogJacobian(total, logJac) {
  return total === -Infinity ? -Infinity : total - logJac;
}

// The variance of one noise term, as probrob.motion._noise_variance: a*m² + b*n² (+ c*o²) in the
// "variance" form, (a|m| + b|n| (+ c|o|))² in the "std" form. Plain arguments, no arrays: it
// runs once per grid point in the odometry model's book density.
function noiseVariance(noise, a, m, b, n, c, o) {
  if (noise === "variance") {
    const v = a * (m * m) + b * (n * n);
    return c === undefined ? v : v + c * (o * o);
  }
  let s = a * Math.abs(m) + b * Math.abs(n);
  if (c !== undefined) s = s + c * Math.abs(o);
  return s * s;
}

function decodeFloat64(b64) {
  const bin = atob(b64);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
  return new Float64Array(bytes.buffer);
}
function encodeFloat64(arr) {
  const bytes = new Uint8Array(arr.buffer, arr.byteOffset, arr.byteLength);
  let s = "";
  for (let i = 0; i < bytes.length; i += 0x8000) {
    s += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
  }
  return btoa(s);
}

// numpy.percentile (linear) of the finite values; NaN if there are none.
function percentile(values, q) {
  const f = Float64Array.from(values).filter(Number.isFinite).sort();
  if (!f.length) return NaN;
  const pos = (q / 100) * (f.length - 1);
  const lo = Math.floor(pos);
  const hi = Math.min(lo + 1, f.length - 1);
  return f[lo] + (f[hi] - f[lo]) * (pos - lo);
}

function niceTicks(lo, hi, count) {
  const raw = (hi - lo) / Math.max(count, 1);
  const mag = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 2.5, 5, 10].map((m) => m * mag).find((s) => s >= raw) || raw;
  const ticks = [];
  for (let t = Math.ceil(lo / step) * step; t <= hi + step * 1e-9; t += step) {
    ticks.push(Math.abs(t) < step * 1e-9 ? 0 : t);
  }
  return ticks;
}
function fmtTick(t) {
  const a = Math.abs(t);
  if (a !== 0 && (a >= 1e4 || a < 1e-3)) return t.toExponential(1);
  return String(Number(t.toPrecision(4)));
}

// The canvas keeps the aspect ratio config.width : config.height at any width (CSS width 100 %,
// at most config.width CSS pixels, height from aspect-ratio: no inline height). Its bitmap is
// its displayed size times devicePixelRatio; returns [CSS width, CSS height, devicePixelRatio],
// the size the drawing is laid out for. Before layout (a hidden or not yet attached block) the
// displayed width is unknown: config.width is used.
function fitCanvas(canvas, config) {
  canvas.style.maxWidth = config.width + "px";
  canvas.style.aspectRatio = config.width + " / " + config.height;
  const dpr = window.devicePixelRatio || 1;
  const shown = canvas.getBoundingClientRect().width;
  const w = shown > 0 ? shown : config.width;
  const h = (w * config.height) / config.width;
  const bw = Math.max(1, Math.round(w * dpr));
  const bh = Math.max(1, Math.round(h * dpr));
  if (canvas.width !== bw) canvas.width = bw;
  if (canvas.height !== bh) canvas.height = bh;
  return [w, h, dpr];
}
// Calls redraw() (on the next animation frame) when the canvas's displayed width or the
// devicePixelRatio changes: a rotated phone, a resized window, a zoom.
function watchCanvasSize(canvas, config, redraw) {
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

function mountLiveWidget(root, config, kernel) {
  const n = config.n;
  const nx = config.grid;
  const ny = kernel.kind === "curve" ? 1 : config.grid;
  const draws = {};
  for (const [name, b64] of Object.entries(config.draws)) draws[name] = decodeFloat64(b64);
  const canvas = root.querySelector("canvas");
  const ctx = canvas.getContext("2d");
  // W x H: the canvas's displayed size in CSS pixels (the drawing's coordinates; text in CSS
  // pixels stays legible on a phone); the bitmap is that times devicePixelRatio. See fitCanvas.
  let W = config.width;
  let H = config.height;
  let dpr = window.devicePixelRatio || 1;
  fitCanvas(canvas, config);
  const image = document.createElement("canvas");
  image.width = nx;
  image.height = ny;
  const imageCtx = image.getContext("2d");
  const pixels = imageCtx.createImageData(nx, ny);

  const curve = kernel.kind === "curve";
  const isScene = kernel.kind === "scene";
  const panels = kernel.panels || 1;
  let sceneValues = {};
  const particles = new Float64Array(curve ? n : panels * n * 3);
  const density = new Float64Array(panels * nx * ny);
  const xs = new Float64Array(nx);
  const ys = new Float64Array(ny);
  const values = {};
  const defaults = {};
  const ranges = {};
  const numbers = {};
  const selects = {};
  for (const s of config.sliders) {
    defaults[s.name] = s.value;
    ranges[s.name] = root.querySelector('input[type="range"][data-param="' + s.name + '"]');
    numbers[s.name] = root.querySelector('input[type="number"][data-param="' + s.name + '"]');
  }
  for (const c of config.choices) {
    defaults[c.name] = c.value;
    selects[c.name] = root.querySelector('select[data-param="' + c.name + '"]');
  }
  Object.assign(values, defaults);
  let view = null; // [x0, x1, y0, y1], square
  let hypothesisHeading = 0;
  const timings = { compute: 0, draw: 0, total: 0 };
  let pending = false;

  function params() {
    const p = Object.assign({}, config.constants, values);
    // the "distribution" choice names both the draws and the density (default "normal")
    const family = p.distribution || "normal";
    p.family = family;
    p.logProb = LOG_PROB[family];
    return p;
  }

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
  function contains(outer, inner) {
    return outer[0] <= inner[0] && outer[1] >= inner[1] && outer[2] <= inner[2] && outer[3] >= inner[3];
  }
  // The view only grows while the reader drags (so a growing α is seen to grow the cloud);
  // "fit view" and "reset" shrink it to the cloud again.
  function updateView(box, refit) {
    if (refit || view === null) {
      view = box;
    } else if (!contains(view, box)) {
      const lox = Math.min(view[0], box[0]);
      const hix = Math.max(view[1], box[1]);
      const loy = Math.min(view[2], box[2]);
      const hiy = Math.max(view[3], box[3]);
      const half = Math.max(hix - lox, hiy - loy) / 2;
      const cx = (lox + hix) / 2;
      const cy = (loy + hiy) / 2;
      view = [cx - half, cx + half, cy - half, cy + half];
    }
  }

  // the parameters of each panel (one panel: p itself)
  function panelParams(p) {
    if (panels === 1) return [p];
    return Array.from({ length: panels }, (_, k) => kernel.panel(p, k));
  }
  function compute(refit) {
    const p = params();
    if (isScene) {
      const out = kernel.scene(p);
      sceneValues = out.values;
      const px = out.points.map((q) => q[0]);
      const py = out.points.map((q) => q[1]);
      const cx = (Math.min(...px) + Math.max(...px)) / 2;
      const cy = (Math.min(...py) + Math.max(...py)) / 2;
      const half = Math.max(((Math.max(...px) - Math.min(...px)) / 2) * 1.15, ((Math.max(...py) - Math.min(...py)) / 2) * 1.15, 0.25);
      updateView([cx - half, cx + half, cy - half, cy + half], refit);
      return { p, markers: [] };
    }
    const ps = panelParams(p);
    for (let k = 0; k < panels; k++) {
      kernel.sample(ps[k], draws[p.family], n, particles.subarray(3 * n * k, 3 * n * (k + 1)), draws);
    }
    if (curve) {
      view = [...kernel.xRange(p), 0, 0];
      const dx = (view[1] - view[0]) / nx;
      for (let j = 0; j < nx; j++) xs[j] = view[0] + (j + 0.5) * dx;
      kernel.density(p, xs, ys, null, density);
      return { p, markers: [] };
    }
    const markers = kernel.markers(p);
    updateView(fitBox(markers), refit);
    const dx = (view[1] - view[0]) / nx;
    const dy = (view[3] - view[2]) / ny;
    for (let j = 0; j < nx; j++) xs[j] = view[0] + (j + 0.5) * dx;
    for (let i = 0; i < ny; i++) ys[i] = view[2] + (i + 0.5) * dy;
    hypothesisHeading = kernel.heading(p);
    for (let k = 0; k < panels; k++) {
      kernel.density(ps[k], xs, ys, hypothesisHeading, density.subarray(nx * ny * k, nx * ny * (k + 1)));
    }
    return { p, ps, markers };
  }

  // ---- drawing ------------------------------------------------------------------------
  const M = { left: 62, top: 34, right: 118, bottom: 48 };
  const GAP = 14; // between panels, which share the y axis (its labels on the first only)
  let S = 0;
  function layout() {
    [W, H, dpr] = fitCanvas(canvas, config);
    S = Math.min((W - M.left - M.right - (panels - 1) * GAP) / panels, H - M.top - M.bottom);
  }
  layout();

  function arrow(x, y, th, length, color, sx, sy) {
    const x0 = sx(x);
    const y0 = sy(y);
    const x1 = sx(x + length * Math.cos(th));
    const y1 = sy(y + length * Math.sin(th));
    ctx.strokeStyle = color;
    ctx.fillStyle = color;
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.arc(x0, y0, 3.5, 0, TWO_PI);
    ctx.fill();
    ctx.beginPath();
    ctx.moveTo(x0, y0);
    ctx.lineTo(x1, y1);
    ctx.stroke();
    const a = Math.atan2(y1 - y0, x1 - x0);
    ctx.beginPath();
    ctx.moveTo(x1, y1);
    ctx.lineTo(x1 - 9 * Math.cos(a - 0.4), y1 - 9 * Math.sin(a - 0.4));
    ctx.lineTo(x1 - 9 * Math.cos(a + 0.4), y1 - 9 * Math.sin(a + 0.4));
    ctx.closePath();
    ctx.fill();
  }

  // A plot box of PW x PH pixels at (M.left + offset, M.top) for [x0, x1] x [y0, y1]: frame, ticks,
  // axis labels and title (a panel right of the first, offset > 0, shares its y labels);
  // returns the maps from data to pixels.
  function frame(x0, x1, y0, y1, PW, PH, xlabel, ylabel, title, offset) {
    const left = M.left + (offset || 0);
    const sx = (x) => left + ((x - x0) / (x1 - x0)) * PW;
    const sy = (y) => M.top + PH - ((y - y0) / (y1 - y0)) * PH;
    ctx.strokeStyle = "#000";
    ctx.lineWidth = 1;
    ctx.strokeRect(left + 0.5, M.top + 0.5, PW, PH);
    ctx.fillStyle = "#000";
    ctx.font = "12px sans-serif";
    ctx.textAlign = "center";
    ctx.textBaseline = "top";
    for (const t of niceTicks(x0, x1, 5)) {
      const X = sx(t);
      ctx.fillRect(X, M.top + PH, 1, 5);
      ctx.fillText(fmtTick(t), X, M.top + PH + 7);
    }
    ctx.fillText(xlabel, left + PW / 2, M.top + PH + 26);
    ctx.textAlign = "right";
    ctx.textBaseline = "middle";
    for (const t of niceTicks(y0, y1, 5)) {
      const Y = sy(t);
      ctx.fillRect(left - 5, Y, 5, 1);
      if (!offset) ctx.fillText(fmtTick(t), left - 7, Y);
    }
    if (!offset) {
      ctx.save();
      ctx.translate(left - 46, M.top + PH / 2);
      ctx.rotate(-Math.PI / 2);
      ctx.textAlign = "center";
      ctx.fillText(ylabel, 0, 0);
      ctx.restore();
    }
    ctx.textAlign = "center";
    ctx.textBaseline = "bottom";
    ctx.font = "13px sans-serif";
    ctx.fillText(title, left + PW / 2, M.top - 10);
    return [sx, sy];
  }

  // kind "curve": a histogram of the samples (as a density) under the kernel's curve
  function drawCurve(p) {
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
    const PW = W - M.left - 24;
    const PH = H - M.top - M.bottom;
    const labels = kernel.labels(p);
    const [sx, sy] = frame(x0, x1, 0, ymax, PW, PH, labels.x, labels.y, kernel.title(p));
    ctx.fillStyle = "rgba(214, 39, 40, 0.35)";
    for (let k = 0; k < bins; k++) {
      const top = sy(Math.min(hist[k], ymax));
      ctx.fillRect(sx(x0 + k * width), top, sx(x0 + (k + 1) * width) - sx(x0 + k * width), sy(0) - top);
    }
    ctx.strokeStyle = "#1f77b4";
    ctx.lineWidth = 2;
    ctx.beginPath();
    for (let j = 0; j < nx; j++) {
      const y = sy(Math.min(Number.isFinite(density[j]) ? density[j] : ymax, ymax));
      if (j === 0) ctx.moveTo(sx(xs[j]), y);
      else ctx.lineTo(sx(xs[j]), y);
    }
    ctx.stroke();
  }

  function draw(state) {
    const { p, markers } = state;
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.fillStyle = "#fff";
    ctx.fillRect(0, 0, W, H);
    if (curve) {
      drawCurve(p);
      return;
    }
    const [x0, x1, y0, y1] = view;
    if (isScene) {
      const sx = (x) => M.left + ((x - x0) / (x1 - x0)) * S;
      const sy = (y) => M.top + S - ((y - y0) / (y1 - y0)) * S;
      kernel.drawScene(ctx, p, sceneValues, sx, sy, { left: M.left, top: M.top, size: S, right: W });
      frame(x0, x1, y0, y1, S, S, "x [m]", "y [m]", kernel.title(p));
      return;
    }
    const ps = state.ps;
    // density image (grey, darker is more probable; linear from 0 to the 99.5th percentile,
    // as probrob.plotting.plot_density_xy; one grey scale for all panels)
    let vmax = percentile(density, 99.5);
    if (!(vmax > 0)) vmax = 1;
    for (let panel = 0; panel < panels; panel++) {
      const ox = panel * (S + GAP);
      const sx = (x) => M.left + ox + ((x - x0) / (x1 - x0)) * S;
      const sy = (y) => M.top + S - ((y - y0) / (y1 - y0)) * S;
      const d0 = panel * nx * ny;
      const p0 = panel * n * 3;
      const px = pixels.data;
      for (let i = 0; i < ny; i++) {
        const row = (ny - 1 - i) * nx;
        for (let j = 0; j < nx; j++) {
          let v = density[d0 + i * nx + j];
          if (Number.isNaN(v)) v = 0;
          const g = Math.round(255 * (1 - Math.min(v / vmax, 1)));
          const k = 4 * (row + j);
          px[k] = g;
          px[k + 1] = g;
          px[k + 2] = g;
          px[k + 3] = 255;
        }
      }
      imageCtx.putImageData(pixels, 0, 0);
      ctx.imageSmoothingEnabled = false;
      ctx.drawImage(image, M.left + ox, M.top, S, S);

      // samples, and the heading of the first few
      ctx.save();
      ctx.beginPath();
      ctx.rect(M.left + ox, M.top, S, S);
      ctx.clip();
      // one path for all dots: one fill call instead of n (the canvas's cost is per call)
      ctx.fillStyle = "rgba(214, 39, 40, 0.6)";
      ctx.beginPath();
      for (let i = 0; i < n; i++) {
        ctx.rect(sx(particles[p0 + 3 * i]) - 1.2, sy(particles[p0 + 3 * i + 1]) - 1.2, 2.4, 2.4);
      }
      ctx.fill();
      const len = 0.04 * (x1 - x0);
      ctx.strokeStyle = "rgba(214, 39, 40, 0.8)";
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
      for (const m of markers) {
        if (m.theta === null) {
          ctx.fillStyle = m.color;
          ctx.fillRect(sx(m.x) - 5, sy(m.y) - 5, 10, 10);
        } else {
          arrow(m.x, m.y, m.theta, 0.08 * (x1 - x0), m.color, sx, sy);
        }
      }
      ctx.restore();

      frame(x0, x1, y0, y1, S, S, "x [m]", "y [m]", kernel.title(ps[panel]), ox);
    }

    // colour bar
    const cbx = M.left + panels * S + (panels - 1) * GAP + 16;
    const grad = ctx.createLinearGradient(0, M.top + S, 0, M.top);
    grad.addColorStop(0, "#fff");
    grad.addColorStop(1, "#000");
    ctx.fillStyle = grad;
    ctx.fillRect(cbx, M.top, 14, S);
    ctx.strokeRect(cbx + 0.5, M.top + 0.5, 14, S);
    ctx.fillStyle = "#000";
    ctx.font = "12px sans-serif";
    ctx.textAlign = "left";
    ctx.textBaseline = "middle";
    for (const t of niceTicks(0, vmax, 4)) {
      const Y = M.top + S - (t / vmax) * S;
      ctx.fillRect(cbx + 14, Y, 4, 1);
      ctx.fillText(fmtTick(t), cbx + 20, Y);
    }
    ctx.save();
    ctx.translate(W - 10, M.top + S / 2);
    ctx.rotate(-Math.PI / 2);
    ctx.textAlign = "center";
    ctx.fillText(kernel.densityLabel(p), 0, 0);
    ctx.restore();
  }

  let lastState = null;
  function update(refit) {
    const t0 = performance.now();
    const state = compute(refit);
    lastState = state;
    const t1 = performance.now();
    draw(state);
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
  // a new displayed size: a new bitmap, the same state drawn again (nothing recomputed)
  watchCanvasSize(canvas, config, () => {
    layout();
    if (lastState !== null) draw(lastState);
  });

  // ---- controls -----------------------------------------------------------------------
  function show(name) {
    if (name in ranges) {
      ranges[name].value = String(values[name]);
      numbers[name].value = String(values[name]);
    } else {
      selects[name].value = values[name];
    }
  }
  function setValue(name, raw) {
    if (name in selects) {
      if (![...selects[name].options].some((o) => o.value === raw)) {
        throw new Error("probrob live widget: no option " + raw + " for " + name);
      }
      values[name] = raw;
      return;
    }
    const s = config.sliders.find((t) => t.name === name);
    if (!s) throw new Error("probrob live widget: no parameter " + name);
    const v = Number(raw);
    if (Number.isFinite(v)) values[name] = Math.min(Math.max(v, s.min), s.max);
  }
  for (const name of Object.keys(ranges)) {
    ranges[name].addEventListener("input", () => {
      setValue(name, ranges[name].value);
      numbers[name].value = ranges[name].value;
      schedule();
    });
    numbers[name].addEventListener("change", () => {
      setValue(name, numbers[name].value);
      show(name);
      schedule();
    });
  }
  for (const name of Object.keys(selects)) {
    selects[name].addEventListener("change", () => {
      setValue(name, selects[name].value);
      schedule();
    });
  }
  root.querySelector('[data-action="reset"]').addEventListener("click", () => {
    Object.assign(values, defaults);
    for (const name of Object.keys(defaults)) show(name);
    update(true);
  });
  const fit = root.querySelector('[data-action="fit"]');
  fit.addEventListener("click", () => update(true));
  if (curve) fit.hidden = true; // a curve's axis follows its parameters

  // ---- the test hook (documented in probrob/_live.py) ---------------------------------
  const handle = {
    id: root.id,
    kernel: config.kernel,
    values: () => Object.assign({}, values),
    defaults: () => Object.assign({}, defaults),
    config: () => ({
      sliders: config.sliders,
      choices: config.choices.map((c) => ({
        name: c.name,
        options: [...selects[c.name].options].map((o) => o.value),
      })),
    }),
    set(changes, refit) {
      for (const [name, v] of Object.entries(changes)) setValue(name, v);
      for (const name of Object.keys(changes)) show(name);
      update(Boolean(refit));
      return handle.state();
    },
    state() {
      const p = params();
      return {
        values: Object.assign({}, values),
        n,
        nx,
        ny,
        markers: curve || isScene ? [] : kernel.markers(p),
        panels,
        scene: Object.fromEntries(
          Object.entries(sceneValues).map(([k, v]) => [k, encodeFloat64(typeof v === "number" ? Float64Array.of(v) : v)])
        ),
        theta: hypothesisHeading,
        view: view.slice(),
        xs: encodeFloat64(xs),
        ys: encodeFloat64(ys),
        particles: encodeFloat64(particles),
        density: encodeFloat64(density),
        timings: Object.assign({}, timings),
      };
    },
    draws: (name) => encodeFloat64(draws[name]),
    bench(count) {
      const names = config.sliders.map((s) => s.name);
      const saved = Object.assign({}, values);
      const times = { compute: [], draw: [], total: [] };
      const warmup = 10; // untimed: let the JIT compile the kernel first
      for (let k = 0; k < warmup + count; k++) {
        const s = config.sliders[k % names.length];
        values[s.name] = s.min + ((k * 0.618034) % 1) * (s.max - s.min);
        update(false);
        if (k < warmup) continue;
        for (const key of Object.keys(times)) times[key].push(timings[key]);
      }
      Object.assign(values, saved);
      update(true);
      const out = { count };
      for (const [key, t] of Object.entries(times)) {
        t.sort((a, b) => a - b);
        const at = (q) => t[Math.min(count - 1, Math.floor(q * count))];
        out[key] = { median: at(0.5), p90: at(0.9), max: t[count - 1] };
      }
      return out;
    },
  };
  window.probrobLive = window.probrobLive || { widgets: [] };
  window.probrobLive.widgets.push(handle);
  update(true);
  root.setAttribute("data-ready", "true");
  return handle;
}
