#include "expressions.hpp"

#include "limits.hpp"
#include "settings.hpp"

#include <fmt/format.h>

#include <cctype>

namespace asimov::interpreter {

using ast::Op;

Node ExpressionCompiler::expression(const ast::Expr& e) {
  std::size_t pos = 0;
  ++depth_;
  Node n = climb(operand(e.first), e.rest, pos, 1);
  --depth_;
  if (depth_ == 0) {  // a whole expression (or a target's subscript): compiled once
    mark_plain(n);
    n.fast = RealCode::compile(n);
  }
  return n;
}

// Precedence climbing over the flat operator list the parser produced. Operators of one level
// in a row extend one n-ary chain node (code.hpp): the loop goes from level to level, at most
// seven deep, and never recurses per operator.
Node ExpressionCompiler::climb(Node lhs, const std::vector<ast::Operation>& rest, std::size_t& pos, int min_prec) {
  // The kind of lhs is carried along the chain: asking static_kind of the grown left side at
  // each operator walked it again, quadratic in the chain's length.
  StaticKind kl = pos < rest.size() && precedence(rest[pos].op) >= min_prec ? static_kind(lhs) : StaticKind::unknown;
  bool own = false;  // lhs is a chain built by this loop (not an operand that happens to be one)
  while (pos < rest.size() && precedence(rest[pos].op) >= min_prec) {
    const Op op = rest[pos].op;
    const int p = precedence(op);
    Node rhs = operand(rest[pos].operand);
    ++pos;
    while (pos < rest.size() && precedence(rest[pos].op) > p)
      rhs = climb(std::move(rhs), rest, pos, p + 1);
    const StaticKind kr = static_kind(rhs);
    if ((kl == StaticKind::string && kr == StaticKind::real) || (kl == StaticKind::real && kr == StaticKind::string))
      error("a string and a number cannot be mixed");
    else if ((kl == StaticKind::string || kr == StaticKind::string) && op != Op::add && !(op >= Op::eq && op <= Op::ge))
      error("this operator does not apply to strings");
    if (!own || precedence(lhs.ops[0]) != p) {  // a new chain, with lhs as its first operand
      Node chain;
      chain.kind = NodeKind::chain;
      // Its length, counted ahead (up to the first weaker operator; every operator is counted
      // by at most one chain per level): reserved, the vectors do not grow by doubling, which
      // held up to three times the chain's nodes while it moved them.
      std::size_t length = 2;  // lhs and rhs, then the operators of this level still ahead
      for (std::size_t j = pos; j < rest.size() && precedence(rest[j].op) >= p; ++j) length += precedence(rest[j].op) == p;
      chain.kids.reserve(length);
      chain.ops.reserve(length - 1);
      chain.kids.push_back(std::move(lhs));
      lhs = std::move(chain);
      own = true;
    }
    lhs.ops.push_back(op);
    lhs.kids.push_back(std::move(rhs));
    kl = binary_kind(op, kl, kr);
  }
  return lhs;
}

Node ExpressionCompiler::operand(const ast::Operand& o) {
  struct Visitor {
    ExpressionCompiler& c;
    Node operator()(const ast::Nil&) const { return Node{}; }
    Node operator()(double d) const {
      Node n;
      n.kind = NodeKind::number;
      n.number = d;
      return n;
    }
    Node operator()(const std::string& s) const {
      Node n;
      n.kind = NodeKind::string;
      n.text = s;
      if (s.size() > kMaxStringLength) c.error("string longer than 128 characters");
      return n;
    }
    Node operator()(const ast::VarRef& v) const { return c.variable(v, false); }
    Node operator()(const ast::Call& call) const { return c.function(call); }
    Node operator()(const ast::Unary& u) const {
      Node n;
      n.kind = NodeKind::unary;
      n.op = u.op;
      n.kids.push_back(c.operand(u.operand));
      if (static_kind(n.kids[0]) == StaticKind::string) c.error("this operator does not apply to strings");
      return n;
    }
    Node operator()(const ast::Expr& e) const { return c.expression(e); }
    Node operator()(const ast::TypeStmt& t) const {  // $ENCODE(items)
      Node n;
      n.kind = NodeKind::encode;
      c.format_items(t, n.formats, n.kids);
      for (const ast::Format& f : n.formats)
        if (f.code == 'C' || f.code == 'S') c.error("/C and /S are not allowed in $ENCODE");
      return n;
    }
  };
  return boost::apply_visitor(Visitor{*this}, o);
}

void ExpressionCompiler::note_shape(const std::string& name, bool array) {
  const auto [it, added] = shapes_.emplace(name, array);
  if (!added && it->second != array) error(fmt::format("{} is used both as a scalar and as an array", name));
}

Node ExpressionCompiler::variable(const ast::VarRef& v, bool whole_array_ok, bool shape_use) {
  Node n;
  n.kind = NodeKind::variable;
  n.text = normalize_name(v.name);
  if (!v.subscript.empty()) {
    n.subscripted = true;
    if (ast::is_whole_array(v)) {
      if (!whole_array_ok) error(fmt::format("{}[] is allowed only as a CALL argument", n.text));
    } else {
      if (v.subscript.size() > static_cast<std::size_t>(kMaxSubscripts)) error("at most 3 subscripts");
      for (const ast::Expr& e : v.subscript) n.kids.push_back(expression(e));
    }
  }
  if (shape_use) note_shape(n.text, n.subscripted);
  // Lookup: parameters and AUTO, then LOCAL, then GLOBAL (dialect §2).
  for (std::size_t i = 0; i < prog_.params.size(); ++i)
    if (prog_.params[i].name == n.text) {
      n.ref = {Scope::param, static_cast<int>(i)};
      return n;
    }
  for (std::size_t i = 0; i < prog_.autos.size(); ++i)
    if (prog_.autos[i] == n.text) {
      n.ref = {Scope::param, static_cast<int>(prog_.params.size() + i)};
      return n;
    }
  for (const std::string& local : prog_.locals)
    if (local == n.text) {
      n.ref = {Scope::global, symbols_.global(n.text + "@" + prog_.name)};
      return n;
    }
  n.ref = {Scope::global, symbols_.global(n.text)};
  return n;
}


Node ExpressionCompiler::function(const ast::Call& call) {
  Node n;
  n.kind = NodeKind::function;
  const std::string name = normalize_name(call.name);
  const auto f = find_function(name);
  if (!f) {
    error(fmt::format("unknown function {}", call.name), call.name);  // as written, caret under it
    return n;
  }
  n.func = *f;
  n.text = name;
  std::size_t count = call.args.size();
  if (count == 1 && !call.args[0]) count = 0;  // NAME()
  const FunctionInfo& info = function_info(*f);
  if (static_cast<int>(count) < info.min_args || (info.max_args >= 0 && static_cast<int>(count) > info.max_args)) {
    error(fmt::format("wrong number of arguments to {}", name));
    return n;
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (!call.args[i]) {
      n.kids.emplace_back();  // omitted
      continue;
    }
    if (*f == Func::parameter || *f == Func::switch_ || *f == Func::select) {
      const char* what = *f == Func::parameter ? "PARAMETER" : *f == Func::switch_ ? "SWITCH" : "SELECT";
      const ast::VarRef* v = plain_variable(*call.args[i], false);
      if (!v || v->name[0] == '$' || v->name[0] == '#') {
        error(fmt::format("{} needs a name", what));
        return n;
      }
      n.kids.push_back(setting_name(*v));
      const std::string& setting = n.kids.back().text;  // what would fail when it runs is said now
      if (*f == Func::select && setting != "ROBOT") error("SELECT() knows ROBOT only");
      if (*f == Func::parameter && !known_parameter(setting)) error(fmt::format("unknown parameter {}", setting));
      if (*f == Func::switch_ && !known_switch(setting)) error(fmt::format("unknown switch {}", setting));
    } else if (*f == Func::tas && i == 0) {  // TAS(variable, value): test and set
      const ast::VarRef* v = plain_variable(*call.args[i], true);
      if (!v || v->name[0] == '$' || v->name[0] == '#' || ast::is_whole_array(*v)) {
        error("TAS needs a real variable");
        return n;
      }
      n.kids.push_back(variable(*v, false));
    } else if (*f == Func::decode_s && i == 0) {  // $DECODE(var, ...): takes the front of var
      const ast::VarRef* v = plain_variable(*call.args[i], true);
      if (!v || v->name[0] != '$' || ast::is_whole_array(*v)) {
        error("$DECODE needs a string variable");
        return n;
      }
      n.kids.push_back(variable(*v, false));
    } else if (*f == Func::defined || *f == Func::last) {
      const ast::VarRef* v = plain_variable(*call.args[i], true);
      if (!v || (*f == Func::last && !ast::is_whole_array(*v))) {
        error(*f == Func::last ? "LAST needs an array a[]" : "DEFINED needs a variable");
        return n;
      }
      n.kids.push_back(variable(*v, *f == Func::last, *f == Func::last));
    } else {
      n.kids.push_back(expression(*call.args[i]));
    }
  }
  return n;
}

// The variable when `e` is just a variable (by-reference argument, HERE target ...).
const ast::VarRef* ExpressionCompiler::plain_variable(const ast::Expr& e, bool subscript_ok) {
  if (!e.rest.empty()) return nullptr;
  const auto* v = boost::get<ast::VarRef>(&e.first);
  if (!v || (!v->subscript.empty() && !subscript_ok)) return nullptr;
  return v;
}

// TYPE and $ENCODE items: a format (code in upper case) or an expression (code 0).
void ExpressionCompiler::format_items(const ast::TypeStmt& t, std::vector<ast::Format>& formats, std::vector<Node>& values) {
  for (const ast::TypeItem& item : t.items) {
    if (const auto* f = boost::get<ast::Format>(&item)) {
      ast::Format spec = *f;
      spec.code = static_cast<char>(std::toupper(static_cast<unsigned char>(spec.code)));
      // Widths and counts within the string limit, checked here: /I2000000000 wrote 2 GB at run
      // time before any limit applied.
      if (spec.width > kMaxStringLength || spec.decimals > kMaxStringLength)
        error(fmt::format("/{}{} is wider than {} characters", spec.code, std::max(spec.width, spec.decimals), kMaxStringLength));
      formats.push_back(spec);
    } else {
      formats.push_back(ast::Format{0, 0, 0});
      values.push_back(expression(boost::get<ast::Expr>(item)));
    }
  }
}
// A switch or parameter name (CP, HAND.TIME, ...) as an upper-case string node.
Node ExpressionCompiler::setting_name(const ast::VarRef& v) {
  Node n;
  n.kind = NodeKind::string;
  for (char c : v.name) n.text += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return n;
}

}  // namespace asimov::interpreter
