// Kernel of the CIR report (deck 003, eqs. 2-8): one step of a differential drive about its
// centre of instantaneous rotation, written as probrob.kinematics writes it (cir_radius_angle,
// cir_step_transform as the literal product of three matrices, cir_state_function) and held
// equal to it by tests/test_live_widgets_tr_cir.py. Widget: probrob.live.kinematics.
// cir_step_live (kind "scene"). The report's convention: the heading θ is clockwise (the robot
// faces (cos θ, -sin θ)), α > 0 is a right turn. Parameters: ssx, sdx (left and right wheel arc
// lengths) [m], l (wheel base) [m], theta (the start heading) [rad]; the robot starts at the
// origin.

// probrob.kinematics._translation, _deck_rotation and a 3 × 3 product (row-major arrays)
function cirTranslation(tx, ty) {
  return [1, 0, tx, 0, 1, ty, 0, 0, 1];
}
function cirDeckRotation(angle) {
  const c = Math.cos(angle);
  const s = Math.sin(angle);
  return [c, s, 0, -s, c, 0, 0, 0, 1];
}
function cirMatmul(A, B) {
  const C = new Array(9);
  for (let i = 0; i < 3; i++) {
    for (let j = 0; j < 3; j++) {
      C[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
    }
  }
  return C;
}
// eq. 4: r = l s_dx / (s_sx - s_dx) (±inf on a straight line, the sign of s_dx), α = (s_sx - s_dx) / l
function cirRadiusAngle(ssx, sdx, l) {
  const diff = ssx - sdx;
  const r = diff !== 0 ? (l * sdx) / diff : sdx < 0 ? -Infinity : Infinity;
  return [r, diff / l];
}
// eqs. 5-7: about the CIR, T(0, -ρ) R(α) T(0, ρ) with ρ = r + l/2; straight: T(s_sx, 0)
function cirStepTransform(ssx, sdx, l) {
  const [r, alpha] = cirRadiusAngle(ssx, sdx, l);
  if (!Number.isFinite(r)) return cirTranslation(ssx, 0);
  const rho = r + 0.5 * l;
  return cirMatmul(cirMatmul(cirTranslation(0, -rho), cirDeckRotation(alpha)), cirTranslation(0, rho));
}
// eq. 2: the pose's homogeneous matrix, the transpose of the usual rotation
function cirPoseMatrix(x, y, th) {
  const t = cirDeckRotation(th);
  t[2] = x;
  t[5] = y;
  return t;
}
// eqs. 3 and 8: f(x, u) = (T^w_Rt(1, 3), T^w_Rt(2, 3), θ + α)
function cirStateFunction(x, y, th, ssx, sdx, l) {
  const world = cirMatmul(cirPoseMatrix(x, y, th), cirStepTransform(ssx, sdx, l));
  return [world[2], world[5], th + (ssx - sdx) / l];
}
// T @ (px, py, 1), the order of numpy's matmul
function cirApply(T, px, py) {
  return [T[0] * px + T[1] * py + T[2] * 1, T[3] * px + T[4] * py + T[5] * 1];
}

const CIR_PATH = 61; // points of each path: the step's fractions linspace(0, 1, 61)
const CIR_VIEW = 2; // the view holds the CIR if it is at most this far from the axle [m]

kernels.cir = {
  kind: "scene",
  scene(p) {
    const l = p.l;
    const [r, alpha] = cirRadiusAngle(p.ssx, p.sdx, l);
    const step = cirStepTransform(p.ssx, p.sdx, l);
    const pose = cirStateFunction(0, 0, p.theta, p.ssx, p.sdx, l);
    const frac = new Float64Array(CIR_PATH);
    const mid = new Float64Array(3 * CIR_PATH);
    const left = new Float64Array(2 * CIR_PATH);
    const right = new Float64Array(2 * CIR_PATH);
    const step0 = 1 / (CIR_PATH - 1); // numpy.linspace: k * step, the last one exactly 1
    for (let k = 0; k < CIR_PATH; k++) {
      frac[k] = k === CIR_PATH - 1 ? 1 : k * step0;
      const q = cirStateFunction(0, 0, p.theta, frac[k] * p.ssx, frac[k] * p.sdx, l);
      mid.set(q, 3 * k);
      const F = cirPoseMatrix(q[0], q[1], q[2]);
      left.set(cirApply(F, 0, l / 2), 2 * k);
      right.set(cirApply(F, 0, -l / 2), 2 * k);
    }
    // the CIR, (0, -(r + l/2)) in the start frame (eq. 6); none on a straight line
    const rho = r + l / 2;
    const cir = Number.isFinite(r) ? cirApply(cirPoseMatrix(0, 0, p.theta), 0, -rho) : [NaN, NaN];
    const points = [];
    for (let k = 0; k < CIR_PATH; k++) points.push([left[2 * k], left[2 * k + 1]], [right[2 * k], right[2 * k + 1]]);
    for (const q of [[0, 0, p.theta], pose]) {
      points.push([q[0] + 0.3 * Math.cos(q[2]), q[1] - 0.3 * Math.sin(q[2])]);
    }
    if (Math.abs(rho) <= CIR_VIEW) points.push(cir);
    return {
      values: { r, alpha, rho, step: Float64Array.from(step), pose: Float64Array.from(pose), cir: Float64Array.from(cir), frac, mid, left, right },
      points,
    };
  },
  drawScene(ctx, p, v, { sx, sy, theme }) {
    const K = CIR_PATH;
    const path = (pts) => pts.map((q) => [sx(q[0]), sy(q[1])]);
    const pts = (arr, dim) => Array.from({ length: K }, (_, k) => [arr[dim * k], arr[dim * k + 1]]);
    // the radius: from the CIR to the middle of the axle, before and after
    if (Number.isFinite(v.r)) {
      for (const k of [0, K - 1]) polyline(ctx, path([v.cir, [v.mid[3 * k], v.mid[3 * k + 1]]]), theme.red, 1);
    }
    polyline(ctx, path(pts(v.left, 2)), theme.green, 2.5);
    polyline(ctx, path(pts(v.right, 2)), theme.orange, 2.5);
    polyline(ctx, path(pts(v.mid, 3)), theme.fg, 1, [5, 4]);
    // the robot before (grey) and after (the foreground colour): axle and heading (clockwise θ)
    for (const [k, color] of [[0, theme.muted], [K - 1, theme.fg]]) {
      polyline(ctx, path([[v.left[2 * k], v.left[2 * k + 1]], [v.right[2 * k], v.right[2 * k + 1]]]), color, 4);
      const [x, y, th] = v.mid.subarray(3 * k, 3 * k + 3);
      arrow(ctx, sx(x), sy(y), sx(x + 0.25 * Math.cos(th)), sy(y - 0.25 * Math.sin(th)), color, 2, 9, 0);
    }
    if (Number.isFinite(v.r)) cross(ctx, sx(v.cir[0]), sy(v.cir[1]), theme.red);
  },
  legendRows: 6,
  legend(p, v, theme) {
    const fmt = (x) => (Math.abs(x) >= 1e4 ? x.toExponential(1) : x.toFixed(2));
    const finite = Number.isFinite(v.r);
    const numbers = finite
      ? [["r = " + fmt(v.r) + " m"], ["ρ = " + fmt(v.rho) + " m"]]
      : [["straight line:"], ["r = " + (v.r > 0 ? "+" : "−") + "∞, no CIR"]];
    numbers.push(["α = " + fmt(v.alpha) + " rad"]);
    if (finite && Math.abs(v.rho) > CIR_VIEW) numbers.push(["(CIR off the plot)", theme.red]);
    return [
      ...numbers,
      null,
      ["— left wheel", theme.green],
      ["— right wheel", theme.orange],
      ["- - axle's middle"],
      ["× CIR, — radius", theme.red],
      ["grey: before"],
      [(theme.mode === "dark" ? "white" : "black") + ": after"],
    ];
  },
  title(p) {
    return "CIR step: s_sx = " + p.ssx.toFixed(2) + " m, s_dx = " + p.sdx.toFixed(2) + " m, l = " + p.l.toFixed(2) + " m";
  },
};
