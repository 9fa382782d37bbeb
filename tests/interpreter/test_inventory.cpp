// The inventory of the V+ language (docs/val2-dialect.md §13): every word listed there is
// implemented, accepted with no effect (with the reason), or refused by name (with the reason),
// and asimov behaves so. A row of another status, or a word that is none of the three, fails.
#include "interpreter_fixture.hpp"
#include "interpreter/src/functions.hpp"
#include "interpreter/src/parser.hpp"
#include "interpreter/src/settings.hpp"
#include "interpreter/src/vplus_words.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <set>
#include <sstream>

using namespace asimov::interpreter;
using asimov::test::InterpreterFixture;
using asimov::test::MonitorFixture;

namespace {

struct Row {
  std::string word, kind, status, why;
};

std::string trim(std::string s) {
  const auto a = s.find_first_not_of(" `"), b = s.find_last_not_of(" `");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// The rows `| word | kind | status | test, or why |` of §13.
std::vector<Row> inventory() {
  std::ifstream in(std::string(ASIMOV_SOURCE_DIR) + "/docs/val2-dialect.md");
  REQUIRE(in);
  std::vector<Row> rows;
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("## ", 0) == 0) inside = line.rfind("## 13.", 0) == 0;
    if (!inside || line.rfind("| `", 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream s(line.substr(1));
    for (std::string c; std::getline(s, c, '|');) cells.push_back(trim(c));
    REQUIRE(cells.size() >= 4);
    rows.push_back({cells[0], cells[1], cells[2], cells[3]});
  }
  return rows;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

WordKind kind_of(const std::string& k) {
  if (k == "instruction") return WordKind::instruction;
  if (k == "function") return WordKind::function;
  if (k == "monitor") return WordKind::monitor;
  if (k == "switch") return WordKind::switch_;
  REQUIRE(k == "parameter");
  return WordKind::parameter;
}

std::string program(const std::string& body) { return ".PROGRAM main()\n" + body + "\n.END\n"; }

// How a word is used in a program line, for its behaviour.
std::string usage(const Row& r) {
  if (r.kind == "instruction") return r.word == "FOPEN" || r.word == "FCMND" ? r.word + " (5) \"x\"" : r.word;
  if (r.kind == "function") return r.word[0] == '$' ? "$x = " + r.word + "()" : "x = " + r.word + "()";
  if (r.kind == "switch") return "ENABLE " + r.word;
  return "PARAMETER " + r.word + " = 1";
}

bool implemented(const Row& r) {
  switch (kind_of(r.kind)) {
    case WordKind::instruction: {
      if (vplus_word(r.word, WordKind::instruction)) return false;
      const std::string line = r.word == "EXECUTE" ? "EXECUTE p" : r.word;  // needs its program
      for (const Diagnostic& d : parse_source(program(line), "t.v2").errors)
        if (d.detail == "expected a statement") return false;
      return true;
    }
    case WordKind::function: {
      if (r.word == "$ENCODE") return parse_source(program("$s = $ENCODE(1)"), "t.v2").errors.empty();  // its own rule
      const auto f = find_function(lower(r.word));
      return f && *f != Func::vplus;
    }
    case WordKind::monitor: {
      const CommandMatch m = match_command(r.word);
      return m.match == Match::found && command_info(m.command).name == r.word;
    }
    case WordKind::switch_: return known_switch(r.word);
    case WordKind::parameter: return known_parameter(r.word);
  }
  return false;
}

}  // namespace

TEST_CASE("every word of the inventory is implemented, accepted without effect, or refused by name", "[inventory]") {
  const std::vector<Row> rows = inventory();
  REQUIRE(rows.size() > 300);
  std::set<std::pair<std::string, std::string>> listed;
  for (const Row& r : rows) {
    INFO(r.word << " (" << r.kind << "): " << r.status);
    CHECK(listed.insert({r.word, r.kind}).second);  // once each
    if (r.status == "implemented") {
      CHECK(implemented(r));
      CHECK_FALSE(r.why.empty());  // the test that shows it
      continue;
    }
    REQUIRE((r.status == "no effect" || r.status == "refused"));
    const VplusWord* w = vplus_word(r.word, kind_of(r.kind));
    REQUIRE(w);
    CHECK((w->support == Support::no_effect) == (r.status == "no effect"));
    CHECK(r.why == std::string(w->reason));
    if (r.kind == "monitor") {
      MonitorFixture f;
      CHECK(f.run(r.word).rfind("*Not supported in simulation*  " + r.word + ":", 0) == 0);
      continue;
    }
    InterpreterFixture f;
    const auto result = f.run(program(usage(r)));
    INFO(f.load_report);
    REQUIRE(f.loaded);  // a V+ word always loads
    if (r.status == "refused") {
      REQUIRE(result.status == RunStatus::error);
      CHECK(result.error.message == "*Not supported in simulation*");
      CHECK(result.error.detail.rfind(r.word, 0) == 0);  // named
    } else {
      CHECK(result.status == RunStatus::completed);
      if (r.kind != "parameter") {
        REQUIRE(result.warnings.size() == 1);
        CHECK(result.warnings[0].detail.find(r.word) != std::string::npos);
      }
    }
  }
  // Every word asimov refuses or ignores is in the inventory.
  for (const VplusWord& w : vplus_words()) {
    const char* kinds[] = {"instruction", "function", "monitor", "switch", "parameter"};
    INFO(w.name);
    CHECK(listed.count({std::string(w.name), kinds[static_cast<int>(w.kind)]}) == 1);
  }
}

TEST_CASE("a word V+ does not have keeps its syntax error; a V+ word is refused by name", "[inventory]") {
  InterpreterFixture f;
  auto d = f.load(program("FROBNICATE 3"));
  REQUIRE(d.size() == 1);
  CHECK(d[0].detail == "expected a statement");
  d = f.load(program("x = FROB(2)"));
  REQUIRE(d.size() == 1);
  CHECK(d[0].detail == "unknown function FROB");
  InterpreterFixture g;
  const auto r = g.run(program("TYPE \"before\"\nVPICTURE 1\nTYPE \"after\""));
  REQUIRE(g.loaded);
  REQUIRE(r.status == RunStatus::error);
  CHECK(r.error.detail == "VPICTURE: vision (AdeptVision) is not simulated");
  CHECK(g.out.str() == "before\n");
  InterpreterFixture h;
  const auto n = h.run(program("x = VSTATUS(1, 2)\n"));
  REQUIRE(h.loaded);
  CHECK(n.error.detail == "VSTATUS: vision (AdeptVision) is not simulated");
}
