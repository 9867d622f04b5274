// Table 5.2 kernel (kind "curve"): the zero-mean normal or triangular density with variance b2
// over ±4.5 b (as probrob.plotting.plot_distribution), and a histogram of the embedded
// standardized draws scaled by b (Table 5.4). The smallest curve kernel: a beam model's
// p(z | z*) kernel would have this shape, with its own parameters and draws.
kernels.distribution = {
  kind: "curve",
  xRange(p) {
    const b = Math.sqrt(p.b2);
    return [-4.5 * b, 4.5 * b];
  },
  sample(p, z, n, out) {
    const b = Math.sqrt(p.b2);
    for (let i = 0; i < n; i++) out[i] = b * z[i];
  },
  density(p, xs, ys, theta, out) {
    for (let j = 0; j < xs.length; j++) out[j] = Math.exp(p.logProb(xs[j], p.b2));
  },
  title(p) {
    return p.distribution + " density of Table 5.2, b² = " + p.b2.toFixed(3);
  },
  labels() {
    return { x: "a", y: "density p(a)" };
  },
};
