// Expressions that would overflow the stack or cost quadratic time (issue 17): refused at load
// with *Expression too complex* at file:line:column past the documented limits, and just inside
// them parsed, checked, compiled and run (also in the sanitizer build, whose frames are larger).
#include "interpreter_fixture.hpp"

#include "interpreter/src/limits.hpp"

#include <catch2/catch.hpp>

#include <chrono>

using namespace asimov;
using test::InterpreterFixture;
using interpreter::kMaxExpressionNesting;
using interpreter::kMaxExpressionOperators;

namespace {

std::string repeat(const std::string& s, int n) {
  std::string out;
  out.reserve(s.size() * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) out += s;
  return out;
}

std::string program(const std::string& statement) { return ".PROGRAM main()\n  " + statement + "\n.END\n"; }

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TEST_CASE("deep nesting and long chains are *Expression too complex* at their column", "[hostile][expressions]") {
  struct Input {
    std::string statement;
    std::string detail;
  };
  const std::string nesting = "more than 64 parentheses, brackets, calls and signs inside one another";
  const std::string chain = "more than 1000 operators in one statement";
  const std::vector<Input> inputs = {
      {"x = " + repeat("(", 10000) + "1" + repeat(")", 10000), nesting},
      {"x = " + repeat("-", 30000) + "1", nesting},
      {"x = " + repeat("- ", 30000) + "1", nesting},
      {"x = " + repeat("NOT ", 5000) + "TRUE", nesting},
      {"x = " + repeat("SIN(", 5000) + "1" + repeat(")", 5000), nesting},
      {"x = a" + repeat("[a", 5000) + repeat("]", 5000), nesting},
      {"x = 1" + repeat(" * 1", 100000), chain},
      {"x = 1" + repeat(" == 1", 100000), chain},
      {"x = 1" + repeat(" + 1", 80000), chain},
      {"$s = \"\"" + repeat(" + \"\"", 100000), chain},
      {"x = 1" + repeat(" AND 1", 5000), chain},
      {"SET p = TRANS(1,2,3,0,0,0)" + repeat(":TRANS(1,2,3,0,0,0)", 2000), chain},
  };
  for (const auto& in : inputs) {
    InterpreterFixture f;
    const auto t0 = std::chrono::steady_clock::now();
    const auto d = f.load(program(in.statement));
    INFO(in.statement.substr(0, 60));
    CHECK(seconds(t0) < 5);
    REQUIRE(d.size() == 1);
    CHECK(d[0].message == "*Expression too complex*");
    CHECK(d[0].detail == in.detail);
    CHECK(d[0].file == "test.v2");
    CHECK(d[0].line == 2);
    CHECK(d[0].column > 3);
  }
}

TEST_CASE("just inside the limits: parsed, checked and run", "[hostile][expressions]") {
  {
    InterpreterFixture f;  // 60 parentheses around a sum of 900 terms
    const auto r = f.run(program("x = " + repeat("(", kMaxExpressionNesting - 4) + "0" + repeat(" + 1", 900) +
                                 repeat(")", kMaxExpressionNesting - 4) + "\n  TYPE x"));
    INFO(f.load_report);
    REQUIRE(f.loaded);
    CHECK(r.status == interpreter::RunStatus::completed);
    CHECK(f.out.str() == "900\n");
  }
  {
    InterpreterFixture f;  // 60 signs in a row
    const auto r = f.run(program("x = " + repeat("- ", kMaxExpressionNesting - 4) + "3\n  TYPE x"));
    REQUIRE(f.loaded);
    CHECK(r.status == interpreter::RunStatus::completed);
    CHECK(f.out.str() == "3\n");
  }
  {
    InterpreterFixture f;  // 999 comparisons and products
    const auto r = f.run(program("x = 1" + repeat(" * 1", kMaxExpressionOperators / 2 - 2) +
                                 repeat(" == 1", kMaxExpressionOperators / 2 - 2) + "\n  TYPE x"));
    REQUIRE(f.loaded);
    CHECK(r.status == interpreter::RunStatus::completed);
  }
  {
    InterpreterFixture f;  // a string sum: the kind of each prefix is known without re-walking it
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = f.run(program("$s = \"\"" + repeat(" + \"a\"", 120) + "\n  TYPE $s"));
    REQUIRE(f.loaded);
    CHECK(r.status == interpreter::RunStatus::completed);
    CHECK(f.out.str() == std::string(120, 'a') + "\n");
    CHECK(seconds(t0) < 5);
  }
}

TEST_CASE("strings and comments do not count toward the limits", "[hostile][expressions]") {
  InterpreterFixture f;
  const auto r = f.run(program("$s = \"" + repeat("(-", 60) + "\"  ; " + repeat("((((+", 1000) + "\n  TYPE $s"));
  REQUIRE(f.loaded);
  CHECK(r.status == interpreter::RunStatus::completed);
}

TEST_CASE("a long program of many lines and labels loads in linear time", "[hostile][expressions]") {
  std::string text = ".PROGRAM main()\n  x = 0\n";
  for (int i = 1; i <= 60000; ++i) text += std::to_string(i) + " x = x + 1\n";
  text += "  TYPE x\n.END\n";
  InterpreterFixture f;
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = f.run(text);
  REQUIRE(f.loaded);
  CHECK(r.status == interpreter::RunStatus::completed);
  CHECK(f.out.str() == "60000\n");
  CHECK(seconds(t0) < 30);
}
