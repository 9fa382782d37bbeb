// Suites of sample programs (app/suite.hpp): discovery, expected files, one run, the matcher.
#include "app/suite.hpp"

#include "app/atomic_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>
#include <sstream>
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

// The name `asimov run` prints in "Program completed: NAME": the first .PROGRAM of the file,
// lower case (dialect §1). Empty when the file has none (the run then fails anyway).
std::string first_program_name(const std::string& source) {
  std::istringstream in(source);
  std::string line;
  while (std::getline(in, line)) {
    std::size_t i = line.find_first_not_of(" \t");
    if (i == std::string::npos || line.size() - i < 8) continue;
    std::string word = line.substr(i, 8);
    std::transform(word.begin(), word.end(), word.begin(), [](unsigned char c) { return std::tolower(c); });
    if (word != ".program") continue;
    i = line.find_first_not_of(" \t", i + 8);
    if (i == std::string::npos) continue;
    std::string name;
    for (; i < line.size() && (std::isalnum(static_cast<unsigned char>(line[i])) || line[i] == '.' || line[i] == '_'); ++i)
      name += static_cast<char>(std::tolower(static_cast<unsigned char>(line[i])));
    return name;
  }
  return {};
}

bool is_range(const json& expected) {
  if (!expected.is_object() || expected.empty()) return false;
  for (const auto& [key, value] : expected.items())
    if (key != "min" && key != "max") return false;
  return true;
}

std::optional<Expectation> load_json_expectation(const Case& c, std::string& why) {
  const fs::path file = c.file(kExpectSuffix);
  const std::string where = file.lexically_normal().generic_string();
  if (is_file(c.file(".out"))) {
    why = fmt::format("{}: {} is there too; a case has one kind of expected file", where,
                      c.file(".out").lexically_normal().generic_string());
    return std::nullopt;
  }
  const auto text = read_text(file);
  if (!text) {
    why = where + ": cannot read the file";
    return std::nullopt;
  }
  json doc;
  try {
    doc = json::parse(*text);
  } catch (const json::parse_error& e) {
    std::string message = e.what();
    if (const auto pos = message.find("] "); pos != std::string::npos) message = message.substr(pos + 2);
    why = fmt::format("{}: malformed JSON: {}", where, message);
    return std::nullopt;
  }
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
    if (key == "exit") {
      if (!value.is_number_integer()) return wrong("an integer");
      e.exit = value.get<int>();
    } else if (key == "cell" || key == "main" || key == "stdout") {
      if (!value.is_string()) return wrong("a string");
      if (key == "cell") e.cell = value.get<std::string>();
      if (key == "main") e.main = value.get<std::string>();
      if (key == "stdout") e.stdout_text = value.get<std::string>();
    } else if (key == "stderr_has") {
      if (!value.is_array()) return wrong("an array of strings");
      for (const auto& line : value) {
        if (!line.is_string()) return wrong("an array of strings");
        e.stderr_has.push_back(line.get<std::string>());
      }
    } else if (key == "report") {
      if (!value.is_object()) return wrong("an object");
      e.report = value;
    } else {
      why = fmt::format("{}: unknown key \"{}\" (known: cell, exit, main, report, stderr_has, stdout)", where, key);
      return std::nullopt;
    }
  }
  if (!doc.contains("exit")) {
    why = where + ": \"exit\" is required";
    return std::nullopt;
  }
  return e;
}

std::optional<Expectation> load_out_expectation(const Case& c, const std::string& source, std::string& why) {
  const auto out = read_text(c.file(".out"));
  if (!out) {
    why = c.file(".out").lexically_normal().generic_string() + ": file not found (a NAME.err case needs its NAME.out)";
    return std::nullopt;
  }
  Expectation e;
  e.stdout_text = *out;
  if (is_file(c.file(".err"))) {
    e.exit = 2;  // the run stops with a program error whose report is NAME.err
    e.stderr_text = read_text(c.file(".err")).value_or("");
  } else {
    e.exit = 0;
    e.stderr_text = "Program completed: " + first_program_name(source) + "\n";
  }
  return e;
}

}  // namespace

Discovery discover(const std::vector<std::string>& paths) {
  Discovery d;
  std::map<std::string, Case> found;
  // Adds the case `file` belongs to; false when it belongs to none.
  const auto consider = [&](const fs::path& file, bool named) {
    const std::string filename = file.filename().string();
    std::string stem;
    for (const char* ext : {kExpectSuffix, ".v2", ".out", ".err"})
      if (ends_with(filename, ext) && filename.size() > std::string(ext).size()) {
        stem = filename.substr(0, filename.size() - std::string(ext).size());
        break;
      }
    if (stem.empty()) return false;
    const fs::path parent = file.parent_path();
    Case c;
    c.dir = parent.empty() ? fs::path(".") : parent;
    c.stem = stem;
    const bool has_json = is_file(c.file(kExpectSuffix));
    // NAME.txt + NAME.out is a monitor session (tests/app/test_monitor_sessions.cpp), no case.
    const bool session = !has_json && is_file(c.file(".txt"));
    // NAME.out/.err make a case only beside NAME.v2 (a compiler's a.out is none).
    const bool out_case = is_file(c.file(".v2")) && (is_file(c.file(".out")) || is_file(c.file(".err")));
    if (session || (!has_json && !out_case)) {
      // A .v2 without expected results (e.g. one a monitor session loads) is no case, unless named.
      if (named)
        d.errors.push_back(session ? fmt::format("*Not a test case*  {}: {}.txt makes it a monitor session",
                                                 file.lexically_normal().generic_string(), stem)
                                   : fmt::format("*Not a test case*  {}: no {}.v2 with {}{} or {}.out beside it",
                                                 file.lexically_normal().generic_string(), stem, stem, kExpectSuffix,
                                                 stem));
      return named;
    }
    c.kind = has_json ? CaseKind::expect_json : CaseKind::out_files;
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
        d.errors.push_back(fmt::format("*Not a test case*  {}: expected NAME.v2, NAME{}, NAME.out or NAME.err", p,
                                       kExpectSuffix));
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

std::optional<Expectation> load_expectation(const Case& c, std::string& why) {
  const fs::path program = c.file(".v2");
  const auto source = read_text(program);
  if (!is_file(program) || !source) {
    why = program.lexically_normal().generic_string() + ": file not found (every expected file needs its program)";
    return std::nullopt;
  }
  return c.kind == CaseKind::expect_json ? load_json_expectation(c, why) : load_out_expectation(c, *source, why);
}

std::vector<std::string> run_arguments(const Case& c, const Expectation& e, const fs::path& report) {
  std::vector<std::string> args = {"run", c.stem + ".v2"};
  if (!e.main.empty()) args.insert(args.end(), {"--main", e.main});
  if (!e.cell.empty()) args.insert(args.end(), {"--cell", e.cell});
  if (!report.empty()) args.insert(args.end(), {"--report", report.string()});
  return args;
}

Actual run_case(const Case& c, const Expectation& e, const std::string& executable, const fs::path& scratch,
                const std::string& tag, std::chrono::seconds timeout, const std::atomic<bool>* stop) {
  using Clock = std::chrono::steady_clock;
  Actual a;
  const fs::path out_file = scratch / (tag + ".stdout"), err_file = scratch / (tag + ".stderr");
  const fs::path report = e.report ? scratch / (tag + ".report.json") : fs::path();
  std::error_code ec;
  fs::remove(report, ec);
  // Everything the child needs is built before fork: after it only async-signal-safe calls.
  std::vector<std::string> args = run_arguments(c, e, report);
  args.insert(args.begin(), executable);
  std::vector<char*> argv;
  for (auto& s : args) argv.push_back(s.data());
  argv.push_back(nullptr);
  const std::string dir = c.dir.string(), out_path = out_file.string(), err_path = err_file.string();
  static const char kExecFailed[] = "asimov test: cannot start the asimov executable\n";

  const Clock::time_point start = Clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) {
    a.exit_note = "cannot start a process";
    return a;
  }
  if (pid == 0) {
    const int in = ::open("/dev/null", O_RDONLY);
    const int out = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (in >= 0 && out >= 0 && err >= 0 && ::dup2(in, 0) >= 0 && ::dup2(out, 1) >= 0 && ::dup2(err, 2) >= 0 &&
        ::chdir(dir.c_str()) == 0)
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
  return a;
}

std::optional<std::string> first_line_difference(const std::string& label, const std::string& expected,
                                                 const std::string& actual) {
  if (expected == actual) return std::nullopt;
  const auto want = split_lines(expected), got = split_lines(actual);
  for (std::size_t i = 0; i < std::max(want.size(), got.size()); ++i) {
    if (i < want.size() && i < got.size() && want[i] == got[i]) continue;
    return fmt::format("{} line {}: expected {}, got {}", label, i + 1,
                       i < want.size() ? shown(want[i]) : "end of output",
                       i < got.size() ? shown(got[i]) : "end of output");
  }
  // Same lines; only the final newline differs.
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
    if (a.report) match_report(*e.report, *a.report, "report", diffs);
    else diffs.push_back("report: " + a.report_problem);
  }
  return diffs;
}

namespace {

using ordered_json = nlohmann::ordered_json;

// Replaces the exact values of `expected` that `actual` contradicts; ranges and missing keys are
// decisions a person takes, so they are only noted.
void update_report(ordered_json& expected, const json& actual, const std::string& path,
                   std::vector<std::string>& notes) {
  const json plain = json::parse(expected.dump());
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
  if (!diffs.empty()) expected = ordered_json::parse(actual.dump());
}

}  // namespace

std::vector<std::string> update_expectation(const Case& c, const Expectation& e, const Actual& a) {
  if (!a.exit_note.empty()) return {"not updated: the run did not finish (" + a.exit_note + ")"};
  std::vector<std::string> notes;
  const auto write = [&](const fs::path& p, const std::string& text) {
    std::string why;
    notes.push_back(write_file_atomically(p.string(), text, why) ? "wrote " + p.lexically_normal().generic_string() : "not updated: " + why);
  };
  if (c.kind == CaseKind::out_files) {
    const bool completed = a.exit_code == 0 && a.err.rfind("Program completed: ", 0) == 0 &&
                           std::count(a.err.begin(), a.err.end(), '\n') == 1;
    if (!completed && a.exit_code != 2)
      return {fmt::format("not updated: exit code {} with this stderr does not fit NAME.out/NAME.err; "
                          "write a NAME{} instead", a.exit_code, kExpectSuffix)};
    if (a.out != e.stdout_text.value_or("")) write(c.file(".out"), a.out);
    if (a.exit_code == 2 && (e.exit != 2 || a.err != e.stderr_text.value_or(""))) write(c.file(".err"), a.err);
    std::error_code ec;
    if (completed && fs::remove(c.file(".err"), ec)) notes.push_back("removed " + c.file(".err").lexically_normal().generic_string());
    return notes;
  }
  const fs::path file = c.file(kExpectSuffix);
  ordered_json doc;
  try {
    doc = ordered_json::parse(read_text(file).value_or(""));
  } catch (const json::parse_error&) {
    return {"not updated: " + file.lexically_normal().generic_string() + " is malformed"};
  }
  const ordered_json before = doc;
  doc["exit"] = a.exit_code;
  if (doc.contains("stdout")) doc["stdout"] = a.out;
  for (const std::string& line : e.stderr_has)
    if (a.err.find(line) == std::string::npos) notes.push_back("left for a person: stderr line " + shown(line));
  if (doc.contains("report")) {
    if (a.report) update_report(doc["report"], *a.report, "report", notes);
    else notes.push_back("left for a person: report: " + a.report_problem);
  }
  if (doc != before) write(file, doc.dump(2) + "\n");
  return notes;
}

}  // namespace asimov::app::suite
