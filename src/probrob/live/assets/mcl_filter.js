// Kernel of Tables 8.2, 8.3 and 8.4, Monte Carlo localization, augmented MCL and KLD-sampling,
// over a stretch of a laser log: the odometry sampler (Table 5.6, odometryDeltas and
// noiseVariance of maths.js), the likelihood field (Table 6.3, likelihood_field.js) or the beam
// model (Table 6.1, beam_model.js) and the low-variance sampler (Table 4.4), written as
// probrob.mcl.mcl, probrob.mcl.augmented_mcl, probrob.mcl.kld_sampling_mcl and
// probrob.mcl.estimate_pose write them (and as probrob.mcl.run_mcl chains them, the kidnapping
// as its on_step) and held equal to them, step by step, by tests/test_live_mcl.py. Widget:
// probrob.live.mcl.particle_filter_live, which documents the embedded data and random numbers
// and the kidnapping; its layer (the picture and the buttons) is mcl.js.

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

// probrob.mcl.estimate_pose of n particles, equally weighted (w null) or of weights w (n,):
// bins of side `radius` in (x, y) and `nTheta` equal heading sectors that wrap at ±π; the block
// of 3 x 3 x 3 bins that holds the most particles (weight) seeds the cluster (ties: the smallest
// centre bin in (x, y, θ) order, numpy.unique's); then the weighted mean of the particles
// within 2·radius of the block's mean in x and y and within two sectors of its circular mean
// heading, θ by circular mean
function estimatePose(x, n, radius, nTheta, w) {
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
    counts.set(key, (counts.get(key) || 0) + (w ? w[i] : 1)); // whole counts if unweighted
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
  const wgt = (i) => (w ? w[i] : 1 / n);
  let sx = 0;
  let sy = 0;
  let ss = 0;
  let sc = 0;
  let sw = 0;
  for (let i = 0; i < n; i++) {
    const dt = (((bt[i] - best.kt + 1) % nTheta) + nTheta) % nTheta;
    if (Math.abs(bx[i] - best.kx) <= 1 && Math.abs(by[i] - best.ky) <= 1 && dt <= 2) {
      sx += x[3 * i] * wgt(i);
      sy += x[3 * i + 1] * wgt(i);
      ss += wgt(i) * Math.sin(th[i]);
      sc += wgt(i) * Math.cos(th[i]);
      sw += wgt(i);
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
      ax += x[3 * i] * wgt(i);
      ay += x[3 * i + 1] * wgt(i);
      as += wgt(i) * Math.sin(th[i]);
      ac += wgt(i) * Math.cos(th[i]);
      fraction += wgt(i);
    }
  }
  return { pose: [ax / fraction, ay / fraction, Math.atan2(as, ac)], fraction };
}

// The KLD bound of Table 8.4, line 15 (probrob.mcl._kld_bound): ceil(M_chi(k)), at least 1,
// for k >= 2 occupied bins, with z = z_{1-δ}
function kldBound(k, epsilon, z) {
  const km1 = k - 1.0;
  const a = 2.0 / (9.0 * km1);
  const m = (km1 / (2.0 * epsilon)) * (1.0 - a + Math.sqrt(a) * z) ** 3;
  return Math.max(Math.ceil(m), 1);
}

// A random order of idx (in place) by Fisher-Yates from the last index down, swapping i with
// floor(u (i + 1)), u the uniforms U[(s + c) % U.length] for c = cursor, cursor + 1, ...
// (probrob.live.mcl.particle_filter_draws); returns the cursor after it
function shuffle(idx, U, s, cursor) {
  for (let i = idx.length - 1; i > 0; i--) {
    const j = Math.floor(U[(s + cursor++) % U.length] * (i + 1));
    const tmp = idx[i];
    idx[i] = idx[j];
    idx[j] = tmp;
  }
  return cursor;
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
    rounds: Float64Array.from(decodeTyped(config.data.rounds, Float32Array)),
    shuffles: decodeTyped(config.data.shuffle, Uint32Array),
  };
}

// The runs of the live filter (probrob.live.mcl.particle_filter_live): the particle sets X_0 ..
// X_t of the current parameters (the model's values), recomputed when one of them changes.
// Returns ensure(t) (the estimate of step t, running the filter up to it), error(est, t), the
// current run (current(): {p, steps: [{x, n, w, logW, random, wSlow, wFast, ...}]}), reset()
// and the decoded data.
function filterRuns(config, model) {
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
  const { pool, offsets, resample, uniforms, rounds, shuffles } = data;
  const P = pool.length;
  const table = new Float64Array((h + 2) * (w + 2)); // the likelihood field's, padded
  let tableKey = null;
  let traversal = null; // the beam model's ray-casting tables, made on first use
  let mixture = null;

  // ---- the filter -------------------------------------------------------------------------
  let run = null;
  const runNames = ["a1", "a2", "a3", "a4", "sigma", "zrand", "beams", "kappa", "n", "start",
    "sensor", "method", "aslow", "afast", "eps", "delta", "kidnap"];
  const runKey = () => JSON.stringify(runNames.map((k) => model.get(k)));
  function filterParams() {
    const p = model.values();
    p.n = Math.round(p.n);
    p.beams = Math.round(p.beams);
    p.kidnap = Math.round(p.kidnap);
    p.zHit = C.zSum * (1 - p.zrand);
    p.zRand = C.zSum * p.zrand;
    p.sel = beamSelection(K, p.beams);
    p.ca = Float64Array.from(p.sel, (k) => Math.cos(beamAngles[k]));
    p.sa = Float64Array.from(p.sel, (k) => Math.sin(beamAngles[k]));
    p.kldZ = C.kldZ[Math.round(p.delta / C.deltaStep) - 1]; // z_{1-δ}, from probrob
    return p;
  }
  // the c-th of n poses uniform over the free cells, from the uniforms' row `row`
  // (probrob.mcl.uniform_particles(grid, n, uniforms=...))
  function uniformPose(x, c, row) {
    const count = freeCells.length;
    const pick = freeCells[Math.floor(uniforms[4 * row] * count)];
    const ci = Math.floor(pick / w);
    const cj = pick - ci * w;
    x[3 * c] = ox + (cj + uniforms[4 * row + 1]) * res;
    x[3 * c + 1] = oy + (ci + uniforms[4 * row + 2]) * res;
    x[3 * c + 2] = -Math.PI + 2 * Math.PI * uniforms[4 * row + 3];
  }
  function initialSet(p) {
    const n = p.n;
    const x = new Float64Array(3 * n);
    if (p.start === "global") {
      for (let i = 0; i < n; i++) uniformPose(x, i, i);
    } else {
      for (let i = 0; i < n; i++) {
        for (let k = 0; k < 3; k++) x[3 * i + k] = truth[k] + C.spread[k] * pool[k * nMax + i];
      }
    }
    return x;
  }
  function ensureModel(p) {
    if (p.sensor === "beam") {
      if (traversal === null) traversal = traversalTables(codes, dist, h, w, res);
      const key = ["beam", p.zHit, p.zRand, p.sigma].join(",");
      if (key !== tableKey) {
        mixture = beamMixture({ zHit: p.zHit, zShort: C.zShort, zMax: C.zMaxWeight,
          zRand: p.zRand, sigma: p.sigma, lambda: C.lambdaShort, maxRange: C.maxRange });
        tableKey = key;
      }
      return;
    }
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
  // log p(z_t | x) of `count` poses xs (Table 8.2 line 5, probrob.mcl._log_weights): the
  // likelihood field or the beam model, tempered by the exponent; -inf off the map
  function weigh(p, xs, count, t) {
    ensureModel(p);
    const zt = scans.subarray(K * (t - 1), K * t);
    const beam = p.sensor === "beam";
    const zr = Float64Array.from(p.sel, (k) => zt[k] / res);
    const use = Uint8Array.from(p.sel, (k) => (zt[k] < C.maxRange ? 1 : 0)); // max-range: skipped
    const zb = Float64Array.from(p.sel, (k) => Math.min(zt[k], C.maxRange));
    const top = beam ? mixture.shortNumerators(zb) : null;
    const logW = new Float64Array(count);
    for (let i = 0; i < count; i++) {
      const xi = xs[3 * i];
      const yi = xs[3 * i + 1];
      if (!(xi >= ox && xi < xMax && yi >= oy && yi < yMax)) {
        logW[i] = -Infinity;
      } else if (beam) {
        const gx = (xi - ox) / res;
        const gy = (yi - oy) / res;
        const lp = beamScanLogLikelihood(traversal, mixture, zb, top, p.ca, p.sa, gx, gy, xs[3 * i + 2],
          res, C.maxRange);
        logW[i] = p.kappa * lp;
      } else {
        logW[i] = logWeight(p, zr, use, (xi - ox) / res, (yi - oy) / res, xs[3 * i + 2]);
      }
    }
    return logW;
  }
  // line 4: x_t^[m] ~ p(x_t | u_t, x_{t-1}^[m]) (Table 5.6, variance form) for `count` particles
  // x[idx[i]] (idx null: x[i]); particle i of the step (`base` + i) reads the pool at the step's
  // three offsets
  function motion(p, x, idx, count, t, base) {
    const u = odometry.subarray(6 * (t - 1), 6 * t);
    const [r1, tr, r2] = odometryDeltas(new Float64Array(3), u[0], u[1], u[2], u[3], u[4], u[5]);
    // as probrob.motion._odometry_variances
    const b1 = Math.sqrt(noiseVariance("variance", p.a1, r1, p.a2, tr));
    const bt = Math.sqrt(noiseVariance("variance", p.a3, tr, p.a4, r1, p.a4, r2));
    const b2 = Math.sqrt(noiseVariance("variance", p.a1, r2, p.a2, tr));
    const [o0, o1, o2] = offsets.subarray(3 * (t - 1), 3 * t);
    const xBar = new Float64Array(3 * count);
    for (let i = 0; i < count; i++) {
      const m = idx ? idx[i] : i;
      const r1Hat = r1 - b1 * pool[(o0 + base + i) % P];
      const tHat = tr - bt * pool[(o1 + base + i) % P];
      const r2Hat = r2 - b2 * pool[(o2 + base + i) % P];
      const heading = x[3 * m + 2] + r1Hat;
      xBar[3 * i] = x[3 * m] + tHat * Math.cos(heading);
      xBar[3 * i + 1] = x[3 * m + 1] + tHat * Math.sin(heading);
      xBar[3 * i + 2] = heading + r2Hat;
    }
    return xBar;
  }
  // the weights normalised by log-sum-exp (probrob.mcl._normalise_log): no weight, equal
  // weights; an infinite one (the beam model's point mass) takes all
  function normalise(logW) {
    const n = logW.length;
    const wts = new Float64Array(n);
    let best = -Infinity;
    let top = 0;
    for (let i = 0; i < n; i++) {
      if (logW[i] > best) best = logW[i];
      if (logW[i] === Infinity) top++;
    }
    if (top > 0) {
      for (let i = 0; i < n; i++) wts[i] = logW[i] === Infinity ? 1 / top : 0;
    } else if (best === -Infinity) {
      wts.fill(1 / n);
    } else {
      let s = 0;
      for (let i = 0; i < n; i++) s += Math.exp(logW[i] - best);
      const lse = Math.log(s) + best;
      for (let i = 0; i < n; i++) wts[i] = Math.exp(logW[i] - lse);
    }
    return wts;
  }
  function pick(xBar, idx) {
    const out = new Float64Array(3 * idx.length);
    for (let k = 0; k < idx.length; k++) out.set(xBar.subarray(3 * idx[k], 3 * idx[k] + 3), 3 * k);
    return out;
  }
  // One step of Table 8.2 from X_{t-1} (prev.x) with u_t = odometry[t - 1], z_t = scans[t - 1]
  function mclStep(p, prev, t) {
    const n = prev.n;
    const xBar = motion(p, prev.x, null, n, t, 0); // line 4
    const logW = weigh(p, xBar, n, t); // line 5
    const idx = lowVarianceSampler(normalise(logW), n, n, resample[t - 1], new Int32Array(n));
    return { x: pick(xBar, idx), n, w: null, logW, random: 0 }; // lines 8-11
  }
  // One step of Table 8.3 (probrob.mcl.augmented_mcl), w_slow and w_fast carried in prev
  function augmentedStep(p, prev, t) {
    const n = prev.n;
    const xBar = motion(p, prev.x, null, n, t, 0); // line 6
    const logW = weigh(p, xBar, n, t); // line 7
    let best = -Infinity;
    for (let i = 0; i < n; i++) if (logW[i] > best) best = logW[i];
    let logAvg = -Infinity; // line 9, w_avg in logs: logsumexp(log w) - log M
    if (best === Infinity) {
      logAvg = Infinity; // the beam model's point mass: probrob raises OverflowError
    } else if (best > -Infinity) {
      let s = 0;
      for (let i = 0; i < n; i++) s += Math.exp(logW[i] - best);
      logAvg = Math.log(s) + best - Math.log(n);
    }
    const wAvg = Math.exp(logAvg); // probrob raises OverflowError where this is inf
    const wSlow = prev.wSlow + p.aslow * (wAvg - prev.wSlow); // line 11
    const wFast = prev.wFast + p.afast * (wAvg - prev.wFast); // line 12
    const pRandom = wSlow > 0 ? Math.max(0, 1 - wFast / wSlow) : 0; // line 14
    // the binomial count of random particles, from the uniforms at the step's start s
    const [s0, q0] = shuffles.subarray(2 * (t - 1), 2 * t);
    let nRandom = 0;
    if (pRandom > 0) for (let i = 0; i < n; i++) if (uniforms[(s0 + i) % uniforms.length] < pRandom) nRandom++;
    const out = { n, w: null, logW, wSlow, wFast, pRandom, random: nRandom, overflow: !(wAvg < Infinity) };
    if (nRandom === n || best === -Infinity) {
      out.x = new Float64Array(3 * n);
      for (let c = 0; c < n; c++) uniformPose(out.x, c, (q0 + c) % nMax);
      out.random = n;
      return out;
    }
    const m = n - nRandom; // lines 16-18: the others drawn by weight
    const idx = lowVarianceSampler(normalise(logW), n, m, resample[t - 1], new Int32Array(m));
    out.x = new Float64Array(3 * n);
    out.x.set(pick(xBar, idx));
    for (let c = 0; c < nRandom; c++) uniformPose(out.x.subarray(3 * m), c, (q0 + c) % nMax);
    return out;
  }
  // One step of Table 8.4 (probrob.mcl.kld_sampling_mcl): rounds of the missing particles
  // drawn by weight (line 8: low-variance, in random order), moved (line 9) and weighted (line
  // 10); the bins of the histogram counted in order (lines 12-16) until M >= M_chi and M >=
  // M_chi_min (line 18). Returns a weighted set.
  function kldStep(p, prev, t) {
    const nMin = C.kldMin;
    const [bx, by, bt] = C.kldBins;
    const seen = new Set();
    const xs = [];
    const lws = [];
    let m = 0;
    let k = 0;
    let target = nMin;
    let cursor = 0;
    const s0 = shuffles[2 * (t - 1)];
    for (let r = 0; m < target; r++) {
      const L = target - m;
      const off = r === 0 ? resample[t - 1] : rounds[(t - 1) * C.kldRounds + ((r - 1) % C.kldRounds)];
      const idx = lowVarianceSampler(prev.w || new Float64Array(prev.n).fill(1 / prev.n), prev.n, L,
        off, new Int32Array(L));
      cursor = shuffle(idx, uniforms, s0, cursor);
      const xNew = motion(p, prev.x, idx, L, t, m); // line 9
      const lw = weigh(p, xNew, L, t); // line 10
      let keep = L;
      let stopped = false;
      let mChi = 0;
      for (let q = 0; q < L; q++) {
        const key = Math.floor(xNew[3 * q] / bx) + "," + Math.floor(xNew[3 * q + 1] / by) + "," +
          Math.floor(wrapAngle(xNew[3 * q + 2]) / bt);
        if (!seen.has(key)) {
          seen.add(key);
          k++;
        }
        const mAfter = m + 1 + q;
        mChi = k > 1 ? kldBound(k, p.eps, p.kldZ) : 0;
        if (mAfter >= Math.max(mChi, nMin) || mAfter >= nMax) {
          keep = q + 1;
          stopped = true;
          break;
        }
      }
      xs.push(xNew.subarray(0, 3 * keep));
      lws.push(lw.subarray(0, keep));
      m += keep;
      target = stopped ? m : Math.min(nMax, Math.max(nMin, mChi));
    }
    const x = new Float64Array(3 * m);
    const logW = new Float64Array(m);
    let at = 0;
    for (let r = 0; r < xs.length; r++) {
      x.set(xs[r], 3 * at);
      logW.set(lws[r], at);
      at += lws[r].length;
    }
    return { x, n: m, w: normalise(logW), logW, random: 0, bins: k };
  }
  const STEPS = { mcl: mclStep, augmented: augmentedStep, kld: kldStep };
  // the kidnapping after step k: X_k - truth[k] + truth[s], s the reference position farthest
  // from truth[k] (probrob.live.mcl.particle_filter_kidnap_target)
  function kidnapTarget(k) {
    let s = 0;
    let far = -1;
    for (let j = 0; j <= T; j++) {
      const d = Math.hypot(truth[3 * j] - truth[3 * k], truth[3 * j + 1] - truth[3 * k + 1]);
      if (d > far) {
        far = d;
        s = j;
      }
    }
    return s;
  }
  function kidnapped(x, k) {
    const s = kidnapTarget(k);
    for (let i = 0; i < x.length; i++) x[i] = x[i] - truth[3 * k + (i % 3)] + truth[3 * s + (i % 3)];
  }
  function ensure(t) {
    const key = runKey();
    if (run === null || run.key !== key) {
      const p = filterParams();
      const x0 = initialSet(p);
      run = { key, p, steps: [{ x: x0, n: p.n, w: null, logW: null, random: 0, wSlow: 0, wFast: 0 }],
        estimates: [] };
    }
    const step = STEPS[run.p.method];
    while (run.steps.length <= t) {
      const k = run.steps.length;
      const prev = run.steps[k - 1];
      const s = step(run.p, prev, k);
      if (s.wSlow === undefined) Object.assign(s, { wSlow: prev.wSlow, wFast: prev.wFast });
      if (k === run.p.kidnap) kidnapped(s.x, k); // as run_mcl's on_step, after step k
      run.steps.push(s);
    }
    if (!run.estimates[t]) {
      const s = run.steps[t];
      run.estimates[t] = estimatePose(s.x, s.n, C.radius, C.headingBins, s.w);
    }
    return run.estimates[t];
  }
  function error(est, t) {
    const tx = truth[3 * t];
    const ty = truth[3 * t + 1];
    return [Math.hypot(est.pose[0] - tx, est.pose[1] - ty), Math.abs(wrapAngle(est.pose[2] - truth[3 * t + 2]))];
  }
  return { data, ensure, error, current: () => run, reset: () => (run = null) };
}
