// The sample programs of programs/language: each NAME.v2 runs its first program in an empty
// PUMA 560 cell and must print exactly NAME.out. errors.v2 must stop with an error.
#include "interpreter_fixture.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST_CASE("programs/language samples print their .out", "[samples]") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(ASIMOV_SOURCE_DIR) / "programs" / "language";
  int count = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".v2") continue;
    ++count;
    const std::string name = entry.path().stem().string();
    SECTION(name) {
      asimov::test::InterpreterFixture f;
      const auto diags = f.interp.load_file(entry.path().string());
      std::string report;
      for (const auto& d : diags) report += asimov::val::format_diagnostic(d);
      INFO(report);
      REQUIRE(diags.empty());
      const auto r = f.interp.run(f.interp.program_names().front());
      INFO(asimov::val::format_diagnostic(r.error));
      if (name == "errors") {
        CHECK(r.status == asimov::val::RunStatus::error);
        CHECK(r.error.message == "*Undefined value*");
        CHECK(r.error.step == 3);
      } else {
        CHECK(r.status == asimov::val::RunStatus::completed);
      }
      fs::path expected = entry.path();
      expected.replace_extension(".out");
      CHECK(f.out.str() == read_text(expected));
    }
  }
  CHECK(count >= 5);
}
