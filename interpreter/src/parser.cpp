// The VAL II grammar in Spirit X3. The only X3 translation unit of the project (compile time).
// Each rule is preceded by its EBNF line. Keywords are case-insensitive and end at a
// character that cannot continue a name, so `speed.x` is a name, not SPEED.
#include "parser.hpp"

#include "instructions.hpp"
#include "limits.hpp"
#include "module_format.hpp"
#include "vplus_words.hpp"

#include <fmt/format.h>
#include <boost/fusion/include/adapt_struct.hpp>
#include <boost/spirit/home/x3.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <set>
#include <string_view>

BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::VarRef, name, subscript)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::Unary, op, operand)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::Operation, op, operand)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::Expr, first, rest)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::Call, name, args)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::Instruction, kw, args, units, trailing)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::Binding, kw, target, value)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::ForStmt, var, from, to, step)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::IfStmt, cond, goto_label)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::CallStmt, name, args)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::CallsStmt, program, args)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::Format, code, width, decimals)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::TypeStmt, kw, items)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::ProgramHeader, name, params)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::Declaration, kw, names)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::TimerStmt, number, value)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::AccelStmt, profile, values)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::Unsupported, keyword, rest)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::IoStmt, keyword, unit, items)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::ExecuteHead, task, program)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::ExecuteStmt, head, args, rest)
BOOST_FUSION_ADAPT_STRUCT(asimov::interpreter::ast::DataLine, name, indices, values, text)

namespace asimov::interpreter {

std::string normalize_name(const std::string& name) {
  std::string out;
  for (char c : name) {
    if (c == '$' || c == '#') {
      out += c;
      continue;
    }
    if (out.size() - (out.size() && (out[0] == '$' || out[0] == '#')) >= kNameLength) break;
    out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return out;
}

namespace {

namespace x3 = boost::spirit::x3;
using ast::Kw;
using ast::Op;

// Reserved words (the `reserved` rows of instructions.def): they never parse as variable
// names (dialect §1). Instruction keywords are not reserved: they are names wherever no
// instruction can stand (expressions, declarations, `name =` lines).
bool is_reserved(const std::string& word) {
  std::string lower = word;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const Word& w : words())
    if ((w.flags & word_flag::reserved) && w.spelling == lower) return true;
  return false;
}

// An X3 symbol table of the words of instructions.def that `pick` selects.
template <class Pick>
x3::symbols<Kw> keyword_table(Pick pick) {
  x3::symbols<Kw> table;
  for (const Word& w : words())
    if (w.kw != Kw::none && pick(w)) table.add(std::string(w.spelling), w.kw);
  return table;
}

// Reals without "nan"/"inf" spellings, unsigned (the sign is a unary operator).
struct strict_real_policies : x3::ureal_policies<double> {
  template <typename It, typename Attr>
  static bool parse_nan(It&, It const&, Attr&) { return false; }
  template <typename It, typename Attr>
  static bool parse_inf(It&, It const&, Attr&) { return false; }
};
const x3::real_parser<double, strict_real_policies> real_literal;

struct strict_signed_policies : x3::real_policies<double> {
  template <typename It, typename Attr>
  static bool parse_nan(It&, It const&, Attr&) { return false; }
  template <typename It, typename Attr>
  static bool parse_inf(It&, It const&, Attr&) { return false; }
};
const x3::real_parser<double, strict_signed_policies> signed_real;

struct symbol_ops_table : x3::symbols<Op> {
  symbol_ops_table() {
    add("*", Op::mul)("/", Op::div)("+", Op::add)("-", Op::sub)("==", Op::eq)("<>", Op::ne)
       ("<", Op::lt)(">", Op::gt)("<=", Op::le)(">=", Op::ge)("=<", Op::le)("=>", Op::ge)
       (":", Op::compound);
  }
} const symbol_ops;

struct word_ops_table : x3::symbols<Op> {
  word_ops_table() {
    add("mod", Op::mod)("and", Op::and_)("band", Op::band)("or", Op::or_)("xor", Op::xor_)
       ("bor", Op::bor)("bxor", Op::bxor);
  }
} const word_ops;

struct unary_ops_table : x3::symbols<Op> {
  unary_ops_table() { add("-", Op::neg)("+", Op::plus); }
} const unary_sign;

// Instruction keywords parsed by the generic `instruction` rule, and the words around them.
const x3::symbols<Kw> instruction_words = keyword_table([](const Word& w) { return w.instruction; });
const x3::symbols<Kw> trailing_words = keyword_table([](const Word& w) { return (w.flags & word_flag::trailing) != 0; });
const x3::symbols<Kw> unit_words = keyword_table([](const Word& w) { return (w.flags & word_flag::unit) != 0; });
const x3::symbols<Kw> declaration_words = keyword_table([](const Word& w) { return (w.flags & word_flag::declaration) != 0; });
const x3::symbols<Kw> binding_words = keyword_table([](const Word& w) { return (w.flags & word_flag::binding) != 0; });

struct type_word_table : x3::symbols<x3::unused_type> {
  type_word_table() { add("real")("double")("loc"); }
} const type_words;

// Dialect §7, §13: the V+ instructions asimov does not simulate (vplus_words.cpp) load, and stop
// the program (or warn) when they run.
struct unsupported_table : x3::symbols<x3::unused_type> {
  unsupported_table() {
    for (const VplusWord& w : vplus_words())
      if (w.kind == WordKind::instruction) {
        std::string lower(w.name);
        for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        add(lower);
      }
  }
} const unsupported_words;

// Dialect §7a, §7b: the I/O instructions (disk files simulated; network and serial stop) and
// the task instructions ABORT, KILL, CYCLE.END, RELEASE, which share their form.
struct io_table : x3::symbols<x3::unused_type> {
  io_table() {
    for (const char* w : {"attach", "detach", "fopen", "fopenr", "fopenw", "fopena", "fopend", "fclose", "fempty",
                          "fdelete", "fcmnd", "read", "write", "abort", "kill", "cycle.end", "release"})
      add(w);
  }
} const io_words;

// Function words that need no parentheses.
struct bare_function_table : x3::symbols<std::string> {
  bare_function_table() {
    for (const char* w : {"here", "dest", "#pdest", "pi", "true", "false", "null", "random", "tool", "base"})
      add(w, std::string(w));
  }
} const bare_function_words;

const auto name_char = x3::alnum | x3::char_("._");

auto kw(const char* word) { return x3::lexeme[x3::no_case[x3::lit(word)] >> !name_char]; }
template <typename P>
auto word_of(const P& table) { return x3::lexeme[x3::no_case[table] >> !name_char]; }

const auto check_not_reserved = [](auto& ctx) { x3::_pass(ctx) = !is_reserved(x3::_attr(ctx)); };
const auto check_label = [](auto& ctx) { x3::_pass(ctx) = x3::_attr(ctx) <= kMaxLabel; };
const auto check_finite = [](auto& ctx) { x3::_pass(ctx) = std::isfinite(x3::_attr(ctx)); };

x3::rule<class word_class, std::string> const word = "name";
x3::rule<class identifier_class, std::string, true> const identifier = "name";
x3::rule<class number_class, double, true> const number = "number";
x3::rule<class string_class, std::string> const string_literal = "string";
x3::rule<class expression_class, ast::Expr> const expression = "expression";
x3::rule<class operand_class, ast::Operand> const operand = "operand";
x3::rule<class unary_class, ast::Unary> const unary = "operand";
x3::rule<class primary_class, ast::Operand> const primary = "operand";
x3::rule<class call_class, ast::Call> const call = "function";
x3::rule<class function_name_class, std::string> const function_name = "function";
x3::rule<class variable_class, ast::VarRef> const variable = "variable";
x3::rule<class var_name_class, std::string> const var_name = "variable";
x3::rule<class subscript_class, std::vector<ast::Expr>, true> const subscript = "subscript";
x3::rule<class binary_op_class, Op> const binary_op = "operator";
x3::rule<class args_class, std::vector<boost::optional<ast::Expr>>> const arguments = "arguments";
x3::rule<class label_class, unsigned, true> const label = "label";
x3::rule<class instruction_class, ast::Instruction> const instruction = "instruction";
x3::rule<class binding_class, ast::Binding> const binding = "assignment";
x3::rule<class assignment_class, ast::Binding> const assignment = "assignment";
x3::rule<class for_class, ast::ForStmt> const for_stmt = "FOR";
x3::rule<class if_class, ast::IfStmt> const if_stmt = "IF";
x3::rule<class call_stmt_class, ast::CallStmt> const call_stmt = "CALL";
x3::rule<class calls_stmt_class, ast::CallsStmt> const calls_stmt = "CALLS";
x3::rule<class calls_target_class, ast::Operand> const calls_target = "string";
x3::rule<class format_class, ast::Format> const format = "format";
x3::rule<class type_item_class, ast::TypeItem> const type_item = "TYPE item";
x3::rule<class type_class, ast::TypeStmt> const type_stmt = "TYPE";
x3::rule<class encode_class, ast::TypeStmt> const encode = "$ENCODE";
x3::rule<class param_class, std::string> const param = "parameter";
x3::rule<class header_class, ast::ProgramHeader> const program_header = ".PROGRAM";
x3::rule<class statement_class, ast::Statement> const statement = "statement";
x3::rule<class data_line_class, ast::DataLine, true> const data_line = "data line";
x3::rule<class optional_expression_class, ast::Expr> const optional_expression = "expression";
x3::rule<class declaration_class, ast::Declaration> const declaration = "declaration";
x3::rule<class timer_class, ast::TimerStmt> const timer_stmt = "TIMER";
x3::rule<class accel_class, ast::AccelStmt> const accel_stmt = "ACCEL";
x3::rule<class unsupported_class, ast::Unsupported> const unsupported = "statement";
x3::rule<class io_class, ast::IoStmt> const io_stmt = "statement";
x3::rule<class unit_class, std::vector<ast::Expr>> const unit_args = "arguments";
x3::rule<class execute_class, ast::ExecuteStmt> const execute_stmt = "EXECUTE";
x3::rule<class execute_head_class, ast::ExecuteHead> const execute_head = "program";
x3::rule<class to_class> const to_keyword = "TO";

// name = letter { letter | digit | "." | "_" }
const auto word_def = x3::lexeme[x3::alpha >> *name_char];
// identifier = name - keyword
const auto identifier_def = word[check_not_reserved];
// label = integer 0..65535
const auto label_def = x3::lexeme[x3::uint_ >> !name_char][check_label];
// number = real | "^D" real | "^B" binary | "^H" hex | "^" octal | "'" char   (^D: ignored)
const auto number_def = real_literal[check_finite]
    | x3::lexeme[x3::lit('^') >> x3::no_case['d'] >> real_literal[check_finite]]
    | x3::lexeme[x3::lit('^') >> x3::no_case['b'] >> x3::bin]
    | x3::lexeme[x3::lit('^') >> x3::no_case['h'] >> x3::hex]
    | x3::lexeme[x3::lit('^') >> x3::oct]
    | x3::lexeme[x3::lit('\'') >> x3::char_("\x20-\x7e")];
// string = '"' { character - '"' } '"'
const auto string_literal_def = x3::lexeme['"' > *(x3::char_("\x20-\x7e") - '"') > '"'];
// expression = operand { binary_op operand }      (precedence: checker, dialect §3)
const auto expression_def = operand >> *(binary_op > operand);
// binary_op = "*" | "/" | "+" | "-" | ":" | relational | MOD | AND | BAND | OR | XOR | BOR | BXOR
// (a ":" ending the line closes a CASE's VALUE list and is no operator)
const auto binary_op_def = (symbol_ops - (x3::lit(':') >> x3::eoi)) | word_of(word_ops);
// operand = ( "-" | "+" | NOT ) operand | primary
const auto operand_def = unary | primary;
const auto unary_def = (unary_sign | (kw("not") >> x3::attr(Op::not_))) > operand;
// primary = number | string | encode | function | variable | "(" expression ")"
const auto primary_def = number | string_literal | encode | call | variable
    | ('(' > expression > ')');
// encode = "$ENCODE" "(" type_item { "," type_item } ")"
const auto encode_def = (x3::attr(Kw::type) >> x3::lexeme[x3::no_case["$encode"] >> !name_char] >> '(')
    > (type_item % ',') > ')';
// function = [ "#" | "$" ] name "(" arguments ")" | HERE | DEST | #PDEST | PI | TRUE | FALSE | NULL | ...
const auto function_name_def = x3::raw[x3::lexeme[-x3::char_("#$") >> word]];
const auto call_def = ((function_name >> '(') > arguments > ')')
    | (word_of(bare_function_words) >> x3::attr(std::vector<boost::optional<ast::Expr>>()));
// arguments = [ expression ] { "," [ expression ] }
//   (SHIFT(t BY dx, dy, dz): BY separates like a comma)
const auto arguments_def = -expression % (x3::lit(',') | kw("by"));
// variable = [ "$" | "#" ] identifier [ "[" [ expression { "," expression } ] "]" ]
const auto var_name_def = x3::raw[x3::lexeme[(x3::char_("$#") >> word) | identifier]];
const auto variable_def = var_name >> -subscript;
// subscript = "[" [ expression { "," expression } ] "]"   (a[] is kept as one Nil expression)
const auto mark_whole_array = [](auto& ctx) { x3::_val(ctx).resize(1); };
const auto subscript_def = '[' > ((&x3::lit(']'))[mark_whole_array] | (expression % ',')) > ']';

// instruction = KEYWORD [ optional_expression { "," optional_expression } ] [ MMPS | IPS ]
//               [ ALWAYS | MONITOR | DO | THEN | OF ] [ ":" ]
const auto instruction_def = word_of(instruction_words) >> -(optional_expression % ',')
    >> -word_of(unit_words) >> -word_of(trailing_words) >> x3::omit[-x3::lit(':')];
// optional_expression = [ expression ]    (omitted: a Nil operand)
const auto optional_expression_def = expression | x3::attr(ast::Expr());
// binding = ( SET | DECOMPOSE | PARAMETER ) variable "=" expression | assignment
// assignment = variable "=" expression
const auto assignment_def = (x3::attr(Kw::assign) >> variable >> '=') > expression;
const auto binding_def = (word_of(binding_words) > variable > '=' > expression) | assignment;
// A line `name [subscript] =` (not `==`) is an assignment even when the name is an instruction
// keyword: `stop = STATE(4) BAND 4` (V+).
const auto assignment_ahead = &(variable >> '=' >> !x3::lit('='));
// for = FOR variable "=" expression TO expression [ STEP expression ]
const auto to_keyword_def = kw("to");
const auto for_stmt_def = kw("for") > variable > '=' > expression > to_keyword > expression
    > -(kw("step") > expression);
// if = IF expression ( GOTO label | [ THEN ] )
const auto if_stmt_def = kw("if") > expression > -(kw("goto") > label) > -kw("then");
// call = CALL name [ "(" arguments ")" ]
const auto call_stmt_def = kw("call") > word > -('(' > arguments > ')');
// calls = CALLS ( string | variable ) [ "(" arguments ")" ]    (not followed by "=")
const auto calls_target_def = string_literal | variable;
const auto calls_stmt_def = (kw("calls") >> !x3::lit('=')) > calls_target > -('(' > arguments > ')');
// format = "/D" | "/S" | "/N" | "/F" w "." d | "/I" w | "/X" [n] | "/C" [n]   (/N: no wait, no effect)
const auto format_def = x3::lexeme['/' >> (
    (x3::no_case[x3::char_("dsn")] >> x3::attr(0u) >> x3::attr(0u))
    | (x3::no_case[x3::char_('f')] >> x3::uint_ >> '.' >> x3::uint_)
    | (x3::no_case[x3::char_('i')] >> x3::uint_ >> x3::attr(0u))
    | (x3::no_case[x3::char_("xc")] >> (x3::uint_ | x3::attr(1u)) >> x3::attr(0u)))];
// type_item = format | expression
const auto type_item_def = format | expression;
// type = TYPE [ type_item { "," type_item } ]
const auto type_stmt_def = x3::attr(Kw::type) >> kw("type") >> -(type_item % ',');
// param = [ "$" | "#" ] name [ "[" "]" ]
const auto param_def = x3::raw[x3::lexeme[-x3::char_("$#") >> word >> -(x3::lit('[') >> ']')]];
// program_header = ".PROGRAM" name [ "(" [ param { "," param } ] ")" ]
const auto program_header_def = kw(".program") > word > -('(' > -(param % ',') > ')');
// declaration = ( AUTO | LOCAL | GLOBAL ) [ REAL | DOUBLE | LOC ] variable { "," variable }
const auto declaration_def = word_of(declaration_words) >> x3::omit[-word_of(type_words)]
    > (variable % ',');
// timer = TIMER expression "=" expression
const auto timer_stmt_def = kw("timer") > expression > '=' > expression;
// accel = ACCEL [ "(" expression ")" ] optional_expression { "," optional_expression }
//   (not followed by "=": `accel = 1` is an assignment)
const auto accel_stmt_def = kw("accel") >> !x3::lit('=')
    >> (('(' > expression > ')') | x3::attr(ast::Expr())) >> (optional_expression % ',');
// unsupported = V+_KEYWORD { any }     (not followed by "=": `read = 1` is an assignment)
const auto unsupported_def = x3::raw[word_of(unsupported_words)] >> !x3::lit('=')
    >> x3::raw[x3::lexeme[*x3::char_]];
// io = IO_KEYWORD [ "(" optional_expression { "," optional_expression } ")" ] [ type_item { "," type_item } ]
const auto unit_args_def = '(' > (optional_expression % ',') > ')';
const auto io_stmt_def = x3::raw[word_of(io_words)] >> !x3::lit('=') >> -unit_args >> -(type_item % ',');
// execute = EXECUTE [ "/C" ] ( expression name | name ) [ "(" arguments ")" ] { "," optional_expression }
//   (`EXECUTE 1 ros.srv.fdb()`; without a number: task 0. An expression is tried first: `prog()`
//   alone then parses as the program, since no name follows it.)
const auto execute_head_def = (expression >> word) | (x3::attr(ast::Expr()) >> word);
const auto execute_stmt_def = kw("execute") >> x3::omit[-x3::lexeme[x3::no_case[x3::lit("/c")] >> !name_char]]
    >> execute_head >> -('(' > arguments > ')') >> *(',' >> optional_expression);
// statement = assignment (when the line reads `name [subscript] =`) | program_header
//           | declaration | type | for | if | call | calls | timer | accel | io | execute | instruction | unsupported
//           | binding
const auto statement_def = (assignment_ahead >> assignment) | program_header | declaration | type_stmt
    | for_stmt | if_stmt | call_stmt | calls_stmt | timer_stmt | accel_stmt | io_stmt | execute_stmt | instruction
    | unsupported | binding;

// data_line = [ "$" | "#" ] name [ "[" int { "," int } "]" ] { [ "," ] number } [ string ]
const auto data_line_def = x3::raw[x3::lexeme[-x3::char_("$#") >> word]]
    >> -('[' > (x3::int_ % ',') > ']')
    >> *(x3::omit[-x3::lit(',')] >> signed_real[check_finite])
    >> -string_literal;

BOOST_SPIRIT_DEFINE(data_line, word, identifier, label, number, string_literal, expression, binary_op,
                    operand, unary, primary, call, function_name, arguments, var_name, variable, subscript, instruction,
                    binding, assignment, for_stmt, if_stmt, call_stmt, format, type_item, type_stmt, param,
                    program_header, statement, to_keyword, declaration, optional_expression, timer_stmt, accel_stmt,
                    unsupported, encode, io_stmt, unit_args, execute_stmt, execute_head, calls_stmt, calls_target)

// skipper = blank | ";" { any }
const auto skipper = x3::blank | (';' >> *x3::char_);

// Turns X3's description of what was expected into the detail of dialect §10.
std::string expected_text(const std::string& which) {
  std::string w = which;
  if (w.size() >= 2 && w.front() == '\'' && w.back() == '\'') w = w.substr(1, w.size() - 2);
  if (w == "\"") return "expected closing \"";
  if (w.size() == 1) return "expected \"" + w + "\"";
  if (w.find("boost") != std::string::npos) return "unexpected text";
  return "expected " + w;
}

// A "#" where the parse stopped is most often a comment written in another language's way.
std::string with_hint(std::string::const_iterator where, std::string::const_iterator last, std::string detail) {
  if (where != last && *where == '#') detail += "; comments start with \";\" in V+";
  return detail;
}

// What a control character is, for the message (a form feed, Ctrl-Z ...).
std::string control_name(unsigned char c) {
  char code[8];
  std::snprintf(code, sizeof code, "0x%02X", c);
  const char* name = c == 0 ? "NUL" : c == 7 ? "bell" : c == 8 ? "backspace" : c == 0x0B ? "vertical tab"
                     : c == 0x0C ? "form feed" : c == 0x1B ? "escape" : c == 0x7F ? "delete" : nullptr;
  const std::string what = name ? name : std::string("Ctrl-") + static_cast<char>('@' + c);
  return "control character " + std::string(code) + " (" + what + ")";
}

// A reserved word followed by "=" (not "=="): `pi = 3`.
bool keyword_assignment(const std::string& text, std::size_t at, std::string& word) {
  std::size_t end = at;
  while (end < text.size() && (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '.' || text[end] == '_'))
    ++end;
  std::size_t eq = end;
  while (eq < text.size() && (text[eq] == ' ' || text[eq] == '\t')) ++eq;
  word = text.substr(at, end - at);
  return end > at && eq < text.size() && text[eq] == '=' && (eq + 1 == text.size() || text[eq + 1] != '=')
      && is_reserved(word);
}

// Lines end at LF, CR LF, CR CR LF (a CR LF file converted once more on the way) or a lone CR
// (dialect §1); a last line without newline is a line.
std::vector<std::string> split_lines(const std::string& source) {
  std::vector<std::string> lines;
  std::size_t start = 0, i = 0;
  const std::size_t n = source.size();
  while (i < n) {
    const char c = source[i];
    if (c != '\n' && c != '\r') {
      ++i;
      continue;
    }
    lines.push_back(source.substr(start, i - start));
    if (c == '\r' && i + 1 < n && source[i + 1] == '\n') i += 2;
    else if (c == '\r' && i + 2 < n && source[i + 1] == '\r' && source[i + 2] == '\n') i += 3;
    else ++i;
    start = i;
  }
  if (start < n) lines.push_back(source.substr(start));
  return lines;
}

// A numeric literal at `where` that does not fit a double gets its own detail.
std::string refine(std::string::const_iterator where, std::string::const_iterator last, std::string detail) {
  if (where == last || !(std::isdigit(static_cast<unsigned char>(*where)) || *where == '.')) return detail;
  const std::string rest(where, last);
  const double v = std::strtod(rest.c_str(), nullptr);
  return std::isfinite(v) ? detail : "number out of range";
}

// Where a line passes the expression limits of limits.hpp, and which; nullopt when it does not.
// Counted on the text before X3 sees it (the parser itself recurses per level): brackets
// outside strings and comments, operators (symbols and MOD AND BAND OR XOR BOR BXOR NOT), and
// runs of operators in a row (unary signs nest: - - - x). Over-counting is harmless here.
struct TooComplex {
  std::size_t offset;
  std::string detail;
};
// `file_ops`: the operators of the file's lines before this one; this line's are added.
std::optional<TooComplex> too_complex(const std::string& text, std::int64_t& file_ops, std::int64_t max_file_ops) {
  static const std::set<std::string> words = {"mod", "and", "band", "or", "xor", "bor", "bxor", "not"};
  int depth = 0, ops = 0, run = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == ';') break;
    if (c == ' ' || c == '\t') continue;
    if (c == '"') {
      const auto close = text.find('"', i + 1);
      if (close == std::string::npos) break;
      i = close;
      run = 0;
      continue;
    }
    bool op = false;
    if (c == '(' || c == '[') {
      ++depth;
      run = 0;
    } else if (c == ')' || c == ']') {
      if (depth > 0) --depth;
      run = 0;
    } else if (std::strchr("+-*/<>=:", c)) {
      op = true;
      if (std::strchr("<>=", c) && i + 1 < text.size() && std::strchr("<>=", text[i + 1])) ++i;  // ==, <>, <=, ...
    } else if (std::isalpha(static_cast<unsigned char>(c))) {
      std::size_t end = i;
      std::string w;
      while (end < text.size() && (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '.' || text[end] == '_'))
        w += static_cast<char>(std::tolower(static_cast<unsigned char>(text[end++])));
      op = words.count(w) > 0;
      if (!op) run = 0;
      i = end - 1;
    } else {
      run = 0;
    }
    if (op) ++ops, ++run, ++file_ops;
    if (depth + run > kMaxExpressionNesting)
      return TooComplex{i, fmt::format("more than {} parentheses, brackets, calls and signs inside one another", kMaxExpressionNesting)};
    if (ops > kMaxExpressionOperators)
      return TooComplex{i, fmt::format("more than {} operators in one statement", kMaxExpressionOperators)};
    if (file_ops > max_file_ops) return TooComplex{i, fmt::format("more than {} operators in one file", max_file_ops)};
  }
  return std::nullopt;
}

}  // namespace

ParsedSource parse_source(const std::string& source, const std::string& file, std::int64_t max_file_operators) {
  ParsedSource out;
  out.file = file;
  out.text = split_lines(module_text(source));  // the stored module format: dialect §1
  out.lines.resize(out.text.size());

  bool in_data = false;  // inside .LOCATIONS / .REALS / .STRINGS
  std::int64_t file_ops = 0;  // operators so far (kMaxFileOperators)
  for (std::size_t i = 0; i < out.text.size(); ++i) {
    const std::string& text = out.text[i];
    auto first = text.begin();
    const auto last = text.end();
    ast::Line& line = out.lines[i];
    auto fail = [&](std::string::const_iterator where, std::string detail) {
      Diagnostic d;
      d.message = "*Syntax error*";
      d.detail = std::move(detail);
      d.file = file;
      d.line = static_cast<int>(i) + 1;
      d.column = static_cast<int>(where - text.begin()) + 1;
      d.source_line = text;
      out.errors.push_back(std::move(d));
      line = ast::Line{};
    };
    // Bytes outside ASCII and control characters (but TAB) are allowed only in comments
    // (dialect §1).
    bool in_string = false;
    auto bad = text.end();
    for (auto it = text.begin(); it != text.end(); ++it) {
      if (*it == '"') in_string = !in_string;
      if (*it == ';' && !in_string) break;
      const auto c = static_cast<unsigned char>(*it);
      if (c > 126 || (c < 32 && c != '\t')) {
        bad = it;
        break;
      }
    }
    if (bad != text.end()) {
      const auto c = static_cast<unsigned char>(*bad);
      fail(bad, c > 127 ? "character outside ASCII" : control_name(c));
      continue;
    }
    if (!in_data) {
      if (const auto deep = too_complex(text, file_ops, max_file_operators)) {
        fail(text.begin() + static_cast<std::ptrdiff_t>(deep->offset), deep->detail);
        out.errors.back().message = "*Expression too complex*";
        if (file_ops > max_file_operators) {  // the rest of the file is not read: one message
          out.truncated = true;
          break;
        }
        continue;
      }
    }
    try {
      unsigned number = 0;
      if (x3::phrase_parse(first, last, label, skipper, number)) line.label = number;
      x3::phrase_parse(first, last, x3::eps, skipper);
      line.column = static_cast<int>(first - text.begin()) + 1;
      ast::Statement stmt;
      ast::DataLine data;
      auto before = first;
      if (first == last) {
      } else if (in_data && !x3::phrase_parse(first, last, kw(".end"), skipper)) {
        if (x3::phrase_parse(first, last, data_line, skipper, data)) line.data = std::move(data);
        else first = before;
      } else if (x3::phrase_parse(first = before, last, statement, skipper, stmt)) {
        const auto* in = boost::get<ast::Instruction>(&stmt);
        if (in && (in->kw == Kw::dot_locations || in->kw == Kw::dot_reals || in->kw == Kw::dot_strings))
          in_data = true;
        if (in && in->kw == Kw::dot_end) in_data = false;
        line.statement = std::move(stmt);
      } else {
        first = before;
      }
      x3::phrase_parse(first, last, x3::eps, skipper);
      if (first != last) {
        std::string detail = line.statement ? "unexpected text" : "expected a statement";
        // A number where the statement starts that did not parse as a label: too large.
        if (!line.statement && !line.label && std::isdigit(static_cast<unsigned char>(*first))) {
          auto digits_end = first;
          while (digits_end != last && std::isdigit(static_cast<unsigned char>(*digits_end))) ++digits_end;
          if (digits_end - first > 5 || std::stoul(std::string(first, digits_end)) > kMaxLabel)
            detail = fmt::format("label {} is above {}", std::string(first, digits_end), kMaxLabel);
        }
        const auto* keyword = line.statement ? boost::get<ast::Instruction>(&*line.statement) : nullptr;
        if (*first == '=' && keyword && keyword->args.size() <= 1)
          detail = "\"" + text.substr(static_cast<std::size_t>(line.column - 1),
                                      text.find_first_of(" \t=", static_cast<std::size_t>(line.column - 1)) -
                                          static_cast<std::size_t>(line.column - 1)) +
                   "\" is a keyword, not a variable";
        else if (*first == '=')
          detail = "\"=\" is not an operator; use \"==\" to compare";
        std::string word;
        if (!line.statement && keyword_assignment(text, static_cast<std::size_t>(first - text.begin()), word))
          detail = "\"" + word + "\" is a keyword, not a variable";
        fail(first, refine(first, last, with_hint(first, last, detail)));
      }
    } catch (const x3::expectation_failure<std::string::const_iterator>& e) {
      auto where = e.where();
      while (where != last && (*where == ' ' || *where == '\t')) ++where;
      std::string detail = expected_text(e.which());
      if (where != last && *where == '=' && detail != "expected \"=\"")
        detail = "\"=\" is not an operator; use \"==\" to compare";
      fail(where, refine(where, last, with_hint(where, last, detail)));
    }
  }
  return out;
}

}  // namespace asimov::interpreter
