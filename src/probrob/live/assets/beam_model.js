// Kernel of Table 6.1, the beam model of a whole scan: the exact ray casting of its expected
// ranges z* (probrob.maps.ray_cast, the "hybrid" traversal of the compiled _cast_hybrid:
// sphere tracing across open space, then Amanatides-Woo steps that skip what the distance
// field proves free) and the mixture p(z | z*) in log space (probrob.sensors._mixture, with
// its fall-back to log components where the linear sum underflows). Written operation for
// operation as probrob writes them (IEEE double precision, no fused operations, as numba
// compiles them), so that the ranges agree to the last bit but where Math.cos and numpy's cos
// differ in theirs; held to probrob.mcl with sensor="beam" by tests/test_live_mcl.py. Uses
// normalCdf of beam.js (Φ, for p_hit's normaliser) and the distance field of
// likelihood_field.js. Widget: probrob.live.mcl.particle_filter_live, whose kernel mcl.js
// weighs the particles with beamScanLogLikelihood (2,000 particles of 60 beams on the Intel
// map: 120,000 rays, ~12 traversal steps each, about 20 ms in Chromium on this machine class:
// the beam model does not fit in one frame there; the likelihood field takes ~1 ms).

// probrob.maps._HALF_DIAGONAL and _PULL_BACK; the smallest normal double (_TINY)
const HALF_DIAGONAL = Math.sqrt(0.5) + 1e-9;
const PULL_BACK = 1e-10;
const TINY = 2.2250738585072014e-308;

// probrob.maps.OccupancyGrid._traversal_tables: padded by one ring, the cell codes (0 free, 1
// occupied, 2 outside) and a lower bound (in cells) of the distance from any point of a cell
// to any occupied cell, from the metric distance field `dist` (h x w)
function traversalTables(codes, dist, h, w, res) {
  const W2 = w + 2;
  const code = new Uint8Array((h + 2) * W2).fill(2);
  const free = new Float64Array((h + 2) * W2);
  for (let i = 0; i < h; i++) {
    for (let j = 0; j < w; j++) {
      code[(i + 1) * W2 + j + 1] = codes[i * w + j] === 2 ? 1 : 0;
      free[(i + 1) * W2 + j + 1] = dist[i * w + j] / res - 2.0 * HALF_DIAGONAL;
    }
  }
  return { code, free, h, w };
}

// clip(floor(v), lo, hi) for integers lo < hi (probrob.maps._floor_clip): v below lo floors
// below lo, v above hi floors to hi or above, so the clip comes first (NaN stays NaN)
function floorClip(v, lo, hi) {
  return v < lo ? lo : v > hi ? hi : Math.floor(v);
}

// The first jump of sphere tracing from (x0, y0), the same for every beam of a pose (at t = 0
// the ray stands in the pose's cell whatever its direction): the free radius there if it
// exceeds a cell (capped at tMax), else 0 (the ray stops sphere tracing at once)
function firstJump(tab, x0, y0, tMax) {
  const f = tab.free[(floorClip(y0, -1, tab.h) + 1) * (tab.w + 2) + floorClip(x0, -1, tab.w) + 1];
  return f > 1 && 0 < tMax ? Math.min(f, tMax) : 0;
}

// probrob.maps._cast_hybrid for one ray from (x0, y0) along (dx, dy), all in cell units, after
// its first jump `t` (firstJump): the range in cells (t_max when nothing is hit). Its proven
// bounds (_step_bounds) hold here too; the loops stop at them.
function castRay(tab, x0, y0, dx, dy, tMax, t) {
  const { code, free, h, w } = tab;
  const W2 = w + 2;
  if (dx !== 0 && Math.abs(dx) < TINY) dx = Math.sign(dx) * TINY; // probrob.maps._ray
  if (dy !== 0 && Math.abs(dy) < TINY) dy = Math.sign(dy) * TINY;
  // sphere tracing alone while the free radius exceeds a cell (_sphere_jump)
  for (let n = 0; t > 0 && n <= h + w + 4; n++) {
    const jj = floorClip(x0 + t * dx, -1, w);
    const ii = floorClip(y0 + t * dy, -1, h);
    const f = free[(ii + 1) * W2 + jj + 1];
    if (!(f > 1 && t < tMax)) break;
    t = Math.min(t + f, tMax);
  }
  // then the traversal (_crossing, _hybrid_step), from positions pulled back along the ray
  const invDx = dx !== 0 ? 1 / dx : 1;
  const cx = dx !== 0 ? (dx > 0 ? 1 : 0) - x0 : Infinity;
  const invDy = dy !== 0 ? 1 / dy : 1;
  const cy = dy !== 0 ? (dy > 0 ? 1 : 0) - y0 : Infinity;
  const sx = dx > 0 ? 1 : -1;
  const sy = dy > 0 ? 1 : -1;
  const bx = x0 - (dx !== 0 ? sx * PULL_BACK : 0);
  const by = y0 - (dy !== 0 ? sy * PULL_BACK : 0);
  const moved = t > 0;
  let j = floorClip(moved ? bx + t * dx : x0, sx > 0 ? 0 : -1, sx > 0 ? w : w - 1);
  let i = floorClip(moved ? by + t * dy : y0, sy > 0 ? 0 : -1, sy > 0 ? h : h - 1);
  for (let n = 0; n <= h + w + 4; n++) {
    const cell = (i + 1) * W2 + j + 1;
    const c = code[cell];
    if (c !== 0 || t >= tMax) return c === 1 && t < tMax ? t : tMax;
    const tx = (j + cx) * invDx;
    const ty = (i + cy) * invDy;
    const tDda = Math.max(Math.min(tx, ty), t);
    const tJump = Math.min(t + free[cell], tMax);
    if (tJump > tDda) {
      let jj = floorClip(bx + tJump * dx, -1, w);
      let ii = floorClip(by + tJump * dy, -1, h);
      jj = sx > 0 ? Math.max(jj, j) : Math.min(jj, j);
      ii = sy > 0 ? Math.max(ii, i) : Math.min(ii, i);
      if (jj !== j || ii !== i) {
        t = tJump;
        i = ii;
        j = jj;
        continue;
      }
    }
    t = tDda;
    if (tx <= ty) j += sx;
    else i += sy;
  }
  return NaN; // beyond the proven bound: a bug (probrob raises RuntimeError)
}

// Φ(x) of beam.js's normalCdf, and exactly 1 from x = 8.5 on, where 1 - Φ(-x) < 2^-54 rounds
// to 1 in both normalCdf and scipy's ndtr (the normaliser of p_hit of a beam far from z_max)
function normalCdfOne(x) {
  return x >= 8.5 ? 1 : normalCdf(x);
}

// The mixture's constants for BeamModelParams-like p: {zHit, zShort, zMax (weight), zRand,
// sigma, lambda, maxRange}
function beamMixture(p) {
  const sigma = p.sigma;
  const zmax = p.maxRange;
  const lam = p.lambda;
  const zShort = p.zShort;
  const hitScale = p.zHit / (sigma * Math.sqrt(2.0 * Math.PI));
  const atMax = p.zMax;
  const rand = p.zRand / zmax;
  const nearLow = 9.0 * sigma;
  const nearHigh = zmax - 9.0 * sigma;
  const logW = [p.zHit, p.zShort, p.zMax, p.zRand].map((v) => (v > 0 ? Math.log(v) : -Infinity));
  const mass = (zs) => normalCdfOne((zmax - zs) / sigma) - normalCdfOne(-zs / sigma); // _hit_mass
  const massAtMax = mass(zmax); // the most common z* far from the walls: a beam that hits nothing
  const hitMass = (zs) => (zs === zmax ? massAtMax : mass(zs));
  // probrob.sensors._log_components and their logsumexp: the fall-back where the sum is 0
  function logComponents(z, zs) {
    const u = (z - zs) / sigma;
    const lc = [
      -0.5 * u * u - Math.log(sigma) - LOG_SQRT_2PI - Math.log(hitMass(zs)),
      zs > 0 ? Math.log(lam) - lam * z - Math.log(-Math.expm1(-lam * zs)) : z === 0 ? Infinity : -Infinity,
      z >= zmax ? 0 : -Infinity,
      z >= zmax ? -Infinity : -Math.log(zmax),
    ];
    if (!(z <= zs)) lc[1] = -Infinity;
    let m = -Infinity;
    const terms = lc.map((l, k) => (logW[k] > -Infinity ? l + logW[k] : -Infinity));
    for (const a of terms) if (a > m) m = a;
    if (m === Infinity) return Infinity;
    const fm = Number.isFinite(m) ? m : 0;
    let s = 0;
    for (const a of terms) s += Math.exp(a - fm);
    return Math.log(s) + fm;
  }
  // log p(z | z*) of one beam, z already capped at z_max (probrob.sensors._mixture); shortTop:
  // p_short's numerator lam e^(-lam z), the same for every particle (shortNumerators)
  function logMixture(z, zs, shortTop) {
    const u = (z - zs) / sigma;
    let q = hitScale * Math.exp(-0.5 * u * u);
    if (zs < nearLow || zs > nearHigh) q /= hitMass(zs);
    if (zShort > 0) {
      let short;
      if (zs > 0) short = shortTop / -Math.expm1(-lam * zs);
      else short = z === 0 ? Infinity : 0;
      q += zShort * (z <= zs ? short : 0);
    }
    q += z >= zmax ? atMax : rand;
    if (q === 0 || (q === Infinity && zs !== 0)) return logComponents(z, zs);
    return Math.log(q);
  }
  const shortNumerators = (z) => Float64Array.from(z, (zk) => lam * Math.exp(-lam * zk));
  return { logMixture, shortNumerators };
}

// Table 6.1: sum over the beams of log p(z^k | z^k*) at the pose (gx, gy) in grid units,
// heading th: z (metres, capped at z_max), p_short's numerators `top` (the mixture's
// shortNumerators(z)) and the beams' cos/sin (ca, sa); the rays' z* in cells, times the
// resolution, capped at z_max (probrob.maps._cast)
function beamScanLogLikelihood(tab, mixture, z, top, ca, sa, gx, gy, th, res, maxRange) {
  const ct = Math.cos(th);
  const st = Math.sin(th);
  const tMax = maxRange / res;
  const t1 = firstJump(tab, gx, gy, tMax);
  let lp = 0;
  for (let k = 0; k < z.length; k++) {
    const dx = ct * ca[k] - st * sa[k];
    const dy = st * ca[k] + ct * sa[k];
    const zs = Math.min(castRay(tab, gx, gy, dx, dy, tMax, t1) * res, maxRange);
    lp += mixture.logMixture(z[k], zs, top[k]);
  }
  return lp;
}
