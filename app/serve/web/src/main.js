// The studio page of `asimov serve` (docs/studio.md): the program in a CodeMirror editor with V+
// highlighting and `check`'s errors under their lines as you type, the monitor console, the cell
// in 3D (three.js) with the arm, runs played back with the tool path and the line being carried
// out, a contact marked with its report, files of the workspace, replay export; the program
// debugger: step, step into, run to a breakpoint, pause, abort, with the execution pointer, the
// breakpoints in the gutter, the arm moving live (frames streamed as each motion is simulated),
// the stopped program's variables (editable) and its tasks. Everything goes
// through one WebSocket (messages in app/serve/protocol.hpp); window.asimovStudio is the API the
// browser tests use.
import { EditorView, basicSetup } from 'codemirror';
import { EditorState, StateEffect, StateField, RangeSet, RangeSetBuilder } from '@codemirror/state';
import { Decoration, GutterMarker, WidgetType, gutter, keymap, lineNumbers } from '@codemirror/view';
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { HighlightStyle, syntaxHighlighting } from '@codemirror/language';
import { tags } from '@lezer/highlight';
import { vplus } from './vplus.js';
import { atEndTime, cellBounds, decodeReplay, fitDistance, frameAt, movingPose, partAt, toolAt } from '../../../replay/viewer.js';

// Colours readable on the dark editor.
const darkHighlight = HighlightStyle.define([
  { tag: tags.keyword, color: '#c792ea' }, { tag: tags.comment, color: '#7f8c98', fontStyle: 'italic' },
  { tag: tags.string, color: '#c3e88d' }, { tag: tags.number, color: '#f78c6c' }, { tag: tags.operator, color: '#89ddff' },
  { tag: [tags.atom, tags.function(tags.variableName)], color: '#82aaff' }, { tag: tags.special(tags.variableName), color: '#ffcb6b' },
  { tag: tags.variableName, color: '#e6e6e6' },
]);

const $ = (tag, attrs = {}, parent = null) => {
  const e = Object.assign(document.createElement(tag), attrs);
  if (parent) parent.appendChild(e);
  return e;
};

// --- layout --------------------------------------------------------------------------------------
$('style', { textContent: `
  html,body{margin:0;height:100%;background:#1d2026;color:#e6e6e6;font:13px/1.4 system-ui,sans-serif}
  #studio{display:grid;grid-template-rows:auto 1fr;grid-template-columns:minmax(320px,46%) 1fr;height:100vh}
  #bar{grid-column:1/3;display:flex;flex-wrap:wrap;gap:6px;align-items:center;padding:6px 8px;background:#111318;border-bottom:1px solid #333}
  #bar button,#bar select,#bar input{font:inherit;background:#2a2e37;color:#eee;border:1px solid #444;border-radius:3px;padding:2px 8px}
  #bar button:disabled{opacity:.45} #bar .sep{width:1px;height:20px;background:#444;margin:0 4px}
  #status{margin-left:auto;font-family:monospace;white-space:nowrap;overflow:hidden;text-overflow:ellipsis;max-width:40%}
  #left{display:flex;flex-direction:column;min-height:0;border-right:1px solid #333}
  #editor{flex:1;min-height:0;overflow:hidden} #editor .cm-editor{height:100%} #editor .cm-scroller{font-family:monospace}
  .cm-diag{font:12px monospace;white-space:pre-wrap;padding:1px 8px;border-left:3px solid #e05252;background:#3a1f24;color:#ffb4b4}
  .cm-diag.warning{border-color:#d8b04a;background:#3a3320;color:#ffe6a0}
  .cm-errorLine{background:#e0525222} .cm-pointerLine{background:#3a6df055 !important}
  .cm-breakpoints{width:14px;cursor:pointer} .cm-breakpoints .cm-gutterElement{color:#ff4545;padding:0 2px}
  .cm-lineNumbers .cm-gutterElement{cursor:pointer}
  #debug{position:absolute;right:8px;top:6px;width:300px;max-height:55%;overflow:auto;font:12px monospace;background:#000b;border-radius:4px;padding:4px 6px}
  #debug table{border-collapse:collapse;width:100%} #debug td{padding:0 4px;vertical-align:top} #debug h4{margin:2px 0;font-size:12px;color:#8ab}
  #debug input{width:100%;box-sizing:border-box;background:#15171b;color:#eee;border:1px solid #444;font:12px monospace}
  #console{height:32%;display:flex;flex-direction:column;border-top:1px solid #333;background:#15171b}
  #out{flex:1;overflow:auto;margin:0;padding:6px 8px;font:12px/1.35 monospace;white-space:pre-wrap}
  #cmd{display:flex;border-top:1px solid #333} #prompt{padding:4px 6px;font:12px monospace;color:#8ab}
  #cmdline{flex:1;background:#15171b;color:#eee;border:0;font:12px monospace;outline:none}
  #right{position:relative;min-height:0;overflow:hidden}
  #view{position:absolute;inset:0} #hud{position:absolute;left:8px;top:6px;font:12px/1.4 monospace;white-space:pre;pointer-events:none;text-shadow:0 0 3px #000}
  #report{position:absolute;left:8px;right:8px;bottom:8px;max-height:38%;overflow:auto;margin:0;padding:6px 8px;font:12px monospace;
    white-space:pre-wrap;background:#000b;border-radius:4px;border-left:3px solid #888}
  #report.collision{border-color:#ff3030} #report.error{border-color:#e0a030} #report.completed{border-color:#50c050}
  .hidden{display:none !important}` }, document.head);
const root = document.getElementById('studio');
const bar = $('div', { id: 'bar' }, root);
const files = $('select', { id: 'files', title: 'files of the workspace' }, bar);
const name = $('input', { id: 'name', size: 16, title: 'file name in the workspace', value: 'untitled.v2' }, bar);
const btn = (id, text, title) => $('button', { id, textContent: text, title }, bar);
const bOpen = btn('open', 'Open', 'open the file chosen on the left');
const bSave = btn('save', 'Save', 'save the editor into the workspace (Ctrl-S)');
$('span', { className: 'sep' }, bar);
const bRun = btn('run', 'Run', 'run the program to its end (Ctrl-Enter)');
const bAbort = btn('abort', 'Abort', 'stop the run or monitor command under way');
const bStep = btn('step', 'Step', 'execute one step; a CALL is one step (SSTEP); starts the program stopped at its first step');
const bInto = btn('stepin', 'Step into', 'execute one step; at a CALL stop at the CALLed program\'s first step (XSTEP)');
const bGo = btn('continue', 'Continue', 'run on to the next breakpoint or the end (PROCEED); click a line number to set a breakpoint');
const bPause = btn('pause', 'Pause', 'pause the program running under the debugger (Continue goes on)');
const bPlay = btn('play', 'Pause', 'pause or go on playing the last run back (Restart: from its start)');
const bRestart = btn('restart', 'Restart', 'play the last run back from its start');
const speed = $('select', { id: 'speed', title: 'playback speed' }, bar);
for (const [v, t] of [[0.25, 'x0.25'], [0.5, 'x0.5'], [1, 'x1'], [2, 'x2'], [4, 'x4'], [0, 'at once']])
  $('option', { value: v, textContent: t, selected: v === 1 }, speed);
const bReplay = btn('export', 'Export replay', 'write the last run as a replay page into the workspace');
const status = $('span', { id: 'status' }, bar);
const left = $('div', { id: 'left' }, root);
const editorBox = $('div', { id: 'editor' }, left);
const consoleBox = $('div', { id: 'console' }, left);
const out = $('pre', { id: 'out' }, consoleBox);
const cmd = $('div', { id: 'cmd' }, consoleBox);
const promptEl = $('span', { id: 'prompt', textContent: '.' }, cmd);
const cmdline = $('input', { id: 'cmdline', placeholder: 'monitor command (HELP lists them)', autocomplete: 'off', spellcheck: false }, cmd);
const right = $('div', { id: 'right' }, root);
const view3d = $('div', { id: 'view' }, right);
const hud = $('div', { id: 'hud' }, right);
const report = $('pre', { id: 'report', className: 'hidden' }, right);
const debugBox = $('div', { id: 'debug', className: 'hidden' }, right);

const setStatus = (text) => { status.textContent = text; status.title = text; };
const print = (text, cls) => {
  const s = $('span', { textContent: text.endsWith('\n') || !text ? text : text + '\n' }, out);
  if (cls) s.style.color = cls;
  out.scrollTop = out.scrollHeight;
};

// --- editor: diagnostics under their lines, the execution pointer --------------------------------
const setDiags = StateEffect.define(), setPointer = StateEffect.define();
class DiagWidget extends WidgetType {
  constructor(d) { super(); this.d = d; }
  eq(o) { return o.d.text === this.d.text; }
  toDOM() {
    const col = this.d.column > 0 ? `col ${this.d.column}: ` : '';
    return $('div', { className: `cm-diag${this.d.warning ? ' warning' : ''}`, textContent: `${col}${this.d.message}${this.d.detail ? '  ' + this.d.detail : ''}` });
  }
}
function diagDecorations(doc, diags) {
  const b = new RangeSetBuilder(), byLine = new Map();
  for (const d of diags) {
    const n = Math.min(Math.max(1, d.line || 1), doc.lines);
    if (!byLine.has(n)) byLine.set(n, []);
    byLine.get(n).push(d);
  }
  for (const n of [...byLine.keys()].sort((a, c) => a - c)) {
    const line = doc.line(n);
    b.add(line.from, line.from, Decoration.line({ class: 'cm-errorLine' }));
    for (const d of byLine.get(n)) b.add(line.to, line.to, Decoration.widget({ widget: new DiagWidget(d), block: true, side: 1 }));
  }
  return b.finish();
}
const diagField = StateField.define({
  create: () => Decoration.none,
  update(deco, tr) {
    deco = deco.map(tr.changes);
    for (const e of tr.effects) if (e.is(setDiags)) deco = diagDecorations(tr.state.doc, e.value);
    return deco;
  },
  provide: (f) => EditorView.decorations.from(f),
});
const pointerField = StateField.define({
  create: () => Decoration.none,
  update(deco, tr) {
    deco = deco.map(tr.changes);
    for (const e of tr.effects)
      if (e.is(setPointer)) {
        const n = e.value;
        deco = n > 0 && n <= tr.state.doc.lines ? Decoration.set([Decoration.line({ class: 'cm-pointerLine' }).range(tr.state.doc.line(n).from)]) : Decoration.none;
      }
    return deco;
  },
  provide: (f) => EditorView.decorations.from(f),
});
// Breakpoints: a gutter of red dots, toggled by a click on it or on the line number.
const toggleBreak = StateEffect.define({ map: (v, mapping) => ({ pos: mapping.mapPos(v.pos), on: v.on }) });
const breakMarker = new (class extends GutterMarker { toDOM() { return document.createTextNode('\u25cf'); } })();
const breakField = StateField.define({
  create: () => RangeSet.empty,
  update(set, tr) {
    set = set.map(tr.changes);
    for (const e of tr.effects)
      if (e.is(toggleBreak)) set = e.value.on ? set.update({ add: [breakMarker.range(e.value.pos)] }) : set.update({ filter: (from) => from !== e.value.pos });
    return set;
  },
});
function breakLines(state = editor.state) {
  const lines = [];
  for (let it = state.field(breakField).iter(); it.value; it.next()) lines.push(state.doc.lineAt(it.from).number);
  return [...new Set(lines)].sort((a, b) => a - b);
}
function setBreakpoint(line, on) {
  if (line < 1 || line > editor.state.doc.lines) return;
  const pos = editor.state.doc.line(line).from;
  if (breakLines().includes(line) === on) return;
  editor.dispatch({ effects: toggleBreak.of({ pos, on }) });
  if (stopped) debug('state');  // the stopped program takes it at once
}
const toggleAt = (view, block) => { const n = view.state.doc.lineAt(block.from).number; setBreakpoint(n, !breakLines().includes(n)); return true; };
const breakGutter = [breakField, gutter({
  class: 'cm-breakpoints', markers: (v) => v.state.field(breakField), initialSpacer: () => breakMarker,
  domEventHandlers: { mousedown: toggleAt },
}), lineNumbers({ domEventHandlers: { mousedown: toggleAt } })];
let checkTimer = 0;
const editor = new EditorView({
  parent: editorBox,
  state: EditorState.create({
    doc: '',
    extensions: [
      breakGutter, basicSetup, vplus, syntaxHighlighting(darkHighlight), diagField, pointerField, EditorView.theme({}, { dark: true }),
      keymap.of([{ key: 'Mod-s', run: () => { save(); return true; } }, { key: 'Mod-Enter', run: () => { run(); return true; } }]),
      EditorView.updateListener.of((u) => { if (u.docChanged) { clearTimeout(checkTimer); checkTimer = setTimeout(check, 250); } }),
    ],
  }),
});
const editorText = () => editor.state.doc.toString();
const setText = (text) => editor.dispatch({ changes: { from: 0, to: editor.state.doc.length, insert: text } });
let pointerLine = 0;
function showPointer(line) {
  if (line === pointerLine) return;
  pointerLine = line;
  editor.dispatch({ effects: setPointer.of(line) });
}

// --- connection ---------------------------------------------------------------------------------
const pending = new Map();
let nextId = 1, ws = null, lastDiagnostics = [], lastRun = null, lastMonitor = null, checks = 0;
let stopped = false, lastDebug = null, lastFrame = null, framesReceived = 0, debugging = false;
function send(msg) {
  const id = nextId++;
  ws.send(JSON.stringify({ ...msg, id }));
  return new Promise((resolve) => pending.set(id, resolve));
}
function connect() {
  const proto = location.protocol === 'https:' ? 'wss' : 'ws';
  ws = new WebSocket(`${proto}://${location.host}/ws?token=${encodeURIComponent(window.ASIMOV_TOKEN || '')}`);
  ws.onmessage = (ev) => {
    const m = JSON.parse(ev.data);
    if (m.type === 'hello') return hello(m);
    if (m.type === 'frame') return onFrame(m);
    if (m.type === 'error') {
      setStatus(`${m.message}  ${m.detail || ''}`);
      print(`${m.message}  ${m.detail || ''}`, '#ff9a9a');
    }
    const resolve = pending.get(m.id);
    if (resolve) { pending.delete(m.id); resolve(m); }
  };
  ws.onclose = () => setStatus('disconnected from asimov serve (reload the page)');
}

async function hello(m) {
  setStatus(`${m.robot} in ${m.cell}; workspace ${m.workspace}`);
  document.title = `asimov studio: ${m.robot}, ${m.cell}`;
  bReplay.disabled = !m.replay;
  name.value = m.file;
  setText(m.text);
  const scene = await send({ type: 'scene' });
  buildScene(decodeReplay(scene.replay));
  await listFiles();
  print('asimov studio: the monitor takes the same commands as `asimov monitor` (HELP lists them).', '#8ab');
  window.asimovStudio.ready = true;
}

async function check() {
  const m = await send({ type: 'check', text: editorText(), file: name.value });
  if (m.type !== 'check') return;
  lastDiagnostics = m.diagnostics;
  ++checks;
  editor.dispatch({ effects: setDiags.of(m.diagnostics) });
  const errors = m.diagnostics.filter((d) => !d.warning).length;
  setStatus(errors ? `${errors} error(s)` : 'no errors');
}

async function listFiles() {
  const m = await send({ type: 'list' });
  files.textContent = '';
  for (const f of m.files || []) $('option', { value: f, textContent: f }, files);
}
async function open() {
  if (!files.value) return;
  const m = await send({ type: 'open', file: files.value });
  if (m.type !== 'open') return;
  name.value = m.file;
  setText(m.text);
  setStatus(`opened ${m.file}`);
}
async function save() {
  const m = await send({ type: 'save', file: name.value, text: editorText() });
  if (m.type === 'save') { setStatus(`saved ${m.file} (${m.bytes} bytes)`); listFiles(); }
}
async function exportReplay() {
  const file = name.value.replace(/\.[^.]*$/, '') + '.html';
  const m = await send({ type: 'replay', file });
  if (m.type === 'replay') { setStatus(`replay page written: ${m.file}`); listFiles(); }
}

// --- 3D -----------------------------------------------------------------------------------------
const COLORS = { link: 0xd98c3a, tool: 0x8a8f98, object: 0x5b87b8 };
const renderer = new THREE.WebGLRenderer({ antialias: true });
renderer.setPixelRatio(window.devicePixelRatio);
view3d.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x20242a);
scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.8);
sun.position.set(1500, -1000, 3000);
scene.add(sun);
const camera = new THREE.PerspectiveCamera(45, 1, 1, 200000);
camera.up.set(0, 0, 1);
const controls = new OrbitControls(camera, renderer.domElement);
let bodies = [], moving = [], marker = null, path = null, framed = null, rep = null, cellGroup = null;
const PART_COLORS = { resting: 0x5fb760, on_conveyor: 0x3cc8d8, carried: 0xc27ae0, removed: 0x808080 };
const DEVICE_COLORS = { conveyor: 0xb0b8c0, sensor: 0xffd54a, sink: 0xff7060, feeder: 0x90d0ff };
const flatGeometry = (m) => {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(m.vertices, 3));
  g.setIndex(new THREE.BufferAttribute(m.triangles, 1));
  const flat = g.toNonIndexed();
  flat.computeVertexNormals();
  return flat;
};
const setPose = (o, p) => { o.position.set(p[0], p[1], p[2]); o.quaternion.set(p[3], p[4], p[5], p[6]); };

function buildScene(data) {
  for (const b of bodies) scene.remove(b.mesh);
  bodies = data.bodies.map((b) => {
    const mesh = new THREE.Mesh(flatGeometry(b), new THREE.MeshStandardMaterial({ color: COLORS[b.kind], roughness: 0.6, metalness: 0.1 }));
    if (b.pose) setPose(mesh, b.pose);
    scene.add(mesh);
    return { mesh, kind: b.kind, name: b.name };
  });
  moving = data.moving;
  data.moving.forEach((b, k) => setPose(bodies[b].mesh, movingPose(data, 0, k)));
  const box = cellBounds(data), lo = new THREE.Vector3(...box.min), hi = new THREE.Vector3(...box.max);
  framed = { centre: lo.clone().add(hi).multiplyScalar(0.5), radius: Math.max(1, hi.distanceTo(lo) / 2) };
  marker = new THREE.Mesh(new THREE.SphereGeometry(Math.max(10, framed.radius * 0.015), 24, 16),
                          new THREE.MeshBasicMaterial({ color: 0xffee00, depthTest: false, transparent: true, opacity: 0.9 }));
  marker.renderOrder = 1;
  marker.visible = false;
  scene.add(marker);
  frameCamera();
}
function frameCamera() {
  if (!framed) return;
  controls.target.copy(framed.centre);
  camera.position.copy(framed.centre).addScaledVector(new THREE.Vector3(1.2, -1.6, 0.9).normalize(),
                                                      fitDistance(framed.radius, camera.fov, camera.aspect) * 1.02);
  controls.update();
}
function resize() {
  const w = right.clientWidth, h = right.clientHeight;
  renderer.setSize(w, h);
  camera.aspect = w / Math.max(1, h);
  camera.updateProjectionMatrix();
}
new ResizeObserver(resize).observe(right);

// Poses the moving bodies (the arm, its tool) from world poses in `moving` order.
function poseMoving(poses) { moving.forEach((b, k) => setPose(bodies[b].mesh, poses[k])); }

// --- runs: played back on the simulated clock ---------------------------------------------------
let playT = 0, playing = false, lastNow = 0, frameCount = 0;
function setPlaying(on) { playing = on && !!rep; bPlay.textContent = playing ? 'Pause' : 'Play'; }
function showRun(m) {
  rep = decodeReplay(m.replay);
  if (path) { scene.remove(path); path = null; }
  if (rep.frames.tool) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(rep.frames.tool.length + 3), 3));
    path = new THREE.Line(g, new THREE.LineBasicMaterial({ color: 0x9fe870 }));
    path.frustumCulled = false;
    scene.add(path);
  }
  for (const b of bodies) b.mesh.material.color.setHex(COLORS[b.kind]);
  marker.visible = false;
  // A cell with parts or devices: the parts with their own shapes, the devices' boxes faintly.
  if (cellGroup) scene.remove(cellGroup);
  cellGroup = null;
  const W = rep.workcell;
  if (W) {
    cellGroup = new THREE.Group();
    const geometries = W.part_meshes.map(flatGeometry);
    cellGroup.userData.parts = W.parts.map((p) => {
      const m = new THREE.Mesh(geometries[p.mesh], new THREE.MeshStandardMaterial({ color: PART_COLORS.resting, roughness: 0.5 }));
      m.visible = false;
      cellGroup.add(m);
      return m;
    });
    for (const d of W.devices) {
      const box = new THREE.LineSegments(new THREE.EdgesGeometry(new THREE.BoxGeometry(...d.size)),
                                         new THREE.LineBasicMaterial({ color: DEVICE_COLORS[d.kind], transparent: true, opacity: 0.5 }));
      setPose(box, d.pose);
      cellGroup.add(box);
    }
    scene.add(cellGroup);
  }
  report.className = 'hidden';
  playT = 0;
  setPlaying(true);
  if (Number(speed.value) === 0) playT = rep.frames.time[rep.frames.count - 1];
}
function poseRun(t) {
  const F = rep.frames, end = F.time[F.count - 1], i = frameAt(F.time, t), j = Math.min(i + 1, F.count - 1);
  const u = j > i ? Math.min(1, Math.max(0, (t - F.time[i]) / (F.time[j] - F.time[i]))) : 0;
  const qa = new THREE.Quaternion(), qb = new THREE.Quaternion();
  rep.moving.forEach((b, k) => {
    const a = movingPose(rep, i, k), c = movingPose(rep, j, k), mesh = bodies[b].mesh;
    mesh.position.set(a[0] + (c[0] - a[0]) * u, a[1] + (c[1] - a[1]) * u, a[2] + (c[2] - a[2]) * u);
    qa.fromArray(a, 3); qb.fromArray(c, 3);
    mesh.quaternion.slerpQuaternions(qa, qb, u);
  });
  if (path) {
    const pos = path.geometry.attributes.position;
    pos.array.set(F.tool.subarray(0, 3 * (i + 1)));
    pos.array.set(toolAt(rep, t), 3 * (i + 1));
    pos.needsUpdate = true;
    path.geometry.setDrawRange(0, i + 2);
  }
  if (cellGroup) cellGroup.userData.parts.forEach((m, k) => {
    const p = partAt(rep, k, t);
    m.visible = p !== null && p.state !== 'removed';
    if (m.visible) { setPose(m, p.pose); m.material.color.setHex(PART_COLORS[p.state]); }
  });
  const line = rep.steps[String(F.step[i])];
  showPointer(line && line.program === rep.program ? line.line : line ? line.line : 0);
  const atEnd = atEndTime(t, end), hit = rep.collision;
  if (hit && atEnd) {
    marker.position.fromArray(hit.point_mm);
    marker.visible = true;
    for (const b of hit.body_index) if (b >= 0) bodies[b].mesh.material.color.setHex(0xff2020);
  }
  const joints = Array.from(F.joints.subarray(i * rep.joint_count, (i + 1) * rep.joint_count), (v) => v.toFixed(1));
  hud.textContent = `${rep.program}  t = ${(atEnd ? end : t).toFixed(3)} s / ${end.toFixed(3)} s\n` +
    (line ? `${line.program}, line ${line.line}: ${line.text}\n` : '\n') + `joints ${joints.join('  ')}`;
  if (atEnd) {
    setPlaying(false);
    report.textContent = `${lastRun.messages}${lastRun.output ? '\n' + lastRun.output : ''}`;
    report.className = lastRun.status === 'collision' ? 'collision' : lastRun.status === 'completed' ? 'completed' : 'error';
    if (hit) showPointer(lastRun.line);
  }
}
renderer.setAnimationLoop((now) => {
  const dt = lastNow ? (now - lastNow) / 1000 : 0;
  lastNow = now;
  ++frameCount;
  if (rep && playing) {
    const s = Number(speed.value), end = rep.frames.time[rep.frames.count - 1];
    playT = s === 0 ? end : Math.min(end, playT + dt * s);
    poseRun(playT);
  }
  controls.update();
  renderer.render(scene, camera);
});

async function run() {
  bRun.disabled = true;
  setStatus('running ...');
  const m = await send({ type: 'run', text: editorText(), file: name.value });
  bRun.disabled = false;
  if (m.type !== 'run') return;
  lastRun = m;
  if (m.diagnostics.length) editor.dispatch({ effects: setDiags.of(m.diagnostics) });
  if (m.status === 'error' && !m.replay) {
    setStatus('the program did not load');
    report.textContent = m.messages;
    report.className = 'error';
    return;
  }
  setStatus(`${m.status}: ${m.messages.split('\n')[0]}`);
  if (m.output) print(m.output);
  showRun(m);
}

async function monitor(line) {
  print(`${promptEl.textContent}${line}`, '#8ab');
  const m = await send({ type: 'monitor', line });
  if (m.type !== 'monitor') return;
  lastMonitor = m;
  if (m.output) print(m.output);
  promptEl.textContent = m.prompt;
  if (m.poses && moving.length) { setPlaying(false); poseMoving(m.poses); }
}
cmdline.addEventListener('keydown', (e) => {
  if (e.key !== 'Enter') return;
  const line = cmdline.value;
  cmdline.value = '';
  monitor(line);
});
bOpen.onclick = open;
bSave.onclick = save;
bRun.onclick = run;
// Abort: the run or command under way stops at once; a program stopped under the debugger ends.
bAbort.onclick = async () => {
  await send({ type: 'abort' });
  if (stopped || debugging) { await waitIdle(); await send({ type: 'debug', action: 'abort' }).then((m) => m.type === 'debug' && (showDebug(m), showPointer(0), print(m.output || ''))); }
};
const waitIdle = () => new Promise((resolve) => { const t = setInterval(() => { if (!debugging) { clearInterval(t); resolve(); } }, 20); });
bReplay.onclick = exportReplay;
// Playback of the last run (the run itself is computed whole: docs/studio.md).
bPlay.onclick = () => {
  if (!rep) return;
  if (!playing && atEndTime(playT, rep.frames.time[rep.frames.count - 1])) return bRestart.onclick();
  setPlaying(!playing);
};
bRestart.onclick = () => {
  if (!rep) return;
  for (const b of bodies) b.mesh.material.color.setHex(COLORS[b.kind]);
  marker.visible = false;
  report.className = 'hidden';
  playT = 0;
  setPlaying(true);
};

// --- the program debugger (docs/studio.md "Stepping") -------------------------------------------
// The arm's poses as the server simulates them: the arm is posed from each frame at once.
function onFrame(m) {
  ++framesReceived;
  lastFrame = m;
  if (!moving.length) return;
  setPlaying(false);
  poseMoving(m.poses);
  hud.textContent = `t = ${m.t.toFixed(3)} s  step ${m.step}\njoints ${m.joints.map((v) => v.toFixed(1)).join('  ')}`;
}
const esc = (t) => String(t).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' })[c]);
function showDebug(m) {
  stopped = m.stopped;
  debugBox.textContent = '';
  if (!m.stopped && !(m.tasks || []).length) { debugBox.className = 'hidden'; return; }
  debugBox.className = '';
  const p = m.place;
  $('h4', { textContent: p ? `${p.program}, step ${p.step}${p.text ? ':  ' + p.text : ''}` : `not stopped (${m.stop})` }, debugBox);
  $('h4', { textContent: 'Tasks' }, debugBox);
  const tasks = $('table', { id: 'tasks' }, debugBox);
  for (const t of m.tasks || []) {
    const tr = $('tr', {}, tasks);
    $('td', { textContent: String(t.number) }, tr); $('td', { textContent: t.program }, tr); $('td', { textContent: t.state }, tr);
  }
  $('h4', { textContent: `Variables${m.variables_omitted ? ` (${m.variables_omitted} more not shown)` : ''}` }, debugBox);
  const vars = $('table', { id: 'variables' }, debugBox);
  for (const v of m.variables || []) {
    const tr = $('tr', {}, vars);
    $('td', { textContent: v.name }, tr);
    const td = $('td', {}, tr);
    if (v.kind === 'real' || v.kind === 'string') {
      // Editable: Enter sends DO name = value to the monitor (it changes what the next step reads).
      const input = $('input', { value: v.value, title: 'Enter: DO ' + v.name + ' = value' }, td);
      input.dataset.name = v.name;
      input.addEventListener('keydown', (e) => { if (e.key === 'Enter') setVariable(v.name, input.value); });
    } else td.textContent = v.value;
  }
}
async function setVariable(variable, value) {
  await monitor(`DO ${variable} = ${value}`);
  await debug('state');
}
function debugButtons() {
  for (const b of [bStep, bInto, bGo, bRun]) b.disabled = debugging;
  bPause.disabled = !debugging;
}
async function debug(action) {
  if (debugging && action !== 'state') return null;
  if (action !== 'state') { debugging = true; debugButtons(); setStatus(`${action} ...`); }
  const m = await send({ type: 'debug', action, text: editorText(), file: name.value, breakpoints: breakLines(),
                         speed: Number(speed.value) });
  if (action !== 'state') { debugging = false; debugButtons(); }
  if (m.type !== 'debug') return m;
  lastDebug = m;
  if (m.diagnostics && m.diagnostics.length) editor.dispatch({ effects: setDiags.of(m.diagnostics) });
  if (m.output && action !== 'state') print(m.output);
  // Lines that hold no step cannot stop the program: their dots go.
  for (const line of m.refused || []) setBreakpoint(line, false);
  const p = m.place;
  showPointer(m.stopped && p && (!p.file || p.file === name.value) ? p.line : m.line && m.stop === 'collision' ? m.line : 0);
  if (m.poses && moving.length) { setPlaying(false); poseMoving(m.poses); }
  report.className = 'hidden';
  if (m.stop === 'collision' && m.report) { report.textContent = m.report; report.className = 'collision'; }
  showDebug(m);
  if (action !== 'state')
    setStatus(m.stopped && p ? `${m.stop === 'breakpoint' ? 'breakpoint' : m.stop === 'pause' ? 'paused' : 'stopped'} at ${p.program}, step ${p.step}`
              : `${m.stop}${m.output ? ': ' + m.output.trim().split('\n')[0] : ''}`);
  return m;
}
bStep.onclick = () => debug('step');
bInto.onclick = () => debug('into');
bGo.onclick = () => debug('go');
bPause.onclick = () => send({ type: 'pause' });
debugButtons();

// The API of the page (tests, embedding).
window.asimovStudio = {
  ready: false,
  setText, text: editorText, check, run, monitor, save, open, exportReplay,
  step: () => debug('step'), stepInto: () => debug('into'), go: () => debug('go'), pause: () => send({ type: 'pause' }),
  abort: () => bAbort.onclick(), debugState: () => debug('state'),
  setBreakpoint, breakpoints: () => breakLines(),
  setSpeed: (v) => { speed.value = String(v); },
  state: () => ({
    checks, diagnostics: lastDiagnostics, pointerLine, playing, t: playT, frames: frameCount,
    run: lastRun && { status: lastRun.status, line: lastRun.line, messages: lastRun.messages },
    monitor: lastMonitor && { output: lastMonitor.output, status: lastMonitor.status, joints: lastMonitor.joints },
    contactShown: !!(marker && marker.visible), report: report.className === 'hidden' ? '' : report.textContent,
    arm: moving.length ? bodies[moving[moving.length - 1]].mesh.position.toArray() : null,
    file: name.value,
    debug: lastDebug && { stopped: lastDebug.stopped, stop: lastDebug.stop, place: lastDebug.place, variables: lastDebug.variables,
                          tasks: lastDebug.tasks, breakpoints: lastDebug.breakpoints, output: lastDebug.output },
    debugging, framesReceived, frame: lastFrame && { t: lastFrame.t, step: lastFrame.step },
  }),
};
connect();
