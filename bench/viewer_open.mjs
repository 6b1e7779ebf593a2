// Opens an mbd viewer page in headless Chromium and reports the time from navigation until
// the viewer is ready and has drawn a frame (bench/viewer_export.sh). Usage: node viewer_open.mjs PAGE.html
import { resolve } from 'node:path';
import { createRequire } from 'node:module';

const require = createRequire(resolve('viewer/package.json'));
const puppeteer = require('puppeteer-core');
const page_file = resolve(process.argv[2]);
const browser = await puppeteer.launch({ executablePath: process.env.MBD_CHROMIUM || '/usr/bin/chromium', headless: true,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'] });
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 800 });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  const start = Date.now();
  await page.goto('file://' + page_file, { waitUntil: 'load', timeout: 120000 });
  await page.waitForFunction(() => window.mbdViewer !== undefined, { timeout: 120000 });
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  const ms = Date.now() - start;
  const rows = await page.evaluate(() => window.mbdViewer.range());
  console.log(`open .html in Chromium: ${(ms / 1000).toFixed(2)} s (t = ${rows[0]} .. ${rows[1]} s)${errors.length ? ', errors: ' + errors.join(' | ') : ''}`);
} finally {
  await browser.close();
}
