// probrob live widgets: the runtime's drawing helpers (inlined after runtime.js into every
// widget): ticks, text that fits, axes, arrows, polylines, crosses and legends, in CSS pixels on
// a canvas context, in the colours of the page's mode (a theme of runtime.js).

function niceTicks(lo, hi, count) {
  const raw = (hi - lo) / Math.max(count, 1);
  const mag = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 2.5, 5, 10].map((m) => m * mag).find((s) => s >= raw) || raw;
  const ticks = [];
  for (let t = Math.ceil(lo / step) * step; t <= hi + step * 1e-9; t += step) {
    ticks.push(Math.abs(t) < step * 1e-9 ? 0 : t);
  }
  return ticks;
}
function fmtTick(t) {
  const a = Math.abs(t);
  if (a !== 0 && (a >= 1e4 || a < 1e-3)) return t.toExponential(1);
  return String(Number(t.toPrecision(4)));
}
// Text at (x, y) in the current alignment, its font shrunk (to 10 px at the least) to fit
// `width`; else in two lines cut at the ", " or ": " nearest its middle (9 px at the least),
// the first above the second for the baseline "bottom", below it otherwise.
function fitText(ctx, text, x, y, width, size) {
  let px = size;
  const font = (p) => (ctx.font = p + "px sans-serif");
  const fits = (t) => ctx.measureText(t).width <= width;
  font(px);
  while (px > 10 && !fits(text)) font(--px);
  const cuts = [...text.matchAll(/[,:] /g)].map((m) => m.index + 1);
  if (fits(text) || !cuts.length) {
    ctx.fillText(text, x, y);
    return;
  }
  const middle = (a, b) => (Math.abs(b - text.length / 2) < Math.abs(a - text.length / 2) ? b : a);
  const cut = cuts.reduce(middle);
  const lines = [text.slice(0, cut), text.slice(cut + 1)];
  while (px > 9 && !lines.every(fits)) font(--px);
  const first = ctx.textBaseline === "bottom" ? y - px - 2 : y;
  ctx.fillText(lines[0], x, first);
  ctx.fillText(lines[1], x, first + px + 2);
}
// A frame for the box [left, top, w, h] showing [x0, x1] x [y0, y1]: ticks, tick labels, the
// axis labels and a title above (opts: ticks per axis, yLabels false: a panel beside another,
// which shares its y axis). Returns the maps [sx, sy] from data to pixels.
function axes(ctx, theme, box, lim, labels, opts) {
  const [left, top, w, h] = box;
  const [x0, x1, y0, y1] = lim;
  const o = Object.assign({ ticks: 5, yLabels: true }, opts);
  const sx = (x) => left + ((x - x0) / (x1 - x0)) * w;
  const sy = (y) => top + h - ((y - y0) / (y1 - y0)) * h;
  ctx.strokeStyle = theme.fg;
  ctx.lineWidth = 1;
  ctx.strokeRect(left + 0.5, top + 0.5, w, h);
  ctx.fillStyle = theme.fg;
  ctx.font = "12px sans-serif";
  ctx.textAlign = "center";
  ctx.textBaseline = "top";
  for (const t of niceTicks(x0, x1, o.ticks)) {
    ctx.fillRect(sx(t), top + h, 1, 5);
    ctx.fillText(fmtTick(t), sx(t), top + h + 7);
  }
  ctx.fillText(labels.x, left + w / 2, top + h + 26);
  ctx.textAlign = "right";
  ctx.textBaseline = "middle";
  for (const t of niceTicks(y0, y1, o.ticks)) {
    ctx.fillRect(left - 5, sy(t), 5, 1);
    if (o.yLabels) ctx.fillText(fmtTick(t), left - 7, sy(t));
  }
  if (o.yLabels) {
    ctx.save();
    ctx.translate(left - 46, top + h / 2);
    ctx.rotate(-Math.PI / 2);
    ctx.textAlign = "center";
    ctx.fillText(labels.y, 0, 0);
    ctx.restore();
  }
  ctx.textAlign = "center";
  ctx.textBaseline = "bottom";
  fitText(ctx, labels.title, left + w / 2, top - 10, w + (o.yLabels ? 40 : 0), 13);
  return [sx, sy];
}
// An arrow in pixels from (X0, Y0) to (X1, Y1): a dot at its start (dot > 0: its radius), the
// shaft and a filled head of `head` px.
function arrow(ctx, X0, Y0, X1, Y1, color, width, head, dot) {
  ctx.strokeStyle = color;
  ctx.fillStyle = color;
  ctx.lineWidth = width;
  if (dot) {
    ctx.beginPath();
    ctx.arc(X0, Y0, dot, 0, TWO_PI);
    ctx.fill();
  }
  ctx.beginPath();
  ctx.moveTo(X0, Y0);
  ctx.lineTo(X1, Y1);
  ctx.stroke();
  const a = Math.atan2(Y1 - Y0, X1 - X0);
  ctx.beginPath();
  ctx.moveTo(X1, Y1);
  ctx.lineTo(X1 - head * Math.cos(a - 0.4), Y1 - head * Math.sin(a - 0.4));
  ctx.lineTo(X1 - head * Math.cos(a + 0.4), Y1 - head * Math.sin(a + 0.4));
  ctx.closePath();
  ctx.fill();
}
// A polyline through points in pixels [[X, Y], ...], optionally dashed.
function polyline(ctx, points, color, width, dash) {
  ctx.strokeStyle = color;
  ctx.lineWidth = width;
  ctx.setLineDash(dash || []);
  ctx.beginPath();
  points.forEach(([X, Y], k) => (k === 0 ? ctx.moveTo(X, Y) : ctx.lineTo(X, Y)));
  ctx.stroke();
  ctx.setLineDash([]);
}
function cross(ctx, X, Y, color) {
  polyline(ctx, [[X - 6, Y - 6], [X + 6, Y + 6]], color, 2.5);
  polyline(ctx, [[X - 6, Y + 6], [X + 6, Y - 6]], color, 2.5);
}
// A legend: lines [text, colour] (colour optional; null: a gap) from (x, y), 17 px a line; in
// two columns `width` apart (place.columns 2) the gap splits them.
function legend(ctx, theme, place, items) {
  ctx.font = "12px sans-serif";
  ctx.textAlign = "left";
  ctx.textBaseline = "middle";
  const split = items.indexOf(null);
  const columns = place.columns === 2 && split > 0 ? [items.slice(0, split), items.slice(split + 1)] : [items];
  columns.forEach((column, c) => {
    let y = place.y;
    for (const item of column) {
      if (item === null) {
        y += 8;
        continue;
      }
      ctx.fillStyle = item[1] || theme.fg;
      ctx.fillText(item[0], place.x + c * place.width, y);
      y += 17;
    }
  });
}
