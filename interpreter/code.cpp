#include "interpreter/code.hpp"

namespace asimov::val {

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
    case NodeKind::binary: {
      if (n.op == ast::Op::compound) return StaticKind::unknown;
      if (n.op != ast::Op::add) return StaticKind::real;
      const StaticKind a = static_kind(n.kids[0]), b = static_kind(n.kids[1]);
      return a == b ? a : StaticKind::unknown;
    }
    case NodeKind::absent: break;
  }
  return StaticKind::unknown;
}

}  // namespace asimov::val
