// `asimov pairs`: the generated pair matrix of the built-in cell and of a cell file, end to end
// through the CLI; the second run reads the cache.
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <map>
#include <sstream>

using namespace asimov;
using test::run_cli;

namespace {

// "a b" -> reason, from the table printed by `asimov pairs`.
std::map<std::string, std::string> reasons(const std::string& out) {
  std::map<std::string, std::string> m;
  std::istringstream in(out);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string a, b, reason, contacts;
    if (ls >> a >> b >> reason >> contacts && contacts.find('/') != std::string::npos) m[a + " " + b] = reason;
  }
  return m;
}

}  // namespace

TEST_CASE("pairs: the built-in cell, joined links ADJACENT, robot-object pairs enabled, cache reused", "[pairs]") {
  const auto cache_home = test::scratch_dir() / "xdg-cache";
  std::filesystem::remove_all(cache_home);
  ::setenv("XDG_CACHE_HOME", cache_home.string().c_str(), 1);  // the default cell's cache goes here
  const auto first = run_cli("pairs --samples 300");
  INFO(first.err);
  REQUIRE(first.exit_code == 0);
  const auto m = reasons(first.out);
  CHECK(m.size() == 45);  // link0..link6, tool, table, box: 10 bodies
  for (int k = 0; k < 6; ++k)
    CHECK(m.at("link" + std::to_string(k) + " link" + std::to_string(k + 1)) == "ADJACENT");
  CHECK(m.at("link5 tool") == "ADJACENT");
  CHECK(m.at("link6 tool") == "RIGID");
  CHECK(m.at("table box") == "RIGID");
  CHECK(m.at("link0 table") == "RIGID");
  for (const char* object : {"table", "box"}) {
    for (int k = 1; k <= 6; ++k) CHECK(m.at("link" + std::to_string(k) + " " + object) == "ENABLED");
    CHECK(m.at(std::string("tool ") + object) == "ENABLED");
  }
  CHECK(first.out.find(" random poses, seed 20260101") != std::string::npos);  // whole batches: >= 300
  const auto cache = cache_home / "asimov" / "default-cell.pairs";
  CHECK(std::filesystem::exists(cache));
  CHECK(first.err.find("generated, written to " + cache.string()) != std::string::npos);

  const auto second = run_cli("pairs --samples 300");
  REQUIRE(second.exit_code == 0);
  CHECK(second.err.find("read from " + cache.string()) != std::string::npos);
  CHECK(second.out == first.out);
  // Another N is another key: generated again.
  const auto third = run_cli("pairs --samples 200");
  CHECK(third.err.find("generated") != std::string::npos);
  ::unsetenv("XDG_CACHE_HOME");
}

TEST_CASE("pairs: a cell file, its ignore list as USER_IGNORE, cache next to the cell", "[pairs]") {
  const auto dir = test::scratch_dir() / "pairs-cell";
  std::filesystem::create_directories(dir);
  const auto cell = dir / "cell.yaml";
  std::ofstream(cell) << "objects:\n  - {name: post, box: [100, 100, 400], at: [600, 0, -400, 0, 0, 0]}\n"
                         "collision: {ignore: [[link6, post]]}\n";
  std::filesystem::remove(dir / "cell.yaml.pairs");
  const auto r = run_cli("pairs " + cell.string() + " --samples 100");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto m = reasons(r.out);
  CHECK(m.size() == 28);  // link0..link6, post
  CHECK(m.at("link6 post") == "USER_IGNORE");
  CHECK(m.at("link5 post") == "ENABLED");
  CHECK(m.at("link2 link3") == "ADJACENT");
  CHECK(std::filesystem::exists(dir / "cell.yaml.pairs"));
  const auto again = run_cli("pairs " + cell.string() + " --samples 100");
  CHECK(again.err.find("read from") != std::string::npos);
  CHECK(again.out == r.out);
  // --no-cache neither reads nor writes; a bad cell is a usage error.
  CHECK(run_cli("pairs " + cell.string() + " --samples 100 --no-cache").err.find("read from") == std::string::npos);
  CHECK(run_cli("pairs " + (dir / "missing.yaml").string()).exit_code == 1);
  CHECK(run_cli("pairs --samples -5").exit_code == 1);
}
