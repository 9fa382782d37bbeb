// The sample programs of programs/language: each NAME.v2 runs its first program and must print
// exactly NAME.out. When NAME.err exists the run must stop with an error whose report (load
// warnings first) is NAME.err; otherwise it must complete. Every sample runs twice: through
// the library in the default cell's arm (PUMA 560 at READY, 200 mm tool, no objects), and
// through the real CLI (`asimov run NAME.v2`, the default cell), comparing stdout, stderr and
// the exit code.
#include "interpreter_fixture.hpp"
#include "asimov/motion/location.hpp"

#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path samples_dir() { return fs::path(ASIMOV_SOURCE_DIR) / "programs" / "language"; }

std::vector<std::string> sample_names() {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(samples_dir()))
    if (entry.path().extension() == ".v2") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

TEST_CASE("programs/language samples print their .out", "[samples]") {
  const auto names = sample_names();
  CHECK(names.size() >= 40);
  for (const std::string& name : names) {
    SECTION(name) {
      asimov::test::InterpreterFixture f;
      f.sim.set_tool(asimov::motion::trans(0, 0, 200, 0, 0, 0));  // the default cell's tool
      const fs::path dir = samples_dir();
      const auto diags = f.interp.load_source(read_text(dir / (name + ".v2")), name + ".v2");
      std::string report;
      for (const auto& d : diags) {
        INFO(asimov::interpreter::format_diagnostic(d));
        REQUIRE(d.warning);
        report += "Warning: " + asimov::interpreter::format_diagnostic(d);
      }
      const auto r = f.interp.run(f.interp.program_names().front());
      INFO(asimov::interpreter::format_diagnostic(r.error));
      if (fs::exists(dir / (name + ".err"))) {
        CHECK(r.status == asimov::interpreter::RunStatus::error);
        CHECK(report + asimov::interpreter::format_diagnostic(r.error) == read_text(dir / (name + ".err")));
      } else {
        CHECK(r.status == asimov::interpreter::RunStatus::completed);
        CHECK(report.empty());
      }
      CHECK(f.out.str() == read_text(dir / (name + ".out")));
    }
  }
}

TEST_CASE("programs/language samples through the CLI", "[samples][cli]") {
  const fs::path binary = ASIMOV_BINARY;
  if (!fs::exists(binary)) {
    WARN("the asimov executable is not built: " << binary);
    return;
  }
  const fs::path tmp = fs::temp_directory_path() / ("asimov_samples_" + std::to_string(::getpid()));
  fs::create_directories(tmp);
  for (const std::string& name : sample_names()) {
    SECTION(name) {
      const fs::path out = tmp / (name + ".stdout"), err = tmp / (name + ".stderr");
      const std::string command = "cd '" + samples_dir().string() + "' && '" + binary.string() + "' run " + name
          + ".v2 > '" + out.string() + "' 2> '" + err.string() + "' < /dev/null";
      const int status = std::system(command.c_str());
      REQUIRE(WIFEXITED(status));
      const fs::path expected_err = samples_dir() / (name + ".err");
      const bool fails = fs::exists(expected_err);
      CHECK(WEXITSTATUS(status) == (fails ? 2 : 0));
      CHECK(read_text(out) == read_text(samples_dir() / (name + ".out")));
      CHECK(read_text(err) == (fails ? read_text(expected_err) : "Program completed: " + name + "\n"));
    }
  }
  fs::remove_all(tmp);
}
