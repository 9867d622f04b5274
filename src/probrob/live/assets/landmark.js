// Kernel of Tables 6.4 and 6.5, the landmark model: poses from one feature (Table 6.5,
// probrob.sensors.sample_landmark_model_known_correspondence) and the likelihood of the feature
// over the robot's position at a fixed heading (Table 6.4,
// probrob.sensors.landmark_model_known_correspondence), written as the library writes them and
// held equal to it by tests/test_live_widgets.py. Widget: probrob.live.sensors.
// landmark_model_live (kind "cloud"). Parameters: r [m], phi [rad], s (the feature), sr, sphi,
// ss (standard deviations), theta (the heading of the likelihood image) [rad]; constants mx,
// my, ms (the landmark j). Draws: "normal" (rows 0, 1: the range and bearing noise) and "gamma"
// (γ̂ = rand(0, 2π)).
kernels.landmark = {
  markers(p) {
    return [{ x: p.mx, y: p.my, theta: null, color: "blue" }];
  },
  heading(p) {
    return p.theta;
  },
  sample(p, z, n, out, draws) {
    const gamma = draws.gamma;
    const br = Math.sqrt(p.sr * p.sr);
    const bphi = Math.sqrt(p.sphi * p.sphi);
    for (let i = 0; i < n; i++) {
      const rHat = p.r + br * z[i];
      const phiHat = p.phi + bphi * z[n + i];
      out[3 * i] = p.mx + rHat * Math.cos(gamma[i]);
      out[3 * i + 1] = p.my + rHat * Math.sin(gamma[i]);
      out[3 * i + 2] = wrapAngle(gamma[i] - Math.PI - phiHat);
    }
  },
  density(p, xs, ys, th, out) {
    const s2r = p.sr * p.sr;
    const s2phi = p.sphi * p.sphi;
    const s2s = p.ss * p.ss;
    const nx = xs.length;
    for (let i = 0; i < ys.length; i++) {
      for (let j = 0; j < nx; j++) {
        // probrob.sensors.landmark_measurement, then Table 6.4's product
        const dx = p.mx - xs[j];
        const dy = p.my - ys[i];
        const rHat = Math.hypot(dx, dy);
        const phiHat = wrapAngle(Math.atan2(dy, dx) - th);
        let logq = LOG_PROB.normal(p.r - rHat, s2r) + LOG_PROB.normal(wrapAngle(p.phi - phiHat), s2phi);
        logq = logq + LOG_PROB.normal(p.s - p.ms, s2s);
        // inf + (-inf): a point mass matched on one component, missed on another: 0
        if (Number.isNaN(logq)) logq = -Infinity;
        out[i * nx + j] = Math.exp(logq);
      }
    }
  },
  title(p) {
    return (
      "landmark model: f = (" + p.r.toFixed(2) + " m, " + p.phi.toFixed(2) + " rad, " +
      p.s.toFixed(2) + "), poses at θ = " + p.theta.toFixed(2) + " rad"
    );
  },
  densityLabel() {
    return "Table 6.4 likelihood p(f | x, m) at θ";
  },
};
