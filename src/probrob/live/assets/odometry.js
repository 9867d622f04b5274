// Kernel of Tables 5.5 and 5.6, the odometry motion model: the sampler of Table 5.6 and the
// density of Table 5.5, written as probrob.motion writes them (sample_motion_model_odometry and
// motion_model_odometry: wrapped rotations, the variances at the hypothesis for "book" and at
// the odometry for "pose" and "xy") and held equal to them to 1e-9 by
// tests/test_live_widgets.py. Widget: probrob.live.motion.odometry_model_live (kind "cloud").
// Parameters: rot1 [rad], trans [m], rot2 [rad] (the odometry's motion, from an odometry frame
// at the origin), theta (the robot's start heading) [rad], a1..a4, noise, distribution, density.
kernels.odometry = {
  deltas(p) {
    // u_t = (origin, apply_odometry_deltas(origin, rot1, trans, rot2)), read back as Table 5.5
    // lines 2-4 do (so a rotation beyond ±π is wrapped and trans = 0 moves the turn to rot2)
    const heading = 0 + p.rot1;
    const xn = 0 + p.trans * Math.cos(heading);
    const yn = 0 + p.trans * Math.sin(heading);
    return odometryDeltas(new Float64Array(3), 0, 0, 0, xn, yn, heading + p.rot2);
  },
  // the variances of the three noise terms at the motion (r1, t, r2), Table 5.5 / 5.6
  var1: (p, r1, t) => noiseVariance(p.noise, p.a1, r1, p.a2, t),
  varT: (p, r1, t, r2) => noiseVariance(p.noise, p.a3, t, p.a4, r1, p.a4, r2),
  var2: (p, t, r2) => noiseVariance(p.noise, p.a1, r2, p.a2, t),
  end(p) {
    const [r1, t, r2] = this.deltas(p);
    const heading = p.theta + r1;
    return [t * Math.cos(heading), t * Math.sin(heading), heading + r2];
  },
  sample(p, z, n, out) {
    const [r1, t, r2] = this.deltas(p);
    const b1 = Math.sqrt(this.var1(p, r1, t));
    const bt = Math.sqrt(this.varT(p, r1, t, r2));
    const b2 = Math.sqrt(this.var2(p, t, r2));
    for (let i = 0; i < n; i++) {
      const r1Hat = r1 - b1 * z[i];
      const tHat = t - bt * z[n + i];
      const r2Hat = r2 - b2 * z[2 * n + i];
      const heading = p.theta + r1Hat;
      out[3 * i] = tHat * Math.cos(heading);
      out[3 * i + 1] = tHat * Math.sin(heading);
      out[3 * i + 2] = heading + r2Hat;
    }
  },
  density(p, xs, ys, thetaHyp, out) {
    const [r1, t, r2] = this.deltas(p);
    const logProb = logProbOf(p);
    const book = p.density === "book";
    let var1 = this.var1(p, r1, t);
    let varT = this.varT(p, r1, t, r2);
    let var2 = this.var2(p, t, r2);
    const th = p.theta;
    const thn = p.density === "xy" ? th : thetaHyp;
    const hat = new Float64Array(3);
    const nx = xs.length;
    for (let i = 0; i < ys.length; i++) {
      for (let j = 0; j < nx; j++) {
        odometryDeltas(hat, 0, 0, th, xs[j], ys[i], thn);
        if (book) {
          // Table 5.5 as printed: the variances at the hypothesis' motion
          var1 = this.var1(p, hat[0], hat[1]);
          varT = this.varT(p, hat[0], hat[1], hat[2]);
          var2 = this.var2(p, hat[1], hat[2]);
        }
        // in log space, as probrob.motion.motion_model_odometry
        const l1 = logProb(angleDiff(r1, hat[0]), var1);
        const lt = logProb(t - hat[1], varT);
        let total =
          p.density === "xy" ? logProduct(l1, lt) : logProduct(l1, lt, logProb(angleDiff(r2, hat[2]), var2));
        if (!book) total = minusLogJacobian(total, Math.log(hat[1]));
        const q = Math.exp(total);
        out[i * nx + j] = q;
      }
    }
  },
  title(p) {
    return (
      "odometry model: δ = (" + p.rot1.toFixed(2) + " rad, " + p.trans.toFixed(2) + " m, " +
      p.rot2.toFixed(2) + " rad)"
    );
  },
  densityLabel: (p) => motionDensityLabel(p, "Table 5.5"),
};
