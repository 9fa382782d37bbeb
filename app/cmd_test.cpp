// `asimov test [PATH...]`: runs every sample-program case under the paths as `asimov run` would
// and compares with the expected files (app/suite.hpp; formats in programs/README.md).
#include "app/atomic_file.hpp"
#include "asimov/core/output_file.hpp"
#include "app/commands.hpp"
#include "app/exit_codes.hpp"
#include "app/report.hpp"
#include "app/sigint.hpp"
#include "app/suite.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <set>
#include <sstream>
#include <ostream>
#include <thread>

#include <unistd.h>

namespace asimov::app {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  std::optional<suite::Expectation> expectation;  // nullopt: the expected files are unusable
  suite::Actual actual;
  std::vector<std::string> diffs;                 // empty: passed
  std::vector<std::string> updates;               // --update
};

std::string xml_escaped(const std::string& text) {
  std::string s;
  for (const char c : text) {
    switch (c) {
      case '&': s += "&amp;"; break;
      case '<': s += "&lt;"; break;
      case '>': s += "&gt;"; break;
      case '"': s += "&quot;"; break;
      default:
        // XML 1.0 allows no control characters but tab and newline.
        if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t') s += '?';
        else s += c;
    }
  }
  return s;
}

// The <properties> of our JUnit files: the schema of the results and the shard they cover.
std::string junit_properties(const TestOptions& opt) {
  std::string p = fmt::format("    <properties>\n      <property name=\"schema_version\" value=\"{}\"/>\n", kSchemaVersion);
  if (opt.shards > 0) p += fmt::format("      <property name=\"shard\" value=\"{}/{}\"/>\n", opt.shard, opt.shards);
  return p + "    </properties>\n";
}

constexpr const char* kJunitHead = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";

std::string junit_wrap(std::size_t tests, std::size_t failed, double total_s, const std::string& properties,
                       const std::string& body) {
  return fmt::format(
      "{4}<testsuites name=\"asimov test\" tests=\"{0}\" failures=\"{1}\" errors=\"0\" time=\"{2:.3f}\">\n"
      "  <testsuite name=\"asimov test\" tests=\"{0}\" failures=\"{1}\" errors=\"0\" skipped=\"0\" time=\"{2:.3f}\">\n"
      "{5}{3}  </testsuite>\n</testsuites>\n",
      tests, failed, total_s, body, kJunitHead, properties);
}

std::string junit_document(const std::vector<suite::Case>& cases, const std::vector<Outcome>& outcomes,
                           std::size_t failed, double total_s, const TestOptions& opt) {
  std::string body;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto& c = cases[i];
    std::string classname = fs::path(c.name).parent_path().generic_string();
    std::replace(classname.begin(), classname.end(), '/', '.');
    body += fmt::format("    <testcase name=\"{}\" classname=\"{}\" time=\"{:.3f}\"", xml_escaped(c.stem),
                        xml_escaped(classname.empty() ? "." : classname), outcomes[i].actual.seconds);
    const auto& diffs = outcomes[i].diffs;
    if (diffs.empty()) {
      body += "/>\n";
      continue;
    }
    std::string all;
    for (const auto& d : diffs) all += d + "\n";
    body += fmt::format(">\n      <failure message=\"{}\">{}</failure>\n", xml_escaped(diffs.front()), xml_escaped(all));
    body += fmt::format("      <system-out>{}</system-out>\n      <system-err>{}</system-err>\n    </testcase>\n",
                        xml_escaped(outcomes[i].actual.out), xml_escaped(outcomes[i].actual.err));
  }
  return junit_wrap(cases.size(), failed, total_s, junit_properties(opt), body);
}

// One file written by `asimov test --junit`: its <testcase> elements as text, and its counts.
struct JunitPart {
  std::string testcases;
  std::size_t tests = 0, failures = 0;
  double time_s = 0;
};

bool read_junit(const std::string& path, JunitPart& part, std::string& why) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  const std::string xml = text.str();
  const std::string open = "  <testsuite name=\"asimov test\"";
  const auto suite_at = xml.find(open);
  const auto body_at = suite_at == std::string::npos ? suite_at : xml.find(">\n", suite_at);
  const auto end_at = xml.rfind("  </testsuite>");
  if (!in.good() && !in.eof()) {
    why = fmt::format("{}: cannot read", path);
    return false;
  }
  if (xml.rfind(kJunitHead, 0) != 0 || body_at == std::string::npos || end_at == std::string::npos || end_at < body_at) {
    why = fmt::format("{}: not a JUnit file of asimov test --junit", path);
    return false;
  }
  std::string body = xml.substr(body_at + 2, end_at - body_at - 2);
  if (const auto props = body.find("    <properties>"); props == 0) body.erase(0, body.find("    </properties>\n") + 18);
  const auto attribute = [&](const char* name) {
    const std::string key = std::string(" ") + name + "=\"";
    const auto at = xml.find(key, suite_at);
    return at == std::string::npos ? std::string() : xml.substr(at + key.size(), xml.find('"', at + key.size()) - at - key.size());
  };
  try {
    part.tests = std::stoul(attribute("tests"));
    part.failures = std::stoul(attribute("failures"));
    part.time_s = std::stod(attribute("time"));
  } catch (const std::exception&) {
    why = fmt::format("{}: its <testsuite> has no tests/failures/time counts", path);
    return false;
  }
  part.testcases = std::move(body);
  return true;
}

// --merge-junit OUT FILE...: one JUnit file with every case of the shard files (CI: one file for
// the whole suite). A case name met twice is an error: the shards did not partition the suite.
int merge_junit_command(const TestOptions& opt, std::ostream& out, std::ostream& err) {
  if (opt.paths.empty()) {
    err << "*Invalid argument*  --merge-junit OUT needs the JUnit files to merge as PATHs\n";
    return kExitUsage;
  }
  {
    std::vector<core::NamedPath> inputs;
    for (const auto& path : opt.paths) inputs.push_back({"a JUnit file to merge", path});
    auto ok = core::check_output_path(opt.merge_junit);
    if (ok) ok = core::check_outputs_apart(inputs, {{"--merge-junit", opt.merge_junit}});
    if (!ok) {
      err << "*Cannot write file*  " << ok.error().message << '\n';
      return kExitUsage;
    }
  }
  std::string body;
  std::size_t tests = 0, failures = 0;
  double time_s = 0;
  std::set<std::string> seen;
  for (const auto& path : opt.paths) {
    JunitPart part;
    std::string why;
    if (!read_junit(path, part, why)) {
      err << "*Invalid argument*  " << why << '\n';
      return kExitUsage;
    }
    for (std::size_t at = part.testcases.find("<testcase "); at != std::string::npos;
         at = part.testcases.find("<testcase ", at + 1)) {
      const auto name_at = part.testcases.find(" name=\"", at) + 7;
      const auto class_at = part.testcases.find(" classname=\"", at) + 12;
      const std::string id = part.testcases.substr(class_at, part.testcases.find('"', class_at) - class_at) + "/" +
                             part.testcases.substr(name_at, part.testcases.find('"', name_at) - name_at);
      if (!seen.insert(id).second) {
        err << fmt::format("*Invalid argument*  {}: case {} is in an earlier file too\n", path, id);
        return kExitUsage;
      }
    }
    body += part.testcases;
    tests += part.tests;
    failures += part.failures;
    time_s += part.time_s;
  }
  const std::string props = fmt::format("    <properties>\n      <property name=\"schema_version\" value=\"{}\"/>\n"
                                        "      <property name=\"merged_files\" value=\"{}\"/>\n    </properties>\n",
                                        kSchemaVersion, opt.paths.size());
  if (const auto written = write_file_atomically(opt.merge_junit, junit_wrap(tests, failures, time_s, props, body)); !written) {
    err << "*Cannot write file*  " << written.error().message << '\n';
    return kExitUsage;
  }
  out << fmt::format("{}: {} cases from {} files, {} failed\n", opt.merge_junit, tests, opt.paths.size(), failures);
  return failures == 0 ? kExitCompleted : kExitTestFailed;
}

Outcome run_one(const suite::Case& c, const TestOptions& opt, const std::string& executable, const fs::path& scratch,
                std::size_t index, const std::atomic<bool>& stop) {
  Outcome o;
  std::string why;
  o.expectation = suite::load_expectation(c, why);
  if (!o.expectation) {
    o.diffs.push_back(why);
    return o;
  }
  o.actual = suite::run_case(c, *o.expectation, executable, scratch, std::to_string(index),
                             std::chrono::seconds(opt.timeout_s), &stop);
  o.diffs = suite::compare(*o.expectation, o.actual);
  if (opt.update && !o.diffs.empty()) o.updates = suite::update_expectation(c, *o.expectation, o.actual);
  return o;
}

}  // namespace

bool parse_shard(const std::string& text, int& shard, int& shards) {
  const auto slash = text.find('/');
  if (slash == std::string::npos || slash == 0 || slash + 1 == text.size()) return false;
  const auto digits = [](const std::string& t) { return t.size() <= 6 && std::all_of(t.begin(), t.end(), ::isdigit); };
  const std::string k = text.substr(0, slash), n = text.substr(slash + 1);
  if (!digits(k) || !digits(n)) return false;
  shard = std::stoi(k);
  shards = std::stoi(n);
  return shards >= 1 && shards <= 100000 && shard >= 1 && shard <= shards;
}

int shard_of(const std::string& name, int shards) {
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a 64
  for (const unsigned char c : name) h = (h ^ c) * 1099511628211ull;
  return static_cast<int>(h % static_cast<std::uint64_t>(shards));
}

int test_command(const TestOptions& opt, std::ostream& out, std::ostream& err) {
  if (!opt.merge_junit.empty()) return merge_junit_command(opt, out, err);
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  const std::vector<std::string> paths = opt.paths.empty() ? std::vector<std::string>{"."} : opt.paths;
  suite::Discovery found = suite::discover(paths);
  if (!found.errors.empty()) {
    for (const auto& e : found.errors) err << e << '\n';
    return kExitUsage;
  }
  std::vector<suite::Case> cases;
  std::size_t filtered = 0;
  for (auto& c : found.cases) {
    if (!opt.filter.empty() && !suite::filter_matches(opt.filter, c.name)) continue;
    ++filtered;
    if (opt.shards == 0 || shard_of(c.name, opt.shards) == opt.shard - 1) cases.push_back(std::move(c));
  }
  if (cases.empty() && filtered > 0) {
    // A shard may hold no case (more shards than cases): nothing to do is a success for CI.
    out << fmt::format("0 cases in shard {}/{} (of {})\n", opt.shard, opt.shards, filtered);
    if (!opt.junit.empty() && !opt.list) {
      if (const auto written = write_file_atomically(opt.junit, junit_document({}, {}, 0, 0.0, opt)); !written) {
        err << "*Cannot write file*  " << written.error().message << '\n';
        return kExitUsage;
      }
    }
    return kExitCompleted;
  }
  if (cases.empty()) {
    err << (found.cases.empty() ? fmt::format("*No test cases*  none under {}\n", fmt::join(paths, " "))
                                : fmt::format("*No test cases*  none of {} matches --filter {}\n",
                                              found.cases.size(), opt.filter));
    return kExitUsage;
  }
  if (opt.list) {
    for (const auto& c : cases) out << c.name << '\n';
    return kExitCompleted;
  }
  if (!opt.junit.empty()) {
    // The JUnit file must be writable and must not be one of the cases' own files.
    std::vector<core::NamedPath> inputs;
    for (const auto& c : cases)
      for (const char* ext : {".v2", ".session", ".expect.json", ".cell.yaml"})
        if (std::error_code ec; fs::exists(c.file(ext), ec)) inputs.push_back({"a file of case " + c.name, c.file(ext).string()});
    auto ok = core::check_output_path(opt.junit);
    if (ok) ok = core::check_outputs_apart(inputs, {{"--junit", opt.junit}});
    if (!ok) {
      err << "*Cannot write file*  " << ok.error().message << '\n';
      return kExitUsage;
    }
  }
  std::string executable = opt.executable;
  if (executable.empty()) {
    std::error_code ec;
    executable = fs::read_symlink("/proc/self/exe", ec).string();
    if (ec) {
      err << "*Internal error*  cannot find the asimov executable: " << ec.message() << '\n';
      return kExitUsage;
    }
  }
  std::error_code ec;
  // Ctrl-C: running cases are killed, no new one starts, the scratch folder is removed and the
  // command exits 130 after the lines of the cases that finished. SIGTERM and SIGHUP stop it the
  // same way, then end it by that signal. The handlers come before the folder, so no signal
  // finds the folder there and nobody to remove it.
  std::atomic<bool>& interrupted = sigint_flag();
  interrupted.store(false);
  install_sigint(false);
  install_termination();

  const fs::path scratch = fs::temp_directory_path(ec) / fmt::format("asimov-test-{}", ::getpid());
  fs::create_directories(scratch, ec);
  if (ec) {
    err << fmt::format("*Cannot write file*  {}: {}\n", scratch.string(), ec.message());
    reraise_termination();
    return kExitUsage;
  }

  // The scratch folder goes on every way out of here: a return, an exception (the workers are
  // stopped and joined first), Ctrl-C, SIGTERM / SIGHUP. Only SIGKILL leaves it.
  struct RemoveFolder {
    fs::path dir;
    ~RemoveFolder() {
      std::error_code ignored;
      fs::remove_all(dir, ignored);
    }
  } remove_scratch{scratch};

  // Cases run on `jobs` threads, each waiting for its own `asimov run` process; lines are
  // printed in case order as soon as every earlier case is done.
  std::vector<Outcome> outcomes(cases.size());
  std::vector<bool> done(cases.size(), false);
  std::mutex mutex;
  std::condition_variable ready;
  std::size_t next = 0;
  const auto worker = [&] {
    for (;;) {
      std::size_t i;
      {
        std::lock_guard lock(mutex);
        if (next == cases.size() || interrupted.load()) return;
        i = next++;
      }
      Outcome o;
      try {
        o = run_one(cases[i], opt, executable, scratch, i, interrupted);
      } catch (const std::exception& e) {  // a failed case, not a std::terminate of the whole run
        o.diffs.push_back(fmt::format("*Internal error*  {}", e.what()));
      }
      std::lock_guard lock(mutex);
      outcomes[i] = std::move(o);
      done[i] = true;
      ready.notify_all();
    }
  };
  const int jobs = std::clamp<int>(opt.jobs, 1, static_cast<int>(cases.size()));
  std::vector<std::thread> workers;
  struct JoinWorkers {  // on an exception below: stop them, then join (a joinable thread terminates)
    std::vector<std::thread>& workers;
    std::atomic<bool>& stop;
    ~JoinWorkers() {
      for (auto& w : workers)
        if (w.joinable()) stop.store(true);
      for (auto& w : workers)
        if (w.joinable()) w.join();
    }
  } join_workers{workers, interrupted};
  for (int j = 0; j < jobs; ++j) workers.emplace_back(worker);

  std::size_t width = 0, failed = 0, reported = 0;
  for (const auto& c : cases) width = std::max(width, c.name.size());
  // [k/N] before each line only on a terminal: logs and CI files keep the plain format.
  const bool terminal = &out == &std::cout && ::isatty(STDOUT_FILENO) == 1;
  const std::size_t count_width = std::to_string(cases.size()).size();
  for (std::size_t i = 0; i < cases.size(); ++i) {
    {
      // Woken by each finished case; the wait also ends, once interrupted, at the first case no
      // worker started (polled: the signal handler cannot notify).
      std::unique_lock lock(mutex);
      while (!done[i] && !(interrupted.load() && i >= next)) ready.wait_for(lock, std::chrono::milliseconds(50));
      if (!done[i]) break;
    }
    if (interrupted.load() && (outcomes[i].actual.exit_note == "interrupted" ||
                               outcomes[i].actual.exit_code == kExitInterrupted))
      break;  // stopped by the Ctrl-C, not a result
    ++reported;
    const Outcome& o = outcomes[i];
    const bool pass = o.diffs.empty();
    failed += pass ? 0 : 1;
    if (terminal) out << fmt::format("[{:>{}}/{}] ", i + 1, count_width, cases.size());
    out << fmt::format("{} {:<{}} {:7.2f} s\n", pass ? "PASS" : "FAIL", cases[i].name, width, o.actual.seconds);
    for (const auto& d : o.diffs) out << "       " << d << '\n';
    for (const auto& u : o.updates) out << "       update: " << u << '\n';
    out.flush();
  }
  for (auto& w : workers) w.join();
  fs::remove_all(scratch, ec);
  signal(SIGINT, SIG_DFL);
  if (interrupted.load()) {
    out << fmt::format("Interrupted: {} of {} case{} run, {} failed\n", reported, cases.size(),
                       cases.size() == 1 ? "" : "s", failed);
    out.flush();
    reraise_termination();  // ends the process if SIGTERM / SIGHUP stopped it
    return kExitInterrupted;
  }
  reraise_termination();

  const double total_s = std::chrono::duration<double>(Clock::now() - start).count();
  out << fmt::format("{} passed, {} failed, {} case{} in {:.2f} s\n", cases.size() - failed, failed, cases.size(),
                     cases.size() == 1 ? "" : "s", total_s);
  if (!opt.junit.empty()) {
    if (const auto written = write_file_atomically(opt.junit, junit_document(cases, outcomes, failed, total_s, opt)); !written) {
      err << "*Cannot write file*  " << written.error().message << '\n';
      return failed == 0 ? kExitOutputLost : kExitTestFailed;  // the cases' verdict stays
    }
  }
  return failed == 0 ? kExitCompleted : kExitTestFailed;
}

}  // namespace asimov::app
