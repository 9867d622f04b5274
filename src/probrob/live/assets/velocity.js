// Kernel of Tables 5.1 and 5.3, the velocity motion model: the sampler of Table 5.3 and the
// density of Table 5.1, written as probrob.motion writes them (sample_motion_model_velocity and
// motion_model_velocity: the chord form of the arc, the circle found in the robot's frame) and
// held equal to them to 1e-9 by tests/test_live_widgets.py. Widget: probrob.live.motion.
// velocity_model_live (kind "cloud"). Parameters: v [m/s], w [rad/s], dt [s], theta (the start
// heading) [rad], a1..a6, noise ("variance" | "std"), distribution, density ("xy" | "pose" |
// "book").
kernels.velocity = {
  variances(p) {
    return [
      noiseVariance(p.noise, p.a1, p.v, p.a2, p.w),
      noiseVariance(p.noise, p.a3, p.v, p.a4, p.w),
      noiseVariance(p.noise, p.a5, p.v, p.a6, p.w),
    ];
  },
  end(p) {
    // velocity_motion: the chord form, exact at w = 0
    const half = p.w * (0.5 * p.dt);
    const chord = sinc(half) * p.v * p.dt;
    const mid = p.theta + half;
    return [chord * Math.cos(mid), chord * Math.sin(mid), mid + half];
  },
  sample(p, z, n, out) {
    const [varV, varW, varG] = this.variances(p);
    const bv = Math.sqrt(varV);
    const bw = Math.sqrt(varW);
    const bg = Math.sqrt(varG);
    const dt = p.dt;
    for (let i = 0; i < n; i++) {
      const vHat = p.v + bv * z[i];
      const wHat = p.w + bw * z[n + i];
      const gamma = bg * z[2 * n + i];
      const half = wHat * (0.5 * dt);
      const chord = sinc(half) * vHat * dt;
      const mid = p.theta + half;
      out[3 * i] = chord * Math.cos(mid);
      out[3 * i + 1] = chord * Math.sin(mid);
      out[3 * i + 2] = mid + half + gamma * dt;
    }
  },
  density(p, xs, ys, thetaHyp, out) {
    const [varV, varW, varG] = this.variances(p);
    const logProb = logProbOf(p);
    const dt = p.dt;
    const th = p.theta;
    const c = Math.cos(th);
    const s = Math.sin(th);
    // "xy" integrates the heading out; the library then ignores the hypothesis heading
    const xy = p.density === "xy";
    const thn = xy ? th : thetaHyp;
    const nx = xs.length;
    for (let i = 0; i < ys.length; i++) {
      for (let j = 0; j < nx; j++) {
        // probrob.motion._invert_velocity
        const dx = xs[j];
        const dy = ys[i];
        const ahead = c * dx + s * dy;
        const left = c * dy - s * dx;
        const sign = ahead < 0 ? -1 : 1;
        let half = Math.atan2(sign * left, Math.abs(ahead));
        const rho = Math.sqrt(ahead * ahead + left * left);
        const cl = rho > 0 ? left / rho : 0;
        let ratio = cl !== 0 ? half / cl : sign;
        if (!(rho > 0)) {
          half = 0.5 * angleDiff(thn, th);
          ratio = 0;
        }
        const vHat = (rho * ratio) / dt;
        const wHat = half * (2 / dt);
        const gamma = wrapAngle(thn - th - 2 * half) / dt;
        // Table 5.1 in log space, as probrob.motion.motion_model_velocity
        const lv = logProb(p.v - vHat, varV);
        const lw = logProb(p.w - wHat, varW);
        // "xy": the factor of γ̂ integrates to Δt over θ′, one Δt of the Jacobian
        let total = xy ? logProduct(lv, lw) : logProduct(lv, lw, logProb(gamma, varG));
        if (p.density !== "book") {
          let logJac = Math.log(Math.abs(vHat));
          logJac += 2 * Math.log(sinc(half)) + (Math.log(0.5) + (xy ? 3 : 4) * Math.log(dt));
          total = minusLogJacobian(total, logJac);
        }
        const q = Math.exp(total);
        out[i * nx + j] = q;
      }
    }
  },
  title(p) {
    return (
      "velocity model: v = " + p.v.toFixed(2) + " m/s, ω = " + p.w.toFixed(2) +
      " rad/s, Δt = " + p.dt.toFixed(2) + " s"
    );
  },
  densityLabel: (p) => motionDensityLabel(p, "Table 5.1"),
};
