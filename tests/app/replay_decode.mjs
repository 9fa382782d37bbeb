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

function run(demo, expectExit) {
  const html = join(scratch, `${demo}.html`), report = join(scratch, `${demo}.json`), trace = join(scratch, `${demo}.trace.json`);
  let code = 0;
  try {
    execFileSync(asimov, ['run', join(source, 'programs/demo', `${demo}.v2`), '--replay', html, '--report', report,
                          '--trace', trace], { stdio: 'ignore' });
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

console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
