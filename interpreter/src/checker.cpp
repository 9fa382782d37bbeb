#include "checker.hpp"
#include "vplus_words.hpp"

#include "data_section.hpp"
#include "expressions.hpp"
#include "files.hpp"
#include "limits.hpp"
#include "load_errors.hpp"
#include "settings.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <map>

namespace asimov::interpreter {

int Symbols::global(const std::string& name) {
  auto [it, added] = global_slots.try_emplace(name, static_cast<int>(globals.size()));
  if (added) globals.push_back(name);
  return it->second;
}

int Symbols::program(const std::string& name) {
  auto [it, added] = program_slots.try_emplace(name, static_cast<int>(programs.size()));
  if (added) programs.push_back(name);
  return it->second;
}

namespace {

using ast::Kw;
using ast::Op;

// Binary operator levels of dialect §3 (7 = weakest). ':' binds tighter than '*' [assumption].
constexpr int kPrecedence[] = {
    0, 0, 0,           // unary: never binary
    5, 5, 5,           // * / MOD
    4, 4,              // + -
    3, 3, 3, 3, 3, 3,  // relational
    2, 2,              // AND BAND
    1, 1, 1, 1,        // OR XOR BOR BXOR
    6,                 // :
};
static_assert(std::size(kPrecedence) == static_cast<std::size_t>(Op::count));

struct Block {
  Kw kind = Kw::none;         // if_ (Kw::then), while_, do_, for (Kw::next marks FOR)
  int line = 0;               // opening line
  int column = 1;             // and column of its keyword
  int id = 0;
  int test = -1;              // instruction to patch (IF/WHILE jump_false, FOR init, VALUE test)
  bool has_else = false;      // IF: ELSE seen; CASE: ANY seen
  bool arm_open = false;      // CASE: a VALUE or ANY part is open
  int temp = -1;              // CASE: the frame temporary holding the value
  std::vector<int> end_jumps; // IF and CASE: jumps from the end of a part to END
  int start = -1;             // loop start (WHILE test, DO body, FOR body)
  std::vector<int> exits;     // EXIT jumps to patch
  std::vector<int> nexts;     // NEXT jumps to patch
};

constexpr Kw kIfBlock = Kw::then;
constexpr Kw kForBlock = Kw::next;

const char* block_name(Kw kind) {
  switch (kind) {
    case kIfBlock: return "IF";
    case Kw::while_: return "WHILE";
    case Kw::do_: return "DO";
    case kForBlock: return "FOR";
    case Kw::case_: return "CASE";
    default: return "block";
  }
}

// What a value is when the syntax shows it: 'p' precision point, 't' transformation, 's'
// string, 'r' real; 0 when only the run tells (a variable without prefix, an operator).
char location_kind(const Node& n) {
  if (n.kind == NodeKind::variable && n.text[0] == '#') return 'p';
  if (n.kind == NodeKind::chain && n.ops[0] == ast::Op::compound) return 't';
  if (n.kind == NodeKind::function) switch (n.func) {
      case Func::ppoint: case Func::pdest: return 'p';
      case Func::trans: case Func::here: case Func::dest: case Func::null: case Func::inverse:
      case Func::rx: case Func::ry: case Func::rz: case Func::shift: case Func::tool: case Func::base:
      case Func::frame: return 't';
      default: break;
    }
  const StaticKind k = static_kind(n);
  return k == StaticKind::string ? 's' : k == StaticKind::real ? 'r' : 0;
}

void expect_args(LoadErrors& errors_, const ast::Instruction& i, std::size_t lo, std::size_t hi, const char* what) {
  if (i.args.size() < lo || i.args.size() > hi) errors_.here(fmt::format("{} expects {}", what, lo == hi && lo == 0 ? "no argument" : "other arguments"));
}

class Checker {
 public:
  Checker(const ParsedSource& src, Symbols& symbols, int joint_count)
      : src_(src), symbols_(symbols), joint_count_(joint_count) {
    text_ = std::make_shared<const std::vector<std::string>>(src.text);
  }

  CheckResult run() {
    for (std::size_t i = 0; i < src_.lines.size(); ++i) {
      const ast::Line& l = src_.lines[i];
      errors_.start_line(static_cast<int>(i) + 1, l.column);
      if (l.data) {
        data_line(*l.data);
        continue;
      }
      if (data_section(l)) continue;
      if (!l.statement) {
        if (l.label) {
          if (!in_program_) errors_.here("label outside .PROGRAM");
          else define_label(*l.label);
        }
        continue;
      }
      if (const auto* h = boost::get<ast::ProgramHeader>(&*l.statement)) {
        if (l.label) errors_.here("a label cannot precede .PROGRAM");
        begin_program(*h);
        continue;
      }
      if (!in_program_) {
        errors_.here("only comments may appear outside .PROGRAM ... .END");
        continue;
      }
      if (l.label) define_label(*l.label);
      statement(*l.statement);
    }
    // A file read only up to a limit has lost its .END lines: its limit's error says why.
    if (in_program_) {
      if (!src_.truncated) errors_.at(prog_.line, 1, ".PROGRAM without .END");
      in_program_ = false;
    }
    if (data_kind_ != Kw::none && !src_.truncated) errors_.at(data_start_, 1, "data section without .END");
    return std::move(out_);
  }

 private:
  // --- data sections (dialect §8) -------------------------------------------------------
  // Handles .LOCATIONS/.REALS/.STRINGS and the .END closing them; false for anything else.
  bool data_section(const ast::Line& l) {
    const auto* in = l.statement ? boost::get<ast::Instruction>(&*l.statement) : nullptr;
    if (!in) return false;
    if (in->kw == Kw::dot_end && data_kind_ != Kw::none) {
      data_kind_ = Kw::none;
      return true;
    }
    if (in->kw != Kw::dot_locations && in->kw != Kw::dot_reals && in->kw != Kw::dot_strings) return false;
    if (in_program_) errors_.here("a data section cannot be inside a program");
    else if (l.label || in->args.size() > 1 || (in->args.size() == 1 && !ast::is_omitted(in->args[0]))
             || in->trailing != Kw::none)
      errors_.here("unexpected text");
    data_kind_ = in->kw;
    data_start_ = errors_.line();
    return true;
  }

  void data_line(const ast::DataLine& d) {
    auto item = compile_data_line(d, data_kind_, joint_count_, symbols_);
    if (!item) return errors_.here(item.error().message);
    // The elements will be charged against the data limit when the load assigns them; past it
    // the load fails here, once, instead of first holding them all (docs/limits.md).
    if (item->subscripted && (out_.data_bytes += Elements::element_bytes(item->value)) > kMaxDataBytes) {
      if (data_full_) return;
      errors_.here(fmt::format("the data sections exceed {} MiB of program data", kMaxDataBytes >> 20));
      out_.errors.back().message = "*Out of memory*";
      data_full_ = true;
      return;
    }
    out_.data.push_back(std::move(*item));
  }

  // --- programs ------------------------------------------------------------------------
  void begin_program(const ast::ProgramHeader& h) {
    if (in_program_) {
      errors_.at(prog_.line, 1, ".PROGRAM without .END");
      in_program_ = false;
    }
    prog_ = Program{};
    prog_.name = normalize_name(h.name);
    prog_.file = src_.file;
    prog_.line = errors_.line();
    prog_.text = text_;
    for (const std::string& p : h.params) {
      Param param;
      param.array = p.size() > 2 && p.substr(p.size() - 2) == "[]";
      param.name = normalize_name(param.array ? p.substr(0, p.size() - 2) : p);
      for (const Param& other : prog_.params)
        if (other.name == param.name) errors_.here(fmt::format("parameter {} twice", param.name));
      prog_.params.push_back(param);
    }
    expr_.new_scope();
    for (const Param& p : prog_.params) expr_.note_shape(p.name, p.array);
    for (const Program& other : out_.programs)
      if (other.name == prog_.name) errors_.here(fmt::format("program {} defined twice", prog_.name));
    in_program_ = true;
    executable_seen_ = false;
    blocks_.clear();
    block_parent_.assign(1, -1);
    labels_.clear();
    gotos_.clear();
  }

  void end_program() {
    for (auto it = blocks_.rbegin(); it != blocks_.rend(); ++it)
      if (!errors_.parse_error_between(it->line, errors_.line()))
        errors_.at(it->line, it->column, fmt::format("{} without END", block_name(it->kind)));
    for (const Goto& g : gotos_) {
      auto found = labels_.find(g.label);
      if (found == labels_.end()) {
        errors_.at(g.line, g.column, fmt::format("undefined label {}", g.label));
        continue;
      }
      if (!encloses(found->second.block, g.block)) {
        errors_.at(g.line, g.column, fmt::format("GOTO {} jumps into a block", g.label));
        continue;
      }
      prog_.code[static_cast<std::size_t>(g.instr)].jump = found->second.instr;
    }
    for (Instr& in : prog_.code)  // the dispatch loop calls the compiled root directly
      in.fast0 = in.args.empty() || !in.args[0].fast ? nullptr : in.args[0].fast->root();
    out_.programs.push_back(std::move(prog_));
    in_program_ = false;
  }

  // --- labels and blocks -----------------------------------------------------------------
  struct LabelInfo {
    int instr;
    int block;
  };
  struct Goto {
    unsigned label;
    int instr, block, line, column;
  };

  int current_block() const { return blocks_.empty() ? 0 : blocks_.back().id; }
  bool encloses(int outer, int inner) const {
    for (int b = inner; b >= 0; b = block_parent_[static_cast<std::size_t>(b)])
      if (b == outer) return true;
    return false;
  }

  void define_label(unsigned label) {
    if (labels_.count(label)) {
      errors_.here(fmt::format("duplicate label {}", label));
      return;
    }
    labels_[label] = {here(), current_block()};
  }

  void add_goto(unsigned label) {
    gotos_.push_back({label, here() - 1, current_block(), errors_.line(), errors_.column()});
  }

  void open_block(Kw kind, int test, int start) {
    Block b;
    b.kind = kind;
    b.line = errors_.line();
    b.column = errors_.column();
    b.id = static_cast<int>(block_parent_.size());
    b.test = test;
    b.start = start;
    block_parent_.push_back(current_block());
    blocks_.push_back(std::move(b));
  }

  Block* innermost_loop() {
    for (auto it = blocks_.rbegin(); it != blocks_.rend(); ++it)
      if (it->kind != kIfBlock && it->kind != Kw::case_) return &*it;  // CASE is not a loop
    return nullptr;
  }

  // --- code emission ---------------------------------------------------------------------
  int here() const { return static_cast<int>(prog_.code.size()); }
  Instr& emit(Code code) {
    Instr in;
    in.code = code;
    in.line = errors_.line();
    prog_.code.push_back(std::move(in));
    return prog_.code.back();
  }
  Instr& at(int index) { return prog_.code[static_cast<std::size_t>(index)]; }

  void declaration(const ast::Declaration& d) {
    if (executable_seen_) {
      errors_.here("declarations must precede the first executable statement");
      return;
    }
    for (const ast::VarRef& v : d.names) {
      const std::string name = normalize_name(v.name);
      bool clash = false;
      for (const Param& p : prog_.params) clash = clash || p.name == name;
      if (d.kw == Kw::auto_ && clash) errors_.here(fmt::format("{} is a parameter", name));
      expr_.note_shape(name, !v.subscript.empty());  // AUTO a then AUTO a[5]: one name, two shapes
      auto declared = [&](const std::vector<std::string>& names) {
        return std::find(names.begin(), names.end(), name) != names.end();
      };
      const bool in_auto = declared(prog_.autos), in_local = declared(prog_.locals);
      if ((d.kw != Kw::auto_ && in_auto) || (d.kw != Kw::local && in_local) || (d.kw == Kw::global && clash))
        errors_.here(fmt::format("{} declared with another class", name));
      else if (d.kw == Kw::auto_ && !in_auto && !clash) prog_.autos.push_back(name);
      else if (d.kw == Kw::local && !in_local) prog_.locals.push_back(name);
    }
  }

  // --- expressions (expressions.cpp) ------------------------------------------------------

  // --- statements ------------------------------------------------------------------------
  void statement(const ast::Statement& s) {
    struct Visitor {
      Checker& c;
      void operator()(const ast::Instruction& i) const { c.instruction(i); }
      void operator()(const ast::Binding& b) const { c.binding(b); }
      void operator()(const ast::ForStmt& f) const { c.for_statement(f); }
      void operator()(const ast::IfStmt& i) const { c.if_statement(i); }
      void operator()(const ast::CallStmt& call) const { c.call_statement(call); }
      void operator()(const ast::CallsStmt& calls) const { c.calls_statement(calls); }
      void operator()(const ast::TypeStmt& t) const { c.type_statement(t); }
      void operator()(const ast::ProgramHeader&) const {}
      void operator()(const ast::Declaration& d) const { c.declaration(d); }
      void operator()(const ast::Unsupported& u) const { c.unsupported(u); }
      void operator()(const ast::AccelStmt& a) const {  // args: profile, acceleration, deceleration
        if (a.values.size() > 2) return c.errors_.here("ACCEL expects at most an acceleration and a deceleration");
        Instr& in = c.emit(Code::accel);
        in.args.push_back(c.expr_.expression(a.profile));
        for (const ast::Expr& v : a.values) in.args.push_back(c.expr_.expression(v));
      }
      void operator()(const ast::IoStmt& io) const { c.io_statement(io); }
      void operator()(const ast::ExecuteStmt& e) const { c.execute_statement(e); }
      void operator()(const ast::TimerStmt& t) const {
        Instr& in = c.emit(Code::timer);
        in.args.push_back(c.expr_.expression(t.number));
        in.args.push_back(c.expr_.expression(t.value));
      }
    };
    if (!boost::get<ast::Declaration>(&s)) executable_seen_ = true;
    boost::apply_visitor(Visitor{*this}, s);
  }

  // Dialect §7: robot ATTACH ()/DETACH () and SELECT ROBOT = 1 only warn.
  void unsupported(const ast::Unsupported& u) {
    Instr& in = emit(Code::unsupported);
    for (char c : u.keyword) in.target.text += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    std::string rest;
    for (char c : u.rest.substr(0, u.rest.find(';')))
      if (c != ' ' && c != '\t') rest += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    const std::string& k = in.target.text;
    const bool select_robot = k == "SELECT" && rest == "ROBOT=1";
    in.warn_only = ((k == "ATTACH" || k == "DETACH") && rest.rfind("()", 0) == 0) || select_robot;
    // A word of the inventory (dialect §13) says why; one with no effect only warns.
    if (const VplusWord* w = vplus_word(k, WordKind::instruction); w && !select_robot) {
      in.warn_only = in.warn_only || w->support == Support::no_effect;
      in.target.text = vplus_refusal(*w);
    }
  }

  // Dialect §7a. Robot ATTACH () / DETACH () (§7b); FOPEN and FCMND (network) stop with a hint.
  void io_statement(const ast::IoStmt& io) {
    std::string k;
    for (char c : io.keyword) k += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    std::vector<ast::Expr> unit = io.unit;
    if (unit.size() == 1 && ast::is_omitted(unit[0])) unit.clear();
    if ((k == "ATTACH" || k == "DETACH") && unit.empty() && io.items.empty()) {  // the robot
      Instr& in = emit(Code::robot);
      in.target.text = k;
      in.io = k == "ATTACH" ? IoOp::attach : IoOp::detach;
      return;
    }
    if (k == "ABORT" || k == "KILL" || k == "CYCLE.END" || k == "RELEASE") return task_statement(k, unit, io.items);
    if (k == "FOPEN" || k == "FCMND") {
      Instr& in = emit(Code::unsupported);
      in.target.text = k + "; " + std::string(kNetworkHint);
      return;
    }
    static const std::pair<const char*, IoOp> kOps[] = {
        {"ATTACH", IoOp::attach}, {"DETACH", IoOp::detach}, {"FOPENR", IoOp::fopenr}, {"FOPENW", IoOp::fopenw},
        {"FOPENA", IoOp::fopena}, {"FOPEND", IoOp::fopend}, {"FCLOSE", IoOp::fclose}, {"FEMPTY", IoOp::fempty},
        {"FDELETE", IoOp::fdelete}, {"READ", IoOp::read}, {"WRITE", IoOp::write}};
    IoOp op = IoOp::read;
    for (const auto& [name, o] : kOps)
      if (k == name) op = o;
    if (unit.empty() || ast::is_omitted(unit[0])) {
      errors_.here(fmt::format("{} needs a logical unit: {} (lun) ...", k, k));
      return;
    }
    const bool takes_path = op == IoOp::fopenr || op == IoOp::fopenw || op == IoOp::fopena || op == IoOp::fopend
        || op == IoOp::fempty || op == IoOp::fdelete;
    const std::size_t want_max = op == IoOp::read || op == IoOp::write ? kMaxIoItems : takes_path || op == IoOp::attach ? 1 : 0;
    if (io.items.size() > want_max || (takes_path && io.items.empty()) || (op == IoOp::read && io.items.empty())) {
      errors_.here(fmt::format("{} expects {}", k, op == IoOp::read ? "variables after the unit"
                                                : takes_path ? "a file name after the unit"
                                                : want_max ? "at most a device name after the unit" : "only the unit"));
      return;
    }
    Instr& in = emit(Code::io);
    in.io = op;
    in.target.text = k;
    for (const ast::Expr& e : unit) in.args.push_back(ast::is_omitted(e) ? Node{} : expr_.expression(e));
    in.items = static_cast<int>(in.args.size());
    for (const ast::TypeItem& item : io.items) {
      if (const auto* f = boost::get<ast::Format>(&item)) {
        if (op != IoOp::write) {
          errors_.here(fmt::format("{} takes no format", k));
          return;
        }
        ast::Format spec = *f;
        spec.code = static_cast<char>(std::toupper(static_cast<unsigned char>(spec.code)));
        if (spec.width > kMaxStringLength || spec.decimals > kMaxStringLength)
          errors_.here(fmt::format("/{}{} is wider than {} characters", spec.code, std::max(spec.width, spec.decimals), kMaxStringLength));
        in.formats.push_back(spec);
        continue;
      }
      const ast::Expr& e = boost::get<ast::Expr>(item);
      if (op == IoOp::read) {
        const ast::VarRef* v = ExpressionCompiler::plain_variable(e, true);
        if (!v || ast::is_whole_array(*v) || v->name[0] == '#') {
          errors_.here("READ expects real or string variables");
          return;
        }
        in.args.push_back(expr_.variable(*v, false));
        continue;
      }
      Node value = expr_.expression(e);
      if (op != IoOp::write && static_kind(value) == StaticKind::real) errors_.here(fmt::format("{} expects a string", k));
      in.formats.push_back(ast::Format{0, 0, 0});
      in.args.push_back(std::move(value));
    }
  }

  // ABORT n, KILL n, CYCLE.END n, RELEASE [n] (dialect §7b): the task number as the one item.
  void task_statement(const std::string& k, const std::vector<ast::Expr>& unit, const std::vector<ast::TypeItem>& items) {
    const IoOp op = k == "ABORT" ? IoOp::abort : k == "KILL" ? IoOp::kill : k == "CYCLE.END" ? IoOp::cycle_end : IoOp::release;
    std::vector<const ast::Expr*> args;
    for (const ast::Expr& e : unit) args.push_back(&e);
    for (const ast::TypeItem& item : items) {
      const auto* e = boost::get<ast::Expr>(&item);
      if (!e) {
        errors_.here(fmt::format("{} takes no format", k));
        return;
      }
      args.push_back(e);
    }
    if ((op != IoOp::release && args.empty()) || args.size() > (op == IoOp::cycle_end ? 2u : 1u)) {
      errors_.here(fmt::format("{} expects a task number", k));
      return;
    }
    Instr& in = emit(Code::task);
    in.io = op;
    in.target.text = k;
    for (const ast::Expr* e : args) in.args.push_back(expr_.expression(*e));
  }

  // EXECUTE [task] prog(args): the program slot as for CALL; arguments go by value.
  void execute_statement(const ast::ExecuteStmt& e) {
    Instr& in = emit(Code::execute);
    in.program = symbols_.program(normalize_name(e.head.program));
    in.target.text = normalize_name(e.head.program);
    in.args.push_back(ast::is_omitted(e.head.task) ? Node{} : expr_.expression(e.head.task));
    std::size_t count = e.args.size();
    if (count == 1 && !e.args[0]) count = 0;
    for (std::size_t i = 0; i < count; ++i) in.args.push_back(e.args[i] ? expr_.expression(*e.args[i]) : Node{});
  }

  void binding(const ast::Binding& b) {
    if (b.kw == Kw::parameter) {  // PARAMETER name = value: the name is checked when it runs
      if (!b.target.subscript.empty() || b.target.name[0] == '$' || b.target.name[0] == '#')
        errors_.here("PARAMETER expects a parameter name");
      Instr& in = emit(Code::parameter);
      in.target = ExpressionCompiler::setting_name(b.target);
      if (!known_parameter(in.target.text) && !vplus_setting(in.target.text, false))
        errors_.here(fmt::format("unknown parameter {}", in.target.text));
      in.args.push_back(expr_.expression(b.value));
      return;
    }
    // DECOMPOSE a[] = ... fills a[0], a[1] ... (V+); a whole array is no other target.
    Node target = expr_.variable(b.target, b.kw == Kw::decompose, b.kw != Kw::decompose);
    if (b.kw == Kw::decompose) expr_.note_shape(target.text, true);  // DECOMPOSE x = ...: x[0] ...
    const Code code = b.kw == Kw::set ? Code::set : b.kw == Kw::decompose ? Code::decompose : Code::assign;
    Node value = expr_.expression(b.value);
    if (code == Code::set) {  // what fails on first execution is reported now
      const char want = target.text[0] == '#' ? 'p' : 't';
      const char got = location_kind(value);
      if (target.text[0] == '$') errors_.here("SET needs a location variable");
      else if (got && got != want)
        errors_.here(fmt::format("{} cannot hold a {}", target.text, got == 'p' ? "precision point" : got == 't' ? "transformation"
                                                              : got == 's' ? "string" : "real"));
    }
    if (code == Code::assign) {
      const StaticKind k = static_kind(value);
      const bool string_target = target.text[0] == '$';
      if ((string_target && k == StaticKind::real) || (!string_target && k == StaticKind::string))
        errors_.here(string_target ? "a number cannot be put into a string variable"
                            : "a string needs a $ variable");
    }
    Instr& in = emit(code);
    in.real_target = code == Code::assign && target.text[0] != '$' && target.text[0] != '#';
    in.target = std::move(target);
    in.args.push_back(std::move(value));
  }

  void for_statement(const ast::ForStmt& f) {
    if (!f.var.subscript.empty() || f.var.name[0] == '$' || f.var.name[0] == '#')
      errors_.here("FOR needs a plain real variable");
    Instr& in = emit(Code::for_init);
    in.target = expr_.variable(f.var, false);
    in.args.push_back(expr_.expression(f.from));
    in.args.push_back(expr_.expression(f.to));
    if (f.step) in.args.push_back(expr_.expression(*f.step));
    in.temp = prog_.temps;
    prog_.temps += 2;
    open_block(kForBlock, here() - 1, here());
  }

  void if_statement(const ast::IfStmt& i) {
    if (i.goto_label) {
      emit(Code::jump_true).args.push_back(expr_.expression(i.cond));
      add_goto(*i.goto_label);
      return;
    }
    emit(Code::jump_false).args.push_back(expr_.expression(i.cond));
    open_block(kIfBlock, here() - 1, -1);
  }

  void call_statement(const ast::CallStmt& call) {
    Instr& in = emit(Code::call);
    in.program = symbols_.program(normalize_name(call.name));
    call_arguments(in, call.args);
  }

  // CALLS $name(args): the program is the string's value when the step runs; the arguments
  // go as CALL's do.
  void calls_statement(const ast::CallsStmt& calls) {
    ast::Expr name;
    name.first = calls.program;
    Node program = expr_.expression(name);  // a string literal or variable (the parser takes no other)
    Instr& in = emit(Code::calls);
    in.target = std::move(program);
    call_arguments(in, calls.args);
  }

  void call_arguments(Instr& in, const std::vector<boost::optional<ast::Expr>>& args) {
    std::size_t count = args.size();
    if (count == 1 && !args[0]) count = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const auto& a = args[i];
      const ast::VarRef* v = a ? ExpressionCompiler::plain_variable(*a, true) : nullptr;
      // A plain variable or a whole array a[] goes by reference; anything else by value.
      if (v && (v->subscript.empty() || ast::is_whole_array(*v))) {
        in.args.push_back(expr_.variable(*v, true, !v->subscript.empty()));  // a plain name may be either
        in.by_ref.push_back(true);
      } else {
        in.args.push_back(a ? expr_.expression(*a) : Node{});
        in.by_ref.push_back(false);
      }
    }
  }

  void type_statement(const ast::TypeStmt& t) {
    Instr& in = emit(Code::type);
    expr_.format_items(t, in.formats, in.args);
  }


  void instruction(const ast::Instruction& raw) {
    ast::Instruction i = raw;
    if (i.args.size() == 1 && ast::is_omitted(i.args[0])) i.args.clear();  // no arguments
    if (i.trailing != Kw::none) {
      const bool ok = (i.kw == Kw::speed && (i.trailing == Kw::always || i.trailing == Kw::monitor))
          || (i.kw == Kw::duration && i.trailing == Kw::always) || (i.kw == Kw::while_ && i.trailing == Kw::do_)
          || (i.kw == Kw::elseif && i.trailing == Kw::then) || (i.kw == Kw::case_ && i.trailing == Kw::of);
      if (!ok) errors_.here("unexpected word at the end of the statement");
    }
    if (i.units != Kw::none && i.kw != Kw::speed) errors_.here("MMPS and IPS follow SPEED only");
    if (const SimpleForm* form = simple_form(i.kw)) {
      if (static_cast<int>(i.args.size()) < form->min_args
          || (form->max_args >= 0 && static_cast<int>(i.args.size()) > form->max_args))
        errors_.here(fmt::format("{} expects {}", form->name, form->max_args == 0 ? "no argument" : "other arguments"));
      simple(i, form->code);
      Instr& in = prog_.code.back();
      in.word = i.kw;
      in.scope = i.trailing == Kw::always ? SpeedScope::always : SpeedScope::next;
      if (i.kw == Kw::wait_event && !i.args.empty() && !ast::is_omitted(i.args[0]))
        in.code = Code::unsupported, in.target.text = "WAIT.EVENT";  // with a mask (dialect §7)
      return;
    }
    switch (i.kw) {
      case Kw::elseif: return else_if(i);
      case Kw::case_: {
        expect_args(errors_, i, 1, 1, "CASE");
        simple(i, Code::case_init);
        prog_.code.back().temp = prog_.temps;
        open_block(Kw::case_, -1, -1);
        blocks_.back().temp = prog_.temps++;
        return;
      }
      case Kw::value: case Kw::any: return case_part(i);
      case Kw::enable: case Kw::disable: return switches(i);
      case Kw::prompt: return prompt(i);
      case Kw::here: {
        const ast::VarRef* v = i.args.size() == 1 ? ExpressionCompiler::plain_variable(i.args[0], true) : nullptr;
        if (!v) {
          errors_.here("HERE expects a location variable");
          return;
        }
        emit(Code::here).target = expr_.variable(*v, false);
        return;
      }
      case Kw::speed: {
        expect_args(errors_, i, 1, 2, "SPEED");
        simple(i, Code::speed);
        Instr& in = prog_.code.back();
        in.scope = i.trailing == Kw::always ? SpeedScope::always : i.trailing == Kw::monitor ? SpeedScope::monitor : SpeedScope::next;
        if (i.units != Kw::none)  // SPEED ... MMPS / IPS (dialect §7)
          in.code = Code::unsupported, in.target.text = i.units == Kw::mmps ? "SPEED MMPS" : "SPEED IPS";
        return;
      }
      case Kw::goto_: {
        const double* label = i.args.size() == 1 && i.args[0].rest.empty() ? boost::get<double>(&i.args[0].first) : nullptr;
        if (!label || *label < 0 || *label > kMaxLabel || *label != static_cast<unsigned>(*label)) {
          errors_.here("GOTO expects a label (0 to 65535)");
          return;
        }
        emit(Code::jump);
        add_goto(static_cast<unsigned>(*label));
        return;
      }
      case Kw::while_: {
        expect_args(errors_, i, 1, 1, "WHILE");
        const int test = here();
        simple(i, Code::jump_false);
        open_block(Kw::while_, test, test);
        return;
      }
      case Kw::do_: expect_args(errors_, i, 0, 0, "DO"); open_block(Kw::do_, -1, here()); return;
      case Kw::until: return until(i);
      case Kw::else_: return else_part(i);
      case Kw::end: return end_block(i);
      case Kw::exit:
      case Kw::next: {
        expect_args(errors_, i, 0, 0, i.kw == Kw::exit ? "EXIT" : "NEXT");
        Block* loop = innermost_loop();
        if (!loop) {
          errors_.in_block(fmt::format("{} outside a loop", i.kw == Kw::exit ? "EXIT" : "NEXT"));
          return;
        }
        (i.kw == Kw::exit ? loop->exits : loop->nexts).push_back(here());
        emit(Code::jump);
        return;
      }
      case Kw::react: case Kw::reacti: case Kw::reacte: return reaction(i);
      case Kw::dot_end: expect_args(errors_, i, 0, 0, ".END"); return end_program();
      default: errors_.here("unexpected statement"); return;
    }
  }

  // REACT signal, program [, priority]; REACTI signal [, program [, priority]]; REACTE [program]
  // (dialect §7c): the program name resolved to its slot as CALL's, the numbers as expressions.
  void reaction(const ast::Instruction& i) {
    const bool trap = i.kw == Kw::reacte;
    const char* what = trap ? "REACTE" : i.kw == Kw::react ? "REACT" : "REACTI";
    const std::size_t lo = trap ? 0 : i.kw == Kw::react ? 2 : 1, hi = trap ? 1 : 3;
    const std::size_t at = trap ? 0 : 1;  // the program's argument
    const bool named = i.args.size() > at && !ast::is_omitted(i.args[at]);
    if (i.args.size() < lo || i.args.size() > hi || (i.kw == Kw::react && !named)) {
      errors_.here(fmt::format("{} expects {}", what, trap ? "a program name or nothing" : "a signal, a program and a priority"));
      return;
    }
    Instr& in = emit(trap ? Code::reacte : Code::react);
    in.word = i.kw;
    if (!trap) in.args.push_back(expr_.expression(i.args[0]));
    if (named) {
      const ast::VarRef* v = ExpressionCompiler::plain_variable(i.args[at], false);
      if (!v || v->name[0] == '$' || v->name[0] == '#') {
        errors_.here(fmt::format("{} expects a program name", what));
        return;
      }
      in.program = symbols_.program(normalize_name(v->name));
    }
    if (!trap) in.args.push_back(i.args.size() > 2 && !ast::is_omitted(i.args[2]) ? expr_.expression(i.args[2]) : Node{});
  }

  // ENABLE / DISABLE sw, ...: switch names, known ones only (dialect §6).
  void switches(const ast::Instruction& i) {
    Instr& in = emit(i.kw == Kw::enable ? Code::enable : Code::disable);
    for (const ast::Expr& e : i.args) {
      const ast::VarRef* v = ExpressionCompiler::plain_variable(e, false);
      if (!v || v->name[0] == '$' || v->name[0] == '#') {
        errors_.here(fmt::format("{} expects switch names", i.kw == Kw::enable ? "ENABLE" : "DISABLE"));
        return;
      }
      in.args.push_back(ExpressionCompiler::setting_name(*v));
      if (!known_switch(in.args.back().text) && !vplus_setting(in.args.back().text, true))
        errors_.here(fmt::format("unknown switch {}", in.args.back().text));
    }
    if (in.args.empty()) errors_.here("a switch name is missing");
  }


  // PROMPT text, variable
  void prompt(const ast::Instruction& i) {
    const ast::VarRef* v = i.args.size() == 2 ? ExpressionCompiler::plain_variable(i.args[1], true) : nullptr;
    if (!v || ast::is_whole_array(*v) || v->name[0] == '#') {
      errors_.here("PROMPT expects a text and a real or string variable");
      return;
    }
    Node text = expr_.expression(i.args[0]);
    if (static_kind(text) == StaticKind::real) errors_.here("PROMPT expects a text first");
    Instr& in = emit(Code::prompt);
    in.target = expr_.variable(*v, false);
    in.args.push_back(std::move(text));
  }

  void simple(const ast::Instruction& i, Code code) {
    Instr& in = emit(code);
    for (const ast::Expr& e : i.args) in.args.push_back(expr_.expression(e));
  }

  void until(const ast::Instruction& i) {
    expect_args(errors_, i, 1, 1, "UNTIL");
    if (blocks_.empty() || blocks_.back().kind != Kw::do_) {
      errors_.in_block("UNTIL without DO");
      return;
    }
    Block b = std::move(blocks_.back());
    blocks_.pop_back();
    for (int n : b.nexts) at(n).jump = here();
    simple(i, Code::jump_false);
    prog_.code.back().jump = b.start;
    for (int e : b.exits) at(e).jump = here();
  }

  // Ends the open part of an IF or CASE: jump to END, and the pending test lands here.
  void close_part(Block& b) {
    b.end_jumps.push_back(here());
    emit(Code::jump);
    if (b.test >= 0) at(b.test).jump = here();
    b.test = -1;
  }

  void else_part(const ast::Instruction& i) {
    expect_args(errors_, i, 0, 0, "ELSE");
    if (blocks_.empty() || blocks_.back().kind != kIfBlock || blocks_.back().has_else) {
      errors_.in_block("ELSE without IF ... THEN");
      return;
    }
    close_part(blocks_.back());
    blocks_.back().has_else = true;
  }

  // ELSEIF / ELIF cond [THEN]   [ext]
  void else_if(const ast::Instruction& i) {
    expect_args(errors_, i, 1, 1, "ELSEIF");
    if (blocks_.empty() || blocks_.back().kind != kIfBlock || blocks_.back().has_else) {
      errors_.in_block("ELSEIF without IF ... THEN");
      return;
    }
    close_part(blocks_.back());
    blocks_.back().test = here();
    simple(i, Code::jump_false);
  }

  // VALUE e1, e2:  /  ANY
  void case_part(const ast::Instruction& i) {
    const bool any = i.kw == Kw::any;
    expect_args(errors_, i, any ? 0 : 1, any ? 0 : 1000, any ? "ANY" : "VALUE");
    if (blocks_.empty() || blocks_.back().kind != Kw::case_ || blocks_.back().has_else) {
      errors_.in_block(fmt::format("{} outside CASE (or after ANY)", any ? "ANY" : "VALUE"));
      return;
    }
    Block& b = blocks_.back();
    if (b.arm_open) close_part(b);
    b.arm_open = true;
    if (any) {
      b.has_else = true;
      return;
    }
    b.test = here();
    simple(i, Code::case_test);
    prog_.code.back().temp = b.temp;
  }

  void end_block(const ast::Instruction& i) {
    expect_args(errors_, i, 0, 0, "END");
    if (blocks_.empty() || blocks_.back().kind == Kw::do_) {
      errors_.in_block(blocks_.empty() ? "END without a block" : "DO ends with UNTIL, not END");
      return;
    }
    Block b = std::move(blocks_.back());
    blocks_.pop_back();
    if (b.kind == kIfBlock || b.kind == Kw::case_) {
      if (b.test >= 0) at(b.test).jump = here();
      for (int e : b.end_jumps) at(e).jump = here();
      return;
    }
    const int loop_end = here();
    for (int n : b.nexts) at(n).jump = loop_end;
    if (b.kind == Kw::while_) {  // the test again at the bottom (one dispatch per iteration less)
      Instr& again = emit(Code::jump_true);
      again.args = at(b.test).args;
      again.line = at(b.test).line;
      again.jump = b.start + 1;
    } else {  // FOR
      Instr& next = emit(Code::for_next);
      const Instr& init = at(b.test);
      next.target = init.target;
      next.temp = init.temp;
      next.jump = b.start;
    }
    at(b.test).jump = here();
    for (int e : b.exits) at(e).jump = here();
  }

  const ParsedSource& src_;
  Symbols& symbols_;
  CheckResult out_;
  std::shared_ptr<const std::vector<std::string>> text_;
  int joint_count_ = 6;
  Kw data_kind_ = Kw::none;             // the open data section, if any
  int data_start_ = 0;                  // and its line
  bool data_full_ = false;              // the data sections passed kMaxDataBytes (reported once)
  bool in_program_ = false;
  bool executable_seen_ = false;       // declarations must come first
  Program prog_;
  std::vector<Block> blocks_;
  std::vector<int> block_parent_;       // block id -> enclosing block id (0 = program level)
  std::map<unsigned, LabelInfo> labels_;
  std::vector<Goto> gotos_;
  LoadErrors errors_{src_, out_, in_program_, prog_};
  ExpressionCompiler expr_{symbols_, prog_, [this](std::string detail, const std::string& near) {
    errors_.near(std::move(detail), near);
  }};
};

}  // namespace

int precedence(ast::Op op) { return kPrecedence[static_cast<std::size_t>(op)]; }

CheckResult check_source(const ParsedSource& source, Symbols& symbols, int joint_count) {
  return Checker(source, symbols, joint_count).run();
}

}  // namespace asimov::interpreter
