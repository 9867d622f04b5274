// Kernel of Table 8.2, Monte Carlo localization, over a stretch of a laser log: the odometry
// sampler (Table 5.6, odometryDeltas and noiseVariance of maths.js), the likelihood field (Table
// 6.3, likelihood_field.js) and the low-variance sampler (Table 4.4), written as
// probrob.mcl.mcl and probrob.mcl.estimate_pose write them and held equal to them, step by step,
// by tests/test_live_mcl.py. Widget: probrob.live.mcl.particle_filter_live, which documents the
// embedded data and random numbers. Its own layer (render): the map, the particles, the
// reference and the estimate, with step, play and "to start" buttons; the test hook adds
// field() (the distance field), and its bench times filter steps as "play" runs them.

// probrob.live.mcl.particle_filter_beams: round(linspace(0, total - 1, k)), half to even
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

// The data a live filter embeds (probrob.live.mcl.particle_filter_live), decoded: the map's
// cells (0 unexplored, 1 free, 2 occupied) and its exact distance field, the log (odometry,
// ranges in metres, reference poses, beam angles) and the random numbers.
function decodeFilterData(config) {
  const T = config.steps;
  const K = config.beamsTotal;
  const C = config.constants;
  const { h, w, resolution: res } = config.map;
  const packed = decodeBytes(config.map.cells);
  const codes = new Uint8Array(h * w);
  for (let c = 0; c < h * w; c++) codes[c] = (packed[c >> 2] >> (2 * (c & 3))) & 3;
  const occupied = codes.map((c) => (c === 2 ? 1 : 0));
  const freeCells = [];
  for (let c = 0; c < h * w; c++) if (codes[c] === 1) freeCells.push(c);
  const d2 = squaredDistanceField(occupied, h, w);
  const dist = new Float64Array(h * w);
  for (let c = 0; c < h * w; c++) dist[c] = Math.sqrt(d2[c]) * res;
  const mm = decodeTyped(config.data.scans, Uint16Array);
  const scans = new Float64Array(T * K);
  for (let k = 0; k < T * K; k++) scans[k] = mm[k] === 0xffff ? C.maxRange : mm[k] / 1000;
  return {
    codes,
    freeCells,
    dist,
    scans,
    odometry: decodeFloat64(config.data.odometry),
    truth: decodeFloat64(config.data.truth),
    beamAngles: decodeFloat64(config.data.beamAngles),
    pool: Float64Array.from(decodeTyped(config.data.normal, Float32Array)),
    offsets: decodeTyped(config.data.offsets, Uint32Array),
    resample: decodeFloat64(config.data.resample),
    uniforms: Float64Array.from(decodeTyped(config.data.uniforms, Float32Array)),
  };
}

// The live filter's layer: the runs of the filter (the particle sets X_0 .. X_t of the current
// parameters, recomputed when one of them changes), the picture, the step and play buttons.
function particleFilter({ model, config, api }) {
  const T = config.steps;
  const K = config.beamsTotal;
  const nMax = config.nMax;
  const C = config.constants;
  const { h, w, resolution: res } = config.map;
  const [ox, oy] = config.map.origin;
  const xMax = ox + w * res; // probrob.maps.OccupancyGrid.extent
  const yMax = oy + h * res;
  const data = decodeFilterData(config);
  const { codes, freeCells, dist, scans, odometry, truth, beamAngles } = data;
  const { pool, offsets, resample, uniforms } = data;
  const P = pool.length;
  const table = new Float64Array((h + 2) * (w + 2)); // the likelihood field's, padded
  let tableKey = null;

  // ---- the filter -------------------------------------------------------------------------
  let run = null;
  const runNames = ["a1", "a2", "a3", "a4", "sigma", "zrand", "beams", "kappa", "n", "start"];
  const runKey = () => JSON.stringify(runNames.map((k) => model.get(k)));
  function filterParams() {
    const p = model.values();
    p.n = Math.round(p.n);
    p.beams = Math.round(p.beams);
    p.zHit = C.zSum * (1 - p.zrand);
    p.zRand = C.zSum * p.zrand;
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
  // line 5: w_t^[m] = p(z_t | x_t^[m], m), the likelihood field (Table 6.3) in log space, at the
  // pose in grid units (gx, gy, th); a particle off the map weighs zero
  function logWeight(p, zr, use, gx, gy, th) {
    const ct = Math.cos(th);
    const st = Math.sin(th);
    let lp = 0;
    for (let k = 0; k < zr.length; k++) {
      if (!use[k]) continue;
      const ex = gx + zr[k] * (ct * p.ca[k] - st * p.sa[k]);
      const ey = gy + zr[k] * (st * p.ca[k] + ct * p.sa[k]);
      const jj = Math.floor(Math.min(Math.max(ex, -1), w)) + 1;
      const ii = Math.floor(Math.min(Math.max(ey, -1), h)) + 1;
      lp += table[ii * (w + 2) + jj];
    }
    return p.kappa * lp;
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
    const [o0, o1, o2] = offsets.subarray(3 * (t - 1), 3 * t);
    const xBar = new Float64Array(3 * n);
    const logW = new Float64Array(n);
    ensureTable(p);
    const zt = scans.subarray(K * (t - 1), K * t);
    const zr = Float64Array.from(p.sel, (k) => zt[k] / res);
    const use = Uint8Array.from(p.sel, (k) => (zt[k] < C.maxRange ? 1 : 0)); // max-range: skipped
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
      const inside = xi >= ox && xi < xMax && yi >= oy && yi < yMax;
      logW[i] = inside ? logWeight(p, zr, use, (xi - ox) / res, (yi - oy) / res, th) : -Infinity;
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
    for (let k = 0; k < n; k++) out.set(xBar.subarray(3 * idx[k], 3 * idx[k] + 3), 3 * k);
    return { x: out, logW };
  }
  function ensure(t) {
    const key = runKey();
    if (run === null || run.key !== key) {
      const p = filterParams();
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

  // ---- the picture --------------------------------------------------------------------------
  const M = { left: 56, top: 30, right: 12, bottom: 42 };
  let box = null;
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
    const n = run.p.n;
    const x = run.sets[t];
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
    const title = "MCL, step " + t + " of " + T + ": " + n + " particles, " + run.p.beams + " beams";
    axes(ctx, theme, box, v.lim, { x: "x [m]", y: "y [m]", title }, { ticks: 6 });
    api.controls.status.textContent = describe(t, est);
  }
  function describe(t, est) {
    const [pos, head] = error(est, t);
    return (
      "Step " + t + " of " + T + ": the estimate is " + (100 * pos).toFixed(1) + " cm and " +
      ((head * 180) / Math.PI).toFixed(1) + "° from the reference pose; its cluster holds " +
      (100 * est.fraction).toFixed(0) + " % of the " + run.p.n + " particles (" + run.p.beams +
      " beams, " + (model.get("start") === "global" ? "global start" : "known start") + ")."
    );
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
  };

  return {
    layout(W) {
      const H = (W * config.height) / config.width;
      box = [M.left, M.top, W - M.left - M.right, H - M.top - M.bottom];
      return { height: H, plots: [box] };
    },
    compute() {
      const t = Math.round(model.get("t"));
      return { t, est: ensure(t) };
    },
    draw,
    // the step t shown: X_t (n, 3), the log-weights of its step's particles before resampling
    // (n,; none at t = 0), the estimate, its error against truth[t]
    hook() {
      const t = Math.round(model.get("t"));
      const est = ensure(t);
      return {
        t,
        n: run.p.n,
        beams: Array.from(run.p.sel),
        particles: encodeFloat64(run.sets[t]),
        logW: t > 0 ? encodeFloat64(run.logW[t]) : null,
        estimate: est.pose,
        fraction: est.fraction,
        error: error(est, t),
        status: api.controls.status.textContent,
      };
    },
    stop: pause,
    actions,
    // time `count` filter steps (after 10 untimed ones) at the current parameters, as "play"
    // runs them: one step of Table 8.2 and its estimate (compute), the redraw (draw)
    bench(count) {
      pause();
      const saved = model.values();
      run = null;
      goTo(0);
      const out = api.timeRuns(count, () => {
        if (model.get("t") >= T) {
          run = null; // start the run again: every timed update is one new step
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
