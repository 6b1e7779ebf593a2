// Issue 41, what a user sees: chain-50, the Whipple bicycle and the gyroscope in the viewer at
// its default camera, in headless Chromium. At six times through each run:
//  - every body covers at least 20 pixels of the view (an offscreen pass with a flat colour per
//    body, pixels under the plot panel not counted), so it is drawn, visible and in the frame;
//  - every joint's marker is drawn where the joint's point on each of its moving bodies is, that
//    point placed by the body's CSV pose (within 3 px): markers ride on their bodies.
// The bicycle's wheels are discs of the contact radius of the benchmark (Meijaard et al. 2007,
// Table 1: 0.3 m rear, 0.35 m front) about the wheel axle, touching the ground (the rim's lowest
// point at height 0); the gyroscope's rotor carries a bar across its face. The plot's tick labels
// lie whole inside the canvas and read as their values; the axes carry names with units.
// Saves a screenshot of each (the pictures of docs/user-guide.md).
// Usage: node mechanisms.mjs OUT_DIR SCREENSHOT_DIR   (OUT_DIR from make_outputs.sh)
import { mkdirSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { check, launch, openViewer, project, readCsv, tally } from './support.mjs';

const [outDir, shotDir] = process.argv.slice(2).map((p) => resolve(p));
const kMinPixels = 20, kMarkerPixels = 3, kSamples = 6;
const cases = [
  { name: 'chain-50', follow: false, plot: 'l18.angle' },
  { name: 'whipple-bicycle', follow: true, plot: 'rear_wheel.e2',
    wheels: { rear_wheel: 0.3, front_wheel: 0.35 } },
  { name: 'gyroscope', follow: false, plot: 'top.wz', rotor: 'top' },
];

// A body's pose in row r of the CSV: position and rotation matrix (rows of 3).
function csvPose(csv, body, r) {
  const at = (s) => { const k = csv.columns.indexOf(`${body}.${s}`); return k < 0 ? null : csv.rows[r][k]; };
  const p = [at('x'), at('y'), at('z') ?? 0];
  if (at('angle') !== null) {
    const c = Math.cos(at('angle')), s = Math.sin(at('angle'));
    return { p, A: [[c, -s, 0], [s, c, 0], [0, 0, 1]] };
  }
  const [e0, e1, e2, e3] = ['e0', 'e1', 'e2', 'e3'].map(at);  // book Eq. 7.39 (Euler parameters)
  return { p, A: [
    [1 - 2 * (e2 * e2 + e3 * e3), 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
    [2 * (e1 * e2 + e0 * e3), 1 - 2 * (e1 * e1 + e3 * e3), 2 * (e2 * e3 - e0 * e1)],
    [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 * e1 + e2 * e2)]] };
}
const place = ({ p, A }, u) => [0, 1, 2].map((i) => p[i] + A[i][0] * u[0] + A[i][1] * u[1] + A[i][2] * u[2]);
const column = (m, k) => [m[4 * k], m[4 * k + 1], m[4 * k + 2]];
const norm = (v) => Math.hypot(...v);
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];

async function checkWheels(page, csv, c, r) {
  for (const [wheel, radius] of Object.entries(c.wheels)) {
    const shapes = await page.evaluate((n) => window.mbdViewer.bodyShapes(n), wheel);
    const pose = csvPose(csv, wheel, r);
    const axle = [pose.A[0][1], pose.A[1][1], pose.A[2][1]];  // the hub's axis: body y (the scene's [0, 1, 0])
    // a disc: its mesh is round about its own z (equal x and y half-widths) and thin along it
    const discs = shapes.map((s) => {
      const half = [0, 1, 2].map((k) => 0.5 * (s.max[k] - s.min[k]) * s.scale[k]);
      const z = column(s.matrix, 2), zn = norm(z);
      return { s, half, axis: z.map((v) => v / zn), centre: column(s.matrix, 3) };
    }).filter((d) => Math.abs(d.half[0] - d.half[1]) < 1e-6 * d.half[0] && d.half[2] < 0.3 * d.half[0]);
    check(discs.length >= 1, `${c.name}: ${wheel} is drawn with ${discs.length} disc(s) (of ${shapes.length} shapes)`);
    if (!discs.length) continue;
    const d = discs.reduce((a, b) => (b.half[0] > a.half[0] ? b : a));
    const lowest = d.centre[2] - d.half[0] * Math.sqrt(Math.max(0, 1 - d.axis[2] * d.axis[2]));
    check(Math.abs(d.half[0] - radius) < 1e-5 && Math.abs(Math.abs(dot(d.axis, axle)) - 1) < 1e-4 &&
          Math.abs(lowest) < 2e-3,
          `${c.name}: ${wheel}'s disc has radius ${d.half[0].toFixed(5)} m (contact radius ${radius}), ` +
          `axis . axle = ${dot(d.axis, axle).toFixed(6)}, its lowest rim point at z = ${lowest.toExponential(2)} m`);
  }
}

const browser = await launch();
try {
  mkdirSync(shotDir, { recursive: true });
  for (const c of cases) {
    const started = Date.now();
    const { page, errors } = await openViewer(browser, join(outDir, `${c.name}.html`));
    const csv = readCsv(join(outDir, `${c.name}.csv`));
    const names = await page.evaluate(() => window.mbdViewer.bodyNames());
    const joints = await page.evaluate(() => window.mbdViewer.joints());
    const framing = await page.evaluate(() => window.mbdViewer.framing());
    check(framing.follow === c.follow, `${c.name}: the camera follows: ${framing.follow} (travel ${framing.travel.toFixed(3)} m, ` +
          `mechanism ${framing.size.toFixed(3)} m)`);

    const least = Object.fromEntries(names.map((n) => [n, Infinity]));
    let worstMarker = 0, worstMarkerWhat = '', unknown = 0;
    for (let s = 0; s < kSamples; s++) {
      const r = Math.round((s / (kSamples - 1)) * (csv.rows.length - 1));
      const t = csv.rows[r][0];
      await page.evaluate((t) => window.mbdViewer.seek(t), t);
      const cover = await page.evaluate(() => window.mbdViewer.bodyCoverage());
      unknown += cover.unknown;
      names.forEach((n) => { least[n] = Math.min(least[n], cover.pixels[n]); });
      const cam = await page.evaluate(() => window.mbdViewer.camera());
      const markers = await page.evaluate(() => window.mbdViewer.jointMarkers());
      for (const m of markers) {
        const j = joints.find((x) => x.name === m.joint);
        j.bodies.forEach((b, k) => {
          if (b < 0) return;
          const expected = project(cam, place(csvPose(csv, names[b], r), j.points[k]));
          const off = Math.hypot(expected.x - m.x, expected.y - m.y);
          if (off >= worstMarker) { worstMarker = off; worstMarkerWhat = `${m.joint} on ${names[b]} at t = ${t}`; }
        });
      }
      if (c.wheels && (s === 0 || s === kSamples - 1)) await checkWheels(page, csv, c, r);
    }
    const sorted = Object.entries(least).sort((a, b) => a[1] - b[1]);
    check(sorted[0][1] >= kMinPixels && unknown === 0,
          `${c.name}: every one of ${names.length} bodies covers >= ${kMinPixels} px at ${kSamples} times: least ` +
          sorted.slice(0, 4).map(([n, p]) => `${n} ${p}`).join(', ') + `, most ${sorted[sorted.length - 1].join(' ')}` +
          (unknown ? `; ${unknown} pixels of no body` : ''));
    check(worstMarker <= kMarkerPixels, `${c.name}: ${joints.length} joint markers on their bodies' joint points, worst ` +
          `${worstMarker.toFixed(3)} px (${worstMarkerWhat})`);

    if (c.rotor) {
      const shapes = await page.evaluate((n) => window.mbdViewer.bodyShapes(n), c.rotor);
      // a bar across the face: a box mesh (8 distinct corners) longer across the axis than along it
      const axis = shapes.map((s) => column(s.matrix, 2)).find((z, k) => shapes[k].max[0] - shapes[k].min[0] > 0);
      const bars = shapes.filter((s) => (s.max[0] - s.min[0]) > 4 * (s.max[1] - s.min[1]));
      check(bars.length === 1 && Math.abs(dot(column(bars[0].matrix, 0), axis) / norm(axis)) < 1e-6,
            `${c.name}: the rotor ${c.rotor} carries ${bars.length} bar across its axis`);
    }

    // the plot: tick labels whole inside the canvas, each reading as its value; named axes
    await page.evaluate((col) => window.mbdViewer.setPlotColumn(col), c.plot);
    for (const col of [c.plot, `${names[0]}.x`]) {
      await page.evaluate((x) => window.mbdViewer.setPlotColumn(x), col);
      const info = await page.evaluate(() => window.mbdViewer.plotInfo());
      const bad = info.labels.filter((l) => {
        const left = l.align === 'right' ? l.x - l.width : l.x - l.width / 2;
        const right = l.align === 'right' ? l.x : l.x + l.width / 2;
        return left < 0 || right > info.width || Math.abs(Number(l.text) - l.value) > 1e-9 * Math.max(1, Math.abs(l.value)) +
          0.05 * Math.abs(info.labels[1] ? info.labels[1].value - info.labels[0].value : 1);
      });
      check(info.labels.length >= 4 && bad.length === 0 && info.names.x === 't [s]' && info.names.y.startsWith(col),
            `${c.name}: plot of ${col} in [${info.min.toPrecision(5)}, ${info.max.toPrecision(5)}]: labels ` +
            info.labels.map((l) => l.text).join(' ') + `, axes '${info.names.x}' and '${info.names.y}'` +
            (bad.length ? `; clipped or misread: ${bad.map((l) => l.text).join(' ')}` : ''));
    }
    await page.evaluate((col) => window.mbdViewer.setPlotColumn(col), `${names[0]}.x`);
    await page.evaluate((t) => window.mbdViewer.seek(t), csv.rows[Math.round(0.6 * (csv.rows.length - 1))][0]);
    await new Promise((r) => setTimeout(r, 100));
    await page.screenshot({ path: join(shotDir, `viewer-${c.name}.png`) });
    check(errors.length === 0, `${c.name}: no console error${errors.length ? ': ' + errors.join(' | ') : ''}`);
    console.log(`${c.name}: done in ${Date.now() - started} ms`);
    await page.close();
  }
} finally {
  await browser.close();
}
console.log(`${tally.checks - tally.failures} passed, ${tally.failures} failed`);
process.exit(tally.failures ? 1 : 0);
