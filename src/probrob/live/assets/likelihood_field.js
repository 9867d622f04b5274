// Kernel of Table 6.3's table, the likelihood field of a map: the exact distance field of an
// occupancy grid (probrob.maps.OccupancyGrid.distance_field, scipy's exact transform) and the
// log-likelihood per cell (probrob.sensors.likelihood_field_table), computed in the page from
// the map's cells. Held equal to the library by tests/test_live_mcl.py (the distance field
// exactly, the filter's log-weights to 1e-9). Widget: probrob.live.mcl.particle_filter_live,
// whose kernel mcl.js weighs the particles with it.

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
