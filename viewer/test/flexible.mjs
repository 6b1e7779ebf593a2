// Issue 40, a flexible body in the viewer: an ANCF cable pendulum (4 elements, released
// horizontal; its page written by `mbd simulate --animation`, make_outputs.sh). In headless
// Chromium, at every row of the run's CSV:
//  - the page draws the cable's tube through the CSV's node positions, to the page's keyframe
//    tolerance (1e-4 of each column's range, as for mass centres; html_export.cpp) plus float32;
//  - the tube passes through the nodes: the box of its vertices holds every node, and it is as
//    thick as its radius across the plane (z from -r to r).
// Saves a screenshot.
// Usage: node flexible.mjs OUT_DIR SCREENSHOT_DIR   (OUT_DIR from make_outputs.sh)
import { mkdirSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { check, finishPage, launch, openViewer, readCsv, report } from './support.mjs';

const [outDir, shotDir] = process.argv.slice(2).map((p) => resolve(p));
const table = readCsv(join(outDir, 'cable-pendulum.csv'));
const col = (name) => table.columns.indexOf(name);
const nodes = 5;
const range = (c) => { const v = table.rows.map((r) => r[c]); return Math.max(...v) - Math.min(...v); };

const browser = await launch();
try {
  mkdirSync(shotDir, { recursive: true });
  const { page, errors } = await openViewer(browser, join(outDir, 'cable-pendulum.html'));
  check(col('rope.node4.y') > 0, 'the CSV has the cable\'s node columns');
  let worst = 0, enclosed = 0;
  for (const row of table.rows) {
    const tube = await page.evaluate((t) => { window.mbdViewer.seek(t); return window.mbdViewer.flexibleTube('rope'); }, row[0]);
    if (!tube || tube.nodes.length !== nodes) { check(false, `t = ${row[0]}: no tube of ${nodes} nodes`); break; }
    let inside = true;
    for (let k = 0; k < nodes; k++)
      for (const [axis, name] of [[0, 'x'], [1, 'y']]) {
        const c = col(`rope.node${k}.${name}`);
        const error = Math.abs(tube.nodes[k][axis] - row[c]) / (1e-4 * range(c) + 1e-6 * Math.abs(row[c]) + 1e-12);
        worst = Math.max(worst, error);
        inside = inside && tube.box[0][axis] <= tube.nodes[k][axis] && tube.box[1][axis] >= tube.nodes[k][axis];
      }
    const r = tube.radius;
    if (inside && Math.abs(tube.box[0][2] + r) < 1e-3 * r && Math.abs(tube.box[1][2] - r) < 1e-3 * r) enclosed++;
  }
  check(worst <= 1, `every node drawn where the CSV has it, within the page's tolerance (worst ${worst.toFixed(3)} of it)`);
  check(enclosed === table.rows.length, `${enclosed} of ${table.rows.length} rows: the tube holds every node and is 2 r thick across the plane`);
  await finishPage(page, errors, table.rows[Math.floor(table.rows.length / 2)][0], join(shotDir, 'viewer-flexible.png'));
} finally {
  await browser.close();
}
report();
