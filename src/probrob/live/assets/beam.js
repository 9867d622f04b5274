// Kernel of Table 6.1, lines 5-6 (kind "curve"): the beam model's p(z | z*), the mixture of
// probrob.sensors.beam_mixture over [0, z_max), written as the library writes it and held equal
// to it by tests/test_live_widgets.py. Widget: probrob.live.sensors.beam_model_live.
// Parameters: zstar [m], the weights whit, wshort, wmax, wrand (normalised by their sum, as the
// title shows), sigma [m], lambda [1/m]; constant zmax [m] (the sensor's maximum range). The
// point mass of p_max at z = z_max (its weight in the title) is not part of the curve.

// The standard normal CDF Φ(x) = erfc(-x/√2)/2, to about 1e-15 absolute: for |t| < 3 the
// series erf(t) = 2/√π e^(-t²) Σ 2ⁿ t^(2n+1) / (1·3·…·(2n+1)) (positive terms, no
// cancellation), beyond it erfc(t) by its continued fraction
// √π e^(t²) erfc(t) = 1/(t + (1/2)/(t + 1/(t + (3/2)/(t + …)))), evaluated bottom-up.
function normalCdf(x) {
  const t = -x * Math.SQRT1_2;
  const a = Math.abs(t);
  let erfc;
  if (a < 3) {
    let term = a;
    let sum = a;
    for (let n = 1; n < 200 && term > 1e-17 * sum; n++) {
      term *= (2 * a * a) / (2 * n + 1);
      sum += term;
    }
    erfc = 1 - (2 / Math.sqrt(Math.PI)) * Math.exp(-a * a) * sum;
  } else {
    let f = a;
    for (let k = 60; k >= 1; k--) f = a + k / 2 / f;
    erfc = Math.exp(-a * a) / Math.sqrt(Math.PI) / f;
  }
  return t >= 0 ? erfc / 2 : 1 - erfc / 2;
}

kernels.beam = {
  kind: "curve",
  weights(p) {
    const total = p.whit + p.wshort + p.wmax + p.wrand;
    if (!(total > 0)) return [0, 0, 0, 1];
    return [p.whit / total, p.wshort / total, p.wmax / total, p.wrand / total];
  },
  xRange(p) {
    return [0, p.zmax];
  },
  sample() {},
  density(p, xs, ys, theta, out) {
    // probrob.sensors._mixture, operation for operation
    const [zHit, zShort, zMax, zRand] = this.weights(p);
    const zmax = p.zmax;
    const sigma = p.sigma;
    const lam = p.lambda;
    const zs = p.zstar;
    const near = zs < 9 * sigma || zs > zmax - 9 * sigma;
    const norm = near ? normalCdf((zmax - zs) / sigma) - normalCdf(-zs / sigma) : 1;
    for (let j = 0; j < xs.length; j++) {
      const z = Math.min(xs[j], zmax);
      const u = (z - zs) / sigma;
      let q = (zHit / (sigma * Math.sqrt(2 * Math.PI))) * Math.exp(-0.5 * u * u);
      if (near) q /= norm;
      if (zShort > 0) {
        let short;
        if (zs > 0) short = (lam * Math.exp(-lam * z)) / -Math.expm1(-lam * zs);
        else short = z === 0 ? Infinity : 0;
        q += zShort * (z <= zs ? short : 0);
      }
      q += z >= zmax ? zMax : zRand / zmax;
      out[j] = q;
    }
  },
  title(p) {
    const w = this.weights(p).map((v) => v.toFixed(2));
    return "beam model: z* = " + p.zstar.toFixed(2) + " m, weights (hit, short, max, rand) = (" +
      w.join(", ") + ")";
  },
  labels() {
    return { x: "z [m]", y: "p(z | z*) [1/m]" };
  },
};
