// The live particle filter: Monte Carlo localization (Table 8.2) over a stretch of a laser log,
// with the odometry sampler (Table 5.6, odometryDeltas of odometry.js), the likelihood field
// (Table 6.3) and the low-variance sampler (Table 4.4), written as probrob.mcl writes them and
// held equal to it by tests/test_live_mcl.py. Inlined after live.js (wrapAngle, noiseVariance,
// decodeFloat64, encodeFloat64, niceTicks, fmtTick) and odometry.js by
// probrob._live.particle_filter_live, which documents the embedded data and random numbers.
// The test hook (window.probrobLive.widgets) has the generic widgets' values, defaults, config,
// set, state and bench, and field() (the distance field), for the tests and the browser check.

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

// The squared Euclidean distance (in cells²) from every cell centre to the nearest occupied
// cell centre: exact, in integers (Felzenszwalb & Huttenlocher's lower envelope of parabolas,
// one pass down the columns, one along the rows). Every value stays below 2^21, so every
// intersection point is a quotient of small integers and every comparison is exact: the
// distance field is sqrt(d2) * resolution, what scipy's exact transform gives probrob.
function squaredDistanceField(occupied, h, w) {
  const far = h + w + 1; // more than any distance inside the grid
  const g = new Float64Array(h * w);
  for (let j = 0; j < w; j++) {
    let last = -1;
    for (let i = 0; i < h; i++) {
      if (occupied[i * w + j]) last = i;
      g[i * w + j] = last < 0 ? far : i - last;
    }
    last = -1;
    for (let i = h - 1; i >= 0; i--) {
      if (occupied[i * w + j]) last = i;
      if (last >= 0 && last - i < g[i * w + j]) g[i * w + j] = last - i;
    }
  }
  const d2 = new Float64Array(h * w);
  const f = new Float64Array(w);
  const v = new Int32Array(w);
  const z = new Float64Array(w + 1);
  for (let i = 0; i < h; i++) {
    for (let j = 0; j < w; j++) f[j] = g[i * w + j] * g[i * w + j];
    let k = 0;
    v[0] = 0;
    z[0] = -Infinity;
    z[1] = Infinity;
    for (let q = 1; q < w; q++) {
      let s = (f[q] + q * q - (f[v[k]] + v[k] * v[k])) / (2 * q - 2 * v[k]);
      while (s <= z[k]) {
        k--;
        s = (f[q] + q * q - (f[v[k]] + v[k] * v[k])) / (2 * q - 2 * v[k]);
      }
      k++;
      v[k] = q;
      z[k] = s;
      z[k + 1] = Infinity;
    }
    k = 0;
    for (let q = 0; q < w; q++) {
      while (z[k + 1] < q) k++;
      d2[i * w + q] = (q - v[k]) * (q - v[k]) + f[v[k]];
    }
  }
  return d2;
}

// numpy.logaddexp (npy_logaddexp)
function logAddExp(x, y) {
  if (x === y) return x + Math.LN2;
  const tmp = x - y;
  if (tmp > 0) return x + Math.log1p(Math.exp(-tmp));
  if (tmp <= 0) return y + Math.log1p(Math.exp(tmp));
  return tmp;
}

// probrob.sensors.likelihood_field_table: log(z_hit ε_σ²(d) + z_rand / z_max) per cell, padded
// by one cell holding log(z_rand / z_max) (end points outside the map); shape (h + 2, w + 2)
const LOG_SQRT_2PI = 0.5 * Math.log(2 * Math.PI);
function likelihoodTable(d, h, w, zHit, zRand, sigma, maxRange, out) {
  const floor = Math.log(zRand / maxRange);
  const logZHit = Math.log(zHit);
  const logSigma = Math.log(sigma);
  out.fill(floor);
  for (let i = 0; i < h; i++) {
    for (let j = 0; j < w; j++) {
      const q = d[i * w + j] / sigma;
      const logHit = logZHit - 0.5 * (q * q) - logSigma - LOG_SQRT_2PI;
      out[(i + 1) * (w + 2) + j + 1] = logAddExp(logHit, floor);
    }
  }
  return out;
}

// probrob._live.particle_filter_beams: round(linspace(0, total - 1, k)), half to even
function beamSelection(total, k) {
  const out = new Int32Array(k);
  if (k === 1) return out;
  const step = (total - 1) / (k - 1);
  for (let i = 0; i < k; i++) out[i] = roundHalfEven(i * step);
  out[k - 1] = total - 1;
  return out;
}

// probrob.mcl.low_variance_sampler with its offset given (Table 4.4): indices into w (n) for
// m equally spaced pointers k + offset (in units of 1/m), pointer k taking the i with
// m c_{i-1} <= k + offset < m c_i; the pointers below x number floor(x) + [offset < frac(x)]
function lowVarianceSampler(w, n, m, offset, out) {
  let total = 0;
  for (let i = 0; i < n; i++) total += w[i];
  let last = n - 1; // the last particle of weight > 0: c = 1 from there (as probrob)
  while (last > 0 && w[last] === 0) last--;
  let c = 0;
  let done = 0;
  for (let i = 0; i < n; i++) {
    c = i >= last ? 1 : c + w[i] / total; // lines 4 and 10
    const x = m * c;
    const whole = Math.floor(x);
    const below = Math.min(whole + (offset < x - whole ? 1 : 0), m);
    while (done < below) out[done++] = i; // lines 5-9
  }
  return out;
}

// probrob.mcl.estimate_pose of n equally weighted particles: bins of side `radius` in (x, y)
// and `nTheta` equal heading sectors that wrap at ±π; the block of 3 x 3 x 3 bins that holds
// the most particles seeds the cluster (ties: the smallest centre bin in (x, y, θ) order,
// numpy.unique's); then the mean of the particles within 2·radius of the block's mean in x
// and y and within two sectors of its circular mean heading, θ by circular mean
function estimatePose(x, n, radius, nTheta) {
  const counts = new Map();
  const bx = new Float64Array(n);
  const by = new Float64Array(n);
  const bt = new Int32Array(n);
  const th = new Float64Array(n);
  const sector = TWO_PI / nTheta;
  for (let i = 0; i < n; i++) {
    bx[i] = Math.floor(x[3 * i] / radius);
    by[i] = Math.floor(x[3 * i + 1] / radius);
    th[i] = wrapAngle(x[3 * i + 2]);
    bt[i] = Math.min(Math.floor((th[i] + Math.PI) / sector), nTheta - 1);
    const key = bx[i] + "," + by[i] + "," + bt[i];
    counts.set(key, (counts.get(key) || 0) + 1);
  }
  let best = null;
  for (const key of counts.keys()) {
    const [kx, ky, kt] = key.split(",").map(Number);
    let c = 0;
    for (let di = -1; di <= 1; di++) {
      for (let dj = -1; dj <= 1; dj++) {
        for (let dk = -1; dk <= 1; dk++) {
          const t = (((kt + dk) % nTheta) + nTheta) % nTheta;
          c += counts.get(kx + di + "," + (ky + dj) + "," + t) || 0;
        }
      }
    }
    const before = (a) =>
      kx < a.kx || (kx === a.kx && (ky < a.ky || (ky === a.ky && kt < a.kt)));
    if (best === null || c > best.c || (c === best.c && before(best))) best = { c, kx, ky, kt };
  }
  const wgt = 1 / n;
  let sx = 0;
  let sy = 0;
  let ss = 0;
  let sc = 0;
  let sw = 0;
  for (let i = 0; i < n; i++) {
    const dt = (((bt[i] - best.kt + 1) % nTheta) + nTheta) % nTheta;
    if (Math.abs(bx[i] - best.kx) <= 1 && Math.abs(by[i] - best.ky) <= 1 && dt <= 2) {
      sx += x[3 * i] * wgt;
      sy += x[3 * i + 1] * wgt;
      ss += wgt * Math.sin(th[i]);
      sc += wgt * Math.cos(th[i]);
      sw += wgt;
    }
  }
  const cx = sx / sw;
  const cy = sy / sw;
  const heading = Math.atan2(ss, sc);
  let ax = 0;
  let ay = 0;
  let as = 0;
  let ac = 0;
  let fraction = 0;
  for (let i = 0; i < n; i++) {
    if (
      Math.abs(x[3 * i] - cx) <= 2 * radius &&
      Math.abs(x[3 * i + 1] - cy) <= 2 * radius &&
      Math.abs(angleDiff(th[i], heading)) <= 2 * sector
    ) {
      ax += x[3 * i] * wgt;
      ay += x[3 * i + 1] * wgt;
      as += wgt * Math.sin(th[i]);
      ac += wgt * Math.cos(th[i]);
      fraction += wgt;
    }
  }
  return { pose: [ax / fraction, ay / fraction, Math.atan2(as, ac)], fraction };
}

function mountParticleFilter(root, config) {
  const T = config.steps;
  const K = config.beamsTotal;
  const nMax = config.nMax;
  const C = config.constants;
  const { h, w, resolution: res } = config.map;
  const [ox, oy] = config.map.origin;
  const xMax = ox + w * res; // probrob.maps.OccupancyGrid.extent
  const yMax = oy + h * res;

  // ---- the embedded data (probrob._live.particle_filter_live) -----------------------------
  const packed = decodeBytes(config.map.cells);
  const codes = new Uint8Array(h * w); // 0 unexplored, 1 free, 2 occupied
  for (let c = 0; c < h * w; c++) codes[c] = (packed[c >> 2] >> (2 * (c & 3))) & 3;
  const occupied = codes.map((c) => (c === 2 ? 1 : 0));
  const freeCells = [];
  for (let c = 0; c < h * w; c++) if (codes[c] === 1) freeCells.push(c);
  const d2 = squaredDistanceField(occupied, h, w);
  const dist = new Float64Array(h * w);
  for (let c = 0; c < h * w; c++) dist[c] = Math.sqrt(d2[c]) * res;
  const table = new Float64Array((h + 2) * (w + 2));
  let tableKey = null;
  const odometry = decodeFloat64(config.data.odometry);
  const mm = decodeTyped(config.data.scans, Uint16Array);
  const scans = new Float64Array(T * K);
  for (let k = 0; k < T * K; k++) scans[k] = mm[k] === 0xffff ? C.maxRange : mm[k] / 1000;
  const truth = decodeFloat64(config.data.truth);
  const beamAngles = decodeFloat64(config.data.beamAngles);
  const pool = Float64Array.from(decodeTyped(config.data.normal, Float32Array));
  const P = pool.length;
  const offsets = decodeTyped(config.data.offsets, Uint32Array);
  const resample = decodeFloat64(config.data.resample);
  const uniforms = Float64Array.from(decodeTyped(config.data.uniforms, Float32Array));

  // ---- controls -------------------------------------------------------------------------
  const canvas = root.querySelector("canvas");
  const ctx = canvas.getContext("2d");
  // the displayed size in CSS pixels and the bitmap's scale (live.js fitCanvas, watchCanvasSize)
  let [W, H, dpr] = fitCanvas(canvas, config);
  const status = root.querySelector(".pl-status");
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
  const timings = { compute: 0, draw: 0, total: 0 };

  // ---- the filter -------------------------------------------------------------------------
  // run: the particle sets X_0 .. X_t of the current parameters (recomputed when one changes)
  let run = null;
  const runNames = ["a1", "a2", "a3", "a4", "sigma", "zrand", "beams", "kappa", "n", "start"];
  function runKey() {
    return JSON.stringify(runNames.map((k) => values[k]));
  }
  function model() {
    const p = Object.assign({}, values);
    p.n = Math.round(values.n);
    p.beams = Math.round(values.beams);
    p.zHit = C.zSum * (1 - values.zrand);
    p.zRand = C.zSum * values.zrand;
    p.sel = beamSelection(K, p.beams);
    p.ca = Float64Array.from(p.sel, (k) => Math.cos(beamAngles[k]));
    p.sa = Float64Array.from(p.sel, (k) => Math.sin(beamAngles[k]));
    return p;
  }
  function initialSet(p) {
    const n = p.n;
    const x = new Float64Array(3 * n);
    if (p.start === "global") {
      // probrob.mcl.uniform_particles(grid, n, uniforms=...)
      const count = freeCells.length;
      for (let i = 0; i < n; i++) {
        const pick = freeCells[Math.floor(uniforms[4 * i] * count)];
        const ci = Math.floor(pick / w);
        const cj = pick - ci * w;
        x[3 * i] = ox + (cj + uniforms[4 * i + 1]) * res;
        x[3 * i + 1] = oy + (ci + uniforms[4 * i + 2]) * res;
        x[3 * i + 2] = -Math.PI + 2 * Math.PI * uniforms[4 * i + 3];
      }
    } else {
      for (let i = 0; i < n; i++) {
        for (let k = 0; k < 3; k++) x[3 * i + k] = truth[k] + C.spread[k] * pool[k * nMax + i];
      }
    }
    return x;
  }
  function ensureTable(p) {
    const key = [p.zHit, p.zRand, p.sigma].join(",");
    if (key !== tableKey) {
      likelihoodTable(dist, h, w, p.zHit, p.zRand, p.sigma, C.maxRange, table);
      tableKey = key;
    }
  }
  // One step of Table 8.2 from X_{t-1} (x) with u_t = odometry[t - 1] and z_t = scans[t - 1]
  function mclStep(p, x, t) {
    const n = p.n;
    const u = odometry.subarray(6 * (t - 1), 6 * t);
    const [r1, tr, r2] = odometryDeltas(new Float64Array(3), u[0], u[1], u[2], u[3], u[4], u[5]);
    // Table 5.6, variance form, as probrob.motion._odometry_variances
    const b1 = Math.sqrt(noiseVariance("variance", p.a1, r1, p.a2, tr));
    const bt = Math.sqrt(noiseVariance("variance", p.a3, tr, p.a4, r1, p.a4, r2));
    const b2 = Math.sqrt(noiseVariance("variance", p.a1, r2, p.a2, tr));
    const o0 = offsets[3 * (t - 1)];
    const o1 = offsets[3 * (t - 1) + 1];
    const o2 = offsets[3 * (t - 1) + 2];
    const xBar = new Float64Array(3 * n);
    const logW = new Float64Array(n);
    ensureTable(p);
    const zt = scans.subarray(K * (t - 1), K * t);
    const nb = p.sel.length;
    const zr = new Float64Array(nb);
    const use = new Uint8Array(nb);
    for (let k = 0; k < nb; k++) {
      zr[k] = zt[p.sel[k]] / res;
      use[k] = zt[p.sel[k]] < C.maxRange ? 1 : 0; // max-range readings are skipped
    }
    let best = -Infinity;
    for (let i = 0; i < n; i++) {
      // line 4: x_t^[m] ~ p(x_t | u_t, x_{t-1}^[m]) (Table 5.6)
      const r1Hat = r1 - b1 * pool[(o0 + i) % P];
      const tHat = tr - bt * pool[(o1 + i) % P];
      const r2Hat = r2 - b2 * pool[(o2 + i) % P];
      const heading = x[3 * i + 2] + r1Hat;
      const xi = x[3 * i] + tHat * Math.cos(heading);
      const yi = x[3 * i + 1] + tHat * Math.sin(heading);
      const th = heading + r2Hat;
      xBar[3 * i] = xi;
      xBar[3 * i + 1] = yi;
      xBar[3 * i + 2] = th;
      // line 5: w_t^[m] = p(z_t | x_t^[m], m), the likelihood field (Table 6.3), log space;
      // a particle off the map weighs zero
      if (!(xi >= ox && xi < xMax && yi >= oy && yi < yMax)) {
        logW[i] = -Infinity;
        continue;
      }
      const gx = (xi - ox) / res;
      const gy = (yi - oy) / res;
      const ct = Math.cos(th);
      const st = Math.sin(th);
      let lp = 0;
      for (let k = 0; k < nb; k++) {
        if (!use[k]) continue;
        const ex = gx + zr[k] * (ct * p.ca[k] - st * p.sa[k]);
        const ey = gy + zr[k] * (st * p.ca[k] + ct * p.sa[k]);
        const jj = Math.floor(Math.min(Math.max(ex, -1), w)) + 1;
        const ii = Math.floor(Math.min(Math.max(ey, -1), h)) + 1;
        lp += table[ii * (w + 2) + jj];
      }
      logW[i] = p.kappa * lp;
      if (logW[i] > best) best = logW[i];
    }
    // normalised by log-sum-exp (probrob.mcl._normalise_log); no weight: equal weights
    const wts = new Float64Array(n);
    if (best === -Infinity) {
      wts.fill(1 / n);
    } else {
      let s = 0;
      for (let i = 0; i < n; i++) s += Math.exp(logW[i] - best);
      const lse = Math.log(s) + best;
      for (let i = 0; i < n; i++) wts[i] = Math.exp(logW[i] - lse);
    }
    // lines 8-11: draw n by the low-variance sampler
    const idx = lowVarianceSampler(wts, n, n, resample[t - 1], new Int32Array(n));
    const out = new Float64Array(3 * n);
    for (let k = 0; k < n; k++) {
      out[3 * k] = xBar[3 * idx[k]];
      out[3 * k + 1] = xBar[3 * idx[k] + 1];
      out[3 * k + 2] = xBar[3 * idx[k] + 2];
    }
    return { x: out, logW };
  }
  function ensure(t) {
    const key = runKey();
    if (run === null || run.key !== key) {
      const p = model();
      run = { key, p, sets: [initialSet(p)], logW: [null], estimates: [] };
    }
    while (run.sets.length <= t) {
      const s = mclStep(run.p, run.sets[run.sets.length - 1], run.sets.length);
      run.sets.push(s.x);
      run.logW.push(s.logW);
    }
    if (!run.estimates[t]) run.estimates[t] = estimatePose(run.sets[t], run.p.n, C.radius, C.headingBins);
    return run.estimates[t];
  }
  function error(est, t) {
    const tx = truth[3 * t];
    const ty = truth[3 * t + 1];
    return [Math.hypot(est.pose[0] - tx, est.pose[1] - ty), Math.abs(wrapAngle(est.pose[2] - truth[3 * t + 2]))];
  }

  // ---- drawing ------------------------------------------------------------------------------
  const mapImage = document.createElement("canvas");
  mapImage.width = w;
  mapImage.height = h;
  {
    const mctx = mapImage.getContext("2d");
    const img = mctx.createImageData(w, h);
    const grey = [217, 255, 0]; // unexplored, free, occupied
    for (let i = 0; i < h; i++) {
      const row = h - 1 - i; // row 0 of the grid is the lowest y: the image's last row
      for (let j = 0; j < w; j++) {
        const g = grey[codes[i * w + j]];
        const k = 4 * (row * w + j);
        img.data[k] = g;
        img.data[k + 1] = g;
        img.data[k + 2] = g;
        img.data[k + 3] = 255;
      }
    }
    mctx.putImageData(img, 0, 0);
  }
  const M = { left: 56, top: 30, right: 12, bottom: 42 };
  let PW = W - M.left - M.right;
  let PH = H - M.top - M.bottom;
  function layout() {
    [W, H, dpr] = fitCanvas(canvas, config);
    PW = W - M.left - M.right;
    PH = H - M.top - M.bottom;
  }
  function viewBox(t) {
    let x0;
    let x1;
    let y0;
    let y1;
    if (values.view === "robot") {
      const half = 6;
      [x0, x1, y0, y1] = [truth[3 * t] - half, truth[3 * t] + half, truth[3 * t + 1] - half, truth[3 * t + 1] + half];
    } else {
      [x0, x1, y0, y1] = [ox, xMax, oy, yMax];
    }
    // equal scales in x and y, centred in the plot box
    const scale = Math.min(PW / (x1 - x0), PH / (y1 - y0));
    const cx = (x0 + x1) / 2;
    const cy = (y0 + y1) / 2;
    return { scale, x0: cx - PW / 2 / scale, x1: cx + PW / 2 / scale, y0: cy - PH / 2 / scale, y1: cy + PH / 2 / scale };
  }
  function draw(t, est) {
    const p = run.p;
    const n = p.n;
    const x = run.sets[t];
    const v = viewBox(t);
    const sx = (a) => M.left + (a - v.x0) * v.scale;
    const sy = (b) => M.top + PH - (b - v.y0) * v.scale;
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.fillStyle = "#fff";
    ctx.fillRect(0, 0, W, H);
    ctx.save();
    ctx.beginPath();
    ctx.rect(M.left, M.top, PW, PH);
    ctx.clip();
    ctx.fillStyle = "#d9d9d9";
    ctx.fillRect(M.left, M.top, PW, PH);
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(mapImage, sx(ox), sy(yMax), w * res * v.scale, h * res * v.scale);
    // the reference path and pose
    ctx.strokeStyle = "rgba(44, 160, 44, 0.7)";
    ctx.lineWidth = 1.2;
    ctx.beginPath();
    for (let k = 0; k <= T; k++) {
      if (k === 0) ctx.moveTo(sx(truth[0]), sy(truth[1]));
      else ctx.lineTo(sx(truth[3 * k]), sy(truth[3 * k + 1]));
    }
    ctx.stroke();
    // particles: one path, one fill
    ctx.fillStyle = "rgba(214, 39, 40, 0.55)";
    ctx.beginPath();
    const dot = 2.2;
    for (let i = 0; i < n; i++) ctx.rect(sx(x[3 * i]) - dot / 2, sy(x[3 * i + 1]) - dot / 2, dot, dot);
    ctx.fill();
    ctx.strokeStyle = "#2ca02c";
    ctx.lineWidth = 2.5;
    ctx.beginPath();
    ctx.arc(sx(truth[3 * t]), sy(truth[3 * t + 1]), 8, 0, TWO_PI);
    ctx.stroke();
    // the estimate: an arrow
    const [ex, ey, eth] = est.pose;
    const len = 24;
    const X0 = sx(ex);
    const Y0 = sy(ey);
    const X1 = X0 + len * Math.cos(eth);
    const Y1 = Y0 - len * Math.sin(eth);
    ctx.strokeStyle = "#1f77b4";
    ctx.fillStyle = "#1f77b4";
    ctx.lineWidth = 2.5;
    ctx.beginPath();
    ctx.arc(X0, Y0, 3.5, 0, TWO_PI);
    ctx.fill();
    ctx.beginPath();
    ctx.moveTo(X0, Y0);
    ctx.lineTo(X1, Y1);
    ctx.stroke();
    const a = Math.atan2(Y1 - Y0, X1 - X0);
    ctx.beginPath();
    ctx.moveTo(X1, Y1);
    ctx.lineTo(X1 - 9 * Math.cos(a - 0.4), Y1 - 9 * Math.sin(a - 0.4));
    ctx.lineTo(X1 - 9 * Math.cos(a + 0.4), Y1 - 9 * Math.sin(a + 0.4));
    ctx.closePath();
    ctx.fill();
    ctx.restore();
    // frame, ticks, labels, title
    ctx.strokeStyle = "#000";
    ctx.lineWidth = 1;
    ctx.strokeRect(M.left + 0.5, M.top + 0.5, PW, PH);
    ctx.fillStyle = "#000";
    ctx.font = "12px sans-serif";
    ctx.textAlign = "center";
    ctx.textBaseline = "top";
    for (const tk of niceTicks(v.x0, v.x1, 6)) {
      ctx.fillRect(sx(tk), M.top + PH, 1, 5);
      ctx.fillText(fmtTick(tk), sx(tk), M.top + PH + 7);
    }
    ctx.fillText("x [m]", M.left + PW / 2, M.top + PH + 24);
    ctx.textAlign = "right";
    ctx.textBaseline = "middle";
    for (const tk of niceTicks(v.y0, v.y1, 6)) {
      ctx.fillRect(M.left - 5, sy(tk), 5, 1);
      ctx.fillText(fmtTick(tk), M.left - 7, sy(tk));
    }
    ctx.save();
    ctx.translate(14, M.top + PH / 2);
    ctx.rotate(-Math.PI / 2);
    ctx.textAlign = "center";
    ctx.fillText("y [m]", 0, 0);
    ctx.restore();
    ctx.textAlign = "center";
    ctx.textBaseline = "bottom";
    ctx.font = "13px sans-serif";
    ctx.fillText(
      "MCL, step " + t + " of " + T + ": " + n + " particles, " + p.beams + " beams",
      M.left + PW / 2,
      M.top - 9,
    );
  }
  function describe(t, est) {
    const [pos, head] = error(est, t);
    return (
      "Step " + t + " of " + T + ": the estimate is " + (100 * pos).toFixed(1) + " cm and " +
      ((head * 180) / Math.PI).toFixed(1) + "° from the reference pose; its cluster holds " +
      (100 * est.fraction).toFixed(0) + " % of the " + run.p.n + " particles (" + run.p.beams +
      " beams, " + (values.start === "global" ? "global start" : "known start") + ")."
    );
  }
  function update() {
    const t = Math.round(values.t);
    const t0 = performance.now();
    const est = ensure(t);
    const t1 = performance.now();
    draw(t, est);
    status.textContent = describe(t, est);
    const t2 = performance.now();
    timings.compute = t1 - t0;
    timings.draw = t2 - t1;
    timings.total = t2 - t0;
  }
  let pending = false;
  function schedule() {
    if (pending) return;
    pending = true;
    requestAnimationFrame(() => {
      pending = false;
      update();
    });
  }
  // a new displayed size: a new bitmap, the current step drawn again
  watchCanvasSize(canvas, config, () => {
    layout();
    update();
  });

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
    const s = config.sliders.find((q) => q.name === name);
    if (!s) throw new Error("probrob live widget: no parameter " + name);
    let v = Number(raw);
    if (!Number.isFinite(v)) return;
    if (name === "t" || name === "beams" || name === "n") v = Math.round(v / (name === "n" ? 100 : 1)) * (name === "n" ? 100 : 1);
    values[name] = Math.min(Math.max(v, s.min), s.max);
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
  const playButton = root.querySelector('[data-action="play"]');
  let timer = null;
  function pause() {
    if (timer !== null) clearInterval(timer);
    timer = null;
    playButton.textContent = "play";
    playButton.setAttribute("aria-pressed", "false");
  }
  function advance() {
    if (values.t >= T) {
      pause();
      return;
    }
    values.t += 1;
    show("t");
    update();
  }
  playButton.addEventListener("click", () => {
    if (timer !== null) {
      pause();
      return;
    }
    if (values.t >= T) values.t = 0;
    playButton.textContent = "pause";
    playButton.setAttribute("aria-pressed", "true");
    timer = setInterval(advance, 100);
  });
  root.querySelector('[data-action="step"]').addEventListener("click", () => {
    pause();
    advance();
  });
  root.querySelector('[data-action="start"]').addEventListener("click", () => {
    pause();
    values.t = 0;
    show("t");
    update();
  });
  root.querySelector('[data-action="reset"]').addEventListener("click", () => {
    pause();
    Object.assign(values, defaults);
    for (const name of Object.keys(defaults)) show(name);
    update();
  });

  // ---- the test hook ------------------------------------------------------------------------
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
    set(changes) {
      pause();
      for (const [name, v] of Object.entries(changes)) setValue(name, v);
      for (const name of Object.keys(changes)) show(name);
      update();
      return handle.state();
    },
    // the step t shown: X_t (n, 3), the log-weights of its step's particles before resampling
    // (n,; none at t = 0), the estimate, its error against truth[t], the last update's times
    state() {
      const t = Math.round(values.t);
      const est = ensure(t);
      return {
        values: Object.assign({}, values),
        t,
        n: run.p.n,
        beams: Array.from(run.p.sel),
        particles: encodeFloat64(run.sets[t]),
        logW: t > 0 ? encodeFloat64(run.logW[t]) : null,
        estimate: est.pose,
        fraction: est.fraction,
        error: error(est, t),
        status: status.textContent,
        timings: Object.assign({}, timings),
      };
    },
    field: () => encodeFloat64(dist),
    // time `count` filter steps (after 10 untimed ones) at the current parameters, as "play"
    // runs them: one step of Table 8.2 and its estimate (compute), the redraw (draw)
    bench(count) {
      pause();
      const saved = Object.assign({}, values);
      const times = { compute: [], draw: [], total: [] };
      const warmup = 10;
      run = null;
      values.t = 0;
      update();
      for (let k = 0; k < warmup + count; k++) {
        if (values.t >= T) {
          run = null; // start the run again: every timed update is one new step
          values.t = 0;
          update();
        }
        values.t += 1;
        update();
        if (k < warmup) continue;
        for (const key of Object.keys(times)) times[key].push(timings[key]);
      }
      Object.assign(values, saved);
      for (const name of Object.keys(saved)) show(name);
      update();
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
  update();
  root.setAttribute("data-ready", "true");
  return handle;
}
