#include "app/serve/protocol.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <utility>

namespace asimov::serve {
namespace {

Error invalid(std::string detail) { return Error{"*Invalid message*", std::move(detail), {}, 0, 0}; }

constexpr std::array<std::pair<const char*, RequestKind>, 11> kKinds = {{
    {"check", RequestKind::check}, {"monitor", RequestKind::monitor}, {"run", RequestKind::run},
    {"abort", RequestKind::abort}, {"list", RequestKind::list}, {"open", RequestKind::open},
    {"save", RequestKind::save}, {"replay", RequestKind::replay}, {"scene", RequestKind::scene},
    {"debug", RequestKind::debug}, {"pause", RequestKind::pause},
}};

constexpr std::array<std::pair<const char*, DebugAction>, 6> kActions = {{
    {"start", DebugAction::start}, {"step", DebugAction::step}, {"into", DebugAction::into},
    {"go", DebugAction::go}, {"abort", DebugAction::abort}, {"state", DebugAction::state},
}};

// A string field: absent is "" unless required; present must be a string within `limit` bytes.
bool field(const nlohmann::json& j, const char* key, std::size_t limit, bool required, std::string& out, Error& error) {
  const auto it = j.find(key);
  if (it == j.end()) {
    if (required) error = invalid(std::string("\"") + key + "\" is missing");
    return !required;
  }
  if (!it->is_string()) {
    error = invalid(std::string("\"") + key + "\" is not a string");
    return false;
  }
  const auto& s = it->get_ref<const std::string&>();
  if (s.size() > limit) {
    error = invalid(std::string("\"") + key + "\" is longer than " + std::to_string(limit) + " bytes");
    return false;
  }
  out = s;
  return true;
}

}  // namespace

const char* kind_name(RequestKind kind) {
  for (const auto& [name, k] : kKinds)
    if (k == kind) return name;
  return "?";
}

int json_depth(std::string_view text) {
  int depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (char c : text) {
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') in_string = true;
    else if (c == '[' || c == '{') deepest = std::max(deepest, ++depth);
    else if ((c == ']' || c == '}') && depth > 0) --depth;
  }
  return deepest;
}

Result<Request> parse_request(std::string_view message) {
  if (message.size() > kMaxMessageBytes) return invalid("longer than " + std::to_string(kMaxMessageBytes) + " bytes");
  if (json_depth(message) > kMaxDepth) return invalid("nested deeper than " + std::to_string(kMaxDepth));
  const nlohmann::json j = nlohmann::json::parse(message.begin(), message.end(), nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return invalid("not JSON (or not UTF-8)");
  if (!j.is_object()) return invalid("not a JSON object");
  Request r;
  Error error;
  std::string type;
  if (!field(j, "type", 32, true, type, error)) return error;
  bool known = false;
  for (const auto& [name, k] : kKinds)
    if (type == name) r.kind = k, known = true;
  if (!known) return invalid("unknown type \"" + type + "\"");
  if (const auto it = j.find("id"); it != j.end()) {
    if (!it->is_number_integer()) return invalid("\"id\" is not an integer");
    r.id = it->is_number_unsigned() ? static_cast<std::int64_t>(std::min<std::uint64_t>(it->get<std::uint64_t>(), INT64_MAX))
                                    : it->get<std::int64_t>();
  }
  const bool text = r.kind == RequestKind::check || r.kind == RequestKind::run || r.kind == RequestKind::save;
  if (r.kind == RequestKind::debug) {
    std::string action;
    if (!field(j, "action", 16, true, action, error)) return error;
    bool found = false;
    for (const auto& [name, a] : kActions)
      if (action == name) r.action = a, found = true;
    if (!found) return invalid("unknown action \"" + action + "\"");
    if (const auto it = j.find("breakpoints"); it != j.end()) {
      if (!it->is_array()) return invalid("\"breakpoints\" is not an array");
      if (it->size() > kMaxBreakpoints) return invalid("more than " + std::to_string(kMaxBreakpoints) + " breakpoints");
      for (const auto& b : *it) {
        if (!b.is_number_integer() || b.get<std::int64_t>() < 1 || b.get<std::int64_t>() > 10'000'000)
          return invalid("a breakpoint is not a line number");
        r.breakpoints.push_back(static_cast<int>(b.get<std::int64_t>()));
      }
    }
    if (const auto it = j.find("speed"); it != j.end()) {
      if (!it->is_number() || !(it->get<double>() >= 0 && it->get<double>() <= 100))
        return invalid("\"speed\" is not a number from 0 to 100");
      r.speed = it->get<double>();
    }
  }
  const bool file_required = r.kind == RequestKind::open || r.kind == RequestKind::save || r.kind == RequestKind::replay;
  if (!field(j, "text", kMaxTextBytes, text, r.text, error)) return error;
  if (!field(j, "file", kMaxNameBytes, file_required, r.file, error)) return error;
  if (!field(j, "line", kMaxLineBytes, r.kind == RequestKind::monitor, r.line, error)) return error;
  if (!field(j, "main", kMaxNameBytes, false, r.main, error)) return error;
  if (r.line.find_first_of("\r\n") != std::string::npos) return invalid("\"line\" holds a line break");
  return r;
}

}  // namespace asimov::serve
