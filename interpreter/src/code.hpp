// Stage 2 output: programs compiled by the checker into flat instruction lists with names
// resolved to slots (globals, parameters, programs) and jumps resolved to instruction indices.
#pragma once
#include "ast.hpp"
#include "instructions.hpp"
#include "functions.hpp"
#include "asimov/interpreter/interpreter.hpp"
#include "realcode.hpp"
#include <memory>
#include <string>
#include <vector>

namespace asimov::interpreter {

enum class Scope : unsigned char { global, param };

struct Ref {
  Scope scope = Scope::global;
  int slot = -1;                // index into the globals or the frame's slots (params, AUTO)
};

enum class NodeKind : unsigned char { number, string, variable, unary, chain, function, encode, absent };

// An expression tree node. Variables carry their resolved slot; `kids` are operands,
// subscripts (variables) or arguments (functions).
// A chain is a left-associative run of binary operators of one precedence level, n-ary:
// kids[0] ops[0] kids[1] ops[1] kids[2] ... means ((kids[0] ops[0] kids[1]) ops[1] kids[2]) ...
// and is walked by a loop everywhere, so the tree is as deep as the nesting of the text (at
// most levels x kMaxExpressionNesting), not as its operators are many (issue 17).
struct Node {
  NodeKind kind = NodeKind::absent;
  ast::Op op = ast::Op::add;    // unary
  Func func = Func::pi;         // function
  double number = 0;            // number literal
  std::string text;             // string literal, or the variable's name for messages
  Ref ref;                      // variable
  bool subscripted = false;     // variable written with [...]
  bool plain = false;           // only numbers, variables, unary and arithmetic / relational /
                                // logical operators below: the evaluator's real fast path
  std::vector<Node> kids;
  std::vector<ast::Op> ops;     // chain: kids.size() - 1 operators
  std::vector<ast::Format> formats;  // $ENCODE: one per item; code 0 = the next of `kids`
  std::shared_ptr<const RealCode> fast;  // top-level plain real trees: the compiled form
};

// Opcodes: the motions and the other codes of instructions.def.
enum class Code : unsigned char {
#define ASIMOV_MOTION(kw, ...) kw,
#define ASIMOV_CODE(code) code,
#include "instructions.def"
};

// The motion instructions' path (instructions.def): a straight line of the tool or a joint move.
bool straight_path(Code code);

// The I/O instructions of dialect §7a and the task instructions of §7b (Instr::io).
enum class IoOp : unsigned char {
  attach, detach, fopenr, fopenw, fopena, fopend, fclose, fempty, fdelete, read, write,
  abort, kill, cycle_end, release
};

// SPEED and DURATION: for the next motion only, ALWAYS, or (SPEED) the monitor speed.
enum class SpeedScope : unsigned char { next, always, monitor };

// One instruction. Each field means one thing; the codes that use it are named.
struct Instr {
  Code code = Code::jump;
  int line = 0;                    // file line
  bool real_target = false;        // assign: the target holds reals (no '$' or '#')
  const RNode* fast0 = nullptr;    // args[0].fast's root (owned by it), for the dispatch loop
  Node target;                     // assign/set/here/decompose/for/prompt: the variable written;
                                   //   calls: the name expression; unsupported, execute: the
                                   //   text for messages (target.text)
  std::vector<Node> args;          // operands in source order (FOR: from, to, step)
  std::vector<ast::Format> formats;  // TYPE, WRITE: one per item; code 0 = the next of `args`
  int jump = -1;                   // jumps, FOR exit / FOR body start, CASE's next test
  int temp = -1;                   // FOR: two frame temporaries (limit, step); CASE: one
  int items = -1;                  // io: args[0, items) are the unit arguments, then the items
  int program = -1;                // CALL, EXECUTE, REACT, REACTE: program slot
  std::vector<bool> by_ref;        // CALL: argument i passed by reference
  SpeedScope scope = SpeedScope::next;  // SPEED, DURATION
  bool warn_only = false;          // unsupported: a warning (robot ATTACH () ...), not an error
  ast::Kw word = ast::Kw::none;    // the keyword of the simple forms (configure: RIGHTY ...;
                                   //   hand: OPEN ...; REACT or REACTI)
  IoOp io = IoOp::read;            // io, task and robot instructions: which
};

// Instructions that compile to one Instr holding their arguments (the ASIMOV_MOTION and
// ASIMOV_SIMPLE rows of instructions.def): the keyword, its code and how many arguments it
// takes (max -1: any number).
struct SimpleForm {
  ast::Kw kw;
  Code code;
  int min_args, max_args;
  const char* name;                // for "NAME expects ..." messages
};
const SimpleForm* simple_form(ast::Kw kw);

// What an expression yields when the syntax shows it (dialect §3: a visible mix of
// strings and numbers is a load-time error).
enum class StaticKind { unknown, real, string };
StaticKind static_kind(const Node& n);
// The kind of `a op b` from the kinds of a and b (what static_kind says of one step of a chain,
// without walking its prefix again: a chain of n additions is checked in O(n)).
StaticKind binary_kind(ast::Op op, StaticKind a, StaticKind b);
// Sets Node::plain over the tree (bottom-up; recursion as deep as the tree, not as a chain is long).
void mark_plain(Node& n);

struct Param {
  std::string name;                // normalized, with prefix
  bool array = false;              // written a[]
};

struct Program {
  std::string name;                // normalized
  std::string file;
  int line = 0;                    // line of .PROGRAM
  std::vector<Param> params;
  std::vector<std::string> autos;  // AUTO variables: frame slots after the parameters
  std::vector<std::string> locals; // LOCAL variables (global slots named "name@program")
  std::vector<Instr> code;
  int temps = 0;                   // frame temporaries (FOR limits and steps)
  std::shared_ptr<const std::vector<std::string>> text;  // the file's lines, for reports
  bool executable = true;          // false: LOAD reported an error in it (dialect §8); a CALL,
                                   //   EXECUTE or run of it stops with *Program not executable*
};

// Fills the program, file, line, step and source line of `d` for `line` of `p`.
void locate_at(Diagnostic& d, const Program& p, int line);

}  // namespace asimov::interpreter
