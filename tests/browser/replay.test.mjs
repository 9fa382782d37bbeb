// The replay page (`asimov run --replay`) in a real browser: it opens, seeks, shows the contact
// at the run's end time (also as `?t=END` to the millisecond), frames the whole cell, hides its
// side panel, draws the tool path, survives hostile object names, and its screenshots are not
// blank (pixels checked). usage: node replay.test.mjs ASIMOV SOURCE_DIR SCRATCH_DIR
import { execFileSync } from 'node:child_process';
import { mkdirSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { GREEN, RED, YELLOW, check, launch, pixelStats, summary } from './browser.mjs';

const [asimov, source, scratch] = process.argv.slice(2);
mkdirSync(scratch, { recursive: true });

// Runs a program with --replay; returns the page's file URL.
function replay(name, program, args = [], expectExit = 0) {
  const html = join(scratch, `${name}.html`);
  let code = 0;
  try { execFileSync(asimov, ['run', program, ...args, '--replay', html], { stdio: 'ignore' }); } catch (e) { code = e.status; }
  check(code === expectExit, `${name}: asimov run exit ${code}, expected ${expectExit}`);
  return pathToFileURL(html).href;
}

const { context, close } = await launch();
const errors = [];
async function open(url, viewport = { width: 1280, height: 800 }) {
  const page = await context.newPage();
  await page.setViewportSize(viewport);
  page.on('pageerror', (e) => errors.push(`${url}: ${e.message}`));
  await page.goto(url);
  await page.waitForFunction(() => window.asimovReplay && window.asimovReplay.ready, null, { timeout: 60000 });
  await page.waitForTimeout(300);  // a few animation frames
  return page;
}
const state = (page) => page.evaluate(() => window.asimovReplay.state());

try {
  // crash.v2: the contact at the end, not before.
  const crashUrl = replay('crash', join(source, 'programs/demo/crash.v2'), [], 3);
  let page = await open(crashUrl);
  const end = await page.evaluate(() => window.asimovReplay.end);
  check(end > 1, `crash: end ${end}`);
  let s = await state(page);
  check(s.t === 0 && !s.contactShown, 'crash: opens at t = 0 without the contact');
  check(s.framed, 'crash: the first camera frames the whole cell');
  const start = await pixelStats(context, await page.screenshot(), { red: RED, yellow: YELLOW });
  check(start.nonBackground > 0.05 && start.colours > 20, `crash at 0: a blank screenshot (${JSON.stringify(start)})`);
  check(start.matched.red < 50, `crash at 0: ${start.matched.red} red pixels before the contact`);
  check((await page.evaluate(() => window.asimovReplay.seek(1e9))) === end, 'crash: seek past the end clamps to the end');
  await page.waitForTimeout(200);
  s = await state(page);
  check(s.atEnd && s.contactShown && /\*Collision\*/.test(s.hud), `crash: seek(end) shows the contact (${s.hud})`);
  const hit = await pixelStats(context, await page.screenshot({ path: join(scratch, 'crash-end.png') }), { red: RED, yellow: YELLOW });
  check(hit.matched.red > 500, `crash at end: ${hit.matched.red} red pixels`);
  check(hit.matched.yellow > 30, `crash at end: ${hit.matched.yellow} yellow pixels of the marker`);
  check((await page.evaluate(() => window.asimovReplay.seek(0.5))) === 0.5, 'crash: seek(0.5)');
  s = await state(page);
  check(!s.contactShown && s.frame > 0, 'crash: seek back hides the contact');
  check((await page.evaluate(() => window.asimovReplay.seek('nonsense'))) === 0.5, 'crash: a non-number seek keeps the time');
  await page.close();

  // ?t=END as printed to the millisecond (the run halted between two milliseconds).
  page = await open(`${crashUrl}?t=${end.toFixed(3)}`);
  s = await state(page);
  check(s.contactShown && /\*Collision\*/.test(s.hud), `crash ?t=${end.toFixed(3)}: the contact shown (end ${end})`);
  await page.close();
  page = await open(`${crashUrl}?t=${(end - 0.002).toFixed(3)}`);
  check(!(await state(page)).contactShown, 'crash: 2 ms before the end no contact');
  await page.close();

  // belt_pick at 800 x 600: the side panel starts hidden, the scene shows, the cell is framed
  // (the chute at the belt's end too); the panel comes back and hides again.
  const beltUrl = replay('belt_pick', join(source, 'programs/cells/belt_pick.v2'),
                         ['--cell', join(source, 'programs/cells/belt_cell.yaml')]);
  page = await open(beltUrl, { width: 800, height: 600 });
  s = await state(page);
  check(!s.panel && s.framed, `belt_pick 800x600: panel hidden ${!s.panel}, cell framed ${s.framed}`);
  // The arm waits for the barrier at the start: the HUD names the WAIT, not a bare step.
  check(/belt_pick, line 10: WAIT SIG\(1001\)/.test(s.hud) && !/\nstep \d/.test(s.hud), `belt_pick at 0: the waiting line named (${s.hud})`);
  const small = await pixelStats(context, await page.screenshot({ path: join(scratch, 'belt-800x600.png') }));
  check(small.nonBackground > 0.08, `belt_pick 800x600: the scene covers ${small.nonBackground}`);
  check(await page.evaluate(() => window.asimovReplay.panel(true)), 'belt_pick: the panel shows');
  check(await page.isVisible('#cell'), 'belt_pick: #cell visible');
  check(!(await page.evaluate(() => window.asimovReplay.panel(false))) && !(await page.isVisible('#cell')), 'belt_pick: the panel hides');
  await page.keyboard.press('h');
  check(await page.isVisible('#cell'), 'belt_pick: key h shows the panel');
  await page.close();
  page = await open(beltUrl, { width: 1400, height: 900 });
  check((await state(page)).panel, 'belt_pick 1400x900: the panel starts shown');
  await page.close();

  // draw_strokes: the tool path is drawn (green), all of it at the end; hidden with its button.
  const drawUrl = replay('draw_strokes', join(source, 'programs/demo/draw_strokes.v2'));
  page = await open(`${drawUrl}?t=1e9`);
  s = await state(page);
  check(s.path && s.tool && Math.abs(s.tool[2] - -330 - 30) < 1, `draw_strokes: ends 30 mm over the sheet (${s.tool})`);
  const drawn = await pixelStats(context, await page.screenshot({ path: join(scratch, 'draw-end.png') }), { green: GREEN });
  await page.keyboard.press('p');
  s = await state(page);
  await page.waitForTimeout(200);
  const hidden = await pixelStats(context, await page.screenshot(), { green: GREEN });
  check(!s.path && drawn.matched.green > 400 && hidden.matched.green < drawn.matched.green / 4,
        `draw_strokes: path pixels ${drawn.matched.green} shown, ${hidden.matched.green} hidden`);
  await page.close();

  // A cell object named like markup that would end or swallow the page's scripts.
  const cell = join(scratch, 'hostile_cell.yaml'), prog = join(scratch, 'hostile.v2');
  writeFileSync(cell, 'robot: puma560\nobjects:\n  - {name: "<!--<script>", box: [100, 100, 100], at: [700, 0, -300, 0, 0, 0]}\n' +
                      '  - {name: "</script><b>x", box: [100, 100, 100], at: [-700, 0, -300, 0, 0, 0]}\n');
  writeFileSync(prog, '.PROGRAM hostile()\n    MOVE #PPOINT(10, -90, 90, 0, 0, 0)\n.END\n');
  page = await open(replay('hostile', prog, ['--cell', cell]));
  const names = await page.evaluate(() => JSON.parse(document.getElementById('asimov-replay-data').textContent).bodies.map((b) => b.name));
  check(names.includes('<!--<script>') && names.includes('</script><b>x'), `hostile names: the page works and keeps them (${names})`);
  check((await page.$$('b')).length === 0, 'hostile names: no markup injected');
  await page.close();
} finally {
  await close();
}
check(errors.length === 0, `page errors: ${errors.join('; ')}`);
summary();
