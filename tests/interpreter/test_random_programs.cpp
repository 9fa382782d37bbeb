// Random token soup (fixed seed): loading never throws and reports syntax errors with a
// line and column; whatever loads also runs to a status without throwing.
#include "interpreter_fixture.hpp"

#include <catch2/catch.hpp>

#include <random>

TEST_CASE("random programs load and run without escaping exceptions", "[random]") {
  const char* tokens[] = {
      "x", "y", "a[1]", "a[]", "$s", "#p", "=", "==", "<>", "(", ")", "[", "]", ",", ":", ";",
      "+", "-", "*", "/", "MOD", "AND", "OR", "NOT", "1", "2.5", "0", "-1", "1e999", "^B101",
      "\"txt\"", "\"", "IF", "THEN", "ELSE", "END", "FOR", "TO", "STEP", "WHILE", "DO", "UNTIL",
      "GOTO", "10", "CALL", "sub", "RETURN", "STOP", "TYPE", "/F6.2", "/S", "SET", "TRANS",
      "HERE", "MOVE", "DEPART", "BREAK", "SPEED", "ALWAYS", "SIN", "MAX", "DECOMPOSE", "CASE",
      "OF", "VALUE", "ANY", "EXIT", "AUTO", ".END", ".PROGRAM", "\t", "SIGNAL", "SIG", "LAST"};
  std::mt19937 rng(12345);
  std::uniform_int_distribution<std::size_t> pick(0, std::size(tokens) - 1);
  std::uniform_int_distribution<int> length(0, 7);
  // Expressions from the expression alphabet, statements from valid one-line templates.
  const char* operands[] = {"x", "y", "a[1]", "a[x]", "1", "0", "-2.5", "1e300", "SIN(x)",
                            "MAX(x, 2)", "(x + 1)", "NOT y", "TRUE", "DZ(t)", "t", "LEN($s)"};
  const char* operators[] = {"+", "-", "*", "/", "MOD", "AND", "OR", "==", "<", "=>", "BAND", ":"};
  std::uniform_int_distribution<std::size_t> operand(0, std::size(operands) - 1);
  std::uniform_int_distribution<std::size_t> op(0, std::size(operators) - 1);
  auto expression = [&] {
    std::string e = operands[operand(rng)];
    for (int k = length(rng) / 3; k > 0; --k) e += std::string(" ") + operators[op(rng)] + " " + operands[operand(rng)];
    return e;
  };
  const char* templates[] = {"x = @", "y = @", "TYPE @, @", "IF @ GOTO 10", "a[@] = @", "$s = $s + \"@\"",
                             "CALL sub(x, @)", "SET t = TRANS(@, @)", "DECOMPOSE a[0] = t", "SIGNAL @",
                             "SPEED @", "TYPE LAST(a[]), DEFINED(y)", "x = SIG(@)"};
  std::uniform_int_distribution<std::size_t> pick_template(0, std::size(templates) - 1);
  int loaded = 0;
  for (int round = 0; round < 300; ++round) {
    std::string text = ".PROGRAM main()\n  x = 1\n  y = 0\n  $s = \"s\"\n  SET t = NULL\n";
    for (int line = 0; line < 6; ++line) {
      if (round % 2 == 0) {  // token soup
        const int n = length(rng);
        for (int t = 0; t < n; ++t) text += std::string(tokens[pick(rng)]) + " ";
      } else {
        for (const char* c = templates[pick_template(rng)]; *c; ++c) text += *c == '@' ? expression() : std::string(1, *c);
      }
      text += "\n";
    }
    text += "10 y = 1\n.END\n.PROGRAM sub(a, b)\n  a = 1\n.END\n";
    INFO(text);
    asimov::test::InterpreterFixture f;
    f.interp.limits().max_statements = 10'000;
    std::vector<asimov::interpreter::Diagnostic> d;
    REQUIRE_NOTHROW(d = f.load(text));
    for (const auto& e : d) {
      CHECK(e.line >= 1);
      CHECK(e.column >= 1);
      CHECK_FALSE(asimov::interpreter::format_diagnostic(e).empty());
    }
    if (!d.empty()) continue;
    ++loaded;
    REQUIRE_NOTHROW(f.interp.run("main"));
  }
  CHECK(loaded > 30);
}
