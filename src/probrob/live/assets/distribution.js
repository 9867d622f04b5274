// Kernel of Tables 5.2 and 5.4 (kind "curve"): the zero-mean normal or triangular density with
// variance b2 over ±4.5 b (probrob.distributions.prob_normal_distribution and
// prob_triangular_distribution, as probrob.plotting.plot_distribution shows them), and a
// histogram of the embedded standardized draws scaled by b (the samplers of Table 5.4). Held to
// the library by tests/test_live_widgets.py. Widget: probrob.live.distributions.distribution_live.
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
    const logProb = logProbOf(p);
    for (let j = 0; j < xs.length; j++) out[j] = Math.exp(logProb(xs[j], p.b2));
  },
  title(p) {
    return p.distribution + " density of Table 5.2, b² = " + p.b2.toFixed(3);
  },
  labels() {
    return { x: "a", y: "density p(a)" };
  },
};
