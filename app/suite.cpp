// Suites of sample programs (app/suite.hpp), in the order a case goes through them: discovery,
// the expected file, one run, comparing, --update.
#include "app/suite.hpp"

#include "app/atomic_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>
#include <sstream>
#include <string_view>
#include <thread>

#include <fcntl.h>
#include <fnmatch.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

namespace asimov::app::suite {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kExpectSuffix = ".expect.json";
constexpr const char* kSessionSuffix = ".session";

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

std::optional<std::string> read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A value as JSON text, cut so one diff line stays readable.
std::string shown(const json& value) {
  std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
  if (text.size() > 100) text = text.substr(0, 97) + "...";
  return text;
}

std::string shown(const std::string& text) { return shown(json(text)); }

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    if (end == std::string::npos) {
      lines.push_back(text.substr(start));
      break;
    }
    lines.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

bool is_range(const json& expected) {
  if (!expected.is_object() || expected.empty()) return false;
  for (const auto& [key, value] : expected.items())
    if (key != "min" && key != "max") return false;
  return true;
}

}  // namespace

// ---- discovery ---------------------------------------------------------------------------

Discovery discover(const std::vector<std::string>& paths) {
  Discovery d;
  std::map<std::string, Case> found;
  // Adds the case `file` belongs to; false when it belongs to none.
  const auto consider = [&](const fs::path& file, bool named) {
    const std::string filename = file.filename().string();
    std::string stem;
    for (const char* ext : {kExpectSuffix, kSessionSuffix, ".v2"})
      if (ends_with(filename, ext) && filename.size() > std::string(ext).size()) {
        stem = filename.substr(0, filename.size() - std::string(ext).size());
        break;
      }
    if (stem.empty()) return false;
    const fs::path parent = file.parent_path();
    Case c;
    c.dir = parent.empty() ? fs::path(".") : parent;
    c.stem = stem;
    c.kind = is_file(c.file(kSessionSuffix)) ? CaseKind::session : CaseKind::program;
    // A program without NAME.expect.json is none (a session may load it); a session always is.
    if (c.kind == CaseKind::program && !is_file(c.file(kExpectSuffix))) {
      if (named)
        d.errors.push_back(fmt::format("*Not a test case*  {}: no {}{} beside it",
                                       file.lexically_normal().generic_string(), stem, kExpectSuffix));
      return named;
    }
    c.name = (parent / stem).lexically_normal().generic_string();
    found.emplace(c.name, c);
    return true;
  };
  for (const std::string& p : paths) {
    std::error_code ec;
    const fs::path path(p);
    if (fs::is_directory(path, ec)) {
      auto it = fs::recursive_directory_iterator(path, fs::directory_options::skip_permission_denied, ec);
      for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
        const std::string filename = it->path().filename().string();
        std::error_code entry_ec;  // a dangling link is no case, not a folder error
        if (it->is_directory(entry_ec) && !filename.empty() && filename[0] == '.') {
          it.disable_recursion_pending();  // .git, editor folders
          continue;
        }
        if (it->is_regular_file(entry_ec)) consider(it->path(), false);
      }
      if (ec) d.errors.push_back(fmt::format("*Cannot read folder*  {}: {}", p, ec.message()));
    } else if (is_file(path)) {
      if (!consider(path, true))
        d.errors.push_back(fmt::format("*Not a test case*  {}: expected NAME.v2, NAME{} or NAME{}", p,
                                       kSessionSuffix, kExpectSuffix));
    } else {
      d.errors.push_back(fmt::format("*File not found*  {}", p));
    }
  }
  for (auto& [name, c] : found) d.cases.push_back(std::move(c));
  return d;
}

bool filter_matches(const std::string& pattern, const std::string& name) {
  if (pattern.find_first_of("*?[") != std::string::npos) return ::fnmatch(pattern.c_str(), name.c_str(), 0) == 0;
  return name.find(pattern) != std::string::npos;
}

// ---- the expected file -------------------------------------------------------------------

namespace {

// stdout and stderr are a string (the exact text) or an array of lines, each ending in a newline.
std::optional<std::string> output_text(const json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (!value.is_array()) return std::nullopt;
  std::string text;
  for (const auto& line : value) {
    if (!line.is_string()) return std::nullopt;
    text += line.get<std::string>() + "\n";
  }
  return text;
}

std::optional<std::vector<std::string>> string_list(const json& value) {
  if (!value.is_array()) return std::nullopt;
  std::vector<std::string> list;
  for (const auto& item : value) {
    if (!item.is_string()) return std::nullopt;
    list.push_back(item.get<std::string>());
  }
  return list;
}

// The keys of NAME.expect.json and the JSON type of each (programs/README.md).
constexpr const char* kKnownKeys = "args, cell, exit, main, report, stderr, stderr_has, stdout";

std::optional<Expectation> parse_expectation(const json& doc, CaseKind kind, const std::string& where,
                                             std::string& why) {
  if (!doc.is_object()) {
    why = where + ": expected a JSON object";
    return std::nullopt;
  }
  Expectation e;
  for (const auto& item : doc.items()) {
    // Plain references, not a structured binding: clang 14 cannot capture those in a lambda.
    const std::string& key = item.key();
    const json& value = item.value();
    const auto wrong = [&](const char* type) {
      why = fmt::format("{}: \"{}\" must be {}", where, key, type);
      return std::nullopt;
    };
    if (kind == CaseKind::session && (key == "main" || key == "report")) {
      why = fmt::format("{}: \"{}\" is for programs (asimov run), not monitor sessions", where, key);
      return std::nullopt;
    }
    if (key == "exit") {
      if (!value.is_number_integer()) return wrong("an integer");
      e.exit = value.get<int>();
    } else if (key == "cell" || key == "main") {
      if (!value.is_string()) return wrong("a string");
      (key == "cell" ? e.cell : e.main) = value.get<std::string>();
    } else if (key == "stdout" || key == "stderr") {
      const auto text = output_text(value);
      if (!text) return wrong("a string or an array of lines");
      (key == "stdout" ? e.stdout_text : e.stderr_text) = *text;
    } else if (key == "args" || key == "stderr_has") {
      const auto list = string_list(value);
      if (!list) return wrong("an array of strings");
      (key == "args" ? e.args : e.stderr_has) = *list;
    } else if (key == "report") {
      if (!value.is_object()) return wrong("an object");
      e.report = value;
    } else {
      why = fmt::format("{}: unknown key \"{}\" (known: {})", where, key, kKnownKeys);
      return std::nullopt;
    }
  }
  if (!doc.contains("exit")) {
    why = where + ": \"exit\" is required";
    return std::nullopt;
  }
  return e;
}

}  // namespace

std::optional<Expectation> load_expectation(const Case& c, std::string& why) {
  const fs::path file = c.file(kExpectSuffix);
  const std::string where = file.lexically_normal().generic_string();
  if (c.kind == CaseKind::program && !is_file(c.file(".v2"))) {
    why = fmt::format("{}: file not found (NAME{} needs NAME.v2 or NAME{} beside it)",
                      c.file(".v2").lexically_normal().generic_string(), kExpectSuffix, kSessionSuffix);
    return std::nullopt;
  }
  const auto text = read_text(file);
  if (!text) {
    why = where + (is_file(file) ? ": cannot read the file" : ": file not found (every case needs one)");
    return std::nullopt;
  }
  try {
    return parse_expectation(json::parse(*text), c.kind, where, why);
  } catch (const json::parse_error& e) {
    std::string message = e.what();
    if (const auto pos = message.find("] "); pos != std::string::npos) message = message.substr(pos + 2);
    why = fmt::format("{}: malformed JSON: {}", where, message);
    return std::nullopt;
  }
}

// ---- one run -----------------------------------------------------------------------------

std::vector<std::string> run_arguments(const Case& c, const Expectation& e, const fs::path& report) {
  std::vector<std::string> args;
  if (c.kind == CaseKind::session) {
    args = {"monitor"};
    if (!e.cell.empty()) args.insert(args.end(), {"--cell", fs::absolute(c.dir / e.cell).lexically_normal().string()});
    args.insert(args.end(), e.args.begin(), e.args.end());
    return args;
  }
  args = {"run", c.stem + ".v2"};
  if (!e.main.empty()) args.insert(args.end(), {"--main", e.main});
  if (!e.cell.empty()) args.insert(args.end(), {"--cell", e.cell});
  args.insert(args.end(), e.args.begin(), e.args.end());
  if (!report.empty()) args.insert(args.end(), {"--report", report.string()});
  return args;
}

namespace {

// A fresh folder holding copies of the files of the session's folder (links followed), where
// the session runs; empty with `why` filled when it cannot be made.
fs::path session_folder(const Case& c, const fs::path& scratch, const std::string& tag, std::string& why) {
  const fs::path dir = scratch / (tag + ".session");
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir, ec);
  for (auto it = fs::directory_iterator(c.dir, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
    std::error_code entry_ec;
    if (it->is_regular_file(entry_ec)) fs::copy_file(it->path(), dir / it->path().filename(), ec);
    if (ec) break;
  }
  if (ec) {
    why = fmt::format("cannot copy {} to {}: {}", c.dir.generic_string(), dir.string(), ec.message());
    return {};
  }
  return dir;
}

// A fresh copy of a program case's folder (links copied as links): the program's files root
// (`--files`), so a case that creates, appends to or deletes a file finds the folder as it is in
// the source every time. The program, its cell and the messages keep their names: the run
// itself stays in the source folder. Empty with `why` filled when it cannot be made.
// Whether the program can create, change or delete a file: only FOPENW/FOPENA/FOPEND/FOPENR,
// FEMPTY and FDELETE reach the files root (dialect §7a), so a program without them needs no copy
// (copying a folder of 400 files for each of its 200 cases cost half a minute of system time).
bool touches_files(const Case& c) {
  std::error_code ec;
  if (!fs::is_regular_file(c.file(".v2"), ec)) return false;  // the run reports what it is
  std::string text = read_text(c.file(".v2")).value_or("");
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char ch) { return static_cast<char>(std::toupper(ch)); });
  return text.find("FOPEN") != std::string::npos || text.find("FEMPTY") != std::string::npos ||
         text.find("FDELETE") != std::string::npos;
}

fs::path files_copy(const Case& c, const fs::path& scratch, const std::string& tag, std::string& why) {
  const fs::path dir = scratch / (tag + ".files");
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::copy(c.dir, dir, fs::copy_options::recursive | fs::copy_options::copy_symlinks, ec);
  if (ec) {
    why = fmt::format("cannot copy {} to {}: {}", c.dir.generic_string(), dir.string(), ec.message());
    return {};
  }
  return dir;
}

}  // namespace

Actual run_case(const Case& c, const Expectation& e, const std::string& executable, const fs::path& scratch,
                const std::string& tag, std::chrono::seconds timeout, const std::atomic<bool>* stop) {
  using Clock = std::chrono::steady_clock;
  Actual a;
  const fs::path out_file = scratch / (tag + ".stdout"), err_file = scratch / (tag + ".stderr");
  const fs::path report = e.report ? scratch / (tag + ".report.json") : fs::path();
  std::error_code ec;
  fs::remove(report, ec);
  fs::path dir = c.dir, in_file = "/dev/null";
  if (c.kind == CaseKind::session) {
    in_file = fs::absolute(c.file(kSessionSuffix), ec);
    dir = session_folder(c, scratch, tag, a.exit_note);
    if (dir.empty()) return a;
  }
  // Everything the child needs is built before fork: after it only async-signal-safe calls.
  std::vector<std::string> args = run_arguments(c, e, report);
  fs::path files;  // the program's files root: a copy of its folder
  if (c.kind == CaseKind::program && std::find(e.args.begin(), e.args.end(), "--files") == e.args.end() &&
      touches_files(c)) {
    files = files_copy(c, scratch, tag, a.exit_note);
    if (files.empty()) return a;
    args.insert(args.end(), {"--files", files.string()});
  }
  args.insert(args.begin(), executable);
  std::vector<char*> argv;
  for (auto& s : args) argv.push_back(s.data());
  argv.push_back(nullptr);
  const std::string dir_path = dir.string(), in_path = in_file.string(), out_path = out_file.string(),
                    err_path = err_file.string();
  static const char kExecFailed[] = "asimov test: cannot start the asimov executable\n";

  const Clock::time_point start = Clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) {
    a.exit_note = "cannot start a process";
    return a;
  }
  if (pid == 0) {
    const int in = ::open(in_path.c_str(), O_RDONLY);
    const int out = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (in >= 0 && out >= 0 && err >= 0 && ::dup2(in, 0) >= 0 && ::dup2(out, 1) >= 0 && ::dup2(err, 2) >= 0 &&
        ::chdir(dir_path.c_str()) == 0)
      ::execv(argv[0], argv.data());
    if (::write(2, kExecFailed, sizeof kExecFailed - 1) < 0) {}
    ::_exit(127);
  }
  int status = 0;
  auto pause = std::chrono::microseconds(200);
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0) {
      a.exit_note = "lost the process";
      break;
    }
    if (stop && stop->load()) {
      ::kill(pid, SIGKILL);  // our own child, never anything else
      ::waitpid(pid, &status, 0);
      a.exit_note = "interrupted";
      break;
    }
    if (Clock::now() - start > timeout) {
      ::kill(pid, SIGKILL);  // our own child, never anything else
      ::waitpid(pid, &status, 0);
      a.exit_note = fmt::format("timed out after {} s", timeout.count());
      break;
    }
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(20000));
  }
  a.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (a.exit_note.empty()) {
    if (WIFEXITED(status)) a.exit_code = WEXITSTATUS(status);
    else if (WIFSIGNALED(status)) a.exit_note = fmt::format("killed by signal {}", WTERMSIG(status));
  }
  a.out = read_text(out_file).value_or("");
  a.err = read_text(err_file).value_or("");
  fs::remove(out_file, ec);
  fs::remove(err_file, ec);
  if (e.report) {
    if (const auto text = read_text(report)) {
      try {
        a.report = json::parse(*text);
      } catch (const json::parse_error& ex) {
        a.report_problem = std::string("the report is malformed JSON: ") + ex.what();
      }
    } else {
      a.report_problem = "no report was written";
    }
    fs::remove(report, ec);
  }
  if (c.kind == CaseKind::session) fs::remove_all(dir, ec);
  if (!files.empty()) fs::remove_all(files, ec);
  return a;
}

// ---- comparing ---------------------------------------------------------------------------

namespace {

// A line as compared: a monitor STATUS line ends with wall-clock times ("Accuracy: ...; wall
// parse 0.001 s, ..."), which differ from run to run.
std::string_view comparable(std::string_view line) {
  if (line.rfind("Accuracy: ", 0) == 0)
    if (const auto at = line.find("; wall "); at != std::string_view::npos) return line.substr(0, at);
  return line;
}

// The one field of the report schema that is null by design (README: no contact, no bracket);
// any other null is a NaN or an infinity written by nlohmann.
constexpr const char* kNullable = "report.accuracy.contact_bracket_s";

void find_nulls(const json& value, const std::string& path, std::vector<std::string>& diffs) {
  if (path == kNullable) return;
  if (value.is_null()) diffs.push_back(path + ": null (a NaN or an infinity)");
  if (value.is_object())
    for (const auto& [key, item] : value.items()) find_nulls(item, path + "." + key, diffs);
  if (value.is_array())
    for (std::size_t i = 0; i < value.size(); ++i) find_nulls(value[i], fmt::format("{}[{}]", path, i), diffs);
}

}  // namespace

std::optional<std::string> first_line_difference(const std::string& label, const std::string& expected,
                                                 const std::string& actual) {
  if (expected == actual) return std::nullopt;
  const auto want = split_lines(expected), got = split_lines(actual);
  for (std::size_t i = 0; i < std::max(want.size(), got.size()); ++i) {
    if (i < want.size() && i < got.size() && comparable(want[i]) == comparable(got[i])) continue;
    return fmt::format("{} line {}: expected {}, got {}", label, i + 1,
                       i < want.size() ? shown(want[i]) : "end of output",
                       i < got.size() ? shown(got[i]) : "end of output");
  }
  // Same lines; only the final newline or a wall time differs.
  if (ends_with(expected, "\n") == ends_with(actual, "\n")) return std::nullopt;
  return fmt::format("{}: expected {} final newline", label, ends_with(expected, "\n") ? "a" : "no");
}

void match_report(const json& expected, const json& actual, const std::string& path, std::vector<std::string>& diffs) {
  if (is_range(expected)) {
    const bool bounds_ok = (!expected.contains("min") || expected["min"].is_number()) &&
                           (!expected.contains("max") || expected["max"].is_number());
    const std::string range = fmt::format("a number in [{}, {}]",
                                          expected.contains("min") ? shown(expected["min"]) : "-inf",
                                          expected.contains("max") ? shown(expected["max"]) : "inf");
    if (!bounds_ok) {
      diffs.push_back(fmt::format("{}: the range bounds must be numbers, got {}", path, shown(expected)));
    } else if (!actual.is_number() ||
               (expected.contains("min") && actual.get<double>() < expected["min"].get<double>()) ||
               (expected.contains("max") && actual.get<double>() > expected["max"].get<double>())) {
      diffs.push_back(fmt::format("{}: expected {}, got {}", path, range, shown(actual)));
    }
    return;
  }
  if (expected.is_object()) {
    if (!actual.is_object()) {
      diffs.push_back(fmt::format("{}: expected an object, got {}", path, shown(actual)));
      return;
    }
    for (const auto& [key, value] : expected.items()) {
      if (!actual.contains(key)) diffs.push_back(fmt::format("{}.{}: missing, expected {}", path, key, shown(value)));
      else match_report(value, actual[key], path + "." + key, diffs);
    }
  } else if (expected.is_array()) {
    if (!actual.is_array() || actual.size() != expected.size()) {
      diffs.push_back(fmt::format("{}: expected {}, got {}", path, shown(expected), shown(actual)));
      return;
    }
    for (std::size_t i = 0; i < expected.size(); ++i)
      match_report(expected[i], actual[i], fmt::format("{}[{}]", path, i), diffs);
  } else if (expected.is_number() && actual.is_number()) {
    if (actual.get<double>() != expected.get<double>())
      diffs.push_back(fmt::format("{}: expected {}, got {}", path, shown(expected), shown(actual)));
  } else if (actual != expected) {
    diffs.push_back(fmt::format("{}: expected {}, got {}", path, shown(expected), shown(actual)));
  }
}

std::vector<std::string> compare(const Expectation& e, const Actual& a) {
  std::vector<std::string> diffs;
  if (!a.exit_note.empty()) return {"run: " + a.exit_note};  // its outputs are cut short: no use comparing
  if (a.exit_code != e.exit) diffs.push_back(fmt::format("exit code: expected {}, got {}", e.exit, a.exit_code));
  if (e.stdout_text)
    if (auto d = first_line_difference("stdout", *e.stdout_text, a.out)) diffs.push_back(*d);
  if (e.stderr_text)
    if (auto d = first_line_difference("stderr", *e.stderr_text, a.err)) diffs.push_back(*d);
  for (const std::string& line : e.stderr_has)
    if (a.err.find(line) == std::string::npos) diffs.push_back("stderr: missing " + shown(line));
  if (e.report) {
    if (a.report) {
      match_report(*e.report, *a.report, "report", diffs);
      find_nulls(*a.report, "report", diffs);
    } else {
      diffs.push_back("report: " + a.report_problem);
    }
  }
  return diffs;
}

// ---- --update ----------------------------------------------------------------------------

namespace {

using ordered_json = nlohmann::ordered_json;

// Replaces the exact values of `expected` that `actual` contradicts; ranges and missing keys are
// decisions a person takes, so they are only noted.
void update_report(ordered_json& expected, const json& actual, const std::string& path,
                   std::vector<std::string>& notes) {
  const json plain = json::parse(expected.dump(-1, ' ', false, json::error_handler_t::replace));
  if (is_range(plain)) {
    std::vector<std::string> diffs;
    match_report(plain, actual, path, diffs);
    for (const auto& d : diffs) notes.push_back("left for a person: " + d);
    return;
  }
  if (expected.is_object() && actual.is_object()) {
    for (auto& [key, value] : expected.items()) {
      if (actual.contains(key)) update_report(value, actual[key], path + "." + key, notes);
      else notes.push_back(fmt::format("left for a person: {}.{} is not in the report", path, key));
    }
    return;
  }
  if (expected.is_array() && actual.is_array() && expected.size() == actual.size()) {
    for (std::size_t i = 0; i < expected.size(); ++i)
      update_report(expected[i], actual[i], fmt::format("{}[{}]", path, i), notes);
    return;
  }
  std::vector<std::string> diffs;
  match_report(plain, actual, path, diffs);
  if (!diffs.empty()) expected = ordered_json::parse(actual.dump(-1, ' ', false, json::error_handler_t::replace));
}

}  // namespace

std::vector<std::string> update_expectation(const Case& c, const Expectation& e, const Actual& a) {
  if (!a.exit_note.empty()) return {"not updated: the run did not finish (" + a.exit_note + ")"};
  const fs::path file = c.file(kExpectSuffix);
  ordered_json doc;
  try {
    doc = ordered_json::parse(read_text(file).value_or(""));
  } catch (const json::parse_error&) {
    return {"not updated: " + file.lexically_normal().generic_string() + " is malformed"};
  }
  std::vector<std::string> notes;
  const ordered_json before = doc;
  doc["exit"] = a.exit_code;
  // An output keeps its form: an array of lines while the text ends with a newline.
  const auto update_output = [&](const char* key, const std::optional<std::string>& expected, const std::string& actual) {
    if (!doc.contains(key) || !first_line_difference(key, expected.value_or(""), actual)) return;
    if (doc[key].is_array() && (actual.empty() || ends_with(actual, "\n"))) {
      doc[key] = ordered_json::array();
      for (const auto& line : split_lines(actual)) doc[key].push_back(line);
    } else {
      doc[key] = actual;
    }
  };
  update_output("stdout", e.stdout_text, a.out);
  update_output("stderr", e.stderr_text, a.err);
  for (const std::string& line : e.stderr_has)
    if (a.err.find(line) == std::string::npos) notes.push_back("left for a person: stderr line " + shown(line));
  if (doc.contains("report")) {
    if (a.report) update_report(doc["report"], *a.report, "report", notes);
    else notes.push_back("left for a person: report: " + a.report_problem);
  }
  if (doc != before) {
    const Result<void> written = write_file_atomically(file.string(), doc.dump(2, ' ', false, ordered_json::error_handler_t::replace) + "\n");
    notes.push_back(written ? "wrote " + file.lexically_normal().generic_string()
                            : "not updated: " + written.error().message);
  }
  return notes;
}

}  // namespace asimov::app::suite
