// The HTML viewer in a real headless Chromium (Debian chromium driven by puppeteer-core):
// for each case the page opens with no console error; after seek(T) every body is drawn
// where its CSV mass-centre position projects through the page's camera (within 2 px);
// play advances time; the plot panel draws the chosen column (its range equals the CSV
// column's, its line is on the canvas, its cursor follows the time). Saves a screenshot.
// Usage: node browser.mjs OUT_DIR SCREENSHOT_DIR   (OUT_DIR from make_outputs.sh)
import { mkdirSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { check, launch, openViewer, project, readCsv, tally } from './support.mjs';

const [outDir, shotDir] = process.argv.slice(2).map((p) => resolve(p));
const cases = [
  { name: 'four-bar', body: 'coupler', column: 'coupler.omega', fraction: 0.63 },  // an envelope column
  { name: 'gyroscope', body: 'top', column: 'top.x', fraction: 0.41 },
  { name: 'statics', column: null, fraction: 0 },
];

const browser = await launch();
try {
  mkdirSync(shotDir, { recursive: true });
  for (const c of cases) {
    const started = Date.now();
    const { page, errors } = await openViewer(browser, join(outDir, `${c.name}.html`));
    console.log(`${c.name}: viewer ready in ${Date.now() - started} ms`);

    const csvFile = c.name === 'statics' ? null : join(outDir, `${c.name}.csv`);
    const csv = csvFile ? readCsv(csvFile) : null;
    const names = await page.evaluate(() => window.mbdViewer.bodyNames());
    const dims = csv && csv.columns.includes(`${names[0]}.z`) ? 3 : 2;

    // positions after seek(T), at a row and halfway between two rows (linear in between)
    if (csv) {
      const k = Math.floor(c.fraction * (csv.rows.length - 1));
      for (const [label, t, f] of [['at a row', csv.rows[k][0], 0], ['between rows', 0.5 * (csv.rows[k][0] + csv.rows[k + 1][0]), 0.5]]) {
        await page.evaluate((t) => window.mbdViewer.seek(t), t);
        const cam = await page.evaluate(() => window.mbdViewer.camera());
        let worst = 0;
        for (const name of names) {
          const col = (s) => csv.columns.indexOf(`${name}.${s}`);
          const at = (s) => (col(s) < 0 ? 0 : csv.rows[k][col(s)] + f * (csv.rows[k + 1][col(s)] - csv.rows[k][col(s)]));
          const expected = project(cam, [at('x'), at('y'), dims === 3 ? at('z') : 0]);
          const drawn = await page.evaluate((n) => window.mbdViewer.bodyScreenPosition(n), name);
          worst = Math.max(worst, Math.hypot(drawn.x - expected.x, drawn.y - expected.y));
        }
        check(worst <= 2, `${c.name}: ${names.length} bodies at t = ${t.toFixed(4)} (${label}) drawn at their CSV positions, worst ${worst.toFixed(3)} px`);
        // and the rendered image has a body colour (saturated, unlike the grey background, grid
        // and joints) at each expected position
        const pixels = await page.evaluate((points) => {
          const gl = document.querySelector('#view canvas');
          const copy = document.createElement('canvas');
          copy.width = gl.width; copy.height = gl.height;
          const g = copy.getContext('2d');
          g.drawImage(gl, 0, 0);
          const r = gl.getBoundingClientRect(), sx = gl.width / r.width, sy = gl.height / r.height;
          return points.map((p) => Array.from(g.getImageData(Math.round((p.x - r.left) * sx), Math.round((p.y - r.top) * sy), 1, 1).data));
        }, names.map((name) => {
          const col = (s) => csv.columns.indexOf(`${name}.${s}`);
          const at = (s) => (col(s) < 0 ? 0 : csv.rows[k][col(s)] + f * (csv.rows[k + 1][col(s)] - csv.rows[k][col(s)]));
          return project(cam, [at('x'), at('y'), dims === 3 ? at('z') : 0]);
        }));
        const coloured = pixels.filter(([r, g, b]) => Math.max(r, g, b) - Math.min(r, g, b) > 40).length;
        check(coloured === names.length, `${c.name}: a body colour at ${coloured} of the ${names.length} projected CSV positions (${label})`);
      }
      // the body of interest is inside the canvas (a real position, not off-screen)
      const p = await page.evaluate((n) => window.mbdViewer.bodyScreenPosition(n), c.body);
      check(p.x > 0 && p.x < 1280 && p.y > 0 && p.y < 800 - 44, `${c.name}: ${c.body} is on screen at (${p.x.toFixed(1)}, ${p.y.toFixed(1)})`);

      // the body's name on hover over its drawn mass centre
      const hover = await page.evaluate((n) => window.mbdViewer.bodyScreenPosition(n), c.body);
      await page.mouse.move(hover.x, hover.y);
      const tip = await page.evaluate(() => { const e = document.getElementById('tip'); return e.style.display === 'block' ? e.textContent : ''; });
      check(tip === c.body, `${c.name}: hovering at (${hover.x.toFixed(1)}, ${hover.y.toFixed(1)}) names '${tip}' (expected '${c.body}')`);
      await page.mouse.move(1, 1);

      // play advances time
      const t0 = await page.evaluate(() => { window.mbdViewer.seek(window.mbdViewer.range()[0]); window.mbdViewer.play(); return window.mbdViewer.time(); });
      await page.waitForFunction((t0) => window.mbdViewer.time() > t0, { timeout: 30000, polling: 100 }, t0).catch(() => {});
      const t1 = await page.evaluate(() => { const t = window.mbdViewer.time(); window.mbdViewer.pause(); return t; });
      check(t1 > t0, `${c.name}: play advances time from ${t0} to ${t1.toFixed(4)} s`);

      // plot panel: the chosen column's range, its line on the canvas, the cursor at the time
      const ci = csv.columns.indexOf(c.column);
      const values = csv.rows.map((r) => r[ci]);
      const lo = Math.min(...values), hi = Math.max(...values);
      const tSeek = csv.rows[k][0];
      const info = await page.evaluate((col, t) => { window.mbdViewer.setPlotColumn(col); window.mbdViewer.seek(t); return window.mbdViewer.plotInfo(); }, c.column, tSeek);
      const tol = 1e-6 * Math.max(1, Math.abs(lo), Math.abs(hi));
      check(info.column === c.column && Math.abs(info.min - lo) <= tol && Math.abs(info.max - hi) <= tol,
            `${c.name}: plot of ${info.column} spans [${info.min.toPrecision(6)}, ${info.max.toPrecision(6)}], CSV [${lo.toPrecision(6)}, ${hi.toPrecision(6)}]`);
      const plotted = await page.evaluate(() => {
        const canvas = document.getElementById('chart');
        const d = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
        let line = 0;
        for (let i = 0; i < d.length; i += 4) if (d[i + 2] > 150 && d[i] < 90 && d[i + 1] < 140) line++;
        return line;
      });
      check(plotted > 200, `${c.name}: the plot line covers ${plotted} pixels of the canvas`);
      const w = info.width - info.margin.left - info.margin.right;
      const t0csv = csv.rows[0][0], t1csv = csv.rows[csv.rows.length - 1][0];
      const cursor = info.margin.left + ((tSeek - t0csv) / (t1csv - t0csv)) * w;
      check(Math.abs(info.cursorX - cursor) < 1, `${c.name}: plot cursor at x = ${info.cursorX.toFixed(2)} for t = ${tSeek} (expected ${cursor.toFixed(2)})`);
      await page.evaluate((t) => window.mbdViewer.seek(t), csv.rows[k][0]);
    } else {
      const [t0, t1] = await page.evaluate(() => window.mbdViewer.range());
      check(t0 === t1 && names.length > 0, `${c.name}: the equilibrium is one frame (t = ${t0}) of ${names.length} bodies`);
    }
    await new Promise((r) => setTimeout(r, 100));
    await page.screenshot({ path: join(shotDir, `viewer-${c.name}.png`) });
    check(errors.length === 0, `${c.name}: no console error${errors.length ? ': ' + errors.join(' | ') : ''}`);
    await page.close();
  }
} finally {
  await browser.close();
}
console.log(`${tally.checks - tally.failures} passed, ${tally.failures} failed`);
process.exit(tally.failures ? 1 : 0);
