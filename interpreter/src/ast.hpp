// The syntax tree the parser builds, one Line per source line. It mirrors the text: names are
// raw strings, binary operators are a flat list (the checker applies the precedence table of
// dialect §3), and no name is resolved yet. Only parser.cpp adapts these structs for X3.
#pragma once
#include <boost/optional.hpp>
#include <boost/spirit/home/x3/support/ast/variant.hpp>
#include <string>
#include <vector>

namespace asimov::interpreter::ast {

namespace x3 = boost::spirit::x3;

// Operators, shared by the parser (symbols) and the checker (precedence, code).
// ORDER: kPrecedence in checker.cpp, kText in operators.cpp (both static_assert'ed).
enum class Op : int {
  neg, plus, not_,                        // unary
  mul, div, mod,                          // level 3
  add, sub,                               // level 4
  eq, ne, lt, gt, le, ge,                 // level 5
  and_, band,                             // level 6
  or_, xor_, bor, bxor,                   // level 7
  compound,                               // ':' (location compound)
  count
};

struct Nil {};
struct Expr;
struct Call;
struct Unary;
struct TypeStmt;  // also the items of $ENCODE(...)

// A variable reference: `x`, `$s`, `#p`, `a[i,j]`, or a whole array `a[]` (empty subscript).
struct VarRef {
  std::string name;                                   // with its '$' or '#' prefix
  std::vector<Expr> subscript;                        // empty: scalar; one Nil: a[]
};

struct Operand : x3::variant<Nil, double, std::string, VarRef, x3::forward_ast<Call>,
                             x3::forward_ast<Unary>, x3::forward_ast<Expr>,
                             x3::forward_ast<TypeStmt>> {
  using base_type::base_type;
  using base_type::operator=;
};

struct Unary {
  Op op = Op::neg;
  Operand operand;
};

struct Operation {
  Op op = Op::add;
  Operand operand;
};

// operand { binary_op operand }; a parenthesized group is an Operand holding an Expr.
struct Expr {
  Operand first;
  std::vector<Operation> rest;
};

// `name(args)` (args may be omitted: `TRANS(,,300)`), or a bare function word (`HERE`, `PI`).
// `a[]`: the whole array (a CALL argument).
inline bool is_whole_array(const VarRef& v) {
  return v.subscript.size() == 1 && v.subscript[0].rest.empty()
      && boost::get<Nil>(&v.subscript[0].first) != nullptr;
}

// An omitted argument (`DRAW , , 50`).
inline bool is_omitted(const Expr& e) { return e.rest.empty() && boost::get<Nil>(&e.first) != nullptr; }

struct Call {
  std::string name;                                   // with '#' or '$' prefix if written
  std::vector<boost::optional<Expr>> args;
};

// Keywords: those that start an instruction and the trailing, unit, declaration and binding
// words, all rows of instructions.def (the parser spells them from there). `assign` is the
// binding without a keyword (`x = 1`).
enum class Kw : int {
  none, assign,
#define ASIMOV_MOTION(kw, ...) kw,
#define ASIMOV_SIMPLE(kw, ...) kw,
#define ASIMOV_STATEMENT(kw, ...) kw,
#define ASIMOV_WORD(kw, ...) kw,
#include "instructions.def"
  count
};

// KEYWORD [ [expression] { "," [expression] } ] [ MMPS | IPS ] [ trailing_word ] [ ":" ]
struct Instruction {
  Kw kw = Kw::none;
  std::vector<Expr> args;                             // an omitted one holds a Nil operand
  Kw units = Kw::none;                                // SPEED ... MMPS / IPS (dialect §7)
  Kw trailing = Kw::none;                             // ALWAYS, MONITOR, DO, THEN, OF
};

// (SET | DECOMPOSE | PARAMETER | <assign>) variable "=" expression
struct Binding {
  Kw kw = Kw::assign;
  VarRef target;
  Expr value;
};

// FOR variable "=" expression TO expression [ STEP expression ]
struct ForStmt {
  VarRef var;
  Expr from;
  Expr to;
  boost::optional<Expr> step;
};

// IF expression ( GOTO label | [THEN] )
struct IfStmt {
  Expr cond;
  boost::optional<unsigned> goto_label;
};

// CALL name [ "(" [ [expression] { "," [expression] } ] ")" ]
struct CallStmt {
  std::string name;
  std::vector<boost::optional<Expr>> args;
};

// CALLS string [ "(" arguments ")" ]: calls the program the string names (V+).
struct CallsStmt {
  Operand program;                                    // a string variable or literal
  std::vector<boost::optional<Expr>> args;
};

// A TYPE format specifier: /D /Fw.d /Iw /Xn /Cn /S.
struct Format {
  char code = 'D';
  unsigned width = 0;
  unsigned decimals = 0;
};

struct TypeItem : x3::variant<Format, Expr> {
  using base_type::base_type;
  using base_type::operator=;
};

// TYPE [ type_item { "," type_item } ]   (kw = Kw::type; also $ENCODE's arguments)
struct TypeStmt {
  Kw kw = Kw::type;
  std::vector<TypeItem> items;
};

// ( AUTO | LOCAL | GLOBAL ) [ REAL | DOUBLE | LOC ] variable { "," variable }
struct Declaration {
  Kw kw = Kw::auto_;
  std::vector<VarRef> names;                          // array sizes are ignored
};

// A V+ construct that loads but is not simulated (dialect §7): KEYWORD { any }
struct Unsupported {
  std::string keyword;
  std::string rest;                                   // the rest of the line, as written
};

// ACCEL [ "(" profile ")" ] [ acceleration ] [ "," [ deceleration ] ]
struct AccelStmt {
  Expr profile;              // a Nil operand when omitted
  std::vector<Expr> values;  // acceleration, deceleration (an omitted one holds a Nil operand)
};

// V+ I/O (dialect §7a): KEYWORD [ "(" [expression] { "," [expression] } ")" ] [ items ]
// ATTACH (lun, 4) "DISK", FOPENR (lun) "f.txt", READ (lun) $s, x, WRITE (lun) $s, /S, FCLOSE (lun)
struct IoStmt {
  std::string keyword;                                // as written
  std::vector<Expr> unit;                             // lun, mode ... (an omitted one: Nil)
  std::vector<TypeItem> items;                        // device or path, READ's variables, WRITE's items
};

// EXECUTE [ /C ] [ task ] program [ "(" arguments ")" ] { "," [ expression ] }   (dialect §7b)
struct ExecuteHead {
  Expr task;                                          // Nil: task 0
  std::string program;
};
struct ExecuteStmt {
  ExecuteHead head;
  std::vector<boost::optional<Expr>> args;
  std::vector<Expr> rest;                             // cycles, step, priority (ignored)
};

// TIMER expression "=" expression
struct TimerStmt {
  Expr number;
  Expr value;
};

// .PROGRAM name [ "(" [ param { "," param } ] ")" ]
struct ProgramHeader {
  std::string name;
  std::vector<std::string> params;                    // with prefix; "a[]" for an array
};

struct Statement : x3::variant<Instruction, Binding, ForStmt, IfStmt, CallStmt, TypeStmt,
                               ProgramHeader, Declaration, TimerStmt, AccelStmt, Unsupported, IoStmt,
                               ExecuteStmt, CallsStmt> {
  using base_type::base_type;
  using base_type::operator=;
};

// A line of a .LOCATIONS, .REALS or .STRINGS section (dialect §8).
// data_line = variable_name [ "[" int { "," int } "]" ] { [","] signed_number } [ string ]
struct DataLine {
  std::string name;                                   // with '$' or '#' prefix
  std::vector<int> indices;
  std::vector<double> values;
  boost::optional<std::string> text;
};

// [ label ] [ statement ]   (comments and blanks are skipped), or a data line
struct Line {
  boost::optional<unsigned> label;
  boost::optional<Statement> statement;
  boost::optional<DataLine> data;                     // inside a data section
  int column = 1;                                     // 1-based column of the statement
};

}  // namespace asimov::interpreter::ast
