// Opens an mbd viewer page in headless Chromium and reports the time from navigation until
// the viewer is ready and has drawn a frame (bench/viewer_export.sh): as a fresh browser's
// first page, and in a running browser (the figure a user sees; the first page of a fresh
// browser also pays for starting its GPU process). Usage: node viewer_open.mjs PAGE.html
import { resolve } from 'node:path';
import { createRequire } from 'node:module';

const require = createRequire(resolve('viewer/package.json'));
const puppeteer = require('puppeteer-core');
const page_file = resolve(process.argv[2]);
const browser = await puppeteer.launch({ executablePath: process.env.MBD_CHROMIUM || '/usr/bin/chromium', headless: true,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'] });
// Opens the page and returns the milliseconds from navigation until the viewer is ready and
// has drawn two frames.
async function open(page_url) {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 800 });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  const start = Date.now();
  await page.goto(page_url, { waitUntil: 'load', timeout: 120000 });
  await page.waitForFunction(() => window.mbdViewer !== undefined, { timeout: 120000 });
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  const ms = Date.now() - start;
  const range = await page.evaluate(() => window.mbdViewer.range());
  await page.close();
  if (errors.length) throw new Error(`${page_file}: ${errors.join(' | ')}`);
  return { ms, range };
}
try {
  // cold: the browser's first page, which also starts its GPU process (software WebGL here)
  const cold = await open('file://' + page_file);
  // in a running browser, as when a user opens the file: a page that has drawn with WebGL
  // (not the viewer: nothing of mbd's script is cached) opened first
  const warm = await browser.newPage();
  await warm.goto('data:text/html,<canvas id=c></canvas><script>const g=document.getElementById("c").getContext("webgl2");g.clearColor(1,0,0,1);g.clear(g.COLOR_BUFFER_BIT);</script>');
  await warm.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  await warm.close();
  const running = await open('file://' + page_file);
  console.log(`open .html in Chromium: ${(running.ms / 1000).toFixed(2)} s in a running browser, ` +
              `${(cold.ms / 1000).toFixed(2)} s as a fresh browser's first page (t = ${running.range[0]} .. ${running.range[1]} s)`);
} finally {
  await browser.close();
}
