#include "code.hpp"

#include <iterator>

namespace asimov::interpreter {
namespace {

using ast::Kw;
using namespace word_flag;

enum Path : bool { joint = false, straight = true };

constexpr SimpleForm kSimpleForms[] = {
#define ASIMOV_MOTION(kw, spelling, min, max, path, what) {Kw::kw, Code::kw, min, max, what},
#define ASIMOV_SIMPLE(kw, spelling, code, min, max, flags, what) {Kw::kw, Code::code, min, max, what},
#include "instructions.def"
};

constexpr Word kWords[] = {
#define ASIMOV_MOTION(kw, spelling, ...) {spelling, Kw::kw, do_ok, true},
#define ASIMOV_SIMPLE(kw, spelling, code, min, max, flags, what) {spelling, Kw::kw, flags, true},
#define ASIMOV_STATEMENT(kw, spelling, flags) {spelling, Kw::kw, flags, true},
#define ASIMOV_ALIAS(kw, spelling, flags) {spelling, Kw::kw, flags, true},
#define ASIMOV_WORD(kw, spelling, flags) {spelling, Kw::kw, flags, false},
#define ASIMOV_SPELLING(spelling, flags) {spelling, Kw::none, flags, false},
#include "instructions.def"
};

// Indexed by Code: the motions' paths (false for every other code).
constexpr bool kStraight[] = {
#define ASIMOV_MOTION(kw, spelling, min, max, path, what) path,
#define ASIMOV_CODE(code) false,
#include "instructions.def"
};

// Every Kw but none and assign has exactly one row; every Code one entry.
constexpr std::size_t kKeywordRows = 0
#define ASIMOV_MOTION(...) +1
#define ASIMOV_SIMPLE(...) +1
#define ASIMOV_STATEMENT(...) +1
#define ASIMOV_WORD(...) +1
#include "instructions.def"
    ;
static_assert(kKeywordRows + 2 == static_cast<std::size_t>(Kw::count));
constexpr std::size_t kCodes = 0
#define ASIMOV_MOTION(...) +1
#define ASIMOV_CODE(...) +1
#include "instructions.def"
    ;
static_assert(std::size(kStraight) == kCodes && kCodes <= 256);  // Code is an unsigned char
static_assert(std::size(kSimpleForms) <= kKeywordRows);
static_assert(std::size(kWords) > kKeywordRows);

}  // namespace

const SimpleForm* simple_form(ast::Kw kw) {
  for (const SimpleForm& f : kSimpleForms)
    if (f.kw == kw) return &f;
  return nullptr;
}

std::span<const Word> words() { return kWords; }

bool straight_path(Code code) { return kStraight[static_cast<std::size_t>(code)]; }

void mark_plain(Node& n) {
  bool plain = n.kind == NodeKind::number || n.kind == NodeKind::variable
      || n.kind == NodeKind::unary || (n.kind == NodeKind::chain && n.ops[0] != ast::Op::compound);  // ':' is a level of its own
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
    case NodeKind::chain: {
      // The fold of binary_kind over the chain, from its last operator that is not '+' (an
      // operator other than '+' decides alone), so only the operands after it are looked at;
      // once unknown, always unknown.
      std::size_t i = n.ops.size();
      while (i > 0 && n.ops[i - 1] == ast::Op::add) --i;
      StaticKind k = i > 0 ? binary_kind(n.ops[i - 1], StaticKind::unknown, StaticKind::unknown) : static_kind(n.kids[0]);
      for (; i < n.ops.size() && k != StaticKind::unknown; ++i) k = binary_kind(ast::Op::add, k, static_kind(n.kids[i + 1]));
      return k;
    }
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
