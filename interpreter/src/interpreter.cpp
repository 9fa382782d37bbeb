// Interpreter: LOAD (parse -> check -> install atomically) and EXECUTE (evaluator).
#include "asimov/interpreter/interpreter.hpp"

#include "checker.hpp"
#include "evaluator.hpp"
#include "limits.hpp"
#include "parser.hpp"

#include <fmt/format.h>

#include "asimov/collision/text_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <fstream>
#include <sstream>

namespace asimov::interpreter {

namespace {

// Adds program and step to syntax errors found by the parser (which parses line by line).
void locate_in_programs(const ParsedSource& source, std::vector<Diagnostic>& diagnostics) {
  for (Diagnostic& d : diagnostics) {
    if (!d.program.empty() || d.line < 1) continue;
    // The nearest .PROGRAM above the line, unless an .END closes it first.
    for (int i = d.line - 2; i >= 0; --i) {
      const auto& stmt = source.lines[static_cast<std::size_t>(i)].statement;
      if (!stmt) continue;
      if (const auto* h = boost::get<ast::ProgramHeader>(&*stmt)) {
        d.program = normalize_name(h->name);
        d.step = d.line - (i + 1);
        break;
      }
      const auto* in = boost::get<ast::Instruction>(&*stmt);
      if (in && in->kw == ast::Kw::dot_end) break;
    }
  }
}

// The program whose lines hold file line `line` (its .PROGRAM line included); "" outside all.
std::string program_at(const ParsedSource& source, int line) {
  for (int i = std::min(line, static_cast<int>(source.lines.size())) - 1; i >= 0; --i) {
    const auto& stmt = source.lines[static_cast<std::size_t>(i)].statement;
    if (!stmt) continue;
    if (const auto* h = boost::get<ast::ProgramHeader>(&*stmt)) return normalize_name(h->name);
    const auto* in = boost::get<ast::Instruction>(&*stmt);
    if (in && in->kw == ast::Kw::dot_end && i + 1 < line) return {};
  }
  return {};
}

}  // namespace

struct Interpreter::Impl {
  motion::Simulator& sim;
  std::ostream& out;
  Memory memory;
  Limits limits;
  std::unique_ptr<Evaluator> evaluator;  // kept between runs: the monitor speed persists
  std::istream* input = nullptr;         // PROMPT (null: std::cin)
  bool interactive = false;

  Evaluator& eval() {
    if (!evaluator) {
      evaluator = std::make_unique<Evaluator>(sim, out, memory, limits);
      evaluator->set_input(input, interactive);
    }
    return *evaluator;
  }
};

Interpreter::Interpreter(motion::Simulator& sim, std::ostream& out)
    : impl_(std::make_unique<Impl>(Impl{sim, out, {}, {}, {}, nullptr, false})) {}

Interpreter::~Interpreter() = default;

std::vector<Diagnostic> Interpreter::load_source(const std::string& text, const std::string& file_name) {
  ParsedSource parsed = parse_source(text, file_name);
  Memory& m = impl_->memory;
  CheckResult checked = check_source(parsed, m.symbols, impl_->sim.robot().joint_count());
  locate_in_programs(parsed, parsed.errors);
  // V+ LOAD: a program with an error is marked not executable and the rest loads. An error
  // outside the programs (stray text, a data row) or a file-wide limit still loads nothing.
  std::set<std::string> broken;
  bool loadable = !parsed.truncated;
  for (const std::vector<Diagnostic>* group : {&parsed.errors, &checked.errors})
    for (const Diagnostic& d : *group) {
      const std::string name = d.line > 0 ? program_at(parsed, d.line) : std::string();
      if (name.empty()) loadable = false;
      else broken.insert(name);
    }
  // Syntax errors first, then checker errors, each group in line order; at most 20.
  std::vector<Diagnostic> all = std::move(parsed.errors);
  all.insert(all.end(), checked.errors.begin(), checked.errors.end());
  std::stable_sort(all.begin(), all.end(), [](const Diagnostic& a, const Diagnostic& b) { return a.line < b.line; });
  if (all.size() + checked.unreported > kMaxLoadErrors) {  // the cap is said, with what it left out
    const std::size_t more = all.size() + checked.unreported - kMaxLoadErrors;
    all.resize(kMaxLoadErrors);
    Diagnostic note;
    note.message = "*Too many errors*";
    note.detail = fmt::format("{} more not reported (at most {} per LOAD)", more, kMaxLoadErrors);
    note.file = file_name;
    all.push_back(std::move(note));
  }
  // V+ LOAD: a program with an error is marked not executable and the rest loads. An error
  // outside the programs (stray text, a data row, a file-wide limit) still loads nothing.
  if (!loadable) return all;
  // The data of this load must fit beside what the process holds (docs/limits.md); this
  // estimate leaves out the index tables, whose charge can still end the assignment below.
  auto out_of_memory = [&](const std::string& detail) {
    Diagnostic d;
    d.message = std::string(message_text(Message::out_of_memory));
    d.detail = detail;
    d.file = file_name;
    return std::vector<Diagnostic>{d};
  };
  if (data_bytes() + checked.data_bytes > kMaxDataBytes)
    return out_of_memory(fmt::format("the data sections need {} MiB; {} MiB of program data are already in use",
                                     (checked.data_bytes >> 20) + 1, data_bytes() >> 20));
  m.programs.resize(m.symbols.programs.size());
  m.globals.resize(m.symbols.globals.size());
  try {
    for (DataItem& item : checked.data) {  // globals of the same name are replaced
      Variable& v = m.globals[static_cast<std::size_t>(item.slot)];
      if (item.subscripted) {
        if (v.scalar) v = Variable{};
        if (!v.elements.empty() && kind_of(v.elements.begin()->second) != kind_of(item.value)) v = Variable{};
        v.elements.set(item.index, std::move(item.value));
      } else {
        v = Variable{};
        v.scalar = std::move(item.value);
      }
    }
  } catch (const Fault& f) {
    return out_of_memory(f.detail);
  }
  std::vector<int> installed;  // program slots of this load
  for (Program& p : checked.programs) {
    p.executable = broken.count(p.name) == 0;
    const int slot = m.symbols.program(p.name);
    installed.push_back(slot);
    m.programs.resize(m.symbols.programs.size());
    if (!m.programs[static_cast<std::size_t>(slot)]) m.load_order.push_back(p.name);
    m.programs[static_cast<std::size_t>(slot)] = std::make_shared<const Program>(std::move(p));
  }
  // A CALL to a program that nothing loaded is a warning now, an error when it executes (of a
  // program that can run: one marked not executable has its errors reported).
  for (int slot : installed) {
    const auto& p = m.programs[static_cast<std::size_t>(slot)];
    if (!p->executable) continue;
    for (const Instr& in : p->code) {
      if ((in.code != Code::call && in.code != Code::execute) || m.programs[static_cast<std::size_t>(in.program)])
        continue;
      Diagnostic d;
      d.message = "*Undefined program or variable name*";
      d.detail = m.symbols.programs[static_cast<std::size_t>(in.program)];
      locate_at(d, *p, in.line);
      d.warning = true;
      all.push_back(std::move(d));
    }
  }
  return all;
}

std::vector<Diagnostic> Interpreter::load_file(const std::string& path) {
  // A FIFO with no writer would block the read below forever: only regular files are read.
  if (const collision::InputFile f = collision::classify_input_file(path); f.missing || !f.not_regular.empty()) {
    Diagnostic d;
    d.message = f.missing ? "*File not found*" : "*Cannot read file*";
    d.detail = f.missing ? path : path + ": " + f.not_regular;
    return {d};
  }
  const Result<std::string> text = collision::read_file_bounded(path, collision::kMaxTextFileBytes);  // a folder, /dev/zero: refused
  if (!text) {
    Diagnostic d;
    d.message = "*Cannot read file*";
    d.detail = path + ": " + text.error().message;
    return {d};
  }
  return load_source(*text, path);
}

std::vector<std::string> Interpreter::program_names() const { return impl_->memory.load_order; }

bool Interpreter::has_program(const std::string& name) const {
  const Memory& m = impl_->memory;
  const auto it = m.symbols.program_slots.find(normalize_name(name));
  return it != m.symbols.program_slots.end() && static_cast<std::size_t>(it->second) < m.programs.size()
      && m.programs[static_cast<std::size_t>(it->second)];
}

std::optional<std::string> Interpreter::not_executable_from(const std::string& name) const {
  const Memory& m = impl_->memory;
  std::vector<int> todo;
  std::set<int> seen;
  const auto it = m.symbols.program_slots.find(normalize_name(name));
  if (it != m.symbols.program_slots.end()) todo.push_back(it->second);
  while (!todo.empty()) {
    const int slot = todo.back();
    todo.pop_back();
    if (!seen.insert(slot).second || static_cast<std::size_t>(slot) >= m.programs.size()) continue;
    const auto& p = m.programs[static_cast<std::size_t>(slot)];
    if (!p) continue;
    if (!p->executable) return p->name;
    for (const Instr& in : p->code)
      if (in.code == Code::call || in.code == Code::execute) todo.push_back(in.program);
  }
  return std::nullopt;
}

std::optional<std::string> Interpreter::set_signal(int k) { return impl_->eval().cell().monitor_signal(k); }

RunResult Interpreter::run(const std::string& name) {
  Memory& m = impl_->memory;
  const int slot = m.symbols.program(normalize_name(name));
  m.programs.resize(m.symbols.programs.size());
  return impl_->eval().run(slot);
}

Limits& Interpreter::limits() { return impl_->limits; }

void Interpreter::set_input(std::istream& in, bool interactive) {
  impl_->input = &in;
  impl_->interactive = interactive;
  if (impl_->evaluator) impl_->evaluator->set_input(&in, interactive);
}

const motion::CellRuntime* Interpreter::cell_state() { return impl_->eval().cell().state(); }

bool Interpreter::can_resume() const { return impl_->evaluator && impl_->evaluator->can_resume(); }

RunResult Interpreter::proceed() {
  return impl_->eval().resume(false);
}

RunResult Interpreter::retry() {
  return impl_->eval().resume(true);
}

void Interpreter::abort() {
  if (impl_->evaluator) impl_->evaluator->abort();
}

Memory& Interpreter::memory() { return impl_->memory; }

RunResult Interpreter::run_detached(const std::string& name) {
  Memory& m = impl_->memory;
  const int slot = m.symbols.program(normalize_name(name));
  m.programs.resize(m.symbols.programs.size());
  return impl_->eval().run(slot, false);
}

void Interpreter::set_step_hook(StepHook hook) { impl_->eval().scheduler().set_step_hook(std::move(hook)); }

double Interpreter::monitor_speed() const { return impl_->evaluator ? impl_->evaluator->arm().monitor_speed() : 100.0; }

void Interpreter::set_monitor_speed(double percent) { impl_->eval().arm().set_monitor_speed(percent); }

double Interpreter::program_speed() const { return impl_->evaluator ? impl_->evaluator->arm().settings().speed_always : 100.0; }

std::optional<double> Interpreter::next_program_speed() const {
  return impl_->evaluator ? impl_->evaluator->arm().settings().speed_next : std::nullopt;
}

}  // namespace asimov::interpreter
