#include "errors.hpp"

#include "asimov/collision/text_file.hpp"

#include "asimov/interpreter/interpreter.hpp"

#include <fmt/format.h>

#include <array>

namespace asimov::interpreter {
namespace {

constexpr std::array<std::string_view, 13> kMessageTexts = {
    "*Syntax error*",
    "*Undefined program or variable name*",
    "*Undefined value*",
    "*Illegal value*",
    "*Division by zero*",
    "*Too many nested calls*",
    "*Too many statements*",  // our limit on executed statements (runaway programs)
    "*Motion error*",         // replaced by the simulator's own text
    "*Not supported in simulation*",
    "*Program interrupted*",  // Ctrl-C (Limits::interrupt) between two steps or in a motion
    "*Wait limit exceeded*",  // WAIT still false after Limits::max_wait_s simulated seconds
    "*Out of memory*",        // the program's data past kMaxDataBytes (limits.hpp)
    "*Program not executable*",  // a program LOAD marked: it had an error (dialect §8)
};
static_assert(kMessageTexts.size() == static_cast<std::size_t>(Message::count));

struct ErrorCode {
  int code;
  std::string_view message;
};
constexpr ErrorCode kErrorCodes[] = {
    {-450, "*Syntax error*"},
    {-406, "*Undefined program or variable name*"},
    {-401, "*Undefined value*"},
    {-402, "*Illegal value*"},
    {-409, "*Division by zero*"},
    {-413, "*Too many nested calls*"},
    {-414, "*Too many statements*"},
    {-1300, "*Not supported in simulation*"},
    {-415, "*Program interrupted*"},
    {-416, "*Wait limit exceeded*"},
    {-304, "*Program not executable*"},
    {-610, "*Location out of reach*"},
    {-611, "*Joint limit exceeded*"},
    {-612, "*Singularity on straight-line path*"},
    {-620, "*Collision*"},
    {-500, "*File not found*"},
    {-503, "*File already exists*"},
    {-504, "*Unexpected end of file*"},
};

}  // namespace

int error_code(std::string_view message) {
  for (const ErrorCode& e : kErrorCodes)
    if (e.message == message) return e.code;
  return -1300;
}

std::string error_text(int code) {
  if (code == 0) return {};
  for (const ErrorCode& e : kErrorCodes)
    if (e.code == code) return std::string(e.message);
  return "*Unknown error code*";
}

std::string_view message_text(Message kind) {
  return kMessageTexts[static_cast<std::size_t>(kind)];
}

Fault fault(Message kind, std::string detail) { return Fault{kind, std::string(message_text(kind)), std::move(detail)}; }

void raise(Message kind, std::string detail) { throw fault(kind, std::move(detail)); }

void raise_text(std::string message, std::string detail) {
  throw Fault{Message::motion, std::move(message), std::move(detail)};
}

std::string format_pause(const RunResult& r) {
  if (r.status != RunStatus::paused && r.status != RunStatus::halted) return {};
  return fmt::format("Program {}: {}, step {}", r.status == RunStatus::paused ? "paused" : "halted", r.program,
                     r.step);
}

const MotionStep* motion_at_step(const std::vector<MotionStep>& motions, int step) {
  const MotionStep* hit = nullptr;
  for (const MotionStep& m : motions)
    if (m.step == step) {
      if (hit) return nullptr;
      hit = &m;
    }
  return hit;
}

std::string format_closest(const motion::Simulator& sim, const std::vector<MotionStep>& motions) {
  const std::vector<motion::ClearanceApproach> near = sim.recorders().clearance.nearest_first();
  if (near.empty()) return {};
  const motion::ClearanceApproach& a = near.front();
  const MotionStep* m = motion_at_step(motions, a.step);
  const std::string where = m ? fmt::format("{}, line {}", m->program, m->line) : fmt::format("step {}", a.step);
  return fmt::format("Closest approach: {} / {} {:.3f} mm at t = {:.6f} s ({})\n", sim.body_name(a.pair.a),
                     sim.body_name(a.pair.b), a.distance_mm, a.time_s, where);
}

std::string format_interrupt(const RunResult& r) {
  if (!r.interrupt) return {};
  const auto& h = *r.interrupt;
  std::string out = fmt::format("motion halted at t = {:.6f} s, {:.1f} % of its path\njoints", h.time_s,
                                100 * h.path_fraction);
  for (Eigen::Index i = 0; i < h.joints.size(); ++i) out += fmt::format(" {:.3f}", h.joints[i]);
  return out + '\n';
}

// The report of dialect §10 (declared in interpreter.hpp, the public face).
std::string format_diagnostic(const Diagnostic& d) {
  // The source line and details quote the file: escape sequences and bad bytes never reach
  // the terminal raw (collision::printable).
  std::string out = d.message;
  if (!d.detail.empty()) out += "  " + collision::printable(d.detail);
  out += '\n';
  const bool syntax = d.column > 0;
  if (syntax) {
    out += fmt::format(" {}:{}:{}", d.file, d.line, d.column);
    if (!d.program.empty()) out += fmt::format("  ({}, step {})", d.program, d.step);
    out += '\n';
  } else if (!d.program.empty()) {
    out += fmt::format(" {}, step {} ({}:{})\n", d.program, d.step, d.file, d.line);
  } else if (!d.file.empty()) {
    out += d.line > 0 ? fmt::format(" {}:{}\n", d.file, d.line) : fmt::format(" {}\n", d.file);
  }
  if (!d.source_line.empty()) {
    out += "    " + collision::printable(d.source_line) + '\n';
    if (syntax) {
      // Caret under the 1-based column; tabs copied so it lines up with the source.
      std::string pad = "    ";
      for (int i = 0; i + 1 < d.column && i < static_cast<int>(d.source_line.size()); ++i)
        pad += d.source_line[static_cast<std::size_t>(i)] == '\t' ? '\t' : ' ';
      out += pad + "^\n";
    }
  }
  return out;
}

}  // namespace asimov::interpreter
