#include "asimov/interpreter/storage.hpp"

#include "evaluator.hpp"

#include "asimov/core/output_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <tuple>
#include <filesystem>
#include <unistd.h>

namespace asimov::interpreter {
namespace {

// `line` is `.END` (any case, any indentation, optional comment).
bool is_end_line(const std::string& line) {
  std::size_t i = line.find_first_not_of(" \t");
  if (i == std::string::npos || line.size() - i < 4) return false;
  std::string word = line.substr(i, 4);
  std::transform(word.begin(), word.end(), word.begin(), [](unsigned char c) { return std::tolower(c); });
  if (word != ".end") return false;
  return i + 4 == line.size() || line[i + 4] == ' ' || line[i + 4] == '\t' || line[i + 4] == ';';
}

std::string element_name(const std::string& base, const Index& idx, bool subscripted) {
  if (!subscripted) return base;
  int last = 0;  // trailing zero indices are implied (a[1] is a[1,0,0])
  for (int k = 0; k < 3; ++k)
    if (idx[static_cast<std::size_t>(k)] != 0) last = k;
  std::string s = base + "[";
  for (int k = 0; k <= last; ++k) s += fmt::format("{}{}", k ? "," : "", idx[static_cast<std::size_t>(k)]);
  return s + "]";
}

std::string row(const GlobalEntry& e, const std::vector<double>& values) {
  std::string s = e.name;
  for (double v : values) s += ' ' + format_real(v);
  return s + '\n';
}

}  // namespace

std::vector<GlobalEntry> global_entries(const Memory& memory) {
  std::vector<GlobalEntry> out;
  const std::size_t n = std::min(memory.symbols.globals.size(), memory.globals.size());
  for (std::size_t slot = 0; slot < n; ++slot) {
    const std::string& name = memory.symbols.globals[slot];
    if (name.find('@') != std::string::npos) continue;  // LOCAL: name@program
    const Variable& v = memory.globals[slot];
    if (v.scalar) out.push_back({name, name, {0, 0, 0}, &*v.scalar});
    for (const auto& [idx, value] : v.elements) out.push_back({element_name(name, idx, true), name, idx, &value});
  }
  std::sort(out.begin(), out.end(), [](const GlobalEntry& a, const GlobalEntry& b) {
    return std::tie(a.base, a.index) < std::tie(b.base, b.index);
  });
  return out;
}

std::string format_real(double x) {
  if (x == 0) return "0";
  return fmt::format("{}", x);  // fmt prints the shortest round-trip form
}

std::vector<std::string> program_lines(const Program& program) {
  std::vector<std::string> lines;
  if (!program.text || program.line < 1) return lines;
  const auto& text = *program.text;
  for (std::size_t i = static_cast<std::size_t>(program.line - 1); i < text.size(); ++i) {
    lines.push_back(text[i]);
    if (i + 1 > static_cast<std::size_t>(program.line) && is_end_line(text[i])) break;
  }
  return lines;
}

std::string store_text(const Memory& memory, const std::vector<std::string>& programs, bool locations_only) {
  std::string out;
  if (!locations_only) {
    for (const std::string& name : programs) {
      const auto it = memory.symbols.program_slots.find(name);
      if (it == memory.symbols.program_slots.end()) continue;
      const auto& p = memory.programs[static_cast<std::size_t>(it->second)];
      if (!p) continue;
      for (const std::string& line : program_lines(*p)) out += line + '\n';
      out += '\n';
    }
  }
  std::string locations, reals, strings;
  for (const GlobalEntry& e : global_entries(memory)) {
    if (const auto* t = std::get_if<motion::Location>(e.value)) {
      const motion::Xyzoat x = motion::decompose(*t);
      locations += row(e, {x.begin(), x.end()});
    } else if (const auto* j = std::get_if<robots::JointVector>(e.value)) {
      locations += row(e, {j->data(), j->data() + j->size()});
    } else if (const auto* r = std::get_if<double>(e.value)) {
      reals += row(e, {*r});
    } else if (const auto* s = std::get_if<std::string>(e.value)) {
      strings += e.name + " \"" + *s + "\"\n";  // strings never hold '"' (dialect §1)
    }
  }
  if (!locations.empty()) out += ".LOCATIONS\n" + locations + ".END\n";
  if (locations_only) return out;
  if (!reals.empty()) out += ".REALS\n" + reals + ".END\n";
  if (!strings.empty()) out += ".STRINGS\n" + strings + ".END\n";
  return out;
}

Result<void> write_file_atomic(const std::string& path, const std::string& text) {
  // The one output writer: a device, FIFO or link to one is refused, never replaced.
  return core::write_output_file(path, text);
}

}  // namespace asimov::interpreter
