// Stage 1: every construct of the slice parses; syntax errors carry line, column and caret.
#include "interpreter/src/parser.hpp"

#include <catch2/catch.hpp>

using namespace asimov::interpreter;

namespace {

// Parses one statement inside a program and returns the errors.
std::vector<Diagnostic> errors_of(const std::string& line) {
  return parse_source(".PROGRAM p()\n" + line + "\n.END\n", "t.v2").errors;
}

template <typename T>
const T* statement_as(const ParsedSource& p, std::size_t index) {
  const auto& l = p.lines.at(index);
  return l.statement ? boost::get<T>(&*l.statement) : nullptr;
}

}  // namespace

TEST_CASE("every slice construct parses", "[parser]") {
  const char* lines[] = {
      "n = n + 1", "10 n = n + 1", "20", "x = -2 * -3", "y = NOT a == b", "a[1,2] = 3",
      "$s = \"text; not a comment\" + $t", "SET p = TRANS(1,2,3):TRANS(,,300)",
      "SET #pp = #PPOINT(0,-90,90,0,0,0)", "SET pp = PPOINT(0,0,0,0,0,0)", "HERE q", "HERE #q",
      "DECOMPOSE arr[1] = HERE", "MOVE p", "MOVES p", "APPRO p, 50", "APPROS p, -5",
      "DEPART 20", "DEPARTS 20", "BREAK", "SPEED 50", "SPEED 50 ALWAYS", "speed.x = 3",
      "ready.pos = 1", "TYPE \"x=\", x, /F8.3, 1/3, /S", "TYPE", "TYPE /C2, /X3, /I4, /D",
      "FOR i = 1 TO 10", "FOR i = 10 TO 1 STEP -1", "END", "IF a <> b THEN", "IF a THEN",
      "ELSE", "IF x =< 3 GOTO 10", "WHILE x > 0 DO", "WHILE x > 0", "DO", "UNTIL x",
      "CALL sub(a, , 3 + 1)", "CALL foo", "CALL foo()", "CALL f(arr[])", "RETURN", "STOP",
      "EXIT", "NEXT", "GOTO 10",
      "z = ^B101 BOR ^HFF BAND ^17 BXOR 'A + .5 + 5. + 1e-3 + 1.5E+6",
      "x = SIN(30) + COS(0) + TAN(1) + ATAN2(1,2) + SQRT(4) + ABS(-1) + INT(2.5) + MIN(1,2) + MAX(3)",
      "x = a AND b OR c XOR d MOD 3", "x = (a + b) * c", "move p ; comment", "\tMOVE\tp",
      "x = 1 == 2", "x = 1 >= 2 + (3 <= 4) + (5 => 6)", "x = DX(HERE) + DISTANCE(a, b)",
  };
  for (const char* line : lines) {
    INFO(line);
    const auto errors = errors_of(line);
    CHECK(errors.empty());
    for (const auto& e : errors) INFO(format_diagnostic(e));
  }
}

TEST_CASE("the parser keeps the text's structure", "[parser]") {
  const auto p = parse_source(".program Main(a, $b, #c, d[]) ; comment\n"
                              "  ; only a comment\n"
                              "10 n = n + 1\n"
                              "  x = -2 * -3\n"
                              "  speed 50 always\n"
                              "  if x goto 10\n"
                              ".end\n", "t.v2");
  REQUIRE(p.errors.empty());
  REQUIRE(p.lines.size() == 7);
  const auto* h = statement_as<ast::ProgramHeader>(p, 0);
  REQUIRE(h);
  CHECK(h->name == "Main");
  CHECK(h->params == std::vector<std::string>{"a", "$b", "#c", "d[]"});
  CHECK(!p.lines[1].statement);
  CHECK(!p.lines[1].label);
  REQUIRE(p.lines[2].label.has_value());
  CHECK(*p.lines[2].label == 10);
  CHECK(p.lines[2].column == 4);
  const auto* b = statement_as<ast::Binding>(p, 3);
  REQUIRE(b);
  CHECK(b->target.name == "x");
  CHECK(b->value.rest.size() == 1);  // flat: the checker applies precedence
  CHECK(b->value.rest[0].op == ast::Op::mul);
  const auto* s = statement_as<ast::Instruction>(p, 4);
  REQUIRE(s);
  CHECK(s->kw == ast::Kw::speed);
  CHECK(s->trailing == ast::Kw::always);
  const auto* i = statement_as<ast::IfStmt>(p, 5);
  REQUIRE(i);
  REQUIRE(i->goto_label.has_value());
  CHECK(*i->goto_label == 10);
}

TEST_CASE("CR LF line ends", "[parser]") {
  const auto p = parse_source(".PROGRAM p()\r\n  x = 1\r\n.END\r\n", "t.v2");
  CHECK(p.errors.empty());
  CHECK(p.text[1] == "  x = 1");
}

TEST_CASE("syntax errors carry line, column and caret", "[parser][errors]") {
  const auto p = parse_source(".PROGRAM pick()\n  total = (n + 2 * k\n.END\n", "pick.v2");
  REQUIRE(p.errors.size() == 1);
  const Diagnostic& d = p.errors[0];
  CHECK(d.message == "*Syntax error*");
  CHECK(d.detail == "expected \")\"");
  CHECK(d.line == 2);
  CHECK(d.column == 21);
  CHECK(format_diagnostic(d) ==
        "*Syntax error*  expected \")\"\n pick.v2:2:21\n      total = (n + 2 * k\n                        ^\n");
}

TEST_CASE("the caret copies tabs", "[parser][errors]") {
  const auto p = parse_source(".PROGRAM p()\n\tx = 3 4\n.END\n", "t.v2");
  REQUIRE(p.errors.size() == 1);
  CHECK(p.errors[0].column == 8);
  CHECK(format_diagnostic(p.errors[0]) == "*Syntax error*  unexpected text\n t.v2:2:8\n    \tx = 3 4\n    \t      ^\n");
}

TEST_CASE("all syntax errors of a file are reported, one per line", "[parser][errors]") {
  const auto p = parse_source(".PROGRAM p()\n"
                              "  x = (1\n"        // 2
                              "  y = 2\n"
                              "  IF a = b THEN\n" // 4
                              "  FOR i = 1 10\n"  // 5
                              "  TYPE \"abc\n"    // 6
                              "  x = 1e999\n"     // 7
                              "  + 3\n"           // 8
                              "  MOVE p q\n"      // 9
                              ".END\n", "t.v2");
  REQUIRE(p.errors.size() == 7);
  const int lines[] = {2, 4, 5, 6, 7, 8, 9};
  for (std::size_t i = 0; i < 7; ++i) CHECK(p.errors[i].line == lines[i]);
  CHECK(p.errors[1].detail == "\"=\" is not an operator; use \"==\" to compare");
  CHECK(p.errors[1].column == 8);
  CHECK(p.errors[2].detail == "expected TO");
  CHECK(p.errors[2].column == 13);
  CHECK(p.errors[3].detail == "expected closing \"");
  CHECK(p.errors[4].detail == "number out of range");
  CHECK(p.errors[5].detail == "expected a statement");
  CHECK(p.errors[6].column == 10);
  CHECK(p.lines[2].statement.has_value());  // line 3 still parsed
}

TEST_CASE("reserved words are not names, extended ones are", "[parser]") {
  for (const char* word : {"here", "tool", "base", "pi", "not", "to", "then", "value"}) {  // never names (dialect §1)
    INFO(word);
    const auto e = errors_of(std::string(word) + " = 3");
    REQUIRE(e.size() == 1);
    CHECK(e[0].detail == "\"" + std::string(word) + "\" is a keyword, not a variable");
  }
  CHECK(errors_of("x = \"tab\there\"").size() == 1);  // strings hold ASCII 32-126
  CHECK_FALSE(errors_of("x = to + 1").empty());
  CHECK(errors_of("move.x = 3").empty());
  CHECK(errors_of("to_go = 3").empty());
  CHECK(errors_of("x = movex").empty());
}

TEST_CASE("non-ASCII bytes only in comments", "[parser]") {
  CHECK(errors_of("x = 1 ; caf\xc3\xa9").empty());
  CHECK_FALSE(errors_of("x = 1 + \xc3\xa9").empty());
}

TEST_CASE("names are lower case and 15 characters", "[parser]") {
  CHECK(normalize_name("ABCdef") == "abcdef");
  CHECK(normalize_name("a234567890123456789") == "a23456789012345");
  CHECK(normalize_name("$Name") == "$name");
  CHECK(normalize_name("#a234567890123456789") == "#a23456789012345");
}

TEST_CASE("the reserved words of instructions.def never parse as variables; instruction keywords may", "[parser]") {
  // Operators, the words inside statements and the functions without parentheses (dialect §1).
  for (const char* w : {"and", "or", "xor", "not", "mod", "band", "bor", "bxor", "to", "step", "then", "else",
                        "end", "do", "always", "monitor", "by", "of", "value", "any", "pi", "true", "false",
                        "dest", "null", "random", "tool", "base", "here", "elseif", "elif"}) {
    INFO(w);
    CHECK(!errors_of(std::string("x = ") + w + "[1] + 1").empty());
  }
  // Instruction keywords are names in expressions, where no instruction can stand.
  for (const char* w : {"until", "while", "for", "if", "goto", "call", "return", "stop", "set", "decompose", "move",
                        "moves", "appro", "appros", "depart", "departs", "break", "speed", "type", "exit", "next",
                        "pause", "halt", "case", "auto", "local", "global", "ready", "draw", "righty", "lefty",
                        "above", "below", "flip", "noflip", "single", "multiple", "signal", "timer", "align",
                        "drive", "wait", "prompt", "open", "close", "relax", "openi", "closei", "relaxi", "movet",
                        "movest", "duration", "enable", "disable", "parameter", "switch"}) {
    INFO(w);
    CHECK(errors_of(std::string("x = ") + w + "[1] + 1").empty());
  }
  for (const char* line : {"x = mmps + ips", "x = wait.event", "mmps = 1", "x = attach + read"}) {
    INFO(line);
    CHECK(errors_of(line).empty());
  }
}

TEST_CASE("lines end at LF, CR LF, CR CR LF or CR; the last needs no newline", "[parser]") {
  for (const std::string eol : {"\n", "\r\n", "\r\r\n", "\r"}) {
    INFO(int(eol.size()));
    const auto p = parse_source(".PROGRAM p()" + eol + eol + "  x = 1" + eol + ".END", "t.v2");
    CHECK(p.errors.empty());
    REQUIRE(p.text.size() == 4);
    CHECK(p.text[1].empty());
    CHECK(p.text[2] == "  x = 1");
    CHECK(p.text[3] == ".END");
  }
  const auto mixed = parse_source(".PROGRAM p()\r\r\n\r\r\n  x = 1\r\n.END\n", "t.v2");
  CHECK(mixed.errors.empty());
  CHECK(mixed.text.size() == 4);
  const auto error_line = parse_source(".PROGRAM p()\r\r\n  x = (\r\r\n.END\r\r\n", "t.v2");  // numbered as written
  REQUIRE(error_line.errors.size() == 1);
  CHECK(error_line.errors[0].line == 2);
}

TEST_CASE("a control character is named", "[parser]") {
  auto e = errors_of("x = 1\f+ 2");  // a form feed inside a statement is no page break
  REQUIRE(e.size() == 1);
  CHECK(e[0].detail == "control character 0x0C (form feed)");
  CHECK(e[0].column == 6);
  CHECK(errors_of("x = 1 \x01")[0].detail == "control character 0x01 (Ctrl-A)");
  CHECK(errors_of("x = 1 \x1a")[0].detail == "control character 0x1A (Ctrl-Z)");  // inside a statement
  CHECK(errors_of("x = \x1b")[0].detail == "control character 0x1B (escape)");
  CHECK(errors_of(std::string("x = 1", 5) + std::string(1, '\0'))[0].detail == "control character 0x00 (NUL)");
  CHECK(errors_of("$s = \"a\x7f\"")[0].detail == "control character 0x7F (delete)");
  CHECK(errors_of("x = 1 ; \f in a comment").empty());
  CHECK(errors_of("x = 1\t; a tab is a blank").empty());
}

TEST_CASE("a module as the controller stores it loads: form feeds, Ctrl-Z, NUL padding, a BOM", "[parser]") {
  // The issue 31 reproducer: a form feed line between the programs, Ctrl-Z at the end.
  const auto p = parse_source(".PROGRAM a()\n TYPE \"a\"\n.END\n\f\n.PROGRAM b()\n CALL a()\n.END\n\x1a", "m.v2");
  CHECK(p.errors.empty());
  CHECK(p.text.size() == 7);
  // Adept's tools: CR LF lines, a form feed after each .END, Ctrl-Z, then the sector's padding.
  const auto adept = parse_source("\xEF\xBB\xBF.PROGRAM a()\r\n  x = (1\r\n.END\f\r\n\f.PROGRAM b()\r\n.END\r\n\x1a"
                                  + std::string(5, '\0') + "\x1a garbage \x01\x02",
                                  "m.v2");
  REQUIRE(adept.errors.size() == 1);  // the one real error, where an editor shows it
  CHECK(adept.errors[0].line == 2);
  CHECK(adept.errors[0].column == 9);
  CHECK(adept.text.size() == 5);
  CHECK(adept.text[0] == ".PROGRAM a()");  // the BOM is not text: columns count after it
  // Trailing NULs without Ctrl-Z; a form feed among leading blanks; an .END in other spellings.
  CHECK(parse_source(".PROGRAM a()\n \f TYPE 1\n.end  ; done\n" + std::string(512, '\0'), "m.v2").errors.empty());
  CHECK(parse_source(".PROGRAM a()\n  TYPE 1\n  .End\t\f\n", "m.v2").errors.empty());
  CHECK(parse_source(".PROGRAM a()\r\n  TYPE 1\r\n.END\x1a\xff\xfe garbage", "m.v2").errors.empty());  // right after .END
  // A NUL that is not padding at the end keeps its error.
  const auto nul = parse_source(std::string(".PROGRAM a()\n x = 1\0\n.END\n", 26), "m.v2");
  REQUIRE(nul.errors.size() == 1);
  CHECK(nul.errors[0].detail == "control character 0x00 (NUL)");
}

TEST_CASE("a # where the parse stops gets the comment hint", "[parser]") {
  auto e = errors_of("x = 1  # set x");
  REQUIRE(e.size() == 1);
  CHECK(e[0].detail == "unexpected text; comments start with \";\" in V+");
  CHECK(e[0].column == 8);
  e = errors_of("# a comment");
  REQUIRE(e.size() == 1);
  CHECK(e[0].detail == "expected a statement; comments start with \";\" in V+");
  CHECK(errors_of("SET #p = #PPOINT(1,2,3,4,5,6)").empty());  // precision points unchanged
}

TEST_CASE("instruction keywords are names where no instruction can stand", "[parser]") {
  // Adept's ACE-generated ROS driver: `LOCAL ..., mode, stop`, `stop = STATE(4) BAND 4`, `IF stop THEN`.
  for (const char* line : {"stop = STATE(4) BAND 4", "IF stop THEN", "move = 3", "type = 2", "wait = 1",
                           "x = wait + open * 2", "speed[2] = 1", "IF (stop) THEN", "signal = SIG(1001)",
                           "timer = 2", "for = 1", "x = call + if"}) {
    INFO(line);
    CHECK(errors_of(line).empty());
  }
  const auto p = parse_source(".PROGRAM p()\n  LOCAL a, mode, stop\n  AUTO type, wait\n  stop = 1\n  STOP\n"
                              "  TIMER 1 = 0\n  FOR i = 1 TO 2\n  END\n.END\n", "t.v2");
  CHECK(p.errors.empty());
  CHECK(statement_as<ast::Binding>(p, 3));
  const auto* stop = statement_as<ast::Instruction>(p, 4);
  REQUIRE(stop);
  CHECK(stop->kw == ast::Kw::stop);
  CHECK(statement_as<ast::TimerStmt>(p, 5));  // still the TIMER statement
  CHECK(statement_as<ast::ForStmt>(p, 6));
  CHECK(errors_of("stop == 1").size() == 1);  // not an assignment: still an error
}
