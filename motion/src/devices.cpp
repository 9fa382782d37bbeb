#include "asimov/motion/device_clock.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace asimov::motion {
namespace {
using collision::Vec3;
constexpr double kInf = std::numeric_limits<double>::infinity();
// A part rests on a conveyor when its lowest point is this close to the belt's top face.
constexpr double kOnBeltMm = 1e-3;
// Changes at one instant before the rules count as a loop (docs/cell-format.md "logic").
constexpr int kMaxChangesPerInstant = 10000;

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

Location PartState::pose_at(double t) const {
  if (velocity.isZero()) return anchor;
  Location p = anchor;
  p.translation() += velocity * (std::min(t, end_s) - anchor_s);
  return p;
}

DeviceClock::DeviceClock(const Workcell& cell)
    : cell_(&cell), timed_done_(cell.logic.size(), false), fed_(cell.feeders.size(), 0) {
  for (const auto& d : cell.parts) {
    parts_.push_back(PartState{d});
    parts_.back().ordinal = static_cast<int>(parts_.size() - 1);
    place(parts_.size() - 1, d.pose);
  }
  settle();
}

bool DeviceClock::running(int c) const {
  const auto& conv = cell_->conveyors[static_cast<std::size_t>(c)];
  return conv.speed_mm_s > 0 && (conv.signal == 0 || signal(conv.signal));
}

void DeviceClock::place(std::size_t i, const Location& pose) {
  note_change();
  PartState& p = parts_[i];
  p.holder = Holder::world, p.conveyor = -1, p.anchor = pose, p.anchor_s = now_;
  p.velocity.setZero(), p.end_s = kInf, p.behind = -1;
  const double bottom = lowest_z(p.def, pose);
  for (std::size_t c = 0; c < cell_->conveyors.size(); ++c) {
    const auto& conv = cell_->conveyors[c];
    const Belt b = belt(conv);
    const Vec3 local = conv.body.pose.inverse() * pose.translation();
    const Vec3 half = conv.body.size / 2;
    if (std::abs(bottom - b.centre.z()) > kOnBeltMm || std::abs(local.x()) > half.x() || std::abs(local.y()) > half.y())
      continue;
    p.holder = Holder::conveyor, p.conveyor = static_cast<int>(c);
    queue(static_cast<int>(c));
    return;
  }
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
  // and behind the origin, and the band across the belt it covers.
  struct OnBelt {
    std::size_t i;
    double s, front, back, lo, hi, stop;
  };
  std::vector<OnBelt> row;
  const Vec3 across = conv.body.pose.linear().col(2).cross(conv.direction);
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    PartState& p = parts_[i];
    if (p.holder != Holder::conveyor || p.conveyor != c) continue;
    if (!runs) {
      halt(p);
      continue;
    }
    const Location pose = p.pose_at(now_);
    OnBelt o{i, conv.direction.dot(pose.translation() - b.centre), 0, 0, kInf, -kInf, 0};
    const double mid = across.dot(pose.translation());
    for (const auto& v : p.def.mesh.vertices) {
      const Vec3 w = pose.linear() * v;
      o.front = std::max(o.front, conv.direction.dot(w)), o.back = std::min(o.back, conv.direction.dot(w));
      o.lo = std::min(o.lo, mid + across.dot(w)), o.hi = std::max(o.hi, mid + across.dot(w));
    }
    if (p.def.mesh.vertices.empty()) o.lo = o.hi = mid;
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
    if (arriving) {
      o.stop = o.s;
    } else if (o.stop > o.s + 1e-9) {
      const double end = now_ + (o.stop - o.s) / conv.speed_mm_s;
      if (p.velocity.isZero() || std::abs(p.end_s - end) > 1e-9) {  // keep the anchor of an unchanged run
        p.anchor = p.pose_at(now_), p.anchor_s = now_, p.velocity = conv.direction * conv.speed_mm_s, p.end_s = end;
        note_change();
      }
    } else {
      halt(p);
    }
    if (!arriving) p.behind = blocker;
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

bool DeviceClock::sensed(const Sensor& s) const {
  for (const auto& p : parts_)
    if ((s.pattern.empty() || name_matches(s.pattern, p.def.name)) && (s.colour.empty() || s.colour == p.def.colour) &&
        inside(p, s.region))
      return true;
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
  parts_.push_back(PartState{std::move(d)});
  parts_.back().feeder = static_cast<int>(f);
  parts_.back().ordinal = fed_[f] - 1;
  place(parts_.size() - 1, fd.part.pose);
  events_.push_back({now_, "feeder", parts_.back().def.name, fd.name, line});
}

void DeviceClock::change(int k, bool on, int line) {
  if (signal(k) == on) return;
  if (on) signals_.insert(k);
  else signals_.erase(k);
  events_.push_back({now_, "signal", std::to_string(k), on_off(on), line});
  for (std::size_t r = 0; r < cell_->logic.size(); ++r) {
    const auto& rule = cell_->logic[r];
    if (rule.at_s < 0 && rule.when == k && rule.is_on == on)
      timers_.push_back({now_ + rule.after_s, seq_++, rule.set, rule.to_on, 0});
  }
  for (std::size_t c = 0; c < cell_->conveyors.size(); ++c)
    if (cell_->conveyors[c].signal == k) queue(static_cast<int>(c));  // it started or stopped
  for (std::size_t f = 0; f < cell_->feeders.size(); ++f)
    if (on && cell_->feeders[f].signal == k) {
      if (spot_empty(f)) feed(f, line);
      else events_.push_back({now_, "feeder_blocked", cell_->feeders[f].name, "spot occupied", line});
    }
}

void DeviceClock::set_signal(int k, bool on, int line) {
  change(k, on, line);
  settle();
}

void DeviceClock::settle() {
  for (int round = 0;; ++round) {
    if (round > kMaxChangesPerInstant)
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
      if (!p.velocity.isZero() && p.end_s <= now_) {
        const auto& conv = cell_->conveyors[static_cast<std::size_t>(p.conveyor)];
        const int behind = p.behind;
        p.anchor = p.pose_at(now_), p.anchor_s = now_, p.velocity.setZero(), p.end_s = kInf;  // still
        note_change();
        if (behind >= 0)
          events_.push_back({now_, "conveyor_queue", p.def.name, parts_[static_cast<std::size_t>(behind)].def.name, 0});
        else
          events_.push_back({now_, "conveyor_end", p.def.name, conv.name, 0});
        queue(p.conveyor);  // the parts behind it now stop against it
        changed = true;
      }
    }
    for (auto& p : parts_)
      for (const auto& s : cell_->sinks)
        if (inside(p, s.region)) {
          p.anchor = p.pose_at(now_), p.anchor_s = now_, p.velocity.setZero(), p.end_s = kInf;
          const int belt = p.holder == Holder::conveyor ? p.conveyor : -1;
          p.holder = Holder::removed;
          note_change();
          if (belt >= 0) queue(belt);  // the parts queued behind it move on
          events_.push_back({now_, "sink", p.def.name, s.name, 0});
          changed = true;
        }
    for (std::size_t f = 0; f < cell_->feeders.size(); ++f)
      if (cell_->feeders[f].when_empty && fed_[f] < cell_->feeders[f].count && spot_empty(f)) {
        feed(f, 0);
        changed = true;
      }
    for (const auto& s : cell_->sensors) {
      const bool on = sensed(s);
      if (on != signal(s.signal)) {
        change(s.signal, on, 0);
        changed = true;
      }
    }
    if (!changed) return;
  }
}

double DeviceClock::next_change() const {
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
    const auto edges = [&](const Region& r) {
      const Interval i = crossing(r, p.anchor.translation(), p.anchor_s, p.velocity);
      if (i.empty()) return;
      if (i.in <= p.end_s) later(i.in);
      if (i.out <= p.end_s) later(i.out);
    };
    for (const auto& s : cell_->sensors) edges(s.region);
    for (const auto& s : cell_->sinks) edges(s.region);
    for (const auto& f : cell_->feeders)
      if (f.when_empty) edges(f.spot);
  }
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
  const double last = std::max(changed_s_, events_.empty() ? -kInf : events_.back().time_s);
  if (t < last) return false;
  now_ = t;  // the parts move by their anchors and velocities, which held since `last`
  return true;
}

void DeviceClock::carry(std::size_t i, int line) {
  PartState& p = parts_[i];
  p.anchor = p.pose_at(now_), p.anchor_s = now_, p.velocity.setZero(), p.end_s = kInf;
  const int belt = p.holder == Holder::conveyor ? p.conveyor : -1;
  p.holder = Holder::carried, p.conveyor = -1;
  note_change();
  if (belt >= 0) queue(belt);  // the parts queued behind it move on
  events_.push_back({now_, "grasp", p.def.name, "", line});
  settle();
}

void DeviceClock::move_carried(std::size_t i, const Location& pose) {
  if (parts_[i].holder == Holder::carried) parts_[i].anchor = pose, parts_[i].anchor_s = now_;
}

void DeviceClock::put_down(std::size_t i, const Location& pose, int line) {
  place(i, pose);
  const Vec3 t = pose.translation();
  events_.push_back({now_, "release", parts_[i].def.name,
                     parts_[i].holder == Holder::conveyor ? cell_->conveyors[static_cast<std::size_t>(parts_[i].conveyor)].name
                                                           : "",
                     line});
  events_.push_back({now_, "placed", parts_[i].def.name, fmt::format("{:.6f} {:.6f} {:.6f}", t.x(), t.y(), t.z()), line});
  settle();
}

}  // namespace asimov::motion
