// asimov replay viewer: inlined by `asimov run --replay` into one HTML page next to the run's
// data (<script id="asimov-replay-data">, format in app/README.md) and three.js (import map).
// The decode functions are exported and touch neither the DOM nor WebGL, so node can check a
// page's data with the same code the browser runs (tests/app/replay_decode.mjs).

// --- data --------------------------------------------------------------------------------------

// Base64 to bytes, in a buffer of its own (typed views need an aligned offset).
export function decodeBytes(b64) {
  if (typeof atob === 'function') {
    const s = atob(b64);
    const out = new Uint8Array(s.length);
    for (let i = 0; i < s.length; ++i) out[i] = s.charCodeAt(i);
    return out;
  }
  return new Uint8Array(Buffer.from(b64, 'base64'));  // node without atob
}
export const decodeFloat32 = (b64) => new Float32Array(decodeBytes(b64).buffer);
export const decodeFloat64 = (b64) => new Float64Array(decodeBytes(b64).buffer);
export const decodeUint32 = (b64) => new Uint32Array(decodeBytes(b64).buffer);
export const decodeInt32 = (b64) => new Int32Array(decodeBytes(b64).buffer);

// The page's JSON with every base64 array decoded.
export function decodeReplay(data) {
  const f = data.frames;
  return {
    ...data,
    bodies: data.bodies.map((b) => ({ ...b, vertices: decodeFloat32(b.vertices), triangles: decodeUint32(b.triangles) })),
    frames: {
      count: f.count,
      time: decodeFloat64(f.time_s),
      step: decodeInt32(f.step),
      checked: decodeBytes(f.checked),
      joints: decodeFloat32(f.joints_deg),
      poses: decodeFloat32(f.poses),
      carried: f.carried ? decodeFloat32(f.carried) : null,
      tool: f.tool_mm ? decodeFloat32(f.tool_mm) : null,
    },
    workcell: data.workcell ? decodeWorkcell(data.workcell) : null,
  };
}

// A cell with parts or devices: part meshes and segments decoded, and per part the range of its
// segments (they come grouped by part, each part's in time order).
function decodeWorkcell(w) {
  const s = w.segments;
  const seg = {
    count: s.count, part: decodeInt32(s.part), time: decodeFloat64(s.time_s), state: decodeBytes(s.state),
    pose: decodeFloat64(s.pose), velocity: decodeFloat64(s.velocity), end: decodeFloat64(s.end_s),
  };
  const first = new Int32Array(w.parts.length).fill(-1), last = new Int32Array(w.parts.length).fill(-1);
  for (let i = 0; i < seg.count; ++i) {
    const k = seg.part[i];
    if (first[k] < 0) first[k] = i;
    last[k] = i;
  }
  return {
    ...w,
    part_meshes: w.part_meshes.map((m) => ({ ...m, vertices: decodeFloat32(m.vertices), triangles: decodeUint32(m.triangles) })),
    segments: seg, first, last,
  };
}

// Part k at simulated time t: null before it is fed, else { state, pose } with state one of
// workcell.states (resting, on_conveyor, carried, removed) and pose [x, y, z, qx, qy, qz, qw]
// (world): a belt carries it at its segment's velocity up to the end stop; a carried part is
// where the frames put it (interpolated between the two frames around t).
export function partAt(rep, k, t) {
  const w = rep.workcell, S = w.segments;
  if (w.first[k] < 0 || S.time[w.first[k]] > t) return null;
  let i = w.first[k];
  while (i < w.last[k] && S.time[i + 1] <= t) ++i;
  const state = w.states[S.state[i]];
  if (state === 'carried') return { state, pose: carriedAt(rep, t) };
  const p = Array.from(S.pose.subarray(7 * i, 7 * i + 7)), dt = Math.min(t, S.end[i]) - S.time[i];
  for (let c = 0; c < 3; ++c) if (S.velocity[3 * i + c] !== 0) p[c] += S.velocity[3 * i + c] * dt;
  return { state, pose: p };
}

// The carried part's pose at t from the frames (a frame without one, zeros, is not used).
function carriedAt(rep, t) {
  const F = rep.frames, C = F.carried, i = frameAt(F.time, t), j = Math.min(i + 1, F.count - 1);
  const at = (n) => Array.from(C.subarray(7 * n, 7 * n + 7));
  const a = at(i), b = at(j), held = (p) => p[6] !== 0 || p[3] !== 0 || p[4] !== 0 || p[5] !== 0;
  if (!held(a) || j === i || F.time[j] <= F.time[i]) return held(a) ? a : b;
  if (!held(b)) return a;
  const u = Math.min(1, Math.max(0, (t - F.time[i]) / (F.time[j] - F.time[i])));
  return lerpPose(a, b, u);
}

// Position linear, rotation normalised lerp (the short way): frames are 1/30 s apart.
export function lerpPose(a, b, u) {
  if (u === 0) return a.slice();
  const dot = a[3] * b[3] + a[4] * b[4] + a[5] * b[5] + a[6] * b[6], sign = dot < 0 ? -1 : 1;
  const out = a.map((v, c) => (c < 3 ? v + (b[c] - v) * u : v + (sign * b[c] - v) * u));
  const n = Math.hypot(out[3], out[4], out[5], out[6]);
  for (let c = 3; c < 7; ++c) out[c] /= n;
  return out;
}

// The signals the run touched (every signal with a change among the events), ascending, and
// those on at time t: the events' signal changes up to t folded from all off.
export function signalsAt(rep, t) {
  const touched = new Set(), on = new Set();
  for (const e of rep.workcell ? rep.workcell.events : []) {
    if (e.kind !== 'signal') continue;
    const k = Number(e.subject);
    touched.add(k);
    if (e.time_s <= t) { if (e.detail === 'on') on.add(k); else on.delete(k); }
  }
  return { touched: [...touched].sort((a, b) => a - b), on };
}

// Index of the last event at or before t (-1: none yet).
export function eventAt(rep, t) {
  const ev = rep.workcell ? rep.workcell.events : [];
  let i = -1;
  while (i + 1 < ev.length && ev[i + 1].time_s <= t) ++i;
  return i;
}

// V+ signal numbering: outputs 1.., inputs 1001.., soft signals 2001...
export const signalKind = (k) => (k >= 2001 ? 'soft' : k >= 1001 ? 'input' : 'output');

// Index of the last frame at or before simulated time t (0 before the first).
export function frameAt(time, t) {
  let lo = 0, hi = time.length - 1;
  if (t >= time[hi]) return hi;
  while (hi - lo > 1) {
    const mid = (lo + hi) >> 1;
    if (time[mid] <= t) lo = mid; else hi = mid;
  }
  return lo;
}

// World pose [x, y, z, qx, qy, qz, qw] of the k-th moving body at frame i.
export function movingPose(rep, i, k) {
  const m = rep.moving.length, at = (i * m + k) * 7;
  return Array.from(rep.frames.poses.subarray(at, at + 7));
}

// A point of a body's mesh (local frame) in the world at `pose`: q v q* + p.
export function transformPoint(pose, v) {
  const [px, py, pz, x, y, z, w] = pose;
  const tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]), tz = 2 * (x * v[1] - y * v[0]);
  return [v[0] + w * tx + (y * tz - z * ty) + px, v[1] + w * ty + (z * tx - x * tz) + py,
          v[2] + w * tz + (x * ty - y * tx) + pz];
}

// The closest approach of the run (the report's clearance "closest"), as the page marks it: the
// frame shown at its instant, the slider position (0..10000) and the midpoint of its witness
// segment. null when no pair came within report_within_mm.
export function closestMark(rep) {
  const c = rep.closest;
  if (!c) return null;
  const F = rep.frames, end = F.time[F.count - 1];
  const mid = [0, 1, 2].map((i) => (c.point_a_mm[i] + c.point_b_mm[i]) / 2);
  return { frame: frameAt(F.time, c.time_s), slider: end > 0 ? Math.round((Math.min(c.time_s, end) / end) * 10000) : 0, mid };
}

// The page shows times to the millisecond: a time that reads as the end time (within half a
// millisecond of it) is the end, where a run that hit something shows the contact. `?t=3.379`
// of a run that halted at 3.37936 s therefore shows the red bodies and the marker.
export const END_TOLERANCE_S = 0.0005;
export const atEndTime = (t, end) => t >= end - END_TOLERANCE_S - 1e-12;

// The tool point at time t (world, mm): the frames' tool path interpolated; null without one.
export function toolAt(rep, t) {
  const F = rep.frames, P = F.tool;
  if (!P) return null;
  const i = frameAt(F.time, t), j = Math.min(i + 1, F.count - 1);
  const u = j > i ? Math.min(1, Math.max(0, (t - F.time[i]) / (F.time[j] - F.time[i]))) : 0;
  return [0, 1, 2].map((c) => P[3 * i + c] + (P[3 * j + c] - P[3 * i + c]) * u);
}

// The box { min, max } (world, mm) that holds the whole cell over the run: the bodies that never
// move, the moving ones at `samples` frames spread over the run (and the first and last), the
// tool path, the devices' regions and every place a part rests or starts on a belt. The first
// camera frames it, so nothing of the cell starts outside the view (the sink at a cell's edge).
export function cellBounds(rep, samples = 24) {
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
  const add = (p) => { for (let c = 0; c < 3; ++c) { if (p[c] < min[c]) min[c] = p[c]; if (p[c] > max[c]) max[c] = p[c]; } };
  const addMesh = (m, pose) => { for (let v = 0; v < m.vertices.length; v += 3) add(transformPoint(pose, m.vertices.subarray(v, v + 3))); };
  const F = rep.frames;
  rep.bodies.forEach((b) => { if (b.pose) addMesh(b, b.pose); });
  const frames = new Set([0, F.count - 1]);
  for (let k = 1; k < samples; ++k) frames.add(Math.round((k * (F.count - 1)) / samples));
  for (const i of frames) rep.moving.forEach((b, k) => addMesh(rep.bodies[b], movingPose(rep, i, k)));
  if (F.tool) for (let i = 0; i < F.count; ++i) add(F.tool.subarray(3 * i, 3 * i + 3));
  const W = rep.workcell;
  if (W) {
    for (const d of W.devices)
      for (const sx of [-1, 1]) for (const sy of [-1, 1]) for (const sz of [-1, 1])
        add(transformPoint(d.pose, [(sx * d.size[0]) / 2, (sy * d.size[1]) / 2, (sz * d.size[2]) / 2]));
    const S = W.segments;
    for (let i = 0; i < S.count; ++i)
      if (W.states[S.state[i]] !== 'carried') addMesh(W.part_meshes[W.parts[S.part[i]].mesh], Array.from(S.pose.subarray(7 * i, 7 * i + 7)));
  }
  if (min[0] > max[0]) return { min: [-500, -500, -500], max: [500, 500, 500] };  // nothing at all
  return { min, max };
}

// The camera distance that shows a sphere of `radius` whole with a vertical field of view of
// `fovDeg` on a view `aspect` (width / height) wide: the narrower of the two angles decides.
export function fitDistance(radius, fovDeg, aspect) {
  const v = (fovDeg * Math.PI) / 360, h = Math.atan(Math.tan(v) * aspect);
  return radius / Math.sin(Math.min(v, h));
}

// --- page --------------------------------------------------------------------------------------

const COLORS = { link: 0xd98c3a, tool: 0x8a8f98, object: 0x5b87b8 };
const PART_COLORS = { resting: 0x5fb760, on_conveyor: 0x3cc8d8, carried: 0xc27ae0, removed: 0x808080 };
const DEVICE_COLORS = { conveyor: 0xb0b8c0, sensor: 0xffd54a, sink: 0xff7060, feeder: 0x90d0ff };
const SPEEDS = [0.25, 0.5, 1, 2, 4];

function el(tag, attrs, parent) {
  const e = Object.assign(document.createElement(tag), attrs);
  if (parent) parent.appendChild(e);
  return e;
}

async function main() {
  const THREE = await import('three');
  const { OrbitControls } = await import('three/addons/controls/OrbitControls.js');
  const rep = decodeReplay(JSON.parse(document.getElementById('asimov-replay-data').textContent));
  const F = rep.frames, end = F.time[F.count - 1];

  document.title = `asimov replay: ${rep.file}`;
  el('style', { textContent: `body{margin:0;overflow:hidden;font:13px/1.4 monospace;background:#20242a;color:#e8e8e8}
    #hud{position:absolute;top:8px;left:10px;white-space:pre;pointer-events:none;text-shadow:0 0 3px #000}
    #bar{position:absolute;bottom:0;left:0;right:0;display:flex;gap:8px;align-items:center;padding:8px;background:#000a}
    #bar input[type=range]{flex:1} button,select{font:inherit}
    #cell{position:absolute;top:8px;right:10px;bottom:52px;width:min(330px,45vw);display:flex;flex-direction:column;gap:6px;
      background:#0008;padding:6px 8px;border-radius:4px;font-size:12px;color-scheme:dark}
    #cell h3{margin:0;font-size:12px;color:#aab}
    #sig div{white-space:pre} #sig .on{color:#7dff7d} #sig .off{color:#889}
    #ev{overflow-y:auto;overflow-x:hidden;flex:1;white-space:pre} #ev div{text-overflow:ellipsis;overflow:hidden} #ev div{cursor:pointer;padding:0 2px} #ev div:hover{background:#fff2}
    #ev .future{color:#778} #ev .now{background:#4a6cff66;color:#fff} .hidden{display:none !important}` }, document.head);
  const hud = el('div', { id: 'hud' }, document.body);
  const bar = el('div', { id: 'bar' }, document.body);
  const play = el('button', { textContent: 'play', title: 'space' }, bar);
  const slider = el('input', { type: 'range', min: 0, max: 10000, value: 0, step: 1 }, bar);
  const near = closestMark(rep);
  if (near) {  // a tick on the slider and a button to go there
    const ticks = el('datalist', { id: 'asimov-ticks' }, bar);
    el('option', { value: near.slider }, ticks);
    slider.setAttribute('list', 'asimov-ticks');
    const go = el('button', { textContent: 'closest', title: 'go to the closest approach' }, bar);
    go.onclick = () => { t = rep.closest.time_s; slider.value = near.slider; setPlaying(false); };
  }
  const speed = el('select', {}, bar);
  for (const s of SPEEDS) el('option', { value: s, textContent: `x${s}`, selected: s === 1 }, speed);
  const pathButton = el('button', { textContent: 'path', title: 'show or hide the tool path (key p)' }, bar);

  const renderer = new THREE.WebGLRenderer({ antialias: true });
  renderer.setPixelRatio(window.devicePixelRatio);
  document.body.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0x20242a);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 1.6));
  const sun = new THREE.DirectionalLight(0xffffff, 1.8);
  sun.position.set(1500, -1000, 3000);
  scene.add(sun);

  // A decoded mesh (vertices, triangles) as a geometry; flat normals suit the boxes and
  // cylinders of a cell.
  function flatGeometry(m) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(m.vertices, 3));
    g.setIndex(new THREE.BufferAttribute(m.triangles, 1));
    const flat = g.toNonIndexed();
    flat.computeVertexNormals();
    return flat;
  }
  // One mesh per body.
  const meshes = rep.bodies.map((b) => {
    const mat = new THREE.MeshStandardMaterial({ color: COLORS[b.kind], roughness: 0.6, metalness: 0.1 });
    const mesh = new THREE.Mesh(flatGeometry(b), mat);
    if (b.pose) setPose(mesh, b.pose);
    scene.add(mesh);
    return mesh;
  });
  function setPose(obj, p) {
    obj.position.set(p[0], p[1], p[2]);
    obj.quaternion.set(p[3], p[4], p[5], p[6]);
  }

  const hit = rep.collision;
  let marker = null;
  if (hit) {
    // Drawn over everything: the point lies on both surfaces, so half of it is inside a body.
    marker = new THREE.Mesh(new THREE.SphereGeometry(10, 24, 16),
                            new THREE.MeshBasicMaterial({ color: 0xffee00, depthTest: false, transparent: true, opacity: 0.9 }));
    marker.renderOrder = 1;
    marker.position.fromArray(hit.point_mm);
    marker.visible = false;
    scene.add(marker);
  }

  // The closest approach: its witness segment (and its two ends), shown at its instant.
  let witness = null;
  if (near) {
    const c = rep.closest, mat = new THREE.MeshBasicMaterial({ color: 0x30e0ff, depthTest: false });
    witness = new THREE.Group();
    for (const p of [c.point_a_mm, c.point_b_mm]) {
      const dot = new THREE.Mesh(new THREE.SphereGeometry(4, 16, 12), mat);
      dot.position.fromArray(p);
      witness.add(dot);
    }
    const g = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(...c.point_a_mm), new THREE.Vector3(...c.point_b_mm)]);
    witness.add(new THREE.Line(g, new THREE.LineBasicMaterial({ color: 0x30e0ff, depthTest: false })));
    witness.renderOrder = 2;
    witness.visible = false;
    scene.add(witness);
  }

  // The tool point's path: the whole run faintly, the part already travelled brightly (its
  // blended corners and a drawing program's strokes show as the tool went).
  let pathAll = null, pathDone = null;
  if (F.tool) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(F.tool, 3));
    pathAll = new THREE.Line(g, new THREE.LineBasicMaterial({ color: 0x9fe870, transparent: true, opacity: 0.22 }));
    const done = new THREE.BufferGeometry();
    done.setAttribute('position', new THREE.BufferAttribute(new Float32Array(F.tool.length + 3), 3));
    pathDone = new THREE.Line(done, new THREE.LineBasicMaterial({ color: 0x9fe870 }));
    pathDone.frustumCulled = pathAll.frustumCulled = false;
    scene.add(pathAll, pathDone);
  }
  pathButton.disabled = !F.tool;
  const showPath = (on) => { if (pathAll) pathAll.visible = pathDone.visible = on; pathButton.style.opacity = on ? 1 : 0.5; };
  pathButton.onclick = () => showPath(!(pathAll && pathAll.visible));
  showPath(true);
  // The travelled part up to t: the frames before t and the interpolated point at t.
  function pathAt(t) {
    if (!pathDone) return;
    const i = frameAt(F.time, t), pos = pathDone.geometry.attributes.position, here = toolAt(rep, t);
    pos.array.set(F.tool.subarray(0, 3 * (i + 1)));
    pos.array.set(here, 3 * (i + 1));
    pos.needsUpdate = true;
    pathDone.geometry.setDrawRange(0, i + 2);
  }

  // A cell with parts or devices: the parts (one geometry per shape, a material per part for its
  // state's colour), the devices' regions drawn faintly, a panel with the signals and events.
  const W = rep.workcell;
  const partMeshes = [], sensorBoxes = [];
  let panel = null;
  let signalRows = null, eventRows = [], shownEvent = -2;
  if (W) {
    const geometries = W.part_meshes.map(flatGeometry);
    const edges = new Map();  // per mesh and colour, the outline of a part whose colour is a CSS one
    for (const p of W.parts) {
      const mesh = new THREE.Mesh(geometries[p.mesh], new THREE.MeshStandardMaterial({ color: PART_COLORS.resting, roughness: 0.5, metalness: 0.05 }));
      if (p.colour && window.CSS && CSS.supports('color', p.colour)) {  // the cell's colour (a sensor may match it)
        const key = `${p.mesh} ${p.colour}`;
        if (!edges.has(key)) edges.set(key, [new THREE.EdgesGeometry(geometries[p.mesh], 20), new THREE.LineBasicMaterial({ color: new THREE.Color(p.colour) })]);
        mesh.add(new THREE.LineSegments(...edges.get(key)));
      }
      mesh.visible = false;
      scene.add(mesh);
      partMeshes.push(mesh);
    }
    for (const d of W.devices) {
      const box = new THREE.BoxGeometry(...d.size), group = new THREE.Group();
      const color = DEVICE_COLORS[d.kind];
      group.add(new THREE.LineSegments(new THREE.EdgesGeometry(box), new THREE.LineBasicMaterial({ color, transparent: true, opacity: 0.45 })));
      if (d.kind !== 'conveyor') {  // the conveyor's box is a cell object already
        const fill = new THREE.Mesh(box, new THREE.MeshBasicMaterial({ color, transparent: true, opacity: 0.06, depthWrite: false }));
        group.add(fill);
        if (d.kind === 'sensor') sensorBoxes.push({ fill, signal: d.signal });
      } else {  // an arrow on the belt, along its direction (world)
        const dir = new THREE.Vector3(...d.direction).normalize(), len = Math.min(200, Math.max(...d.size) / 3);
        const top = new THREE.Vector3(0, 0, d.size[2] / 2 + 2).applyQuaternion(new THREE.Quaternion(...d.pose.slice(3)))
          .add(new THREE.Vector3(...d.pose.slice(0, 3))).addScaledVector(dir, -len / 2);
        scene.add(new THREE.ArrowHelper(dir, top, len, color, 25, 15));
      }
      setPose(group, d.pose);
      scene.add(group);
    }
    // The panel: each signal touched, named by the devices that use it, and the events.
    panel = el('div', { id: 'cell' }, document.body);
    el('h3', { textContent: 'signals' }, panel);
    const sig = el('div', { id: 'sig' }, panel);
    const users = (k) => W.devices.filter((d) => d.signal === k).map((d) => `${d.kind} ${d.name}`).join(', ');
    if (!signalsAt(rep, end).touched.length) el('div', { textContent: '(none changed)', className: 'off' }, sig);
    signalRows = signalsAt(rep, end).touched.map((k) => ({ k, row: el('div', {}, sig), label: `${String(k).padStart(4)} ${signalKind(k).padEnd(6)} ${users(k)}` }));
    el('h3', { textContent: `events (${W.events.length}; click one to go there)` }, panel);
    const ev = el('div', { id: 'ev' }, panel);
    eventRows = W.events.map((e) => {
      const what = `${e.kind} ${e.subject}${e.detail ? ' ' + e.detail : ''}`;
      const row = el('div', { textContent: `${e.time_s.toFixed(3).padStart(8)}  ${what}${e.line ? '  line ' + e.line : ''}` }, ev);
      row.onclick = () => { t = Math.min(end, e.time_s); slider.value = end > 0 ? Math.round((t / end) * 10000) : 0; setPlaying(false); };
      return row;
    });
  }
  const hitParts = hit && hit.part_index ? hit.part_index.filter((k) => k >= 0) : [];
  // The side panel hides (button or key h); a narrow window (800 x 600) starts with it hidden so
  // the scene shows.
  const panelButton = el('button', { textContent: 'panel', title: 'show or hide the side panel (key h)' }, bar);
  panelButton.disabled = !panel;
  const showPanel = (on) => { if (panel) panel.classList.toggle('hidden', !on); panelButton.style.opacity = on ? 1 : 0.5; };
  panelButton.onclick = () => showPanel(!!panel && panel.classList.contains('hidden'));
  showPanel(!!panel && window.innerWidth >= 1000);

  // Parts, sensors, the signal panel and the current event at time t.
  function workcellAt(t, atEnd) {
    const counts = {};
    W.parts.forEach((_, k) => {
      const p = partAt(rep, k, t), m = partMeshes[k];
      m.visible = p !== null && p.state !== 'removed';
      if (!m.visible) return;
      counts[p.state] = (counts[p.state] || 0) + 1;
      setPose(m, p.pose);
      m.material.color.setHex(atEnd && hitParts.includes(k) ? 0xff2020 : PART_COLORS[p.state]);
    });
    const { on } = signalsAt(rep, t);
    for (const s of sensorBoxes) s.fill.material.opacity = on.has(s.signal) ? 0.35 : 0.06;
    for (const r of signalRows) {
      const isOn = on.has(r.k);
      r.row.className = isOn ? 'on' : 'off';
      r.row.textContent = `${isOn ? '\u25cf on ' : '\u25cb off'} ${r.label}`;
    }
    const now = eventAt(rep, t);
    if (now !== shownEvent) {
      eventRows.forEach((row, i) => { row.className = i === now ? 'now' : W.events[i].time_s > t ? 'future' : ''; });
      if (now >= 0) eventRows[now].scrollIntoView({ block: 'nearest' });
      shownEvent = now;
    }
    return Object.entries(counts).map(([k, n]) => `${n} ${k.replace('_', ' ')}`).join(', ') || 'none present';
  }

  const qa = new THREE.Quaternion(), qb = new THREE.Quaternion();  // poseAt's scratch
  const camera = new THREE.PerspectiveCamera(45, 1, 1, 100000);
  camera.up.set(0, 0, 1);  // the cell's Z is up
  const controls = new OrbitControls(camera, renderer.domElement);
  poseAt(0);
  const bounds = cellBounds(rep), lo = new THREE.Vector3(...bounds.min), hi = new THREE.Vector3(...bounds.max);
  const centre = lo.clone().add(hi).multiplyScalar(0.5), radius = Math.max(1, hi.distanceTo(lo) / 2);
  const viewDir = new THREE.Vector3(1.2, -1.6, 0.9).normalize();
  controls.target.copy(centre);
  // The contact marker stays visible however large the cell: 1.5 % of the cell's size, 10 mm at least.
  if (marker) marker.scale.setScalar(Math.max(1, (radius * 0.015) / 10));
  // Placed on every resize too until the user turns the view (the aspect changes the distance).
  let userMoved = false;
  controls.addEventListener('start', () => { userMoved = true; });
  // Every corner of the cell's box inside the view (the API reports it; tests check it).
  function framed() {
    camera.updateMatrixWorld();
    for (const x of [lo.x, hi.x]) for (const y of [lo.y, hi.y]) for (const z of [lo.z, hi.z]) {
      const p = new THREE.Vector3(x, y, z).project(camera);
      if (Math.abs(p.x) > 1 || Math.abs(p.y) > 1 || p.z > 1) return false;
    }
    return true;
  }
  function frameCell() {
    camera.position.copy(centre).addScaledVector(viewDir, fitDistance(radius, camera.fov, camera.aspect) * 1.02);
    camera.far = Math.max(100000, camera.position.distanceTo(centre) + 4 * radius);
    camera.updateProjectionMatrix();
    controls.update();
  }

  // Bodies at simulated time t: frames interpolated (position linear, rotation slerp).
  function poseAt(t) {
    const i = frameAt(F.time, t), j = Math.min(i + 1, F.count - 1);
    const u = j > i ? Math.min(1, Math.max(0, (t - F.time[i]) / (F.time[j] - F.time[i]))) : 0;
    rep.moving.forEach((b, k) => {
      const a = movingPose(rep, i, k), c = movingPose(rep, j, k), m = meshes[b];
      m.position.set(a[0] + (c[0] - a[0]) * u, a[1] + (c[1] - a[1]) * u, a[2] + (c[2] - a[2]) * u);
      qa.fromArray(a, 3);
      qb.fromArray(c, 3);
      m.quaternion.slerpQuaternions(qa, qb, u);
    });
    const atEnd = atEndTime(t, end);
    pathAt(t);
    if (hit) {  // the contact is shown at the halting pose, where the replay ends
      marker.visible = atEnd;
      hit.body_index.forEach((b, k) => {
        if (b >= 0) meshes[b].material.color.setHex(atEnd ? 0xff2020 : COLORS[rep.bodies[b].kind]);
      });
    }
    if (witness) witness.visible = i === near.frame;
    const parts = W ? workcellAt(t, atEnd) : null;
    const s = F.step[i], line = rep.steps[String(s)];
    const joints = Array.from(F.joints.subarray(i * rep.joint_count, (i + 1) * rep.joint_count), (v) => v.toFixed(2));
    hud.textContent = [
      `${rep.file}  ${rep.program}  (${rep.robot})  ${rep.status}`,
      `t = ${(atEnd ? end : t).toFixed(3)} s / ${end.toFixed(3)} s   frame ${i + 1}/${F.count}${F.checked[i] ? '  checked pose' : ''}`,
      line ? `${line.program}, line ${line.line}: ${line.text}` : s > 0 ? `step ${s}` : '',
      `joints [deg]  ${joints.join('  ')}`,
      ...(parts !== null && W.parts.length ? [`parts: ${parts}`] : []),
      rep.closest ? `closest approach${i === near.frame ? ' (this frame)' : ''}: ${rep.closest.bodies.join(' / ')} ` +
                    `${rep.closest.distance_mm.toFixed(3)} mm at t = ${rep.closest.time_s.toFixed(6)} s` : '',
      hit && atEnd ? `*Collision*  ${hit.bodies[0]} / ${hit.bodies[1]} at t = ${hit.time_s.toFixed(6)} s, ` +
                     `point (${hit.point_mm.map((v) => v.toFixed(1)).join(', ')}) mm` : '',
    ].join('\n');
  }

  let t = 0, playing = false, last = 0;
  const setPlaying = (on) => { playing = on; play.textContent = on ? 'pause' : 'play'; };
  play.onclick = () => {
    if (!playing && t >= end) t = 0;  // play again from the start
    setPlaying(!playing);
  };
  slider.oninput = () => { t = (slider.value / 10000) * end; setPlaying(false); };
  window.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLSelectElement || e.target instanceof HTMLInputElement && e.target.type !== 'range') return;
    if (e.code === 'Space') { e.preventDefault(); play.onclick(); }
    if (e.key === 'h') panelButton.onclick();
    if (e.key === 'p') pathButton.onclick();
  });
  function resize() {
    renderer.setSize(window.innerWidth, window.innerHeight);
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    if (!userMoved) frameCell();
  }
  window.addEventListener('resize', resize);
  resize();
  renderer.setAnimationLoop((now) => {
    const dt = last ? (now - last) / 1000 : 0;
    last = now;
    if (playing) {
      t = Math.min(end, t + dt * Number(speed.value));
      if (t >= end) setPlaying(false);
      slider.value = end > 0 ? Math.round((t / end) * 10000) : 10000;
    }
    poseAt(t);
    controls.update();
    renderer.render(scene, camera);
  });
  // Seeking, for the slider's keys, the URL, tests and pages that embed the replay: t clamped to
  // [0, end], a time that reads as the end (atEndTime) is the end.
  function seek(to) {
    const x = Number(to);
    if (!Number.isFinite(x)) return t;
    t = Math.min(end, Math.max(0, x));
    if (atEndTime(t, end)) t = end;
    slider.value = end > 0 ? Math.round((t / end) * 10000) : 10000;
    poseAt(t);
    return t;
  }
  // ?t=SECONDS opens the page at that simulated time, ?play starts playing (screenshots, demos),
  // ?panel=0|1 hides or shows the side panel.
  const params = new URLSearchParams(location.search);
  if (params.has('t')) seek(params.get('t'));
  if (params.has('panel')) showPanel(params.get('panel') !== '0');
  if (params.has('play')) setPlaying(true);
  // The page's JavaScript API (docs/cli.md "Replay page"): what tests and embedding pages use.
  window.asimovReplay = {
    ready: true, frames: F.count, end, file: rep.file, status: rep.status,
    seek, play: () => setPlaying(true), pause: () => setPlaying(false),
    panel: (on) => { showPanel(on === undefined ? !!panel && panel.classList.contains('hidden') : !!on); return !!panel && !panel.classList.contains('hidden'); },
    state: () => {
      const i = frameAt(F.time, t);
      return {
        t, frame: i, playing, end, atEnd: atEndTime(t, end),
        contactShown: !!(marker && marker.visible), hud: hud.textContent,
        tool: toolAt(rep, t), joints: Array.from(F.joints.subarray(i * rep.joint_count, (i + 1) * rep.joint_count)),
        panel: !!panel && !panel.classList.contains('hidden'), path: !!(pathAll && pathAll.visible),
        camera: { position: camera.position.toArray(), target: controls.target.toArray() },
        framed: framed(),
      };
    },
  };
}

// Only on a replay page: the studio (app/serve/web) imports the functions above without it.
if (typeof document !== 'undefined' && document.getElementById('asimov-replay-data')) main();
