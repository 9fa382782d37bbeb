#include "asimov/motion/device_clock.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <unordered_map>

namespace asimov::motion {
namespace {
using collision::Vec3;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Changes at one instant before the rules count as a loop (docs/cell-format.md "logic"), beyond
// one round per part a feeder can place (feeders stop at their count).
constexpr std::size_t kMaxChangesPerInstant = 10000;

double mesh_radius(const collision::Polyhedron& m) {
  double r = 0;
  for (const auto& v : m.vertices) r = std::max(r, v.norm());
  return r;
}

// Separating axes of a part's convex hull in its own frame (overlap sensing): face normals and
// edge directions, each once (parallel ones merged).
struct HullAxes {
  std::vector<Vec3> normals, edges;
};
void add_axis(std::vector<Vec3>& list, Vec3 d) {
  const double n = d.norm();
  if (!(n > 0)) return;
  d /= n;
  for (const Vec3& x : list)
    if (std::abs(x.dot(d)) > 1 - 1e-12) return;
  list.push_back(d);
}
HullAxes hull_axes(const collision::Polyhedron& m) {
  HullAxes h;
  for (const auto& t : m.triangles) {
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    add_axis(h.normals, (b - a).cross(c - a));
    add_axis(h.edges, b - a);
    add_axis(h.edges, c - b);
    add_axis(h.edges, a - c);
  }
  return h;
}

Interval hull_interval(const Region& r, const HullAxes& h, const collision::Polyhedron& mesh, const Location& pose0,
                       double t0, const Vec3& v) {
  const auto& rot = r.pose.linear();
  const Vec3 c = r.pose.translation(), half = r.size / 2;
  Interval out{-kInf, kInf};
  std::vector<Vec3> world(mesh.vertices.size());
  for (std::size_t k = 0; k < world.size(); ++k) world[k] = pose0 * mesh.vertices[k];
  const auto axis = [&](const Vec3& n) {
    double rad = 0;
    for (int k = 0; k < 3; ++k) rad += half[k] * std::abs(n.dot(rot.col(k)));
    const double bl = c.dot(n) - rad, bh = c.dot(n) + rad;
    double pl = kInf, ph = -kInf;
    for (const Vec3& x : world) pl = std::min(pl, x.dot(n)), ph = std::max(ph, x.dot(n));
    const double w = n.dot(v);
    if (w == 0) {
      if (pl > bh || ph < bl) out = {kInf, -kInf};
      return;
    }
    double lo = t0 + (bl - ph) / w, hi = t0 + (bh - pl) / w;
    if (lo > hi) std::swap(lo, hi);
    out.in = std::max(out.in, lo), out.out = std::min(out.out, hi);
  };
  for (int k = 0; k < 3 && !out.empty(); ++k) axis(rot.col(k));
  for (const Vec3& n : h.normals) {
    if (out.empty()) break;
    axis(pose0.linear() * n);
  }
  for (const Vec3& e : h.edges)
    for (int k = 0; k < 3 && !out.empty(); ++k) {
      const Vec3 n = rot.col(k).cross(pose0.linear() * e);
      if (n.squaredNorm() > 1e-24) axis(n);
    }
  if (out.empty()) return {kInf, -kInf};
  // A closed interval in time: the part still touches the box at out.
  return {out.in, std::nextafter(out.out, kInf)};
}

// The belt's top face: centre, and the distance from it to the face's edge along `dir`.
struct Belt {
  Vec3 centre;
  double end;
};
Belt belt(const Conveyor& c) {
  const Vec3 half = c.body.size / 2;
  const Vec3 centre = c.body.pose * Vec3(0, 0, half.z());
  double end = kInf;
  for (int a = 0; a < 2; ++a) {
    const double along = std::abs(c.direction.dot(c.body.pose.linear().col(a)));
    if (along > 1e-12) end = std::min(end, half[a] / along);
  }
  return {centre, end};
}

double lowest_z(const PartDef& d, const Location& pose) {
  double z = kInf;
  for (const auto& v : d.mesh.vertices) z = std::min(z, (pose * v).z());
  return d.mesh.vertices.empty() ? pose.translation().z() : z;
}



std::string on_off(bool on) { return on ? "on" : "off"; }
}  // namespace

bool Region::contains(const Vec3& p) const {
  const Vec3 local = pose.inverse() * p;
  return (local.cwiseAbs() - size / 2).maxCoeff() <= 0;
}

bool name_matches(const std::string& pattern, const std::string& name) {
  // Iterative wildcard match with one backtrack point (the last '*').
  std::size_t p = 0, n = 0, star = std::string::npos, mark = 0;
  const auto eq = [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b)); };
  while (n < name.size()) {
    if (p < pattern.size() && (pattern[p] == '?' || (pattern[p] != '*' && eq(pattern[p], name[n])))) {
      ++p, ++n;
    } else if (p < pattern.size() && pattern[p] == '*') {
      star = p++, mark = n;
    } else if (star != std::string::npos) {
      p = star + 1, n = ++mark;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '*') ++p;
  return p == pattern.size();
}

std::size_t Workcell::max_parts() const {
  std::size_t n = parts.size();
  for (const auto& f : feeders) n += static_cast<std::size_t>(std::max(0, f.count));
  return n;
}

Interval overlap_interval(const Region& r, const collision::Polyhedron& mesh, const Location& pose0, double t0,
                          const Vec3& v) {
  return hull_interval(r, hull_axes(mesh), mesh, pose0, t0, v);
}

bool Workcell::drives(int k) const {
  for (const auto& s : sensors)
    if (s.signal == k) return true;
  for (const auto& r : logic)
    if (r.set == k) return true;
  return false;
}

Interval crossing(const Region& r, const Vec3& p0, double t0, const Vec3& v) {
  const Location inv = r.pose.inverse();
  const Vec3 p = inv * p0, w = inv.linear() * v, half = r.size / 2;
  Interval i{-kInf, kInf};
  for (int a = 0; a < 3; ++a) {
    if (w[a] == 0) {
      if (std::abs(p[a]) > half[a]) return {kInf, -kInf};
      continue;
    }
    double lo = t0 + (-half[a] - p[a]) / w[a], hi = t0 + (half[a] - p[a]) / w[a];
    if (lo > hi) std::swap(lo, hi);
    i.in = std::max(i.in, lo), i.out = std::min(i.out, hi);
  }
  return i;
}

struct DeviceClock::Hulls {
  std::unordered_map<const collision::Polyhedron*, HullAxes> axes;
};

// A fed part's shape is its feeder's (one entry per feeder, not per part).
Interval DeviceClock::hull(const PartState& p, const Region& r, const Location& pose, double t0, const Vec3& v) const {
  const collision::Polyhedron& m = p.feeder >= 0 ? cell_->feeders[static_cast<std::size_t>(p.feeder)].part.mesh : p.def->mesh;
  auto it = shared_->hulls->axes.find(&m);
  if (it == shared_->hulls->axes.end()) it = shared_->hulls->axes.emplace(&m, hull_axes(m)).first;
  return hull_interval(r, it->second, m, pose, t0, v);
}

Location PartState::pose_at(double t) const {
  if (velocity.isZero()) return anchor;
  Location p = anchor;
  p.translation() += velocity * (std::min(t, end_s) - anchor_s);
  return p;
}

DeviceClock::DeviceClock(const Workcell& cell, std::span<const Support> objects)
    : cell_(&cell),
      shared_(std::make_shared<Shared>()),
      log_(std::make_shared<Log>()),
      timed_done_(cell.logic.size(), false),
      fed_(cell.feeders.size(), 0) {
  shared_->objects.assign(objects.begin(), objects.end());
  shared_->hulls = std::make_shared<Hulls>();
  for (const Support& o : objects) shared_->object_radius.push_back(mesh_radius(*o.mesh));
  for (std::size_t k = 0; k < cell.sensors.size(); ++k) {
    auto& groups = shared_->sensor_signals;
    auto g = std::find_if(groups.begin(), groups.end(), [&](const auto& x) { return x.first == cell.sensors[k].signal; });
    if (g == groups.end()) g = groups.insert(groups.end(), {cell.sensors[k].signal, {}});
    g->second.push_back(k);
  }
  shared_->max_rounds = kMaxChangesPerInstant + cell.max_parts();
  parts_.reserve(cell.parts.size());
  for (const auto& d : cell.parts) {
    PartState p;
    p.def = &d;
    p.ordinal = static_cast<int>(parts_.size());
    p.anchor = d.pose;
    p.tolerance_mm = resting_tolerance(d.mesh);
    p.radius_mm = mesh_radius(d.mesh);
    parts_.push_back(std::move(p));
  }
  // Stacks first (each part on the part it rests on, at the declared poses), then each part's
  // own place: a stack's bottom part on a belt takes the parts above it along.
  for (std::size_t i = 0; i < parts_.size(); ++i)
    if (const int s = part_below(i, parts_[i].anchor); s >= 0) attach(i, static_cast<std::size_t>(s));
  for (std::size_t i = 0; i < parts_.size(); ++i)
    if (parts_[i].support < 0) place(i, parts_[i].anchor);
  settle();
}

DeviceClock DeviceClock::scratch_copy() const {
  DeviceClock c = *this;
  c.mute_ = true;
  return c;
}

void DeviceClock::record(CellEvent e) {
  if (mute_) return;
  // A copy restored from before (World::rewind_to) drops the events of the future it replaced.
  if (log_->events.size() > logged_) log_->events.resize(logged_);
  last_event_s_ = std::max(last_event_s_, e.time_s);
  if (logged_ >= kMaxEvents) {
    ++dropped_;
    return;
  }
  log_->events.push_back(std::move(e));
  ++logged_;
}

void DeviceClock::note(CellEvent e) {
  if (mute_) return;
  if (logged_ >= kMaxEvents) return record(std::move(e));
  // An event of an instant before the last one recorded (a resting contact found between two
  // checked poses) goes before the later ones: the log stays in time order.
  std::size_t later = 0;
  while (later < logged_ && log_->events[logged_ - 1 - later].time_s > e.time_s) ++later;
  if (later == 0 || mute_) return record(std::move(e));
  if (log_->events.size() > logged_) log_->events.resize(logged_);
  log_->events.insert(log_->events.end() - static_cast<std::ptrdiff_t>(later), std::move(e));
  ++logged_;
}

bool DeviceClock::running(int c) const {
  const auto& conv = cell_->conveyors[static_cast<std::size_t>(c)];
  return conv.speed_mm_s > 0 && (conv.signal == 0 || signal(conv.signal));
}

int DeviceClock::part_below(std::size_t i, const Location& pose) const {
  const PartState& p = parts_[i];
  const Vec3 o = pose.translation();
  int best = -1;
  bool best_under = false;
  for (std::size_t k = 0; k < parts_.size(); ++k) {
    const PartState& q = parts_[k];
    if (k == i || q.holder == Holder::removed || q.holder == Holder::carried) continue;
    const double tol = std::max(p.tolerance_mm, q.tolerance_mm);
    const Vec3 qo = q.velocity.isZero() ? q.anchor.translation()
                                        : Vec3(q.anchor.translation() + q.velocity * (std::min(now_, q.end_s) - q.anchor_s));
    if ((qo - o).norm() > p.radius_mm + q.radius_mm + tol) continue;
    const Location at = q.pose_at(now_);
    bool cycle = false;  // a part already resting (through others) on i
    for (int s = static_cast<int>(k); s >= 0 && !cycle; s = parts_[static_cast<std::size_t>(s)].support)
      cycle = static_cast<std::size_t>(s) == i;
    if (cycle) continue;
    const auto g = gap_below(p.def->mesh, pose, {&q.def->mesh, at}, tol);
    if (!g || *g > tol) continue;
    // Of several, the one under the part's origin, then the first.
    const Vec3 local = at.inverse() * o;
    bool under = false;
    if (!q.def->mesh.vertices.empty()) {
      Vec3 lo = q.def->mesh.vertices.front(), hi = lo;
      for (const auto& v : q.def->mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
      under = local.x() >= lo.x() && local.x() <= hi.x() && local.y() >= lo.y() && local.y() <= hi.y();
    }
    if (best < 0 || (under && !best_under)) best = static_cast<int>(k), best_under = under;
  }
  return best;
}

int DeviceClock::object_below(std::size_t i, const Location& pose) const {
  const PartState& p = parts_[i];
  for (std::size_t k = 0; k < shared_->objects.size(); ++k) {
    const Support& o = shared_->objects[k];
    if ((o.pose.translation() - pose.translation()).norm() > p.radius_mm + shared_->object_radius[k] + p.tolerance_mm) continue;
    const auto g = gap_below(p.def->mesh, pose, o, p.tolerance_mm);
    if (g && *g <= p.tolerance_mm) return static_cast<int>(k);
  }
  return -1;
}

void DeviceClock::attach(std::size_t r, std::size_t s) {
  PartState& p = parts_[r];
  p.support = static_cast<int>(s);
  p.rel = parts_[s].pose_at(now_).inverse() * p.pose_at(now_);
  p.next_rider = parts_[s].first_rider;
  parts_[s].first_rider = static_cast<int>(r);
  note_change();
}

void DeviceClock::detach(std::size_t r) {
  PartState& p = parts_[r];
  if (p.support < 0) return;
  int* link = &parts_[static_cast<std::size_t>(p.support)].first_rider;
  while (*link >= 0 && *link != static_cast<int>(r)) link = &parts_[static_cast<std::size_t>(*link)].next_rider;
  if (*link == static_cast<int>(r)) *link = p.next_rider;
  p.support = -1, p.next_rider = -1;
  note_change();
}

void DeviceClock::sync(std::size_t i) {
  const PartState& s = parts_[i];
  for (int r = s.first_rider; r >= 0; r = parts_[static_cast<std::size_t>(r)].next_rider) {
    PartState& p = parts_[static_cast<std::size_t>(r)];
    p.holder = s.holder, p.conveyor = s.conveyor, p.anchor_s = s.anchor_s, p.anchor = s.anchor * p.rel;
    p.velocity = s.velocity, p.end_s = s.end_s, p.behind = -1, p.object = -1;
    sync(static_cast<std::size_t>(r));
  }
  if (s.first_rider >= 0) note_change();
}

void DeviceClock::place(std::size_t i, const Location& pose) {
  detach(i);
  note_change();
  PartState& p = parts_[i];
  p.holder = Holder::world, p.conveyor = -1, p.anchor = pose, p.anchor_s = now_;
  p.velocity.setZero(), p.end_s = kInf, p.behind = -1, p.object = -1;
  // On another part: it moves with it from now on.
  if (const int s = part_below(i, pose); s >= 0) {
    attach(i, static_cast<std::size_t>(s));
    const PartState& q = parts_[static_cast<std::size_t>(s)];
    PartState& r = parts_[i];
    r.holder = q.holder, r.conveyor = q.conveyor, r.anchor_s = q.anchor_s, r.anchor = q.anchor * r.rel;
    r.velocity = q.velocity, r.end_s = q.end_s;
    sync(i);
    return;
  }
  const double bottom = lowest_z(*p.def, pose);
  for (std::size_t c = 0; c < cell_->conveyors.size(); ++c) {
    const auto& conv = cell_->conveyors[c];
    const Belt b = belt(conv);
    const Vec3 local = conv.body.pose.inverse() * pose.translation();
    const Vec3 half = conv.body.size / 2;
    if (std::abs(bottom - b.centre.z()) > p.tolerance_mm || std::abs(local.x()) > half.x() ||
        std::abs(local.y()) > half.y())
      continue;
    p.holder = Holder::conveyor, p.conveyor = static_cast<int>(c);
    queue(static_cast<int>(c));
    return;
  }
  p.object = object_below(i, pose);
  sync(i);
}

void DeviceClock::arrived(std::size_t i, int c, int behind) {
  PartState& p = parts_[i];
  if (behind >= 0)
    record({now_, "conveyor_queue", p.def->name, parts_[static_cast<std::size_t>(behind)].def->name, 0});
  else
    record({now_, "conveyor_end", p.def->name, cell_->conveyors[static_cast<std::size_t>(c)].name, 0});
}

void DeviceClock::queue(int c) {
  const auto& conv = cell_->conveyors[static_cast<std::size_t>(c)];
  const Belt b = belt(conv);
  const bool runs = running(c);
  const auto halt = [&](PartState& p) {
    if (p.velocity.isZero()) return;
    p.anchor = p.pose_at(now_), p.anchor_s = now_, p.velocity.setZero(), p.end_s = kInf;
    note_change();
  };
  // One part on the belt: where its origin is along the belt, how far its faces reach ahead of
  // and behind the origin, and the band across the belt it covers. Parts resting on another
  // part move with it and are not in the row.
  struct OnBelt {
    std::size_t i;
    double s, front, back, lo, hi, stop;
  };
  std::vector<OnBelt> row;
  const Vec3 across = conv.body.pose.linear().col(2).cross(conv.direction);
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    PartState& p = parts_[i];
    if (p.holder != Holder::conveyor || p.conveyor != c || p.support >= 0) continue;
    if (!runs) {
      halt(p);
      sync(i);
      continue;
    }
    const Location pose = p.pose_at(now_);
    OnBelt o{i, conv.direction.dot(pose.translation() - b.centre), 0, 0, kInf, -kInf, 0};
    const double mid = across.dot(pose.translation());
    for (const auto& v : p.def->mesh.vertices) {
      const Vec3 w = pose.linear() * v;
      o.front = std::max(o.front, conv.direction.dot(w)), o.back = std::min(o.back, conv.direction.dot(w));
      o.lo = std::min(o.lo, mid + across.dot(w)), o.hi = std::max(o.hi, mid + across.dot(w));
    }
    if (p.def->mesh.vertices.empty()) o.lo = o.hi = mid;
    row.push_back(o);
  }
  if (!runs) return;
  // Downstream first: each part stops at the end stop or against a still part ahead of it in its
  // band, whichever comes first (an accumulating belt: the belt slides under a blocked part).
  // All parts of a running belt move at one speed, so a gap closes only once the part ahead is
  // still: a moving part ahead is ignored, and when it stops the belt is queued again (so a
  // belt whose parts leave at a sink never re-anchors them).
  std::sort(row.begin(), row.end(), [](const OnBelt& x, const OnBelt& y) { return x.s != y.s ? x.s > y.s : x.i < y.i; });
  std::vector<const OnBelt*> ahead;  // the still parts not hidden behind another in all their band
  for (auto& o : row) {
    o.stop = b.end;
    int blocker = -1;
    for (const OnBelt* a : ahead)
      if (std::min(o.hi, a->hi) - std::max(o.lo, a->lo) > 1e-9 && a->stop + a->back - o.front < o.stop)
        o.stop = a->stop + a->back - o.front, blocker = static_cast<int>(a->i);
    o.stop = std::max(o.stop, o.s);  // never backwards (a part placed overlapping one ahead stays)
    PartState& p = parts_[o.i];
    const bool arriving = !p.velocity.isZero() && p.end_s <= now_;  // settle() stops it and reports it
    // Shorter than this is no motion (the rounding of the positions along the belt).
    const double still = 1e-9 + 16 * std::numeric_limits<double>::epsilon() *
                                    (b.centre.cwiseAbs().maxCoeff() + std::abs(o.s) + std::abs(o.stop));
    if (arriving) {
      o.stop = o.s;
    } else if (o.stop > o.s + still) {
      const double end = now_ + (o.stop - o.s) / conv.speed_mm_s;
      if (!(end > now_)) {
        // Too short a way to take time at the clock's resolution (a very fast belt): it is there.
        halt(p);
        p.anchor.translation() += conv.direction * (o.stop - o.s);
        note_change();
        arrived(o.i, c, blocker);
        o.stop = o.s = conv.direction.dot(p.anchor.translation() - b.centre);
      } else if (p.velocity.isZero() || std::abs(p.end_s - end) > 1e-9) {  // keep the anchor of an unchanged run
        p.anchor = p.pose_at(now_), p.anchor_s = now_, p.velocity = conv.direction * conv.speed_mm_s, p.end_s = end;
        note_change();
      }
    } else {
      halt(p);
    }
    if (!arriving) p.behind = blocker;
    sync(o.i);
    if (!p.velocity.isZero() && !arriving) continue;
    std::erase_if(ahead, [&](const OnBelt* a) {
      return o.lo <= a->lo && a->hi <= o.hi && o.stop + o.back <= a->stop + a->back;
    });
    ahead.push_back(&o);
  }
}

bool DeviceClock::inside(const PartState& p, const Region& r) const {
  if (p.holder == Holder::removed || p.holder == Holder::carried) return false;
  // A moving part's interval comes from its anchor, so every instant of one run of the belt is
  // computed from the same numbers (the entry time found by next_change() tests as inside).
  if (p.velocity.isZero() || now_ >= p.end_s) return r.contains(p.pose_at(now_).translation());
  const Interval i = crossing(r, p.anchor.translation(), p.anchor_s, p.velocity);
  return i.in <= now_ && now_ < i.out;
}

bool DeviceClock::overlaps(const PartState& p, const Region& r) const {
  if (p.holder == Holder::removed || p.holder == Holder::carried) return false;
  if (p.velocity.isZero() || now_ >= p.end_s) return !hull(p, r, p.pose_at(now_), now_, Vec3::Zero()).empty();
  const Interval i = hull(p, r, p.anchor, p.anchor_s, p.velocity);
  return i.in <= now_ && now_ < i.out;
}

bool DeviceClock::sensed(const Sensor& s) const {
  for (const auto& p : parts_) {
    if (!(s.pattern.empty() || name_matches(s.pattern, p.def->name)) || !(s.colour.empty() || s.colour == p.def->colour))
      continue;
    if (s.sensing == Sensing::origin ? inside(p, s.region) : overlaps(p, s.region)) return true;
  }
  return false;
}

bool DeviceClock::spot_empty(std::size_t f) const {
  for (const auto& p : parts_)
    if (inside(p, cell_->feeders[f].spot)) return false;
  return true;
}

void DeviceClock::feed(std::size_t f, int line) {
  const Feeder& fd = cell_->feeders[f];
  if (fed_[f] >= fd.count) return;
  PartDef d = fd.part;
  d.name = fmt::format("{}{}", fd.prefix, fed_[f] + 1);
  if (!fd.colours.empty()) d.colour = fd.colours[static_cast<std::size_t>(fed_[f]) % fd.colours.size()];
  ++fed_[f];
  // A copy restored from before (World::rewind_to) feeds again: the definitions are append-only.
  shared_->fed.push_back(std::move(d));
  PartState p;
  p.def = &shared_->fed.back();
  p.feeder = static_cast<int>(f);
  p.ordinal = fed_[f] - 1;
  p.tolerance_mm = resting_tolerance(fd.part.mesh);
  p.radius_mm = mesh_radius(fd.part.mesh);
  parts_.push_back(std::move(p));
  place(parts_.size() - 1, fd.part.pose);
  record({now_, "feeder", parts_.back().def->name, fd.name, line});
}

void DeviceClock::remove(std::size_t i, const std::string& by) {
  detach(i);
  PartState& p = parts_[i];
  p.anchor = p.pose_at(now_), p.anchor_s = now_, p.velocity.setZero(), p.end_s = kInf;
  const int belt = p.holder == Holder::conveyor ? p.conveyor : -1;
  p.holder = Holder::removed;
  note_change();
  record({now_, "sink", p.def->name, by, 0});
  // The parts resting on it go with it (a pallet emptied into a sink).
  while (parts_[i].first_rider >= 0) remove(static_cast<std::size_t>(parts_[i].first_rider), by);
  if (belt >= 0) queue(belt);  // the parts queued behind it move on
}

void DeviceClock::change(int k, bool on, int line) {
  if (signal(k) == on) return;
  next_ok_ = false;
  if (on) signals_.insert(k);
  else signals_.erase(k);
  record({now_, "signal", std::to_string(k), on_off(on), line});
  for (std::size_t r = 0; r < cell_->logic.size(); ++r) {
    const auto& rule = cell_->logic[r];
    if (rule.at_s < 0 && rule.when == k && rule.is_on == on)
      timers_.push_back({now_ + rule.after_s, seq_++, rule.set, rule.to_on, 0});
  }
  for (std::size_t c = 0; c < cell_->conveyors.size(); ++c)
    if (cell_->conveyors[c].signal == k) queue(static_cast<int>(c));  // it started or stopped
  // A gated sink empties on its edge: every part whose origin is in it then.
  for (const auto& s : cell_->sinks)
    if (s.signal == k && s.on_rising == on)
      for (std::size_t i = 0; i < parts_.size(); ++i)
        if (parts_[i].holder != Holder::removed && inside(parts_[i], s.region)) remove(i, s.name);
  for (std::size_t f = 0; f < cell_->feeders.size(); ++f)
    if (on && cell_->feeders[f].signal == k) {
      if (spot_empty(f)) feed(f, line);
      else record({now_, "feeder_blocked", cell_->feeders[f].name, "spot occupied", line});
    }
}

void DeviceClock::set_signal(int k, bool on, int line) {
  change(k, on, line);
  settle();
}

void DeviceClock::settle() {
  next_ok_ = false;
  for (std::size_t round = 0;; ++round) {
    if (round > shared_->max_rounds)
      throw DeviceError(fmt::format("logic rules switch signals forever at {} s (a loop of rules without delay)", now_));
    bool changed = false;
    // Timers due now, oldest first (ties in the order they were set).
    std::sort(timers_.begin(), timers_.end(),
              [](const Timer& a, const Timer& b) { return a.time_s != b.time_s ? a.time_s < b.time_s : a.seq < b.seq; });
    if (!timers_.empty() && timers_.front().time_s <= now_) {
      const Timer t = timers_.front();
      timers_.erase(timers_.begin());
      change(t.set, t.on, t.line);
      continue;
    }
    for (std::size_t r = 0; r < cell_->logic.size(); ++r)
      if (cell_->logic[r].at_s >= 0 && !timed_done_[r] && cell_->logic[r].at_s <= now_) {
        timed_done_[r] = true;
        changed_s_ = now_;
        timers_.push_back({now_ + cell_->logic[r].after_s, seq_++, cell_->logic[r].set, cell_->logic[r].to_on, 0});
        changed = true;
      }
    for (std::size_t i = 0; i < parts_.size(); ++i) {
      PartState& p = parts_[i];
      if (p.support < 0 && !p.velocity.isZero() && p.end_s <= now_) {
        const int behind = p.behind;
        p.anchor = p.pose_at(now_), p.anchor_s = now_, p.velocity.setZero(), p.end_s = kInf;  // still
        note_change();
        arrived(i, p.conveyor, behind);
        queue(parts_[i].conveyor);  // the parts behind it now stop against it
        changed = true;
      }
    }
    for (std::size_t i = 0; i < parts_.size(); ++i)
      for (const auto& s : cell_->sinks)
        if (s.signal == 0 && parts_[i].holder != Holder::removed && inside(parts_[i], s.region)) {
          remove(i, s.name);
          changed = true;
        }
    for (std::size_t f = 0; f < cell_->feeders.size(); ++f)
      if (cell_->feeders[f].when_empty && fed_[f] < cell_->feeders[f].count && spot_empty(f)) {
        feed(f, 0);
        changed = true;
      }
    // Sensors on one signal are wired in parallel (OR).
    for (const auto& [k, list] : shared_->sensor_signals) {
      bool on = false;
      for (const std::size_t s : list)
        if ((on = sensed(cell_->sensors[s]))) break;
      if (on != signal(k)) {
        change(k, on, 0);
        changed = true;
      }
    }
    if (!changed) return;
  }
}

double DeviceClock::next_change() const {
  if (next_ok_) return next_;
  double next = kInf;
  for (const auto& t : timers_) next = std::min(next, t.time_s);
  for (const auto& r : cell_->logic)
    if (r.at_s > now_) next = std::min(next, r.at_s);
  const auto later = [&](double t) {
    if (t > now_) next = std::min(next, t);
  };
  for (const auto& p : parts_) {
    if (p.velocity.isZero() || p.end_s <= now_ || p.holder != Holder::conveyor) continue;
    later(p.end_s);
    const auto edges = [&](const Interval& i) {
      if (i.empty()) return;
      if (i.in <= p.end_s) later(i.in);
      if (i.out <= p.end_s) later(i.out);
    };
    const auto origin = [&](const Region& r) { edges(crossing(r, p.anchor.translation(), p.anchor_s, p.velocity)); };
    for (const auto& s : cell_->sensors) {
      if (!(s.pattern.empty() || name_matches(s.pattern, p.def->name)) || !(s.colour.empty() || s.colour == p.def->colour))
        continue;
      if (s.sensing == Sensing::origin) origin(s.region);
      else edges(hull(p, s.region, p.anchor, p.anchor_s, p.velocity));
    }
    for (const auto& s : cell_->sinks)
      if (s.signal == 0) origin(s.region);
    for (const auto& f : cell_->feeders)
      if (f.when_empty) origin(f.spot);
  }
  next_ = next;
  next_ok_ = true;
  return next;
}

void DeviceClock::advance_to(double t) {
  // Between changes nothing can happen (the state is settled after each), so the clock just
  // moves: the collision world advances it at every checked pose.
  while (now_ < t) {
    const double next = next_change();
    if (next > t) {
      now_ = t;
      return;
    }
    now_ = next;
    settle();
  }
}

bool DeviceClock::rewind(double t) {
  if (!(t < now_)) return t == now_;
  // The last change: a holder, motion or presence (changed_s_), a timer set, or any event
  // (signals, feeders, grasps, releases all leave one).
  const double last = std::max(changed_s_, last_event_s_);
  if (t < last) return false;
  now_ = t;  // the parts move by their anchors and velocities, which held since `last`
  return true;
}

void DeviceClock::carry(std::size_t i, int line) {
  detach(i);
  PartState& p = parts_[i];
  p.anchor = p.pose_at(now_), p.anchor_s = now_, p.velocity.setZero(), p.end_s = kInf;
  const int belt = p.holder == Holder::conveyor ? p.conveyor : -1;
  p.holder = Holder::carried, p.conveyor = -1, p.object = -1;
  note_change();
  sync(i);  // the parts resting on it come along
  if (belt >= 0) queue(belt);  // the parts queued behind it move on
  std::string with;
  for (std::size_t k = 0; k < parts_.size(); ++k)
    if (k != i && parts_[k].holder == Holder::carried) with += (with.empty() ? "with " : ", ") + parts_[k].def->name;
  record({now_, "grasp", parts_[i].def->name, with, line});
  settle();
}

void DeviceClock::move_carried(std::size_t i, const Location& pose) {
  if (parts_[i].holder != Holder::carried) return;
  parts_[i].anchor = pose, parts_[i].anchor_s = now_;
  // The parts resting on it, without counting a change (they were carried before and after).
  const std::uint64_t rev = revision_;
  const double changed = changed_s_;
  sync(i);
  revision_ = rev, changed_s_ = changed;
}

void DeviceClock::put_down(std::size_t i, const Location& pose, int line) {
  place(i, pose);
  const PartState& p = parts_[i];
  const Vec3 t = pose.translation();
  std::string on;
  if (p.support >= 0) on = parts_[static_cast<std::size_t>(p.support)].def->name;
  else if (p.holder == Holder::conveyor) on = cell_->conveyors[static_cast<std::size_t>(p.conveyor)].name;
  record({now_, "release", p.def->name, on, line});
  record({now_, "placed", p.def->name, fmt::format("{:.6f} {:.6f} {:.6f}", t.x(), t.y(), t.z()), line});
  settle();
}

}  // namespace asimov::motion
