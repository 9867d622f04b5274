// probrob live widgets: the library's small helpers that several kernels use, written as
// probrob writes them (probrob.angles; Table 5.2 in log space as probrob.distributions; the
// noise variances, log products and odometry deltas of probrob.motion). Inlined after
// runtime.js into every widget; each kernel's parity test holds them to the library.

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
const SQRT6 = Math.sqrt(6);
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
// the log density of the distribution the parameters choose (p.distribution, default normal)
function logProbOf(p) {
  return LOG_PROB[p.distribution || "normal"];
}

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

// probrob.motion._deltas: (rot1, trans, rot2) from (x, y, th) to (xn, yn, thn), into out[0..2]
function odometryDeltas(out, x, y, th, xn, yn, thn) {
  const dx = xn - x;
  const dy = yn - y;
  const trans = Math.hypot(dx, dy);
  const rot1 = trans > 0 ? angleDiff(Math.atan2(dy, dx), th) : 0;
  let turn = thn - th;
  if (!Number.isFinite(turn)) turn = angleDiff(thn, th);
  out[0] = rot1;
  out[1] = trans;
  out[2] = angleDiff(turn, rot1);
  return out;
}
