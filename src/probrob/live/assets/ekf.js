// Kernel of Table 7.2, EKF localization with known correspondences: one step, the velocity
// motion model's prediction (lines 2-7) and one range-bearing feature's correction (lines
// 8-21), written as probrob.localization.ekf_localization_known_correspondences writes it
// (_ekf_predict, _landmark_at, _ekf_known, _finish) on probrob.motion's chord-form g and
// Jacobians (exact at ω = 0) and probrob.sensors' h; the 95 % ellipses as
// probrob.evaluation.covariance_ellipse. Held equal to the library by
// tests/test_live_widgets_t5.py. Widget: probrob.live.localization.ekf_step_live (kind "scene").
// Parameters: x0, y0, th0 (the prior mean μ_{t-1}) and sx, sy, sth (its standard deviations:
// Σ_{t-1} = diag(sx², sy², sth²)); v, w (the control); a1..a4 (M_t's variances α1 v² + α2 ω²,
// α3 v² + α4 ω²); mx, my (the landmark); sr, sphi (σ_r, σ_φ); dr, dphi (the measurement minus
// the prediction ẑ at μ̄: z = (max(0, r̂ + dr), wrap(φ̂ + dphi))); constants dt and p (the
// ellipses' probability).

// probrob.motion._sinc_derivative: d/dh sin(h)/h, the series below |h| = 0.1
function ekfSincDerivative(h) {
  if (Math.abs(h) < 0.1) {
    const h2 = h * h;
    return h * (-1 / 3 + h2 * (1 / 30 + h2 * (-1 / 840 + h2 * (1 / 45360 - h2 / 3991680))));
  }
  return (h * Math.cos(h) - Math.sin(h)) / (h * h);
}
// row-major products of small matrices: A (n x k) times B (k x m)
function ekfMul(A, B, n, k, m) {
  const C = new Float64Array(n * m);
  for (let i = 0; i < n; i++) {
    for (let j = 0; j < m; j++) {
      let s = 0;
      for (let l = 0; l < k; l++) s += A[i * k + l] * B[l * m + j];
      C[i * m + j] = s;
    }
  }
  return C;
}
function ekfT(A, n, m) {
  const B = new Float64Array(n * m);
  for (let i = 0; i < n; i++) for (let j = 0; j < m; j++) B[j * n + i] = A[i * m + j];
  return B;
}
function ekfAdd(A, B) {
  const C = new Float64Array(A.length);
  for (let i = 0; i < A.length; i++) C[i] = A[i] + B[i];
  return C;
}

// Table 7.2, lines 2-7 (probrob.localization._ekf_predict): μ̄ (heading not wrapped) and Σ̄
function ekfPredict(mu, Sigma, v, w, dt, alpha) {
  const [x, y, th] = mu;
  const h = w * (0.5 * dt); // probrob.motion._velocity_jacobian_entries
  const sn = sinc(h);
  const ds = ekfSincDerivative(h);
  const mid = th + h;
  const c = Math.cos(mid);
  const s = Math.sin(mid);
  const g13 = -v * dt * sn * s;
  const g23 = v * dt * sn * c;
  const v11 = dt * sn * c;
  const v21 = dt * sn * s;
  const v12 = 0.5 * v * (dt * dt) * (ds * c - sn * s);
  const v22 = 0.5 * v * (dt * dt) * (ds * s + sn * c);
  const G = Float64Array.of(1, 0, g13, 0, 1, g23, 0, 0, 1); // line 3
  const V = Float64Array.of(v11, v12, v21, v22, 0, dt); // line 4
  const v2 = v * v;
  const w2 = w * w;
  const M = Float64Array.of(v2 * alpha[0] + w2 * alpha[1], 0, 0, v2 * alpha[2] + w2 * alpha[3]); // line 5
  const chord = sinc(h) * v * dt; // line 6, probrob.motion._arc
  const muBar = Float64Array.of(x + chord * Math.cos(mid), y + chord * Math.sin(mid), mid + h);
  const SigmaBar = ekfAdd(ekfMul(ekfMul(G, Sigma, 3, 3, 3), ekfT(G, 3, 3), 3, 3, 3), ekfMul(ekfMul(V, M, 3, 2, 2), ekfT(V, 3, 2), 3, 2, 3)); // line 7
  return { G, V, M, muBar, SigmaBar };
}

// Table 7.2, lines 11-13 for a landmark (mx, my): ẑ = (r̂, φ̂) and H (2 x 3), or null at q = 0
function ekfMeasure(muBar, mx, my) {
  const dx = mx - muBar[0];
  const dy = my - muBar[1];
  const q = dx * dx + dy * dy;
  if (q === 0) return null;
  const r = Math.sqrt(q);
  const zhat = Float64Array.of(Math.hypot(dx, dy), wrapAngle(Math.atan2(dy, dx) - muBar[2]));
  const H = Float64Array.of(-dx / r, -dy / r, 0, dy / q, -dx / q, -1);
  return { zhat, H };
}

// 2 x 2 symmetric [a b; b c]: inverse, lower Cholesky factor, and eigenvalues ascending with
// unit eigenvectors (the columns of U, as numpy.linalg.eigh returns them up to their signs)
function ekfInv2(S) {
  const det = S[0] * S[3] - S[1] * S[2];
  return Float64Array.of(S[3] / det, -S[1] / det, -S[2] / det, S[0] / det);
}
function ekfChol2(S) {
  const l11 = Math.sqrt(S[0]);
  const l21 = S[2] / l11;
  return [l11, l21, Math.sqrt(S[3] - l21 * l21)];
}
function ekfEigh2(a, b, c) {
  if (b === 0) {
    return a <= c ? { w: [a, c], U: [1, 0, 0, 1] } : { w: [c, a], U: [0, 1, 1, 0] };
  }
  const mean = 0.5 * (a + c);
  const rad = Math.hypot(0.5 * (a - c), b);
  const big = mean + rad;
  const small = a * c - b * b > 0 ? (a * c - b * b) / big : mean - rad;
  // the eigenvector of the larger eigenvalue, from the better conditioned row of A - λI
  let ex = b;
  let ey = big - a;
  if (Math.abs(big - c) > Math.abs(big - a)) {
    ex = big - c;
    ey = b;
  }
  const n = Math.hypot(ex, ey);
  ex /= n;
  ey /= n;
  return { w: [small, big], U: [-ey, ex, ex, ey] }; // columns: (−ey, ex) for small, (ex, ey) for big
}

const EKF_ELLIPSE = 60; // covariance_ellipse's n: n + 1 points, the first repeated at the end

// probrob.evaluation.covariance_ellipse(mu, Sigma, p, n): mu_xy + radius (circle √w) Uᵀ
function ekfEllipse(mu, Sigma, radius) {
  const { w, U } = ekfEigh2(Sigma[0], 0.5 * (Sigma[1] + Sigma[3]), Sigma[4]);
  const s0 = Math.sqrt(Math.max(w[0], 0));
  const s1 = Math.sqrt(Math.max(w[1], 0));
  const out = new Float64Array(2 * (EKF_ELLIPSE + 1));
  const step = TWO_PI / EKF_ELLIPSE;
  for (let k = 0; k <= EKF_ELLIPSE; k++) {
    const t = k === EKF_ELLIPSE ? TWO_PI : k * step;
    const a = Math.cos(t) * s0;
    const b = Math.sin(t) * s1;
    out[2 * k] = mu[0] + radius * (a * U[0] + b * U[1]);
    out[2 * k + 1] = mu[1] + radius * (a * U[2] + b * U[3]);
  }
  return { points: out, w: Float64Array.from(w) };
}

// Table 7.2 lines 14-21 for one feature z (probrob.localization._ekf_known and _finish)
function ekfUpdate(muBar, SigmaBar, zhat, H, z, sr, sphi) {
  const Ht = ekfT(H, 2, 3);
  const S = ekfMul(ekfMul(H, SigmaBar, 2, 3, 3), Ht, 2, 3, 2); // line 14
  S[0] += sr * sr;
  S[3] += sphi * sphi;
  const K = ekfMul(ekfMul(SigmaBar, Ht, 3, 3, 2), ekfInv2(S), 3, 2, 2); // line 15
  const nu = Float64Array.of(z[0] - zhat[0], wrapAngle(z[1] - zhat[1]));
  const Knu = ekfMul(K, nu, 3, 2, 1);
  const mu = Float64Array.of(muBar[0] + Knu[0], muBar[1] + Knu[1], muBar[2] + Knu[2]); // line 16
  const IKH = ekfMul(K, H, 3, 2, 3);
  for (let i = 0; i < 9; i++) IKH[i] = (i % 4 === 0 ? 1 : 0) - IKH[i];
  const P = ekfMul(IKH, SigmaBar, 3, 3, 3); // line 17
  const [l11, l21, l22] = ekfChol2(S); // line 21: log N(ν; 0, S)
  const w0 = nu[0] / l11;
  const w1 = (nu[1] - l21 * w0) / l22;
  const d2 = w0 * w0 + w1 * w1;
  const logp = -0.5 * (d2 + 2 * (Math.log(l11) + Math.log(l22)) + 2 * Math.log(TWO_PI));
  mu[2] = wrapAngle(mu[2]); // lines 19-20: heading wrapped, Σ symmetrised
  const Sigma = new Float64Array(9);
  for (let i = 0; i < 3; i++) for (let j = 0; j < 3; j++) Sigma[3 * i + j] = 0.5 * (P[3 * i + j] + P[3 * j + i]);
  return { S, K, nu, mu, Sigma, logp, d2 };
}

function ekfStep(p) {
  const muPrev = Float64Array.of(p.x0, p.y0, p.th0);
  const SigmaPrev = Float64Array.of(p.sx * p.sx, 0, 0, 0, p.sy * p.sy, 0, 0, 0, p.sth * p.sth);
  const pred = ekfPredict(muPrev, SigmaPrev, p.v, p.w, p.dt, [p.a1, p.a2, p.a3, p.a4]);
  const meas = ekfMeasure(pred.muBar, p.mx, p.my);
  const out = { muPrev, SigmaPrev, pred, meas, up: null, z: null };
  if (meas) {
    out.z = Float64Array.of(Math.max(0, meas.zhat[0] + p.dr), wrapAngle(meas.zhat[1] + p.dphi));
    out.up = ekfUpdate(pred.muBar, pred.SigmaBar, meas.zhat, meas.H, out.z, p.sr, p.sphi);
  }
  return out;
}

kernels.ekf = {
  kind: "scene",
  scene(p) {
    const st = ekfStep(p);
    const radius = Math.sqrt(-2 * Math.log1p(-p.p)); // χ²₂ quantile: -2 log(1 - p)
    const muBar = Float64Array.of(st.pred.muBar[0], st.pred.muBar[1], wrapAngle(st.pred.muBar[2]));
    const ePrior = ekfEllipse(st.muPrev, st.SigmaPrev, radius);
    const eBar = ekfEllipse(muBar, st.pred.SigmaBar, radius);
    const nan = (k) => new Float64Array(k).fill(NaN);
    const up = st.up;
    const mu = up ? up.mu : muBar;
    const Sigma = up ? up.Sigma : st.pred.SigmaBar;
    const ePost = ekfEllipse(mu, Sigma, radius);
    const values = {
      updated: up ? 1 : 0,
      muPrev: st.muPrev,
      SigmaPrev: st.SigmaPrev,
      G: st.pred.G,
      V: st.pred.V,
      M: st.pred.M,
      muBar,
      SigmaBar: st.pred.SigmaBar,
      zhat: st.meas ? st.meas.zhat : nan(2),
      H: st.meas ? st.meas.H : nan(6),
      z: st.z || nan(2),
      S: up ? up.S : nan(4),
      K: up ? up.K : nan(6),
      nu: up ? up.nu : nan(2),
      mu,
      Sigma,
      logp: up ? up.logp : 0,
      radius,
      ellipsePrior: ePrior.points,
      ellipseBar: eBar.points,
      ellipsePost: ePost.points,
      eigPrior: ePrior.w,
      eigBar: eBar.w,
      eigPost: ePost.w,
    };
    const points = [[p.mx, p.my]];
    for (const e of [ePrior.points, eBar.points, ePost.points]) {
      for (let k = 0; k < e.length; k += 2) points.push([e[k], e[k + 1]]);
    }
    for (const m of [st.muPrev, muBar, mu]) points.push([m[0], m[1]]);
    if (st.z) {
      const a = st.pred.muBar[2] + st.z[1];
      points.push([muBar[0] + st.z[0] * Math.cos(a), muBar[1] + st.z[0] * Math.sin(a)]);
    }
    return { values, points };
  },
  drawScene(ctx, p, v, { sx, sy, theme }) {
    const [prior, pred, post, meas] = [theme.muted, theme.orange, theme.blue, theme.red];
    const path = (pts) => Array.from({ length: pts.length / 2 }, (_, k) => [sx(pts[2 * k]), sy(pts[2 * k + 1])]);
    // a pose: a dot and a heading tick 22 px long
    const pose = (m, color) => {
      const [X, Y] = [sx(m[0]), sy(m[1])];
      arrow(ctx, X, Y, X + 22 * Math.cos(m[2]), Y - 22 * Math.sin(m[2]), color, 2, 8, 3.5);
    };
    const mb = v.muBar;
    // the predicted line of sight to the landmark (thin) and the measured one (dashed) with its end
    polyline(ctx, path([mb[0], mb[1], p.mx, p.my]), prior, 1, [2, 3]);
    if (v.updated) {
      const a = mb[2] + v.z[1];
      const end = [mb[0] + v.z[0] * Math.cos(a), mb[1] + v.z[0] * Math.sin(a)];
      polyline(ctx, path([mb[0], mb[1], ...end]), meas, 1.5, [6, 4]);
      cross(ctx, sx(end[0]), sy(end[1]), meas);
    }
    polyline(ctx, path(v.ellipsePrior), prior, 1.5, [5, 4]);
    polyline(ctx, path(v.ellipseBar), pred, 2, [9, 3]);
    polyline(ctx, path(v.ellipsePost), post, 2.5);
    pose(v.muPrev, prior);
    pose(mb, pred);
    pose(v.mu, post);
    ctx.fillStyle = theme.fg;
    ctx.fillRect(sx(p.mx) - 6, sy(p.my) - 6, 12, 12);
  },
  legendRows: 6,
  legend(p, v, theme) {
    const f = (x, d) => (x < 0 ? "−" : "") + Math.abs(x).toFixed(d === undefined ? 2 : d);
    const numbers = v.updated
      ? [
          ["r̂ = " + f(v.zhat[0]) + " m"],
          ["φ̂ = " + f(v.zhat[1]) + " rad"],
          ["z = (" + f(v.z[0]) + ", " + f(v.z[1]) + ")"],
          ["ν = (" + f(v.nu[0]) + ", " + f(v.nu[1]) + ")"],
          ["log p(z) = " + f(v.logp, 1)],
        ]
      : [["landmark at μ̄:", theme.red], ["no update", theme.red]];
    return [
      ["95 % ellipses:"],
      ["- - prior μ, Σ", theme.muted],
      ["– – predicted μ̄, Σ̄", theme.orange],
      ["—— posterior", theme.blue],
      ["■ landmark"],
      ["× measured z", theme.red],
      null,
      ...numbers,
    ];
  },
  title(p) {
    return "EKF step: u = (" + p.v.toFixed(2) + " m/s, " + p.w.toFixed(2) + " rad/s), Δt = " + p.dt + " s";
  },
};
