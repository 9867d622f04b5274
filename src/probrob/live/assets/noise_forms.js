// The Turkish lecture's two noise forms of Tables 5.1/5.3 and 5.5/5.6 side by side, on a motion
// kernel (velocity.js or odometry.js, unchanged: one implementation per model): panel 0 is the
// kernel with noise "std" (each sum α·|m| + ... is a standard deviation) at the sliders' α;
// panel 1 with noise "variance" (each sum α·m² + ... is a variance) at α² ("squared": the same
// noise as panel 0 for a sum of one term) or at the same α ("same"). Both panels use the same
// draws, the same view and the same grey scale. Held equal to probrob.motion by
// tests/test_live_widgets_tr_cir.py. Widgets: probrob.live.motion.velocity_noise_forms_live and
// odometry_noise_forms_live (velocity_forms.js, odometry_forms.js). Parameters: the base
// kernel's, plus pairing.
function noiseForms(base, count) {
  return Object.assign(Object.create(base), {
    panels: 2,
    panel(p, k) {
      const q = Object.assign({}, p, { noise: k === 0 ? "std" : "variance" });
      if (k === 1 && p.pairing === "squared") {
        for (let i = 1; i <= count; i++) q["a" + i] = p["a" + i] * p["a" + i];
      }
      return q;
    },
    title(q) {
      if (q.noise === "std") return 'noise="std" at α';
      return 'noise="variance" at ' + (q.pairing === "squared" ? "α²" : "α");
    },
  });
}
