// Shared by the browser tests: Debian's chromium (never a downloaded browser) driven by
// playwright-core, on a fresh profile, with the network features off (the machine may have no
// network); a tiny check/summary harness; pixel statistics of a screenshot.
import { existsSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

export const CHROMIUM = process.env.ASIMOV_CHROMIUM || '/usr/bin/chromium';

// Exit 77 (CTest: skipped) only where chromium is absent; a missing playwright-core is a failure
// (scripts/install-deps.sh installs it).
export async function launch() {
  if (!existsSync(CHROMIUM)) {
    console.log(`${CHROMIUM} not found: browser test skipped (scripts/install-deps.sh installs chromium)`);
    process.exit(77);
  }
  const { chromium } = await import('playwright-core');
  const profile = mkdtempSync(join(tmpdir(), 'asimov-chromium-'));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: CHROMIUM, headless: true, viewport: { width: 1280, height: 800 },
    bypassCSP: true,  // playwright's waitForFunction evaluates strings; the studio's CSP forbids that
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const close = async () => { await context.close(); rmSync(profile, { recursive: true, force: true }); };
  return { context, close };
}

let passed = 0, failed = 0;
export function check(ok, what) {
  if (ok) ++passed;
  else { ++failed; console.log(`FAILED: ${what}`); }
  return ok;
}
// The closing line CTest's log and CI read; exit 1 on any failure.
export function summary() {
  console.log(`${passed} passed, ${failed} failed`);
  process.exitCode = failed ? 1 : 0;
}

// Pixel statistics of a PNG, decoded by the browser itself on a blank page: how many pixels
// differ from the most common colour (the background), how many distinct colours (quantised),
// and how many match `classes` ({ name: (r, g, b) => bool }).
export async function pixelStats(context, png, classes = {}) {
  const page = await context.newPage();
  const source = Object.fromEntries(Object.entries(classes).map(([k, f]) => [k, f.toString()]));
  const stats = await page.evaluate(async ({ b64, source }) => {
    const img = new Image();
    img.src = `data:image/png;base64,${b64}`;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.width; c.height = img.height;
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    const count = new Map(), tests = Object.entries(source).map(([k, f]) => [k, eval(`(${f})`)]);
    const matched = Object.fromEntries(tests.map(([k]) => [k, 0]));
    for (let i = 0; i < d.length; i += 4) {
      const key = ((d[i] >> 3) << 10) | ((d[i + 1] >> 3) << 5) | (d[i + 2] >> 3);
      count.set(key, (count.get(key) || 0) + 1);
      for (const [k, f] of tests) if (f(d[i], d[i + 1], d[i + 2])) ++matched[k];
    }
    let top = 0;
    for (const n of count.values()) top = Math.max(top, n);
    const total = d.length / 4;
    return { width: c.width, height: c.height, total, colours: count.size, nonBackground: (total - top) / total, matched };
  }, { b64: png.toString('base64'), source });
  await page.close();
  return stats;
}

// Colour classes of the pages: the contact's red bodies, the contact marker's yellow, the tool
// path's green (lit shades vary, so these are ranges).
export const RED = (r, g, b) => r > 150 && g < 80 && b < 80;
export const YELLOW = (r, g, b) => r > 200 && g > 200 && b < 90;
export const GREEN = (r, g, b) => g > 170 && r > 110 && r < 200 && b < 150;
