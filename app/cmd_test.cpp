// `asimov test [PATH...]`: runs every sample-program case under the paths as `asimov run` would
// and compares with the expected files (app/suite.hpp; formats in programs/README.md).
#include "app/atomic_file.hpp"
#include "app/commands.hpp"
#include "app/exit_codes.hpp"
#include "app/sigint.hpp"
#include "app/suite.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <condition_variable>
#include <filesystem>
#include <mutex>
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

std::string junit_document(const std::vector<suite::Case>& cases, const std::vector<Outcome>& outcomes,
                           std::size_t failed, double total_s) {
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
  return fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<testsuites name=\"asimov test\" tests=\"{0}\" failures=\"{1}\" errors=\"0\" time=\"{2:.3f}\">\n"
      "  <testsuite name=\"asimov test\" tests=\"{0}\" failures=\"{1}\" errors=\"0\" skipped=\"0\" time=\"{2:.3f}\">\n"
      "{3}  </testsuite>\n</testsuites>\n",
      cases.size(), failed, total_s, body);
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

int test_command(const TestOptions& opt, std::ostream& out, std::ostream& err) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  const std::vector<std::string> paths = opt.paths.empty() ? std::vector<std::string>{"."} : opt.paths;
  suite::Discovery found = suite::discover(paths);
  if (!found.errors.empty()) {
    for (const auto& e : found.errors) err << e << '\n';
    return kExitUsage;
  }
  std::vector<suite::Case> cases;
  for (auto& c : found.cases)
    if (opt.filter.empty() || suite::filter_matches(opt.filter, c.name)) cases.push_back(std::move(c));
  if (cases.empty()) {
    err << (found.cases.empty() ? fmt::format("*No test cases*  none under {}\n", fmt::join(paths, " "))
                                : fmt::format("*No test cases*  none of {} matches --filter {}\n",
                                              found.cases.size(), opt.filter));
    return kExitUsage;
  }
  if (!opt.junit.empty()) {
    std::error_code ec;
    const fs::path folder = fs::path(opt.junit).parent_path();
    if (!folder.empty() && !fs::is_directory(folder, ec)) {
      err << fmt::format("*Cannot write file*  {}: no folder {}\n", opt.junit, folder.string());
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
  const fs::path scratch = fs::temp_directory_path(ec) / fmt::format("asimov-test-{}", ::getpid());
  fs::create_directories(scratch, ec);
  if (ec) {
    err << fmt::format("*Cannot write file*  {}: {}\n", scratch.string(), ec.message());
    return kExitUsage;
  }

  // Ctrl-C: running cases are killed, no new one starts, the scratch folder is removed and the
  // command exits 130 after the lines of the cases that finished.
  std::atomic<bool>& interrupted = sigint_flag();
  interrupted.store(false);
  install_sigint(false);

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
      Outcome o = run_one(cases[i], opt, executable, scratch, i, interrupted);
      std::lock_guard lock(mutex);
      outcomes[i] = std::move(o);
      done[i] = true;
      ready.notify_all();
    }
  };
  const int jobs = std::clamp<int>(opt.jobs, 1, static_cast<int>(cases.size()));
  std::vector<std::thread> workers;
  for (int j = 0; j < jobs; ++j) workers.emplace_back(worker);

  std::size_t width = 0, failed = 0, reported = 0;
  for (const auto& c : cases) width = std::max(width, c.name.size());
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
    return kExitInterrupted;
  }

  const double total_s = std::chrono::duration<double>(Clock::now() - start).count();
  out << fmt::format("{} passed, {} failed, {} case{} in {:.2f} s\n", cases.size() - failed, failed, cases.size(),
                     cases.size() == 1 ? "" : "s", total_s);
  if (!opt.junit.empty()) {
    if (const auto written = write_file_atomically(opt.junit, junit_document(cases, outcomes, failed, total_s)); !written) {
      err << "*Cannot write file*  " << written.error().message << '\n';
      return kExitUsage;
    }
  }
  return failed == 0 ? kExitCompleted : kExitTestFailed;
}

}  // namespace asimov::app
