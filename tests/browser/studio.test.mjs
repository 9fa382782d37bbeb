// The studio (`asimov serve`) in a real browser and on the wire: the token and Origin checks
// (403), the page on the embedded sample, a program typed with a check error shown under its
// line, a run played back with the pointer and the arm moving, a collision with its report and
// marker, the monitor console moving the arm, the debugger (three steps with the pointer and
// the arm moving, a breakpoint clicked in the gutter and run to, a variable seen and changed),
// files saved, opened and confined to the workspace, a replay page exported, a screenshot that
// is not blank.
// usage: node studio.test.mjs ASIMOV SOURCE_DIR SCRATCH_DIR
import { spawn } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync, rmSync } from 'node:fs';
import net from 'node:net';
import { join } from 'node:path';
import { RED, YELLOW, check, launch, pixelStats, summary } from './browser.mjs';

const [asimov, source, scratch] = process.argv.slice(2);
rmSync(scratch, { recursive: true, force: true });
const workspace = join(scratch, 'ws');
mkdirSync(workspace, { recursive: true });

// The server, its URL from its first line.
const server = spawn(asimov, ['serve', '--workspace', workspace], { stdio: ['ignore', 'pipe', 'inherit'] });
const url = await new Promise((resolve, reject) => {
  let text = '';
  server.stdout.on('data', (d) => { text += d; const m = text.match(/http:\/\/\S+/); if (m) resolve(m[0]); });
  server.on('exit', (code) => reject(new Error(`asimov serve exited ${code}`)));
  setTimeout(() => reject(new Error('no URL within 30 s')), 30000);
});
const { port, searchParams } = new URL(url), token = searchParams.get('token');
check(/^[0-9a-f]{32}$/.test(token) && url.startsWith('http://127.0.0.1:'), `a loopback URL with a 128-bit token: ${url}`);

// One raw HTTP exchange: the status code of the answer.
function rawStatus(request) {
  return new Promise((resolve) => {
    const s = net.connect(Number(port), '127.0.0.1', () => s.write(request));
    let text = '';
    s.on('data', (d) => { text += d; if (text.includes('\r\n')) { s.destroy(); resolve(Number(text.split(' ')[1])); } });
    s.on('error', () => resolve(0));
    setTimeout(() => { s.destroy(); resolve(-1); }, 5000);
  });
}
const upgrade = (target, origin) => `GET ${target} HTTP/1.1\r\nHost: 127.0.0.1:${port}\r\nConnection: Upgrade\r\nUpgrade: websocket\r\n` +
  `Sec-WebSocket-Version: 13\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n${origin ? `Origin: ${origin}\r\n` : ''}\r\n`;
const get = (target) => `GET ${target} HTTP/1.1\r\nHost: 127.0.0.1:${port}\r\n\r\n`;
check((await rawStatus(get('/'))) === 403, 'HTTP without the token: 403');
check((await rawStatus(get('/?token=0123'))) === 403, 'HTTP with a wrong token: 403');
check((await rawStatus(get(`/studio.js`))) === 403, 'the script without the token: 403');
check((await rawStatus(get(`/?token=${token}`))) === 200, 'HTTP with the token: 200');
check((await rawStatus(upgrade('/ws', `http://127.0.0.1:${port}`))) === 403, 'WebSocket without the token: 403');
check((await rawStatus(upgrade(`/ws?token=${token}`, 'http://evil.example'))) === 403, 'WebSocket from another origin: 403');
check((await rawStatus(upgrade(`/ws?token=${token}`, `http://127.0.0.1:${Number(port) + 1}`))) === 403, 'WebSocket from another port: 403');
check((await rawStatus(upgrade(`/ws?token=${token}`, null))) === 403, 'WebSocket without an Origin: 403');
check((await rawStatus(upgrade(`/ws?token=${token}`, `http://127.0.0.1:${port}`))) === 101, 'WebSocket from the page origin: 101');
check((await rawStatus('GARBAGE\r\n\r\n')) <= 400, 'a broken request: refused or closed');

const { context, close } = await launch();
const errors = [];
try {
  const page = await context.newPage();
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(url);
  await page.waitForFunction(() => window.asimovStudio && window.asimovStudio.ready, null, { timeout: 60000 });
  const st = () => page.evaluate(() => window.asimovStudio.state());
  check((await page.evaluate(() => window.asimovStudio.text())).includes('.PROGRAM pick_place()'), 'opens on the embedded sample');
  check(/puma560, built-in default cell/.test(await page.title()), `the title names the arm and cell: ${await page.title()}`);

  // Type a program with an error: the check's message appears under its line.
  await page.click('.cm-content');
  await page.keyboard.press('Control+a');
  await page.keyboard.press('Delete');
  // (the editor keeps the previous line's indentation and closes brackets as one types)
  await page.keyboard.type('.PROGRAM typed()\nMOVE #PPOINT(0, -90, 90, 0, 0, 0)\nSPEED 50 ALWAYS\nx = 1 +\n.END\n', { delay: 2 });
  // The check of the whole text (250 ms after the last key) puts its error under line 4.
  await page.waitForFunction(() => /\.END\n$/.test(window.asimovStudio.text()) &&
                             window.asimovStudio.state().diagnostics.some((d) => !d.warning && d.line === 4), null, { timeout: 20000 });
  await page.waitForSelector('.cm-diag', { timeout: 20000 });
  const diag = await page.textContent('.cm-diag');
  const under = await page.evaluate(() => {  // the message's block sits right below line 4's text
    const lines = [...document.querySelectorAll('.cm-line')], box = document.querySelector('.cm-diag').getBoundingClientRect();
    const l4 = lines.find((l) => l.textContent === 'x = 1 +').getBoundingClientRect();
    return box.top >= l4.bottom - 1 && box.top - l4.bottom < 5;
  });
  check(/\*Syntax error\*/.test(diag) && under, `a check error under the typed line: ${diag} (under ${under})`);
  // The error line fixed: the message goes.
  await page.evaluate(() => window.asimovStudio.setText('.PROGRAM typed()\n    MOVE #PPOINT(0, -90, 90, 0, 0, 0)\n.END\n'));
  await page.waitForFunction(() => window.asimovStudio.state().diagnostics.length === 0 && !document.querySelector('.cm-diag'), null, { timeout: 20000 });
  check(true, 'fixed: no message left');

  // Run the sample: played back, the pointer on motion lines, the arm moving; completed.
  await page.evaluate((t) => window.asimovStudio.setText(t), readFileSync(join(source, 'programs/demo/pick_place.v2'), 'utf8'));
  await page.evaluate(() => window.asimovStudio.setSpeed(4));
  const before = (await st()).arm;
  await page.click('#run');
  await page.waitForFunction(() => window.asimovStudio.state().playing, null, { timeout: 60000 });
  const pointers = new Set(), arms = new Set();
  for (let k = 0; k < 6; ++k) {
    await page.waitForTimeout(400);
    const s = await st();
    if (s.pointerLine) pointers.add(s.pointerLine);
    arms.add(s.arm.map((v) => v.toFixed(0)).join(','));
  }
  check(pointers.size >= 2 && [...pointers].every((l) => [14, 20, 21, 24, 25, 26, 29].includes(l)), `the pointer on motion lines: ${[...pointers]}`);
  check(arms.size >= 3 && !arms.has(before.map((v) => v.toFixed(0)).join(',')) || arms.size >= 4, `the arm moves: ${arms.size} poses`);
  await page.evaluate(() => window.asimovStudio.setSpeed(0));
  await page.waitForFunction(() => !window.asimovStudio.state().playing, null, { timeout: 60000 });
  let s = await st();
  check(s.run.status === 'completed' && /Program completed: pick_place/.test(s.report), `pick_place completed: ${s.report}`);
  // Playback: Restart plays it again from the start, Pause stops it where it is.
  await page.evaluate(() => window.asimovStudio.setSpeed(0.5));
  await page.click('#restart');
  await page.waitForTimeout(500);
  await page.click('#play');
  const paused = await st();
  await page.waitForTimeout(500);
  const later = await st();
  check(!paused.playing && paused.t > 0 && paused.t < 5 && later.t === paused.t && !paused.report &&
        (await page.textContent('#play')) === 'Play', `restart then pause: t ${paused.t} then ${later.t}`);

  // A collision: the report, the marker, the pointer at the line, red bodies in the picture.
  await page.evaluate((t) => window.asimovStudio.setText(t), readFileSync(join(source, 'programs/demo/crash.v2'), 'utf8'));
  await page.click('#run');
  await page.waitForFunction(() => window.asimovStudio.state().run && window.asimovStudio.state().run.status === 'collision' &&
                             window.asimovStudio.state().contactShown, null, { timeout: 60000 });
  s = await st();
  check(/\*Collision\*/.test(s.report) && s.pointerLine === s.run.line && s.run.line > 0, `the collision reported at line ${s.run.line}: ${s.report.split('\n')[0]}`);
  await page.waitForTimeout(300);
  const shot = await pixelStats(context, await page.screenshot({ path: join(scratch, 'studio-crash.png') }), { red: RED, yellow: YELLOW });
  check(shot.nonBackground > 0.2 && shot.colours > 30, `the studio screenshot is not blank: ${JSON.stringify(shot)}`);
  check(shot.matched.red > 300, `the contact bodies red: ${shot.matched.red} pixels`);

  // The monitor console: HELP, a DO MOVE that moves the arm, WHERE.
  const armBefore = (await st()).arm;
  await page.fill('#cmdline', 'DO MOVE #PPOINT(40, -60, 120, 0, 30, 0)');
  await page.press('#cmdline', 'Enter');
  await page.waitForFunction(() => window.asimovStudio.state().monitor, null, { timeout: 30000 });
  await page.fill('#cmdline', 'WHERE');
  await page.press('#cmdline', 'Enter');
  await page.waitForFunction(() => /J1/.test(window.asimovStudio.state().monitor.output), null, { timeout: 30000 });
  s = await st();
  check(/40\.000/.test(s.monitor.output) && s.arm.join() !== armBefore.join(), `the monitor moved the arm: ${s.monitor.output}`);

  // The debugger: a typed program stepped three times (the pointer and the arm move, live
  // frames arrive), a breakpoint set by a click on a line number and run to, a variable's value
  // seen and changed in the watch list, the program continued to its end.
  const debugStart = Date.now();
  await page.click('.cm-content');
  await page.keyboard.press('Control+a');
  await page.keyboard.press('Delete');
  await page.keyboard.type('.PROGRAM walk()\nx = 5\nMOVE #PPOINT(20, -80, 100, 0, 10, 0)\nMOVE #PPOINT(40, -70, 110, 0, 30, 0)\n' +
                           'x = x + 2\nMOVE #PPOINT(-20, -90, 90, 0, 0, 0)\nTYPE "x is ", x\n.END\n', { delay: 1 });
  await page.waitForFunction(() => /\.END\n$/.test(window.asimovStudio.text()), null, { timeout: 20000 });
  await page.evaluate(() => window.asimovStudio.setSpeed(4));
  const stepped = [];
  for (let k = 0; k < 3; ++k) {
    const before = await st();
    await page.click('#step');
    await page.waitForFunction((n) => { const s = window.asimovStudio.state(); return !s.debugging && s.debug && s.debug.place && s.pointerLine === s.debug.place.line && s.framesReceived >= n; },
                               before.framesReceived, { timeout: 30000 });
    const after = await st();
    stepped.push({ line: after.pointerLine, armMoved: after.arm.join() !== before.arm.join(), frames: after.framesReceived - before.framesReceived });
  }
  check(stepped.map((x) => x.line).join() === '2,3,4', `three steps: the pointer at lines ${stepped.map((x) => x.line)}`);
  check(stepped[2].armMoved && stepped[2].frames > 1, `the stepped MOVE moved the arm live: ${stepped[2].frames} frames`);
  const lineNumber = page.locator('.cm-lineNumbers .cm-gutterElement', { hasText: /^6$/ });
  await lineNumber.click();
  const dots = await page.evaluate(() => [...document.querySelectorAll('.cm-breakpoints .cm-gutterElement')]
    .filter((e) => e.textContent === '\u25cf' && getComputedStyle(e).visibility !== 'hidden').length);
  check((await page.evaluate(() => window.asimovStudio.breakpoints())).join() === '6' && dots === 1, `a breakpoint set by a click on line 6: ${dots} dot(s)`);
  await page.click('#continue');
  await page.waitForFunction(() => { const s = window.asimovStudio.state(); return !s.debugging && s.debug && s.debug.stop === 'breakpoint'; }, null, { timeout: 30000 });
  s = await st();
  check(s.pointerLine === 6 && s.debug.place.line === 6, `run to the breakpoint: stopped at line ${s.pointerLine}`);
  const x = page.locator('#variables input[data-name="x"]');
  check((await x.inputValue()) === '7', `the watch list shows x = ${await x.inputValue()}`);
  check(/walk/.test(await page.textContent('#tasks')), `the task list: ${await page.textContent('#tasks')}`);
  const dbgShot = await pixelStats(context, await page.screenshot({ path: join(scratch, 'studio-debug.png') }), {});
  check(dbgShot.nonBackground > 0.2 && dbgShot.colours > 30, `the stopped studio's screenshot is not blank: ${JSON.stringify(dbgShot)}`);
  await x.fill('10');
  await x.press('Enter');
  await page.waitForFunction(() => { const v = (window.asimovStudio.state().debug.variables || []).find((e) => e.name === 'x'); return v && v.value === '10'; }, null, { timeout: 20000 });
  await page.click('#continue');
  await page.waitForFunction(() => { const s = window.asimovStudio.state(); return !s.debugging && s.debug.stop === 'completed'; }, null, { timeout: 30000 });
  s = await st();
  check(/x is 10/.test(s.debug.output) && s.pointerLine === 0, `continued to the end with the changed value: ${s.debug.output.trim()}`);
  await page.evaluate((t) => window.asimovStudio.setText(t), readFileSync(join(source, 'programs/demo/crash.v2'), 'utf8'));
  console.log(`# the debugger part took ${((Date.now() - debugStart) / 1000).toFixed(1)} s`);

  // Files: save into the workspace, confinement, open, export a replay.
  const api = (fn, ...a) => page.evaluate(([f, args]) => window.asimovStudio[f](...args), [fn, a]);
  await page.fill('#name', 'crash_copy.v2');
  await page.click('#save');
  await page.waitForFunction(() => /saved crash_copy\.v2/.test(document.getElementById('status').textContent), null, { timeout: 20000 });
  check(readFileSync(join(workspace, 'crash_copy.v2'), 'utf8').includes('.PROGRAM crash'), 'saved into the workspace');
  await page.fill('#name', '../outside.v2');
  await page.click('#save');
  await page.waitForFunction(() => /Illegal file name|outside|leaves/.test(document.getElementById('status').textContent), null, { timeout: 20000 });
  check(!existsSync(join(scratch, 'outside.v2')), 'a name outside the workspace is refused');
  await page.fill('#cmdline', 'LOAD /etc/passwd');
  await page.press('#cmdline', 'Enter');
  await page.waitForFunction(() => /LOAD|Illegal file name/.test(window.asimovStudio.state().monitor.output), null, { timeout: 20000 });
  check(/\*Illegal file name\*/.test((await st()).monitor.output), 'the monitor cannot LOAD outside the workspace');
  await page.fill('#name', 'crash_copy.v2');
  await page.click('#export');
  await page.waitForFunction(() => /replay page written/.test(document.getElementById('status').textContent), null, { timeout: 60000 });
  check(readFileSync(join(workspace, 'crash_copy.html'), 'utf8').includes('asimov-replay-data'), 'a replay page exported into the workspace');
  await api('setText', '');
  await page.selectOption('#files', 'crash_copy.v2');
  await page.click('#open');
  await page.waitForFunction(() => window.asimovStudio.text().includes('.PROGRAM crash'), null, { timeout: 20000 });
  check(true, 'opened from the workspace');

  // A hostile client: garbage, deep nesting, binary, a huge message; the server and this page live on.
  const hostile = await page.evaluate(async ([tok]) => {
    const ws = new WebSocket(`ws://${location.host}/ws?token=${tok}`);
    const answers = [];
    ws.onmessage = (e) => answers.push(JSON.parse(e.data));
    await new Promise((r) => { ws.onopen = r; });
    ws.send('not json');
    ws.send('['.repeat(100000));
    ws.send(JSON.stringify({ type: 'monitor', line: 'x'.repeat(5000) }));
    ws.send(new Uint8Array([1, 2, 3]));
    ws.send(JSON.stringify({ type: 'open', file: '../../etc/passwd' }));
    for (let k = 0; k < 100 && answers.length < 5; ++k) await new Promise((r) => setTimeout(r, 100));
    const closed = new Promise((r) => { ws.onclose = r; });
    ws.send('x'.repeat(2 << 20));  // over the message limit: this connection closes
    await closed;
    return answers.map((a) => `${a.type} ${a.message || ''}`);
  }, [token]);
  check(hostile.filter((a) => a.startsWith('error')).length === 5, `hostile messages answered with errors: ${hostile.join('; ')}`);
  const m = await page.evaluate(() => window.asimovStudio.monitor('HELP').then(() => window.asimovStudio.state().monitor.output));
  check(/EXECUTE/.test(m), 'the first session still works after a hostile one');
  await page.close();
} finally {
  await close();
  server.kill('SIGTERM');
}
const code = await new Promise((r) => { if (server.exitCode !== null) r(server.exitCode); else server.on('exit', r); });
check(code === 0, `asimov serve stopped by SIGTERM with exit ${code}`);
check(errors.length === 0, `page errors: ${errors.join('; ')}`);
summary();
