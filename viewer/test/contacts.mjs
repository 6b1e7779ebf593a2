// Issue 39, the viewer's contacts: a ball, a brick and a capsule falling onto a plane
// (scenes/examples/force-collision-contact.yaml), its page written by `mbd simulate --animation`
// beside the contact table of `--contacts` of the same run. In headless Chromium:
//  - at t = 0, the bodies apart, no contact and no arrow is drawn;
//  - at times through the run, the page draws exactly the table's contacts at the keyframe it
//    shows (same count; each point, in either order, normal and normal force as in the table to 1e-7), one
//    normal-force arrow per contact, based at the contact point and pointing along the normal
//    the force acts on body j (world direction to 1e-6);
//  - each arrow's base and tip appear on the screen where the page camera projects them (within
//    0.5 px), and the projected arrow runs along the projected normal.
// Saves a screenshot.
// Usage: node contacts.mjs OUT_DIR SCREENSHOT_DIR   (OUT_DIR from make_outputs.sh)
import { mkdirSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { check, finishPage, launch, openViewer, project, readCsv, report } from './support.mjs';

const [outDir, shotDir] = process.argv.slice(2).map((p) => resolve(p));
const table = readCsv(join(outDir, 'collision-contacts.csv'));
const col = (name) => table.columns.indexOf(name);
const rowsAt = (t) => table.rows.filter((r) => r[0] === t);
const sub = (a, b) => a.map((x, i) => x - b[i]);
const norm = (v) => Math.hypot(...v);
const close = (a, b, tol) => norm(sub(a, b)) <= tol * Math.max(1, norm(b));

const browser = await launch();
try {
  mkdirSync(shotDir, { recursive: true });
  const { page, errors } = await openViewer(browser, join(outDir, 'collision.html'));
  const at = (t) => page.evaluate((x) => { window.mbdViewer.seek(x); return window.mbdViewer.contacts(); }, t);

  const start = await at(0);
  check(start.contacts.length === 0 && start.drawn === 0 && rowsAt(0).length === 0,
        `t = 0: the bodies are apart, ${start.contacts.length} contacts and ${start.drawn} arrows drawn`);

  let withContacts = 0;
  for (const t of [0.15, 0.3, 0.45, 0.6, 0.75, 0.9, 1.0]) {
    const shown = await at(t);
    const expected = rowsAt(shown.time);
    check(shown.contacts.length === expected.length,
          `t = ${t}: ${shown.contacts.length} contacts drawn at keyframe t = ${shown.time}, ${expected.length} in the table`);
    if (shown.contacts.length) withContacts++;
    const cam = await page.evaluate(() => window.mbdViewer.camera());
    shown.contacts.forEach((c, i) => {
      // the table's contact at this point (the two may list them in another order)
      const row = expected.find((r) => close(c.point, [r[col('x')], r[col('y')], r[col('z')]], 1e-7));
      if (!row) { check(false, `t = ${shown.time} contact ${i}: no contact of the table at ${c.point}`); return; }
      const point = [row[col('x')], row[col('y')], row[col('z')]];
      const normal = [row[col('nx')], row[col('ny')], row[col('nz')]];
      const fn = row[col('normal_force')];
      check(close(c.point, point, 1e-7) && close(c.normal, normal, 1e-7) && Math.abs(c.normalForce - fn) <= 1e-7 * Math.abs(fn),
            `t = ${shown.time} contact ${i}: point, normal and normal force as in the table`);
      if (!c.arrow) { check(false, `t = ${shown.time} contact ${i}: its normal force ${fn} N has no arrow`); return; }
      const direction = sub(c.arrow.tip, c.arrow.base);
      const along = normal.map((x) => Math.sign(fn) * x);
      check(close(c.arrow.base, point, 1e-6) && norm(sub(direction.map((x) => x / norm(direction)), along)) < 1e-6,
            `t = ${shown.time} contact ${i}: the arrow starts at the point and points along the normal`);
      const base = project(cam, c.arrow.base), tip = project(cam, c.arrow.tip);
      check(Math.hypot(base.x - c.arrow.baseScreen[0], base.y - c.arrow.baseScreen[1]) < 0.5 &&
            Math.hypot(tip.x - c.arrow.tipScreen[0], tip.y - c.arrow.tipScreen[1]) < 0.5,
            `t = ${shown.time} contact ${i}: the arrow is drawn where the camera projects it`);
      // the projected arrow lies along the projected normal (a short step along n from the point)
      const step = project(cam, point.map((x, k) => x + 1e-3 * along[k]));
      const p0 = project(cam, point);
      const a = [tip.x - base.x, tip.y - base.y], b = [step.x - p0.x, step.y - p0.y];
      const cross = (a[0] * b[1] - a[1] * b[0]) / (norm(a) * norm(b)), dot = a[0] * b[0] + a[1] * b[1];
      check(norm(b) < 1e-9 || (Math.abs(cross) < 1e-3 && dot > 0), `t = ${shown.time} contact ${i}: on screen the arrow runs along the normal`);
    });
  }
  check(withContacts >= 5, `${withContacts} of 7 times show contacts`);
  await finishPage(page, errors, 1.0, join(shotDir, 'viewer-contacts.png'));
} finally {
  await browser.close();
}
report();
