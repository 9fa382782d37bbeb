// The replay page as a browser gets it, decoded in node by the viewer's own functions (the
// module inlined in the page, imported as is): mesh sizes, and bodies at the last frame where
// forward kinematics puts them. Registered in tests/CMakeLists.txt; without node CTest skips it.
// usage: node replay_decode.mjs ASIMOV SOURCE_DIR SCRATCH_DIR
import { execFileSync } from 'node:child_process';
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';

const [asimov, source, scratch] = process.argv.slice(2);
mkdirSync(scratch, { recursive: true });
let passed = 0, failed = 0;
function check(ok, what) {
  if (ok) ++passed;
  else { ++failed; console.log(`FAILED: ${what}`); }
}

function run(demo, expectExit, cell) {
  const html = join(scratch, `${demo}.html`), report = join(scratch, `${demo}.json`), trace = join(scratch, `${demo}.trace.json`);
  const program = cell ? join(source, 'programs/cells', `${demo}.v2`) : join(source, 'programs/demo', `${demo}.v2`);
  let code = 0;
  try {
    execFileSync(asimov, ['run', program, ...(cell ? ['--cell', join(source, 'programs/cells', cell)] : []),
                          '--replay', html, '--report', report, '--trace', trace], { stdio: 'ignore' });
  } catch (e) { code = e.status; }
  check(code === expectExit, `${demo}: exit ${code}, expected ${expectExit}`);
  const page = readFileSync(html, 'utf8');
  const script = (id) => {
    const m = page.match(new RegExp(`<script[^>]*id="${id}"[^>]*>([\\s\\S]*?)</script>`));
    if (!m) throw new Error(`${demo}: no script #${id}`);
    return m[1];
  };
  return { page, data: JSON.parse(script('asimov-replay-data')), viewer: script('asimov-replay-viewer'),
           report: JSON.parse(readFileSync(report, 'utf8')), trace: JSON.parse(readFileSync(trace, 'utf8')) };
}

// VAL's TRANS(x, y, z, o, a, t) = translation . Rz(o) Ry(a) Rz(t), as a 3x4 row-major matrix.
function trans([x, y, z, o, a, t]) {
  const r = (d) => (d * Math.PI) / 180;
  const rz = (g) => [[Math.cos(g), -Math.sin(g), 0], [Math.sin(g), Math.cos(g), 0], [0, 0, 1]];
  const ry = (g) => [[Math.cos(g), 0, Math.sin(g)], [0, 1, 0], [-Math.sin(g), 0, Math.cos(g)]];
  const mul = (A, B) => A.map((row) => [0, 1, 2].map((j) => row[0] * B[0][j] + row[1] * B[1][j] + row[2] * B[2][j]));
  return { R: mul(mul(rz(r(o)), ry(r(a))), rz(r(t))), p: [x, y, z] };
}
const apply = (T, v) => [0, 1, 2].map((i) => T.R[i][0] * v[0] + T.R[i][1] * v[1] + T.R[i][2] * v[2] + T.p[i]);
const inverse = (T) => {
  const Rt = [0, 1, 2].map((i) => [0, 1, 2].map((j) => T.R[j][i]));
  return { R: Rt, p: apply({ R: Rt, p: [0, 0, 0] }, T.p).map((v) => -v) };
};
const compose = (A, B) => ({ R: A.R.map((row) => [0, 1, 2].map((j) => row[0] * B.R[0][j] + row[1] * B.R[1][j] + row[2] * B.R[2][j])),
                            p: apply(A, B.p) });

const pick = run('pick_place', 0), crash = run('crash', 3);
// The viewer exactly as inlined; its page part runs only where there is a document.
const viewerFile = join(scratch, 'viewer.mjs');
writeFileSync(viewerFile, pick.viewer.replaceAll('<\\/', '</'));
const V = await import(pathToFileURL(viewerFile).href);

for (const [name, r] of [['pick_place', pick], ['crash', crash]]) {
  const rep = V.decodeReplay(r.data);
  check(rep.bodies.length === 10, `${name}: ${rep.bodies.length} bodies`);
  for (const b of rep.bodies) {
    check(b.vertices.length === 3 * b.vertex_count, `${name} ${b.name}: vertex array`);
    check(b.triangles.length === 3 * b.triangle_count && b.triangle_count > 0, `${name} ${b.name}: triangle array`);
    check(b.triangles.every((i) => i < b.vertex_count), `${name} ${b.name}: triangle indices`);
  }
  const F = rep.frames;
  check(F.time.length === F.count && F.poses.length === F.count * rep.moving.length * 7, `${name}: frame arrays`);
  check(F.joints.length === F.count * rep.joint_count, `${name}: joint array`);
  check(V.frameAt(F.time, F.time[F.count - 1] + 1) === F.count - 1 && V.frameAt(F.time, 0) === 0, `${name}: frameAt`);
}

// pick_place ends at its last checked pose (READY): the tool body's vertices at the last frame
// are where the trace's tool point puts the flange (tool point = flange . TOOL).
{
  const rep = V.decodeReplay(pick.data), F = rep.frames, last = F.count - 1;
  const s = pick.trace.samples.at(-1);
  check(F.time[last] === s.t && F.time[last] === pick.report.sim_time_s, 'pick_place: last frame at the end of the run');
  const flange = compose(trans(s.tool_xyzoat), inverse(trans(rep.tool_xyzoat)));
  const k = rep.moving.findIndex((b) => rep.bodies[b].kind === 'tool');
  const tool = rep.bodies[rep.moving[k]], pose = V.movingPose(rep, last, k);
  let worst = 0;
  for (let i = 0; i < tool.vertex_count; ++i) {
    const v = Array.from(tool.vertices.subarray(3 * i, 3 * i + 3));
    const got = V.transformPoint(pose, v), want = apply(flange, v);
    worst = Math.max(worst, Math.hypot(got[0] - want[0], got[1] - want[1], got[2] - want[2]));
  }
  check(worst < 0.05, `pick_place: tool vertices ${worst.toFixed(4)} mm from FK`);
  console.log(`pick_place: ${F.count} frames, ${pick.page.length} bytes; tool vertices within ${worst.toExponential(2)} mm of FK`);
}

// crash ends at the halting pose: the contact point lies on both highlighted bodies there.
{
  const rep = V.decodeReplay(crash.data), F = rep.frames, last = F.count - 1;
  check(F.time[last] === crash.report.collision.time_free_s, 'crash: last frame at the halting pose');
  for (const b of rep.collision.body_index) {
    const body = rep.bodies[b], k = rep.moving.indexOf(b);
    const pose = k >= 0 ? V.movingPose(rep, last, k) : body.pose;
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (let i = 0; i < body.vertex_count; ++i) {
      const w = V.transformPoint(pose, Array.from(body.vertices.subarray(3 * i, 3 * i + 3)));
      for (let c = 0; c < 3; ++c) lo[c] = Math.min(lo[c], w[c]), hi[c] = Math.max(hi[c], w[c]);
    }
    const inside = rep.collision.point_mm.every((x, c) => x >= lo[c] - 0.5 && x <= hi[c] + 0.5);
    check(inside, `crash: contact point in the world box of ${body.name} at the last frame`);
  }
  console.log(`crash: ${F.count} frames, ${crash.page.length} bytes; contact ${rep.collision.bodies.join(' / ')}`);
}

// The closest approach: the page's mark is the report's closest pair (crash: the contact
// itself, 0 mm), at the frame of its instant, its witnesses on the two bodies' sides.
{
  const rep = V.decodeReplay(crash.data), c = rep.closest, want = crash.report.clearance.closest;
  check(c && want, 'crash: a closest approach in the page and the report');
  if (c && want) {
    check(c.bodies.join('/') === want.bodies.join('/') && c.distance_mm === want.distance_mm && c.time_s === want.time_s,
          'crash: page and report name the same closest approach');
    check(c.distance_mm === 0 && [...c.bodies].sort().join('/') === [...rep.collision.bodies].sort().join('/'),
          `crash: the closest approach is the contact (${c.bodies.join(' / ')} ${c.distance_mm} mm)`);
    const m = V.closestMark(rep), F = rep.frames;
    check(F.time[m.frame] <= c.time_s && (m.frame === F.count - 1 || F.time[m.frame + 1] > c.time_s),
          'crash: the marked frame is the one shown at the closest instant');
    check(m.slider >= 0 && m.slider <= 10000, 'crash: slider tick in range');
    const pairs = crash.report.clearance.pairs;
    check(pairs.every((p, i) => i === 0 || pairs[i - 1].distance_mm <= p.distance_mm), 'crash: clearance pairs nearest first');
    check(pairs.every((p) => p.distance_mm < crash.report.clearance.report_within_mm), 'crash: pairs within report_within_mm');
  }
  check(V.closestMark({ ...V.decodeReplay(pick.data), closest: undefined }) === null, 'no closest: no mark');
}

// A static cell (the demos) has no parts, devices or signals: the page carries none of it.
for (const [name, r] of [['pick_place', pick], ['crash', crash]]) {
  check(!('workcell' in r.data) && !('carried' in r.data.frames), `${name}: no workcell data in a static cell's page`);
  const rep = V.decodeReplay(r.data);
  check(rep.workcell === null && V.signalsAt(rep, 1e9).touched.length === 0 && V.eventAt(rep, 1e9) === -1,
        `${name}: no parts, signals or events decoded`);
}

// Cells that react (docs/cell-format.md "Parts and devices"): the parts and signals of the page
// against the run's report, and the parts' motion against the cell's devices.
const rotation = (q) => {  // unit quaternion [qx, qy, qz, qw] -> 3x3
  const [x, y, z, w] = q;
  return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
          [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
          [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]];
};
const poseT = (p) => ({ R: rotation(p.slice(3)), p: p.slice(0, 3) });
// Largest difference of two poses: position [mm] and rotation matrix entries.
const poseDiff = (A, B) => Math.max(...[0, 1, 2].map((i) => Math.abs(A.p[i] - B.p[i])),
                                    ...[0, 1, 2].flatMap((i) => [0, 1, 2].map((j) => Math.abs(A.R[i][j] - B.R[i][j]))));
const inRegion = (d, point, tol) => {  // the device's closed box, its pose [x y z qx qy qz qw] and size
  const local = apply(inverse(poseT(d.pose)), point);
  return local.every((v, c) => Math.abs(v) <= d.size[c] / 2 + tol);
};

const cells = [['belt_pick', run('belt_pick', 0, 'belt_cell.yaml')], ['palletizer', run('palletizer', 0, 'palletizer_cell.yaml')]];
for (const [name, r] of cells) {
  const rep = V.decodeReplay(r.data), W = rep.workcell, F = rep.frames, end = F.time[F.count - 1];
  check(W !== null && W.parts.length === r.report.parts.length, `${name}: every part of the report in the page`);
  if (!W) continue;
  check(end === r.report.sim_time_s, `${name}: last frame at the end of the run`);
  // The last frame: each part where (and as) the report leaves it; a removed one is not drawn.
  let worst = 0;
  r.report.parts.forEach((want, k) => {
    check(W.parts[k].name === want.name, `${name}: part ${k} is ${want.name}`);
    const got = V.partAt(rep, k, end);
    check(got !== null && got.state === want.state, `${name} ${want.name}: state ${got && got.state}, report ${want.state}`);
    if (!got || got.state === 'removed') return;
    const d = poseDiff(poseT(got.pose), trans(want.pose));
    worst = Math.max(worst, d);
    check(d < 1e-3, `${name} ${want.name}: pose at the last frame ${d.toExponential(2)} from the report's`);
  });
  // Signals: the page's state at the last frame is the run's at its end (the report lists the
  // ones on, from the devices' clock, not from the events the page folds).
  const on = [...V.signalsAt(rep, end).on].sort((a, b) => a - b);
  check(JSON.stringify(on) === JSON.stringify(r.report.signals_on), `${name}: signals on at the end ${on} vs ${r.report.signals_on}`);
  // The events: the report's, in order, with time and program line.
  const ev = W.events, want = r.report.events;
  check(ev.length === want.length && ev.every((e, i) => e.time_s === want[i].time_s && e.kind === want[i].kind &&
                                                   e.subject === want[i].subject && e.line === want[i].line),
        `${name}: the page's events are the report's`);
  check(V.eventAt(rep, -1) === -1 && V.eventAt(rep, end) === ev.length - 1, `${name}: eventAt at both ends`);
  // A grasped part rides rigidly with the tool from its grasp to its release (the tool body's
  // pose is the flange's); at the grasp frame it is where it lay.
  const tk = rep.moving.findIndex((b) => rep.bodies[b].kind === 'tool');
  const grasps = ev.filter((e) => e.kind === 'grasp'), releases = ev.filter((e) => e.kind === 'release');
  check(grasps.length > 0 && grasps.length === releases.length, `${name}: ${grasps.length} grasps, each released`);
  let carriedFrames = 0, rigid = 0, atGrasp = 0;
  grasps.forEach((g, n) => {
    const k = W.parts.findIndex((p) => p.name === g.subject), t0 = g.time_s, t1 = releases[n].time_s;
    let rel = null;
    for (let i = 0; i < F.count; ++i) {
      if (!(F.time[i] >= t0 && F.time[i] < t1)) continue;
      const p = V.partAt(rep, k, F.time[i]);
      if (!p || p.state !== 'carried') { check(false, `${name} ${g.subject}: carried at ${F.time[i]}`); return; }
      ++carriedFrames;
      const T = compose(inverse(poseT(V.movingPose(rep, i, tk))), poseT(p.pose));  // part in the tool frame
      if (rel) rigid = Math.max(rigid, poseDiff(T, rel));
      else rel = T;
    }
    const before = V.partAt(rep, k, t0 - 1e-9), grasped = V.partAt(rep, k, t0);
    if (before && grasped) atGrasp = Math.max(atGrasp, poseDiff(poseT(before.pose), poseT(grasped.pose)));
  });
  check(carriedFrames > 10 && rigid < 1e-3, `${name}: carried part rigid with the tool over ${carriedFrames} frames (${rigid.toExponential(2)})`);
  check(atGrasp < 1e-3, `${name}: grasped where it lay (${atGrasp.toExponential(2)})`);
  console.log(`${name}: ${W.parts.length} parts, ${W.segments.count} segments, ${ev.length} events, ${F.count} frames, ` +
              `${r.page.length} bytes; last-frame poses within ${worst.toExponential(2)} of the report`);
}

// belt_pick: the belt carries a cube while it runs, and the barrier (input 1001) switches on at
// the instant a cube's origin enters its box; the chute takes the fourth cube.
{
  const r = cells[0][1], rep = V.decodeReplay(r.data), W = rep.workcell, F = rep.frames;
  const cube1 = W.parts.findIndex((p) => p.name === 'cube1');
  // From the feeder's spot (x 220) at the belt's speed along +x, frame by frame.
  const belt = W.devices.find((d) => d.kind === 'conveyor'), feeder = W.devices.find((d) => d.kind === 'feeder');
  let frames = 0, off = 0, x0 = null, x1 = null;
  for (let i = 0; i < F.count && F.time[i] < 3.6; ++i) {
    const p = V.partAt(rep, cube1, F.time[i]);
    check(p && p.state === 'on_conveyor', 'belt_pick: cube1 on the belt before the barrier');
    if (!p) continue;
    ++frames;
    off = Math.max(off, Math.abs(p.pose[0] - (feeder.pose[0] + belt.speed_mm_s * F.time[i])), Math.abs(p.pose[1] - feeder.pose[1]));
    x0 ??= p.pose[0];
    x1 = p.pose[0];
  }
  check(frames > 50 && x1 - x0 > 300 && off < 1e-9,
        `belt_pick: cube1 moves with the running belt (${frames} frames, x ${x0} -> ${x1}, ${off.toExponential(2)} mm off)`);
  const barrier = W.devices.find((d) => d.kind === 'sensor' && d.name === 'barrier');
  const chute = W.devices.find((d) => d.kind === 'sink');
  const ons = W.events.filter((e) => e.kind === 'signal' && e.subject === '1001' && e.detail === 'on');
  check(ons.length === 4, `belt_pick: the barrier saw ${ons.length} cubes`);
  for (const e of ons) {
    const seen = W.parts.some((_, k) => { const p = V.partAt(rep, k, e.time_s); return p && p.state !== 'carried' && inRegion(barrier, p.pose.slice(0, 3), 1e-6); });
    const early = W.parts.some((_, k) => { const p = V.partAt(rep, k, e.time_s - 1e-3); return p && p.state !== 'carried' && inRegion(barrier, p.pose.slice(0, 3), 0); });
    check(seen && !early, `belt_pick: a cube enters the barrier at t = ${e.time_s} (not before)`);
  }
  const sunk = W.events.find((e) => e.kind === 'sink');
  const k4 = W.parts.findIndex((p) => p.name === sunk.subject);
  const justBefore = V.partAt(rep, k4, sunk.time_s - 1e-6);
  check(justBefore.state === 'on_conveyor' && inRegion(chute, justBefore.pose.slice(0, 3), 1e-3) &&
        V.partAt(rep, k4, sunk.time_s).state === 'removed', `belt_pick: ${sunk.subject} rides into the chute and is removed`);
  // Before the feeder places it, a part is not there.
  const fed = W.events.find((e) => e.kind === 'feeder' && e.subject === 'cube2');
  check(V.partAt(rep, W.parts.findIndex((p) => p.name === 'cube2'), fed.time_s - 1e-6) === null, 'belt_pick: cube2 absent before it is fed');
}

// carried_crash: the contact names the carried part, which the page marks.
{
  const r = run('carried_crash', 3, 'carried_crash_cell.yaml'), rep = V.decodeReplay(r.data), F = rep.frames;
  const c = rep.collision, k = c ? c.part_index.find((i) => i >= 0) : -1;
  check(c && k >= 0 && c.bodies.some((b) => b === `carried part:${rep.workcell.parts[k].name}`), 'carried_crash: the contact names the carried part');
  const p = k >= 0 ? V.partAt(rep, k, F.time[F.count - 1]) : null;
  check(p && p.state === 'carried', 'carried_crash: carried at the halting pose');
}

console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
