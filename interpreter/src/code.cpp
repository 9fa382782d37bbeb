#include "code.hpp"

#include <array>

namespace asimov::interpreter {
namespace {

using ast::Kw;

constexpr std::array<SimpleForm, 29> kSimpleForms = {{
    {Kw::tool, Code::tool, 0, 1, "TOOL"}, {Kw::signal, Code::signal, 1, -1, "SIGNAL"},
    {Kw::base, Code::base, 1, 4, "BASE"}, {Kw::ready, Code::ready, 0, 0, "READY"},
    {Kw::draw, Code::draw, 1, 3, "DRAW"}, {Kw::align, Code::align, 0, 0, "ALIGN"},
    {Kw::drive, Code::drive, 3, 3, "DRIVE"}, {Kw::move, Code::move, 1, 1, "the motion instruction"},
    {Kw::moves, Code::moves, 1, 1, "the motion instruction"}, {Kw::depart, Code::depart, 1, 1, "the motion instruction"},
    {Kw::departs, Code::departs, 1, 1, "the motion instruction"}, {Kw::appro, Code::appro, 2, 2, "APPRO"},
    {Kw::appros, Code::appros, 2, 2, "APPRO"}, {Kw::break_, Code::break_, 0, 0, "BREAK"},
    {Kw::return_, Code::return_, 0, 0, "RETURN"}, {Kw::stop, Code::stop, 0, 0, "STOP"},
    {Kw::pause, Code::pause, 0, 0, "PAUSE"}, {Kw::halt, Code::halt, 0, 0, "HALT"},
    {Kw::movet, Code::movet, 2, 2, "MOVET"}, {Kw::movest, Code::movest, 2, 2, "MOVEST"},
    {Kw::wait, Code::wait, 0, 1, "WAIT"}, {Kw::wait_event, Code::wait_event, 2, 2, "WAIT.EVENT"},
    {Kw::open, Code::hand, 0, 0, "OPEN"}, {Kw::close, Code::hand, 0, 0, "CLOSE"},
    {Kw::relax, Code::hand, 0, 0, "RELAX"}, {Kw::openi, Code::hand, 0, 0, "OPENI"},
    {Kw::closei, Code::hand, 0, 0, "CLOSEI"}, {Kw::relaxi, Code::hand, 0, 0, "RELAXI"},
    {Kw::duration, Code::duration, 1, 1, "DURATION"},
}};

}  // namespace

const SimpleForm* simple_form(ast::Kw kw) {
  for (const SimpleForm& f : kSimpleForms)
    if (f.kw == kw) return &f;
  return nullptr;
}

void mark_plain(Node& n) {
  bool plain = n.kind == NodeKind::number || n.kind == NodeKind::variable
      || n.kind == NodeKind::unary || (n.kind == NodeKind::binary && n.op != ast::Op::compound);
  if (n.kind == NodeKind::variable && n.subscripted && n.kids.empty()) plain = false;  // a[]
  for (Node& k : n.kids) {
    mark_plain(k);
    plain = plain && k.plain;
  }
  n.plain = plain;
}

StaticKind static_kind(const Node& n) {
  switch (n.kind) {
    case NodeKind::number: case NodeKind::unary: return StaticKind::real;
    case NodeKind::string: case NodeKind::encode: return StaticKind::string;
    case NodeKind::variable: return n.text[0] == '$' ? StaticKind::string : StaticKind::unknown;
    case NodeKind::function: {
      if (n.text.empty()) return StaticKind::unknown;
      if (n.text[0] == '$') return StaticKind::string;
      if (n.text[0] == '#') return StaticKind::unknown;
      switch (n.func) {
        case Func::here: case Func::dest: case Func::null: case Func::trans: case Func::inverse:
        case Func::rx: case Func::ry: case Func::rz: case Func::shift: case Func::tool: case Func::base:
          return StaticKind::unknown;
        default: return StaticKind::real;
      }
    }
    case NodeKind::binary:
      if (n.op != ast::Op::add) return binary_kind(n.op, StaticKind::unknown, StaticKind::unknown);
      return binary_kind(n.op, static_kind(n.kids[0]), static_kind(n.kids[1]));
    case NodeKind::absent: break;
  }
  return StaticKind::unknown;
}

StaticKind binary_kind(ast::Op op, StaticKind a, StaticKind b) {
  if (op == ast::Op::compound) return StaticKind::unknown;
  if (op != ast::Op::add) return StaticKind::real;
  return a == b ? a : StaticKind::unknown;
}

void locate_at(Diagnostic& d, const Program& p, int line) {
  d.program = p.name;
  d.file = p.file;
  d.line = line;
  d.step = line - p.line;
  if (line >= 1 && static_cast<std::size_t>(line) <= p.text->size())
    d.source_line = (*p.text)[static_cast<std::size_t>(line - 1)];
}

}  // namespace asimov::interpreter
