// Shared by the viewer's browser tests: the CSV reader, the projection of a world point
// through the page's camera, the pass/fail tally and the headless Chromium they drive.
import { readFileSync } from 'node:fs';
import puppeteer from 'puppeteer-core';

export function readCsv(file) {
  const lines = readFileSync(file, 'utf8').trim().split('\n');
  const columns = lines[0].split(',');
  return { columns, rows: lines.slice(1).map((l) => l.split(',').map(Number)) };
}

// world point -> CSS pixel through the camera's view and projection (column-major 4x4)
export function project(cam, p) {
  const mul = (m, v) => [0, 1, 2, 3].map((r) => m[r] * v[0] + m[4 + r] * v[1] + m[8 + r] * v[2] + m[12 + r] * v[3]);
  const c = mul(cam.projection, mul(cam.view, [p[0], p[1], p[2], 1]));
  return { x: cam.left + ((c[0] / c[3] + 1) / 2) * cam.width, y: cam.top + ((1 - c[1] / c[3]) / 2) * cam.height };
}

export const tally = { checks: 0, failures: 0 };
export function check(ok, what) {
  tally.checks++;
  if (!ok) tally.failures++;
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
}

export function launch() {
  return puppeteer.launch({
    executablePath: process.env.MBD_CHROMIUM || '/usr/bin/chromium',
    headless: true,
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--window-size=1280,800'],
  });
}

// A page of the viewer opened at 1280 x 800 CSS pixels; its console errors are collected.
export async function openViewer(browser, file) {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 800 });
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto('file://' + file, { waitUntil: 'load' });
  await page.waitForFunction(() => window.mbdViewer !== undefined, { timeout: 20000 });
  return { page, errors };
}

// A page's last look: seek to time t, save its picture at shotPath, check that the page logged no
// console error, and close it.
export async function finishPage(page, errors, t, shotPath) {
  await page.evaluate((time) => window.mbdViewer.seek(time), t);
  await new Promise((r) => setTimeout(r, 100));
  await page.screenshot({ path: shotPath });
  check(errors.length === 0, `no console error${errors.length ? ': ' + errors.join(' | ') : ''}`);
  await page.close();
}

// The tally as the test's last line, and its exit status.
export function report() {
  console.log(`${tally.checks - tally.failures} passed, ${tally.failures} failed`);
  process.exit(tally.failures ? 1 : 0);
}
