// Axes of the viewer's plot panel: "nice" ticks (1, 2 or 5 times a power of ten), labels
// that fit (the left margin grows to the widest one), and the axes' names with units.

// The unit of a result column, from its name (docs/user-guide.md, the CSV's columns).
const units = [
  [/^t$/, 's'], [/\.(x|y|z)$/, 'm'], [/\.angle$/, 'rad'], [/\.e[0-3]$/, ''],
  [/\.v(x|y|z)$/, 'm/s'], [/\.(omega|w[xyz])$/, 'rad/s'], [/\.f[xyz]$/, 'N'], [/\.t[xyz]$/, 'N m'],
  [/energy$/, 'J'], [/power$/, 'W'],
];
export function unitOf(column) {
  for (const [pattern, unit] of units) if (pattern.test(column)) return unit;
  return '';
}
export const axisName = (column) => { const u = unitOf(column); return u ? `${column} [${u}]` : column; };

// Tick values in [lo, hi]: multiples of a step of 1, 2 or 5 times a power of ten, about `count`.
export function niceTicks(lo, hi, count) {
  const raw = (hi - lo) / Math.max(count, 1);
  if (!(raw > 0) || !Number.isFinite(raw)) return { ticks: [lo], step: Math.abs(lo) || 1 };
  const decade = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 5, 10].map((f) => f * decade).find((s) => s >= raw);
  const ticks = [];
  for (let k = Math.ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * step; k++) ticks.push(k * step);
  return { ticks, step };
}

// A tick's text: as few digits as tell the ticks apart, exponent form for very small or
// large magnitudes (1.2e-6, not 0.0000012).
export function tickLabel(value, step) {
  if (value === 0 || Math.abs(value) < 1e-9 * step) return '0';
  const big = Math.max(Math.abs(value), step);
  if (big >= 1e5 || big < 1e-3) {
    const digits = Math.max(0, Math.floor(Math.log10(Math.abs(value))) - Math.floor(Math.log10(step)));
    return value.toExponential(Math.min(digits, 6)).replace('e+', 'e');
  }
  const decimals = Math.max(0, -Math.floor(Math.log10(step) + 1e-9));
  return value.toFixed(Math.min(decimals, 10));
}

// Draws the frame, the ticks and their labels and both axes' names; returns the labels
// drawn ({text, value, x, y, width, align}) for the page's API.
export function drawAxes(ctx, layout, yTicks, xTicks, names) {
  const { margin, width, height, yOf, xOf } = layout;
  const labels = [];
  ctx.strokeStyle = '#99a'; ctx.lineWidth = 1;
  ctx.strokeRect(margin.left, margin.top, width - margin.left - margin.right, height - margin.top - margin.bottom);
  ctx.fillStyle = '#334'; ctx.font = '11px system-ui, sans-serif';
  ctx.textBaseline = 'middle'; ctx.textAlign = 'right';
  for (const { value, text } of yTicks) {
    const y = yOf(value), x = margin.left - 5;
    ctx.fillText(text, x, y);
    ctx.beginPath(); ctx.moveTo(margin.left - 3, y); ctx.lineTo(margin.left, y); ctx.stroke();
    labels.push({ text, value, x, y, width: ctx.measureText(text).width, align: 'right' });
  }
  ctx.textBaseline = 'top'; ctx.textAlign = 'center';
  for (const { value, text } of xTicks) {
    const x = xOf(value), y = height - margin.bottom + 4;
    const w = ctx.measureText(text).width;
    const cx = Math.min(Math.max(x, margin.left + w / 2), width - w / 2 - 1);  // kept inside the canvas
    ctx.fillText(text, cx, y);
    ctx.beginPath(); ctx.moveTo(x, height - margin.bottom); ctx.lineTo(x, height - margin.bottom + 3); ctx.stroke();
    labels.push({ text, value, x: cx, y, width: w, align: 'center' });
  }
  ctx.textAlign = 'right'; ctx.textBaseline = 'bottom';
  ctx.fillText(names.x, width - margin.right, height - 1);
  ctx.save();
  ctx.translate(2, margin.top + (height - margin.top - margin.bottom) / 2);
  ctx.rotate(-Math.PI / 2); ctx.textAlign = 'center'; ctx.textBaseline = 'top';
  ctx.fillText(names.y, 0, 0);
  ctx.restore();
  return labels;
}
