// xacro -> URDF text, on the tinyxml2 DOM, as ROS xacro evaluates it: properties are stored
// unevaluated and evaluated on first use (so a property may name one defined after it), macros
// expand in a scope holding their parameters over the caller's (xacro's dynamic scoping),
// ${} is a Python expression subset with numbers, strings, lists and dicts (load_yaml).
#include "xacro.hpp"

#include "asimov/collision/text_file.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include <tinyxml2.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>
#include <string_view>
#include <vector>

namespace asimov::robots {
namespace {
using tinyxml2::XMLDocument;
using tinyxml2::XMLElement;
using tinyxml2::XMLNode;
namespace fs = std::filesystem;

// Nesting of YAML documents, expressions and lists: far above real descriptions, and a bound on
// the recursion of the readers below.
constexpr int kMaxNesting = 200;

struct Value;
using List = std::vector<Value>;
using Dict = std::vector<std::pair<std::string, Value>>;  // insertion order, as Python's dict

// A namespace of an include with ns= (its properties as name.property).
using Lookup = std::function<std::optional<Value>(const std::string&)>;

struct Value {
  enum Kind { none, number, text, boolean, list, dict, ns } kind = number;
  double num = 0;
  bool integer = false;
  std::string str;
  std::shared_ptr<const List> items;    // list (a tuple when `tuple`)
  std::shared_ptr<const Dict> entries;  // dict
  bool tuple = false;
  std::shared_ptr<const Lookup> lookup;  // ns
};

Value number_value(double d, bool integer = false) {
  Value v;
  v.num = d;
  v.integer = integer;
  return v;
}
Value text_value(std::string s) {
  Value v;
  v.kind = Value::text;
  v.str = std::move(s);
  return v;
}
Value bool_value(bool b) {
  Value v;
  v.kind = Value::boolean;
  v.num = b ? 1.0 : 0.0;
  return v;
}
Value none_value() {
  Value v;
  v.kind = Value::none;
  return v;
}
Value list_value(List items, bool tuple = false) {
  Value v;
  v.kind = Value::list;
  v.items = std::make_shared<const List>(std::move(items));
  v.tuple = tuple;
  return v;
}
Value dict_value(Dict entries) {
  Value v;
  v.kind = Value::dict;
  v.entries = std::make_shared<const Dict>(std::move(entries));
  return v;
}

// Items a comprehension, a generator or a list builtin may produce: far above real
// descriptions, and a bound on what ${[0 for i in range(10**9)]} would allocate.
constexpr std::size_t kMaxItems = 1u << 20;

std::string format(const Value& v);

std::string repr(const Value& v) {
  if (v.kind != Value::text) return format(v);
  std::string out = "'";
  for (char c : v.str) out += c == '\'' ? std::string("\\'") : std::string(1, c);
  return out + "'";
}

// str() of a value, as xacro writes it into the document.
std::string format(const Value& v) {
  switch (v.kind) {
    case Value::text: return v.str;
    case Value::none: return "None";
    case Value::boolean: return v.num != 0 ? "True" : "False";
    case Value::list: {
      std::string out = v.tuple ? "(" : "[";
      for (std::size_t i = 0; i < v.items->size(); ++i) out += (i ? ", " : "") + repr((*v.items)[i]);
      if (v.tuple && v.items->size() == 1) out += ",";
      return out + (v.tuple ? ")" : "]");
    }
    case Value::ns: return "<namespace>";
    case Value::dict: {
      std::string out = "{";
      for (std::size_t i = 0; i < v.entries->size(); ++i)
        out += (i ? ", '" : "'") + (*v.entries)[i].first + "': " + repr((*v.entries)[i].second);
      return out + "}";
    }
    case Value::number: break;
  }
  if (v.integer && std::abs(v.num) < 1e15) return std::to_string(static_cast<long long>(v.num));
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v.num);  // shortest round trip
  std::string s(buf, r.ptr);
  if (s.find_first_of(".eni") == std::string::npos) s += ".0";  // Python writes floats with a point
  return s;
}

// A text read back as a value, as xacro does for property texts: a number when it is one
// (integers stay integers), True/False, else the text.
Value from_text(const std::string& s) {
  const char* b = s.data();
  const char* e = b + s.size();
  while (b < e && *b == ' ') ++b;
  while (e > b && e[-1] == ' ') --e;
  double d = 0;
  auto r = std::from_chars(b, e, d);
  if (b != e && r.ec == std::errc() && r.ptr == e && std::isfinite(d))
    return number_value(d, std::none_of(b, e, [](char c) { return c == '.' || c == 'e' || c == 'E'; }));
  if (s == "True" || s == "true") return bool_value(true);
  if (s == "False" || s == "false") return bool_value(false);
  return text_value(s);
}

// A YAML document as xacro.load_yaml gives it: maps are dicts, sequences lists, scalars numbers,
// booleans (true/false, True/False), null or text.
// Angles tagged `!radians EXPR` / `!degrees EXPR` (ros/xacro since 1.14.5; ur_description's
// joint_limits.yaml) are Python expressions evaluated by `angle`, a number in radians.
using YamlAngle = std::function<double(const std::string& expr, bool degrees)>;

Value from_yaml(const YAML::Node& n, int depth, const std::function<void(const std::string&)>& fail, const YamlAngle& angle) {
  if (depth > kMaxNesting) fail("load_yaml: nested more than " + std::to_string(kMaxNesting) + " levels");
  if (n.Tag() == "!radians" || n.Tag() == "!degrees") {
    if (!n.IsScalar()) fail("load_yaml: " + n.Tag() + " tags a number or an expression, not a " + (n.IsMap() ? "map" : "list"));
    return number_value(angle(n.Scalar(), n.Tag() == "!degrees"));
  }
  if (n.IsMap()) {
    auto d = std::make_shared<Dict>();
    for (const auto& kv : n) d->emplace_back(kv.first.Scalar(), from_yaml(kv.second, depth + 1, fail, angle));
    Value v;
    v.kind = Value::dict;
    v.entries = std::move(d);
    return v;
  }
  if (n.IsSequence()) {
    auto l = std::make_shared<List>();
    for (const auto& item : n) l->push_back(from_yaml(item, depth + 1, fail, angle));
    Value v;
    v.kind = Value::list;
    v.items = std::move(l);
    return v;
  }
  if (n.IsNull()) return none_value();
  const std::string& s = n.Scalar();
  if (n.Tag() == "!") return text_value(s);  // quoted in the file
  if (s == "true" || s == "True" || s == "TRUE") return bool_value(true);
  if (s == "false" || s == "False" || s == "FALSE") return bool_value(false);
  Value v = from_text(s);
  if (v.kind == Value::boolean) return text_value(s);
  return v;
}

struct Macro {
  const XMLElement* def = nullptr;
  std::string file;
  std::vector<std::string> params;  // "name", "name:=default", "name:=^", "name:=^|default", "*block", "**block"
};

// A property: its text, evaluated on first use in the scope it was defined in, or a value.
struct Prop {
  std::string text;
  std::optional<Value> value;
  std::string file;  // where it was defined, for messages
  int line = 0;
  bool busy = false;  // being evaluated: a property that needs itself
};

struct Scope {
  std::map<std::string, Prop> props;
  std::map<std::string, const XMLElement*> blocks;
  Scope* parent = nullptr;
  std::pair<Prop*, Scope*> find(const std::string& n) {
    for (Scope* s = this; s; s = s->parent)
      if (auto it = s->props.find(n); it != s->props.end()) return {&it->second, s};
    return {nullptr, nullptr};
  }
  const XMLElement* block(const std::string& n) const {
    for (const Scope* s = this; s; s = s->parent)
      if (auto it = s->blocks.find(n); it != s->blocks.end()) return it->second;
    return nullptr;
  }
};

// What an expression reaches outside itself: names and the functions that need the expander.
struct ExprContext {
  std::function<std::optional<Value>(const std::string&)> name;
  std::function<std::optional<Value>(const std::string&, const std::vector<Value>&)> call;  // nullopt: not such a function
  std::function<void(const std::string&)> fail;  // throws UrdfError
};

// Position of the `close` matching the `open` at text[start] (brackets nested, quotes skipped),
// or npos.
std::size_t matching(const std::string& text, std::size_t start, char open, char close) {
  int depth = 0;
  char quote = 0;
  for (std::size_t i = start; i < text.size(); ++i) {
    const char c = text[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '\'' || c == '"') {
      quote = c;
    } else if (c == open) {
      ++depth;
    } else if (c == close && --depth == 0) {
      return i;
    }
  }
  return std::string::npos;
}

// Recursive descent over one ${...} expression (Python's grammar and precedence for the subset;
// docs/robots.md "xacro descriptions").
class Expr {
 public:
  Expr(const std::string& text, const ExprContext& cx, int depth = 0) : s_(text), cx_(cx), depth_(depth) {
    if (depth_ > kMaxNesting) die("expression nested too deeply");
  }
  Value run() {
    Value v = conditional();
    skip();
    if (i_ != s_.size()) die("unexpected '" + s_.substr(i_) + "' in ${" + s_ + "}");
    return v;
  }

 private:
  [[noreturn]] void die(const std::string& m) const {
    cx_.fail(m);  // throws UrdfError
    throw std::logic_error(m);
  }
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool word(const char* w) {
    skip();
    const std::size_t n = std::strlen(w);
    if (s_.compare(i_, n, w) != 0) return false;
    if (i_ + n < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_ + n])) || s_[i_ + n] == '_')) return false;
    i_ += n;
    return true;
  }
  bool op(const char* o) {
    skip();
    const std::size_t n = std::strlen(o);
    if (s_.compare(i_, n, o) != 0) return false;
    if (n == 1 && (o[0] == '*' || o[0] == '/' || o[0] == '<' || o[0] == '>' || o[0] == '=') && i_ + 1 < s_.size() &&
        (s_[i_ + 1] == o[0] || s_[i_ + 1] == '='))
      return false;  // '**', '//', '<=', '==' are other operators
    i_ += n;
    return true;
  }
  double num(const Value& v, const char* what) {
    if (v.kind == Value::number || v.kind == Value::boolean) return v.num;
    die("'" + format(v) + "' is not a number (" + what + ") in ${" + s_ + "}");
  }
  static bool truth(const Value& v) {
    switch (v.kind) {
      case Value::text: return !v.str.empty();
      case Value::none: return false;
      case Value::list: return !v.items->empty();
      case Value::dict: return !v.entries->empty();
      default: return v.num != 0;
    }
  }

  // From `from`, the first position at bracket depth 0 outside quotes where `hit` holds
  // (closed false), or of a closing bracket without its opening one, or the end (closed true).
  struct Stop {
    std::size_t at;
    bool closed;
  };
  Stop scan_top(std::size_t from, const std::function<bool(std::size_t)>& hit) const {
    int depth = 0;
    char quote = 0;
    for (std::size_t k = from; k < s_.size(); ++k) {
      const char c = s_[k];
      if (quote) {
        if (c == quote) quote = 0;
      } else if (c == '\'' || c == '"') {
        quote = c;
      } else if (c == '(' || c == '[' || c == '{') {
        ++depth;
      } else if (c == ')' || c == ']' || c == '}') {
        if (depth-- == 0) return {k, true};
      } else if (depth == 0 && hit(k)) {
        return {k, false};
      }
    }
    return {s_.size(), true};
  }
  bool name_char(std::size_t k) const { return std::isalnum(static_cast<unsigned char>(s_[k])) || s_[k] == '_'; }
  // The depth-0 keyword `kw` from `from` (npos: none): the branches of `a if c else b` are cut
  // this way so that only the branch taken is evaluated, as Python does.
  std::size_t find_keyword(std::size_t from, const char* kw) const {
    const std::size_t n = std::strlen(kw);
    const Stop s = scan_top(from, [&](std::size_t k) {
      return s_.compare(k, n, kw) == 0 && (k == 0 || !name_char(k - 1)) && (k + n >= s_.size() || !name_char(k + n));
    });
    return s.closed ? std::string::npos : s.at;
  }
  // The end of the current operand: the first depth-0 ',' or ':' or the enclosing bracket.
  std::size_t operand_end(std::size_t from) const {
    return scan_top(from, [&](std::size_t k) { return s_[k] == ',' || s_[k] == ':'; }).at;
  }
  Value sub(std::size_t b, std::size_t e) { return Expr(s_.substr(b, e - b), cx_, depth_ + 1).run(); }

  // Every recursion of the grammar passes here or through unary() / negation(): one bound
  // on the nesting of brackets, calls, '-' and 'not' (a hostile ${[[[[...]]]]} ends here).
  struct Nest {
    Expr& x;
    explicit Nest(Expr& e) : x(e) {
      if (++x.nest_ > kMaxNesting) x.die("expression nested more than " + std::to_string(kMaxNesting) + " deep");
    }
    ~Nest() { --x.nest_; }
  };

  // a if c else b: c first, then the branch taken only.
  Value conditional() {
    const Nest guard(*this);
    skip();
    const std::size_t end = operand_end(i_);
    const std::size_t kif = find_keyword(i_, "if");
    if (kif == std::string::npos || kif >= end) return disjunction();
    const std::size_t kelse = find_keyword(kif + 2, "else");
    if (kelse == std::string::npos || kelse >= end) die("'if' without 'else' in ${" + s_ + "}");
    const bool c = truth(sub(kif + 2, kelse));
    const std::size_t a = i_;
    i_ = end;
    return c ? sub(a, kif) : sub(kelse + 4, end);
  }
  Value disjunction() {
    Value v = conjunction();
    while (word("or")) {
      Value r = conjunction();
      v = truth(v) ? v : r;
    }
    return v;
  }
  Value conjunction() {
    Value v = negation();
    while (word("and")) {
      Value r = negation();
      v = truth(v) ? r : v;
    }
    return v;
  }
  Value negation() {
    const Nest guard(*this);
    if (word("not")) return bool_value(!truth(negation()));
    return comparison();
  }
  static bool equal(const Value& a, const Value& b) {
    const bool an = a.kind == Value::number || a.kind == Value::boolean, bn = b.kind == Value::number || b.kind == Value::boolean;
    if (an && bn) return a.num == b.num;
    if (an != bn) return false;
    return format(a) == format(b);
  }
  bool contains(const Value& hay, const Value& needle) {
    if (hay.kind == Value::text) return hay.str.find(format(needle)) != std::string::npos;
    if (hay.kind == Value::list)
      return std::any_of(hay.items->begin(), hay.items->end(), [&](const Value& x) { return equal(x, needle); });
    if (hay.kind == Value::dict)
      return std::any_of(hay.entries->begin(), hay.entries->end(), [&](const auto& kv) { return kv.first == format(needle); });
    die("'in' needs a string, list or dict in ${" + s_ + "}");
  }
  Value comparison() {
    Value a = sum();
    for (;;) {
      if (word("in")) {
        a = bool_value(contains(sum(), a));
        continue;
      }
      if (word("not")) {
        if (!word("in")) die("'not' without 'in' in ${" + s_ + "}");
        a = bool_value(!contains(sum(), a));
        continue;
      }
      bool matched = false;
      for (const char* o : {"==", "!=", "<=", ">=", "<", ">"}) {
        if (!op(o)) continue;
        matched = true;
        Value b = sum();
        const std::string so = o;
        if (so == "==") a = bool_value(equal(a, b));
        else if (so == "!=") a = bool_value(!equal(a, b));
        else if (a.kind == Value::text && b.kind == Value::text)
          a = bool_value(so == "<=" ? a.str <= b.str : so == ">=" ? a.str >= b.str : so == "<" ? a.str < b.str : a.str > b.str);
        else {
          const double x = num(a, o), y = num(b, o);
          a = bool_value(so == "<=" ? x <= y : so == ">=" ? x >= y : so == "<" ? x < y : x > y);
        }
        break;
      }
      if (!matched) return a;
    }
  }
  Value sum() {
    Value v = product();
    for (;;) {
      if (op("+")) {
        Value r = product();
        if (v.kind == Value::text && r.kind == Value::text) {
          v.str += r.str;
        } else if (v.kind == Value::list && r.kind == Value::list) {
          auto l = std::make_shared<List>(*v.items);
          l->insert(l->end(), r.items->begin(), r.items->end());
          v.items = std::move(l);
        } else {
          v = number_value(num(v, "+") + num(r, "+"), v.integer && r.integer);
        }
      } else if (op("-")) {
        Value r = product();
        v = number_value(num(v, "-") - num(r, "-"), v.integer && r.integer);
      } else {
        return v;
      }
    }
  }
  Value product() {
    Value v = unary();
    for (;;) {
      if (op("*")) {
        Value r = unary();
        v = number_value(num(v, "*") * num(r, "*"), v.integer && r.integer);
      } else if (op("//")) {
        Value r = unary();
        const double d = num(r, "//");
        if (d == 0) die("division by zero in ${" + s_ + "}");
        v = number_value(std::floor(num(v, "//") / d), v.integer && r.integer);
      } else if (op("/")) {
        Value r = unary();
        const double d = num(r, "/");
        if (d == 0) die("division by zero in ${" + s_ + "}");
        v = number_value(num(v, "/") / d);
      } else if (op("%")) {
        Value r = unary();
        const double d = num(r, "%");
        if (d == 0) die("modulo by zero in ${" + s_ + "}");
        const double x = num(v, "%");
        v = number_value(x - d * std::floor(x / d), v.integer && r.integer);
      } else {
        return v;
      }
    }
  }
  Value unary() {
    const Nest guard(*this);
    if (op("-")) {
      Value v = unary();
      return number_value(-num(v, "-"), v.integer);
    }
    if (op("+")) {
      Value v = unary();
      return number_value(num(v, "+"), v.integer);
    }
    return power();
  }
  Value power() {
    Value v = postfix();
    if (op("**")) {
      Value r = unary();  // right associative, binds tighter than a unary minus on its left
      const double p = std::pow(num(v, "**"), num(r, "**"));
      if (!std::isfinite(p)) die("'**' gives no finite number in ${" + s_ + "}");
      return number_value(p, v.integer && r.integer && r.num >= 0);
    }
    return v;
  }
  // Indexing, slices and attributes: x[0], x[1:-1:2], x['key'], x.key (dicts from load_yaml
  // allow both), and methods of strings, lists and dicts: 'a'.upper(), d.items(), ...
  Value postfix() {
    Value v = primary();
    for (;;) {
      skip();
      if (i_ < s_.size() && s_[i_] == '[') {
        ++i_;
        skip();
        std::optional<Value> bound[3];
        if (i_ < s_.size() && s_[i_] != ':') bound[0] = conditional();
        if (op(":")) {  // a slice: [start:stop:step], each part optional
          skip();
          if (i_ < s_.size() && s_[i_] != ':' && s_[i_] != ']') bound[1] = conditional();
          if (op(":")) {
            skip();
            if (i_ < s_.size() && s_[i_] != ']') bound[2] = conditional();
          }
          if (!op("]")) die("missing ']' in ${" + s_ + "}");
          v = slice(v, bound);
          continue;
        }
        if (!bound[0]) die("empty index in ${" + s_ + "}");
        if (!op("]")) die("missing ']' in ${" + s_ + "}");
        v = index(v, *bound[0]);
      } else if (i_ + 1 < s_.size() && s_[i_] == '.' && (std::isalpha(static_cast<unsigned char>(s_[i_ + 1])) || s_[i_ + 1] == '_')) {
        ++i_;
        std::size_t j = i_;
        while (j < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[j])) || s_[j] == '_')) ++j;
        const std::string name = s_.substr(i_, j - i_);
        i_ = j;
        skip();
        if (i_ < s_.size() && s_[i_] == '(' && v.kind != Value::ns && is_method(v, name)) {
          std::vector<Value> args;
          Dict keywords;
          arguments(name, args, keywords);
          v = method(v, name, args, keywords);
        } else {
          v = attribute(v, name);
        }
      } else {
        return v;
      }
    }
  }
  // Python's slice of a list, tuple or string (negative and omitted bounds, any step but 0).
  Value slice(const Value& v, const std::optional<Value> (&b)[3]) {
    if (v.kind != Value::list && v.kind != Value::text) die("'" + format(v) + "' cannot be sliced in ${" + s_ + "}");
    const long long n = v.kind == Value::list ? static_cast<long long>(v.items->size()) : static_cast<long long>(v.str.size());
    auto whole = [&](const std::optional<Value>& x, const char* what) -> std::optional<long long> {
      if (!x || x->kind == Value::none) return std::nullopt;
      if (x->kind != Value::number || !x->integer) die(std::string("a slice ") + what + " must be an integer in ${" + s_ + "}");
      return static_cast<long long>(std::clamp(x->num, -9e15, 9e15));
    };
    const long long step = whole(b[2], "step").value_or(1);
    if (step == 0) die("slice step cannot be zero in ${" + s_ + "}");
    auto at = [&](std::optional<long long> x, long long dflt) {
      if (!x) return dflt;
      long long k = *x < 0 ? *x + n : *x;
      return step > 0 ? std::clamp(k, 0LL, n) : std::clamp(k, -1LL, n - 1);
    };
    const long long start = at(whole(b[0], "start"), step > 0 ? 0 : n - 1), stop = at(whole(b[1], "stop"), step > 0 ? n : -1);
    List items;
    std::string text;
    for (long long k = start; step > 0 ? k < stop : k > stop; k += step) {
      if (v.kind == Value::list) items.push_back((*v.items)[static_cast<std::size_t>(k)]);
      else text += v.str[static_cast<std::size_t>(k)];
    }
    return v.kind == Value::list ? list_value(std::move(items), v.tuple) : text_value(std::move(text));
  }
  Value index(const Value& v, const Value& k) {
    if (v.kind == Value::dict) {
      const std::string key = format(k);
      for (const auto& [name, x] : *v.entries)
        if (name == key) return x;
      die("no key '" + key + "' in ${" + s_ + "}");
    }
    if (v.kind == Value::list || v.kind == Value::text) {
      if (k.kind != Value::number || !k.integer) die("a list index must be an integer in ${" + s_ + "}");
      const long long n = v.kind == Value::list ? static_cast<long long>(v.items->size()) : static_cast<long long>(v.str.size());
      long long i = static_cast<long long>(k.num);
      if (i < 0) i += n;
      if (i < 0 || i >= n) die("index " + format(k) + " out of range in ${" + s_ + "}");
      return v.kind == Value::list ? (*v.items)[static_cast<std::size_t>(i)] : text_value(std::string(1, v.str[static_cast<std::size_t>(i)]));
    }
    die("'" + format(v) + "' cannot be indexed in ${" + s_ + "}");
  }
  Value attribute(const Value& v, const std::string& name) {
    if (v.kind == Value::ns) {
      if (auto x = (*v.lookup)(name)) return *x;
      die("no property '" + name + "' in the namespace in ${" + s_ + "}");
    }
    if (v.kind != Value::dict) die("'" + format(v) + "' has no attribute '" + name + "' in ${" + s_ + "}");
    for (const auto& [key, x] : *v.entries)
      if (key == name) return x;
    die("no key '" + name + "' in ${" + s_ + "}");
  }
  Value primary() {
    skip();
    if (i_ >= s_.size()) die("incomplete expression ${" + s_ + "}");
    const char c = s_[i_];
    if (c == '(') {
      const std::size_t close = matching(s_, i_, '(', ')');
      if (close == std::string::npos) die("missing ')' in ${" + s_ + "}");
      ++i_;
      Value v;
      if (const std::size_t kfor = find_keyword(i_, "for"); kfor < close) {
        v = comprehension(i_, kfor, close, false);  // a generator: its items
      } else if (scan_top(i_, [&](std::size_t k) { return s_[k] == ','; }).at < close) {
        v = sequence(close, true);  // a tuple
      } else {
        skip();
        v = i_ == close ? list_value({}, true) : sub(i_, close);
      }
      i_ = close + 1;
      return v;
    }
    if (c == '[') return list_literal();
    if (c == '{') return dict_literal();
    if (c == '\'' || c == '"') {
      const std::size_t end = s_.find(c, i_ + 1);
      if (end == std::string::npos) die("unterminated string in ${" + s_ + "}");
      Value v = text_value(s_.substr(i_ + 1, end - i_ - 1));
      i_ = end + 1;
      return v;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      double d = 0;
      auto r = std::from_chars(s_.data() + i_, s_.data() + s_.size(), d);
      if (r.ec != std::errc() || !std::isfinite(d)) die("bad number in ${" + s_ + "}");
      const char* begin = s_.data() + i_;
      const bool integer = std::none_of(begin, r.ptr, [](char ch) { return ch == '.' || ch == 'e' || ch == 'E'; });
      i_ = static_cast<std::size_t>(r.ptr - s_.data());
      return number_value(d, integer);
    }
    if (!(std::isalpha(static_cast<unsigned char>(c)) || c == '_')) die(std::string("unexpected '") + c + "' in ${" + s_ + "}");
    std::size_t j = i_;
    while (j < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[j])) || s_[j] == '_')) ++j;
    std::string name = s_.substr(i_, j - i_);
    i_ = j;
    // math.x and xacro.x are namespaces of functions and constants, not properties.
    for (const char* ns : {"math", "xacro", "python"})
      if (name == ns && i_ < s_.size() && s_[i_] == '.') {
        std::size_t k = ++i_;
        while (k < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[k])) || s_[k] == '_')) ++k;
        name = s_.substr(i_, k - i_);
        i_ = k;
        // ros/xacro's own helpers exist under xacro. only (a property may be called arg).
        if (std::string_view(ns) == "xacro" && (name == "arg" || name == "abs_filename" || name == "dotify" || name == "error"))
          name = "xacro." + name;
      }
    skip();
    if (i_ < s_.size() && s_[i_] == '(') return call(name);
    if (name == "pi") return number_value(std::numbers::pi);
    if (name == "e") return number_value(std::numbers::e);
    if (name == "inf") return number_value(std::numeric_limits<double>::infinity());
    if (name == "True" || name == "true") return bool_value(true);
    if (name == "False" || name == "false") return bool_value(false);
    if (name == "None") return none_value();
    if (auto v = cx_.name(name)) return *v;
    die("unknown property '" + name + "' in ${" + s_ + "}");
  }
  Value list_literal() {
    const std::size_t close = matching(s_, i_, '[', ']');
    if (close == std::string::npos) die("missing ']' in ${" + s_ + "}");
    ++i_;
    Value v;
    if (const std::size_t kfor = find_keyword(i_, "for"); kfor < close) v = comprehension(i_, kfor, close, false);
    else v = sequence(close, false);
    i_ = close + 1;
    return v;
  }
  // Comma-separated items up to `close` (a list or a tuple's).
  Value sequence(std::size_t close, bool tuple) {
    List l;
    skip();
    while (i_ < close) {
      l.push_back(conditional());
      skip();
      if (i_ < close && !op(",")) die(std::string("expected ',' in the ") + (tuple ? "tuple" : "list") + " in ${" + s_ + "}");
      skip();
    }
    return list_value(std::move(l), tuple);
  }
  // The items a `for` runs over: a list or tuple's items, a string's characters, a dict's keys.
  List iterate(const Value& v) {
    if (v.kind == Value::list) return *v.items;
    List out;
    if (v.kind == Value::text)
      for (char ch : v.str) out.push_back(text_value(std::string(1, ch)));
    else if (v.kind == Value::dict)
      for (const auto& kv : *v.entries) out.push_back(from_text_key(kv.first));
    else
      die("'" + format(v) + "' is not iterable in ${" + s_ + "}");
    return out;
  }
  static Value from_text_key(const std::string& k) { return text_value(k); }
  // [element for a, b in iterable if condition ...] over s_[b, e) (the element is s_[b, kfor)),
  // a dict {k: v for ...} when `dict`: each element and condition evaluated with the loop names
  // bound over the surrounding names, as Python does. One `for` clause (a nested one is refused).
  Value comprehension(std::size_t b, std::size_t kfor, std::size_t e, bool dict) {
    const std::size_t kin = find_keyword(kfor + 3, "in");
    if (kin >= e) die("'for' without 'in' in ${" + s_ + "}");
    if (find_keyword(kin + 2, "for") < e) die("nested 'for' clauses are not supported in ${" + s_ + "}");
    std::vector<std::string> names;
    {
      std::string t = s_.substr(kfor + 3, kin - kfor - 3);
      std::erase_if(t, [](char ch) { return ch == '(' || ch == ')'; });
      std::stringstream parts(t);
      for (std::string n; std::getline(parts, n, ',');) {
        n.erase(0, n.find_first_not_of(" \t"));
        n.erase(n.find_last_not_of(" \t") + 1);
        if (n.empty() || !(std::isalpha(static_cast<unsigned char>(n[0])) || n[0] == '_') ||
            !std::all_of(n.begin(), n.end(), [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'; }))
          die("bad loop variable '" + n + "' in ${" + s_ + "}");
        names.push_back(n);
      }
    }
    std::vector<std::pair<std::size_t, std::size_t>> conditions;  // s_ ranges of the `if` clauses
    std::size_t iter_end = e;
    for (std::size_t from = kin + 2;;) {
      const std::size_t kif = find_keyword(from, "if");
      if (kif >= e) break;
      if (conditions.empty()) iter_end = kif;
      else conditions.back().second = kif;
      conditions.emplace_back(kif + 2, e);
      from = kif + 2;
    }
    const List items = iterate(sub(kin + 2, iter_end));
    if (items.size() > kMaxItems) die("more than " + std::to_string(kMaxItems) + " items in ${" + s_ + "}");
    std::map<std::string, Value> bound;
    ExprContext inner;
    inner.fail = cx_.fail;
    inner.call = cx_.call;
    inner.name = [&](const std::string& n) -> std::optional<Value> {
      if (auto it = bound.find(n); it != bound.end()) return it->second;
      return cx_.name(n);
    };
    auto eval = [&](std::size_t from, std::size_t to) { return Expr(s_.substr(from, to - from), inner, depth_ + 1).run(); };
    std::size_t colon = 0;
    if (dict) {
      colon = scan_top(b, [&](std::size_t k) { return s_[k] == ':'; }).at;
      if (colon >= kfor) die("a dict comprehension needs 'key: value' in ${" + s_ + "}");
    }
    List out;
    Dict entries;
    for (const Value& item : items) {
      if (names.size() == 1) {
        bound[names[0]] = item;
      } else {
        if (item.kind != Value::list || item.items->size() != names.size())
          die("cannot unpack '" + format(item) + "' into " + std::to_string(names.size()) + " names in ${" + s_ + "}");
        for (std::size_t k = 0; k < names.size(); ++k) bound[names[k]] = (*item.items)[k];
      }
      if (!std::all_of(conditions.begin(), conditions.end(), [&](const auto& c) { return truth(eval(c.first, c.second)); })) continue;
      if (dict) entries.emplace_back(format(eval(b, colon)), eval(colon + 1, kfor));
      else out.push_back(eval(b, kfor));
    }
    return dict ? dict_value(std::move(entries)) : list_value(std::move(out));
  }
  Value dict_literal() {
    const std::size_t close = matching(s_, i_, '{', '}');
    if (close == std::string::npos) die("missing '}' in ${" + s_ + "}");
    ++i_;
    if (const std::size_t kfor = find_keyword(i_, "for"); kfor < close) {
      Value v = comprehension(i_, kfor, close, true);
      i_ = close + 1;
      return v;
    }
    auto d = std::make_shared<Dict>();
    skip();
    while (i_ < close) {
      const Value k = conditional();
      if (!op(":")) die("expected ':' in the dict in ${" + s_ + "}");
      d->emplace_back(format(k), conditional());
      skip();
      if (i_ < close && !op(",")) die("expected ',' in the dict in ${" + s_ + "}");
      skip();
    }
    i_ = close + 1;
    Value v;
    v.kind = Value::dict;
    v.entries = std::move(d);
    return v;
  }
  Value call(const std::string& name) {
    std::vector<Value> args;
    Dict keywords;  // dict(a=1, b=2)
    arguments(name, args, keywords);
    if (!keywords.empty() && name != "dict") die(name + "() takes no keyword arguments in ${" + s_ + "}");
    return apply(name, args, std::make_shared<Dict>(std::move(keywords)));
  }
  // The arguments of a call at s_[i_] == '(': positional ones, keyword ones, or one generator
  // (f(x for x in l)) as a list.
  void arguments(const std::string& name, std::vector<Value>& args, Dict& kw) {
    const std::size_t close = matching(s_, i_, '(', ')');
    if (close == std::string::npos) die("missing ')' after the arguments of " + name + "() in ${" + s_ + "}");
    ++i_;
    Dict* keywords = &kw;
    if (const std::size_t kfor = find_keyword(i_, "for"); kfor < close) {
      args.push_back(comprehension(i_, kfor, close, false));
      i_ = close + 1;
      return;
    }
    skip();
    while (i_ < close) {
      std::size_t j = i_;
      while (j < close && (std::isalnum(static_cast<unsigned char>(s_[j])) || s_[j] == '_')) ++j;
      std::size_t k = j;
      while (k < close && s_[k] == ' ') ++k;
      if (j > i_ && k < close && s_[k] == '=' && (k + 1 >= s_.size() || s_[k + 1] != '=')) {
        const std::string key = s_.substr(i_, j - i_);
        i_ = k + 1;
        keywords->emplace_back(key, conditional());
      } else {
        args.push_back(conditional());
      }
      skip();
      if (i_ < close && !op(",")) die("expected ',' between the arguments of " + name + "() in ${" + s_ + "}");
      skip();
    }
    i_ = close + 1;
  }
  Value apply(const std::string& name, const std::vector<Value>& args, const std::shared_ptr<Dict>& keywords) {
    auto one = [&](const char* what) {
      if (args.size() != 1) die(name + "() takes one argument in ${" + s_ + "}");
      return num(args[0], what);
    };
    auto checked = [&](double v) {
      if (!std::isfinite(v)) die(name + "() gives no finite number in ${" + s_ + "}");
      return number_value(v);
    };
    if (name == "dict") {
      if (!args.empty()) die("dict() takes keyword arguments only in ${" + s_ + "}");
      Value v;
      v.kind = Value::dict;
      v.entries = keywords;
      return v;
    }
    if (name == "radians") return number_value(one("radians") * std::numbers::pi / 180);
    if (name == "degrees") return number_value(one("degrees") * 180 / std::numbers::pi);
    if (name == "sin") return number_value(std::sin(one("sin")));
    if (name == "cos") return number_value(std::cos(one("cos")));
    if (name == "tan") return checked(std::tan(one("tan")));
    if (name == "asin") return checked(std::asin(one("asin")));
    if (name == "acos") return checked(std::acos(one("acos")));
    if (name == "atan") return number_value(std::atan(one("atan")));
    if (name == "sqrt") return checked(std::sqrt(one("sqrt")));
    if (name == "abs" || name == "fabs") {
      const double v = one("abs");
      return number_value(std::abs(v), args[0].integer && name == "abs");
    }
    if (name == "floor") return number_value(std::floor(one("floor")), true);
    if (name == "ceil") return number_value(std::ceil(one("ceil")), true);
    if (name == "int") {
      if (args.size() == 1 && args[0].kind == Value::text) {
        const Value v = from_text(args[0].str);
        if (v.kind != Value::number) die("int('" + args[0].str + "'): not a number in ${" + s_ + "}");
        return number_value(std::trunc(v.num), true);
      }
      return number_value(std::trunc(one("int")), true);
    }
    if (name == "float") {
      if (args.size() == 1 && args[0].kind == Value::text) {
        const Value v = from_text(args[0].str);
        if (v.kind != Value::number) die("float('" + args[0].str + "'): not a number in ${" + s_ + "}");
        return number_value(v.num);
      }
      return number_value(one("float"));
    }
    if (name == "round") return number_value(std::nearbyint(one("round")), true);
    if (name == "str") {
      if (args.size() != 1) die("str() takes one argument in ${" + s_ + "}");
      return text_value(format(args[0]));
    }
    if (name == "bool") {
      if (args.size() != 1) die("bool() takes one argument in ${" + s_ + "}");
      return bool_value(truth(args[0]));
    }
    if (name == "len") {
      if (args.size() != 1) die("len() takes one argument in ${" + s_ + "}");
      const Value& a = args[0];
      if (a.kind == Value::text) return number_value(static_cast<double>(a.str.size()), true);
      if (a.kind == Value::list) return number_value(static_cast<double>(a.items->size()), true);
      if (a.kind == Value::dict) return number_value(static_cast<double>(a.entries->size()), true);
      die("len() of a number in ${" + s_ + "}");
    }
    if (auto v = sequence_builtin(name, args)) return *v;
    if (name == "atan2" || name == "pow" || name == "min" || name == "max" || name == "copysign" || name == "fmod") {
      if (args.size() != 2) die(name + "() takes two arguments in ${" + s_ + "}");
      const double a = num(args[0], name.c_str()), b = num(args[1], name.c_str());
      if (name == "atan2") return number_value(std::atan2(a, b));
      if (name == "pow") return checked(std::pow(a, b));
      if (name == "copysign") return number_value(std::copysign(a, b));
      if (name == "fmod") return checked(std::fmod(a, b));
      const bool integer = args[0].integer && args[1].integer;
      return number_value(name == "min" ? std::min(a, b) : std::max(a, b), integer);
    }
    if (auto v = cx_.call(name, args)) return *v;
    die("unsupported function " + name + "() in ${" + s_ + "}");
  }

  static bool is_number(const Value& v) { return v.kind == Value::number || v.kind == Value::boolean; }
  bool less(const Value& a, const Value& b) {
    if (is_number(a) && is_number(b)) return a.num < b.num;
    if (a.kind == Value::text && b.kind == Value::text) return a.str < b.str;
    die("cannot order '" + format(a) + "' and '" + format(b) + "' in ${" + s_ + "}");
  }
  List checked_items(const Value& v) {
    List items = iterate(v);
    if (items.size() > kMaxItems) die("more than " + std::to_string(kMaxItems) + " items in ${" + s_ + "}");
    return items;
  }
  // Python builtins over sequences (xacro exposes them, some under python.): list, tuple,
  // sorted, reversed, sum, any, all, range, enumerate, zip, and min / max of one iterable.
  std::optional<Value> sequence_builtin(const std::string& name, const std::vector<Value>& args) {
    auto one = [&]() -> const Value& {
      if (args.size() != 1) die(name + "() takes one argument in ${" + s_ + "}");
      return args[0];
    };
    if (name == "list" || name == "tuple") {
      if (args.empty()) return list_value({}, name == "tuple");
      return list_value(checked_items(one()), name == "tuple");
    }
    if (name == "sorted") {
      List items = checked_items(one());
      std::stable_sort(items.begin(), items.end(), [&](const Value& a, const Value& b) { return less(a, b); });
      return list_value(std::move(items));
    }
    if (name == "reversed") {
      List items = checked_items(one());
      std::reverse(items.begin(), items.end());
      return list_value(std::move(items));
    }
    if (name == "sum") {
      double total = 0;
      bool integer = true;
      for (const Value& x : checked_items(one())) total += num(x, "sum"), integer = integer && x.integer;
      return number_value(total, integer);
    }
    if (name == "any" || name == "all") {
      const List items = checked_items(one());
      const bool any = std::any_of(items.begin(), items.end(), [](const Value& x) { return truth(x); });
      const bool all = std::all_of(items.begin(), items.end(), [](const Value& x) { return truth(x); });
      return bool_value(name == "any" ? any : all);
    }
    if ((name == "min" || name == "max") && args.size() == 1) {
      const List items = checked_items(args[0]);
      if (items.empty()) die(name + "() of an empty sequence in ${" + s_ + "}");
      Value best = items[0];
      for (const Value& x : items)
        if (name == "min" ? less(x, best) : less(best, x)) best = x;
      return best;
    }
    if (name == "range") {
      if (args.empty() || args.size() > 3) die("range() takes 1 to 3 arguments in ${" + s_ + "}");
      long long r[3] = {0, 0, 1};
      for (std::size_t k = 0; k < args.size(); ++k) {
        if (args[k].kind != Value::number || !args[k].integer) die("range() takes integers in ${" + s_ + "}");
        r[args.size() == 1 ? 1 : k] = static_cast<long long>(std::clamp(args[k].num, -9e15, 9e15));
      }
      if (r[2] == 0) die("range() step cannot be zero in ${" + s_ + "}");
      const long double count = std::max<long double>(0, std::ceil(static_cast<long double>(r[1] - r[0]) / r[2]));
      if (count > kMaxItems) die("range() of more than " + std::to_string(kMaxItems) + " items in ${" + s_ + "}");
      List items;
      for (long long k = r[0]; r[2] > 0 ? k < r[1] : k > r[1]; k += r[2]) items.push_back(number_value(static_cast<double>(k), true));
      return list_value(std::move(items));
    }
    if (name == "enumerate") {
      List items;
      const List from = checked_items(one());
      for (std::size_t k = 0; k < from.size(); ++k) items.push_back(list_value({number_value(static_cast<double>(k), true), from[k]}, true));
      return list_value(std::move(items));
    }
    if (name == "zip") {
      std::vector<List> lists;
      std::size_t n = args.empty() ? 0 : kMaxItems;
      for (const Value& a : args) lists.push_back(checked_items(a)), n = std::min(n, lists.back().size());
      List items;
      for (std::size_t k = 0; k < n; ++k) {
        List row;
        for (const List& l : lists) row.push_back(l[k]);
        items.push_back(list_value(std::move(row), true));
      }
      return list_value(std::move(items));
    }
    return std::nullopt;
  }

  static bool is_method(const Value& v, const std::string& name) {
    static const char* const kText[] = {"upper", "lower", "capitalize", "title", "strip", "lstrip", "rstrip", "split",
                                        "join", "replace", "startswith", "endswith", "find", "count", "format", "zfill"};
    static const char* const kList[] = {"index", "count"};
    static const char* const kDict[] = {"keys", "values", "items", "get"};
    auto in = [&](const auto& names) { return std::any_of(std::begin(names), std::end(names), [&](const char* m) { return name == m; }); };
    if (v.kind == Value::text) return in(kText);
    if (v.kind == Value::list) return in(kList);
    if (v.kind == Value::dict) return in(kDict);
    return false;
  }
  std::string text_arg(const std::string& name, const std::vector<Value>& args, std::size_t k) {
    if (k >= args.size() || args[k].kind != Value::text) die(name + "() takes a string argument in ${" + s_ + "}");
    return args[k].str;
  }
  // Methods of strings (Python's str), lists and dicts, for what descriptions write.
  Value method(const Value& v, const std::string& name, const std::vector<Value>& args, const Dict& keywords) {
    if (!keywords.empty() && name != "format") die(name + "() takes no keyword arguments in ${" + s_ + "}");
    auto count_args = [&](std::size_t lo, std::size_t hi) {
      if (args.size() < lo || args.size() > hi) die(name + "() takes " + std::to_string(lo) + (hi > lo ? " to " + std::to_string(hi) : "") + " arguments in ${" + s_ + "}");
    };
    if (v.kind == Value::dict) {
      if (name == "get") {
        count_args(1, 2);
        const std::string key = format(args[0]);
        for (const auto& [k, x] : *v.entries)
          if (k == key) return x;
        return args.size() == 2 ? args[1] : none_value();
      }
      count_args(0, 0);
      List out;
      for (const auto& [k, x] : *v.entries)
        out.push_back(name == "keys" ? text_value(k) : name == "values" ? x : list_value({text_value(k), x}, true));
      return list_value(std::move(out));
    }
    if (v.kind == Value::list) {
      count_args(1, 1);
      const List& l = *v.items;
      if (name == "count") return number_value(static_cast<double>(std::count_if(l.begin(), l.end(), [&](const Value& x) { return equal(x, args[0]); })), true);
      for (std::size_t k = 0; k < l.size(); ++k)
        if (equal(l[k], args[0])) return number_value(static_cast<double>(k), true);
      die("'" + format(args[0]) + "' is not in the list in ${" + s_ + "}");
    }
    const std::string& t = v.str;
    if (name == "upper" || name == "lower" || name == "capitalize" || name == "title") {
      count_args(0, 0);
      std::string out = t;
      bool start = true;
      for (char& ch : out) {
        const auto u = static_cast<unsigned char>(ch);
        const bool up = name == "upper" || ((name == "title" || (name == "capitalize" && &ch == &out[0])) && start);
        ch = static_cast<char>(up ? std::toupper(u) : std::tolower(u));
        start = !std::isalpha(u);
      }
      return text_value(out);
    }
    if (name == "strip" || name == "lstrip" || name == "rstrip") {
      count_args(0, 1);
      const std::string set = args.empty() || args[0].kind == Value::none ? std::string(" \t\n\r\f\v") : text_arg(name, args, 0);
      std::size_t b = 0, e = t.size();
      if (name != "rstrip") while (b < e && set.find(t[b]) != std::string::npos) ++b;
      if (name != "lstrip") while (e > b && set.find(t[e - 1]) != std::string::npos) --e;
      return text_value(t.substr(b, e - b));
    }
    if (name == "split") {
      count_args(0, 2);
      const bool blank = args.empty() || args[0].kind == Value::none;
      const long long maxsplit = args.size() == 2 ? static_cast<long long>(num(args[1], "split")) : -1;
      List out;
      if (blank) {  // runs of whitespace, none empty
        std::size_t k = 0;
        while (k < t.size()) {
          while (k < t.size() && std::isspace(static_cast<unsigned char>(t[k]))) ++k;
          if (k >= t.size()) break;
          if (maxsplit >= 0 && static_cast<long long>(out.size()) == maxsplit) {
            std::string rest = t.substr(k);
            rest.erase(rest.find_last_not_of(" \t\n\r\f\v") + 1);
            out.push_back(text_value(rest));
            break;
          }
          std::size_t j = k;
          while (j < t.size() && !std::isspace(static_cast<unsigned char>(t[j]))) ++j;
          out.push_back(text_value(t.substr(k, j - k)));
          k = j;
        }
      } else {
        const std::string sep = text_arg(name, args, 0);
        if (sep.empty()) die("split() with an empty separator in ${" + s_ + "}");
        std::size_t k = 0;
        for (;;) {
          const std::size_t j = t.find(sep, k);
          if (j == std::string::npos || (maxsplit >= 0 && static_cast<long long>(out.size()) == maxsplit)) break;
          out.push_back(text_value(t.substr(k, j - k)));
          k = j + sep.size();
        }
        out.push_back(text_value(t.substr(k)));
      }
      return list_value(std::move(out));
    }
    if (name == "join") {
      count_args(1, 1);
      std::string out;
      const List items = checked_items(args[0]);
      for (std::size_t k = 0; k < items.size(); ++k) {
        if (items[k].kind != Value::text) die("join() takes strings, not '" + format(items[k]) + "' in ${" + s_ + "}");
        out += (k ? t : std::string()) + items[k].str;
      }
      return text_value(out);
    }
    if (name == "replace") {
      count_args(2, 3);
      const std::string from = text_arg(name, args, 0), to = text_arg(name, args, 1);
      long long left = args.size() == 3 ? static_cast<long long>(num(args[2], "replace")) : -1;
      if (from.empty()) die("replace() of an empty string in ${" + s_ + "}");
      std::string out;
      std::size_t k = 0;
      for (std::size_t j; left != 0 && (j = t.find(from, k)) != std::string::npos; --left) out += t.substr(k, j - k) + to, k = j + from.size();
      return text_value(out + t.substr(k));
    }
    if (name == "startswith" || name == "endswith") {
      count_args(1, 1);
      const std::string x = text_arg(name, args, 0);
      const bool hit = x.size() <= t.size() && (name == "startswith" ? t.compare(0, x.size(), x) == 0 : t.compare(t.size() - x.size(), x.size(), x) == 0);
      return bool_value(hit);
    }
    if (name == "find" || name == "count") {
      count_args(1, 1);
      const std::string x = text_arg(name, args, 0);
      if (name == "find") {
        const std::size_t j = t.find(x);
        return number_value(j == std::string::npos ? -1.0 : static_cast<double>(j), true);
      }
      if (x.empty()) return number_value(static_cast<double>(t.size() + 1), true);
      std::size_t n = 0;
      for (std::size_t j = t.find(x); j != std::string::npos; j = t.find(x, j + x.size())) ++n;
      return number_value(static_cast<double>(n), true);
    }
    if (name == "zfill") {
      count_args(1, 1);
      const auto width = static_cast<std::size_t>(std::clamp(num(args[0], "zfill"), 0.0, 4096.0));
      std::string out = t;
      const std::size_t sign = !out.empty() && (out[0] == '-' || out[0] == '+') ? 1 : 0;
      if (out.size() < width) out.insert(sign, width - out.size(), '0');
      return text_value(out);
    }
    return text_value(format_method(t, args, keywords));
  }
  // str.format: {} / {0} / {name}, with an optional spec [width][.precision][d|f|e|g|s].
  std::string format_method(const std::string& t, const std::vector<Value>& args, const Dict& keywords) {
    std::string out;
    std::size_t auto_index = 0;
    for (std::size_t k = 0; k < t.size(); ++k) {
      if ((t[k] == '{' || t[k] == '}') && k + 1 < t.size() && t[k + 1] == t[k]) {
        out += t[k++];
        continue;
      }
      if (t[k] != '{') {
        out += t[k];
        continue;
      }
      const std::size_t close = t.find('}', k);
      if (close == std::string::npos) die("format(): '{' without '}' in ${" + s_ + "}");
      const std::string field = t.substr(k + 1, close - k - 1);
      const std::size_t colon = field.find(':');
      const std::string key = field.substr(0, colon), spec = colon == std::string::npos ? "" : field.substr(colon + 1);
      const Value* x = nullptr;
      if (key.empty() || std::all_of(key.begin(), key.end(), [](char ch) { return std::isdigit(static_cast<unsigned char>(ch)); })) {
        const std::size_t idx = key.empty() ? auto_index++ : std::stoul(key.substr(0, 6));
        if (idx >= args.size()) die("format(): no argument " + std::to_string(idx) + " in ${" + s_ + "}");
        x = &args[idx];
      } else {
        for (const auto& [name, val] : keywords)
          if (name == key) x = &val;
        if (!x) die("format(): no argument '" + key + "' in ${" + s_ + "}");
      }
      if (spec.empty()) {
        out += format(*x);
      } else {
        std::size_t p = 0;
        int width = 0, precision = -1;
        while (p < spec.size() && std::isdigit(static_cast<unsigned char>(spec[p])) && width < 1000) width = width * 10 + (spec[p++] - '0');
        if (p < spec.size() && spec[p] == '.') {
          precision = 0;
          while (++p < spec.size() && std::isdigit(static_cast<unsigned char>(spec[p])) && precision < 100) precision = precision * 10 + (spec[p] - '0');
        }
        const char type = p < spec.size() ? spec[p++] : (x->kind == Value::text ? 's' : 'g');
        if (p != spec.size() || std::string("dfeEgGs").find(type) == std::string::npos) die("format(): unsupported spec '" + spec + "' in ${" + s_ + "}");
        char buf[256];
        if (type == 's') {
          std::snprintf(buf, sizeof buf, "%*s", width, format(*x).substr(0, precision < 0 ? std::string::npos : static_cast<std::size_t>(precision)).c_str());
        } else if (type == 'd') {
          std::snprintf(buf, sizeof buf, "%*lld", width, static_cast<long long>(std::clamp(num(*x, "format"), -9e18, 9e18)));
        } else {
          const char f[] = {'%', '*', '.', '*', type, 0};
          std::snprintf(buf, sizeof buf, f, width, precision < 0 ? 6 : precision, num(*x, "format"));
        }
        out += buf;
      }
      k = close;
    }
    return out;
  }

  std::string s_;
  const ExprContext& cx_;
  std::size_t i_ = 0;
  int depth_ = 0;
  int nest_ = 0;
};

// Macro parameters, split at blanks outside quotes; a quoted default (p:='a b', p:='') loses
// its quotes, as xacro reads it.
std::vector<std::string> split_params(const std::string& text) {
  std::vector<std::string> out;
  std::string cur;
  char quote = 0;
  bool quoted = false;
  for (const char c : text) {
    if (quote) {
      if (c == quote) quote = 0;
      else cur += c;
    } else if ((c == '\'' || c == '"') && cur.find(":=") != std::string::npos) {
      quote = c;
      quoted = true;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      if (!cur.empty() || quoted) out.push_back(cur);
      cur.clear();
      quoted = false;
    } else {
      cur += c;
    }
  }
  if (!cur.empty() || quoted) out.push_back(cur);
  return out;
}

class Expander {
 public:
  Expander(const PackagePath& packages, const std::map<std::string, std::string>& args)
      : packages_(packages), args_(args) {}

  std::string run(const std::string& path) {
    const XMLDocument& in = load(path, nullptr, "");
    const XMLElement* root = in.RootElement();
    if (!root) throw UrdfError(path, 0, "xacro: no root element");
    XMLElement* out_root = out_.NewElement(root->Name());
    out_.InsertEndChild(out_root);
    files_.push_back(path);
    children(root, out_root, global_);
    // The root's attributes last: <robot name="$(arg name)"> may use an arg declared inside.
    copy_attributes(root, out_root, global_);
    files_.pop_back();
    tinyxml2::XMLPrinter printer(nullptr, true);  // compact: no whitespace added to text
    out_.Print(&printer);
    return std::string(printer.CStr(), static_cast<std::size_t>(printer.CStrSize() > 0 ? printer.CStrSize() - 1 : 0));
  }

 private:
  [[noreturn]] void fail(const XMLElement* e, const std::string& what) const {
    throw UrdfError(files_.empty() ? std::string() : files_.back(), e ? e->GetLineNum() : 0, what);
  }

  const XMLDocument& load(const std::string& path, const XMLElement* from, const std::string& from_file) {
    std::string xml;
    if (Result<std::string> text = collision::read_file_bounded(path, collision::kMaxTextFileBytes)) {
      xml = std::move(*text);
    } else {
      if (from) throw UrdfError(from_file, from->GetLineNum(), "<xacro:include>: " + text.error().message);
      throw UrdfError(path, 0, text.error().message);
    }
    auto doc = std::make_unique<XMLDocument>();
    if (doc->Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS)
      throw UrdfError(path, doc->ErrorLineNum(), std::string("XML error: ") + doc->ErrorStr());
    docs_.push_back(std::move(doc));
    return *docs_.back();
  }

  static bool is_xacro(const XMLElement* e) { return std::strncmp(e->Name(), "xacro:", 6) == 0; }

  void grow(std::size_t n, const XMLElement* e) {
    out_bytes_ += n;
    if (out_bytes_ > kMaxXacroOutputBytes)
      fail(e, "xacro: the expansion exceeds " + std::to_string(kMaxXacroOutputBytes >> 20) + " MiB (docs/limits.md)");
  }

  // The context of an expression in `scope`: its properties (evaluated on first use in the scope
  // that holds them) and load_yaml.
  ExprContext context(const XMLElement* e, Scope& scope) {
    ExprContext cx;
    cx.fail = [this, e](const std::string& m) { fail(e, "xacro: " + m); };
    cx.name = [this, &scope](const std::string& n) -> std::optional<Value> {
      auto [p, holder] = scope.find(n);
      if (!p) return std::nullopt;
      return property_value(*p, *holder);
    };
    cx.call = [this, e](const std::string& name, const std::vector<Value>& args) -> std::optional<Value> {
      // ros/xacro's xacro namespace: arg(name) (the argument's text), abs_filename(spec) (a
      // package:// or file:// URI, or a path relative to this file, made absolute), dotify(d)
      // (our dicts already take d.key), error(text) (stops the expansion with the text).
      if (name.rfind("xacro.", 0) == 0) {
        const std::string fn = name.substr(6);
        if (args.size() != 1) fail(e, "xacro: xacro." + fn + "() takes one argument");
        if (fn == "dotify") {
          if (args[0].kind != Value::dict) fail(e, "xacro: xacro.dotify() takes a dict");
          return args[0];
        }
        if (args[0].kind != Value::text) fail(e, "xacro: xacro." + fn + "() takes a string");
        const std::string& a = args[0].str;
        if (fn == "arg") {
          if (auto it = args_.find(a); it != args_.end()) return text_value(it->second);
          fail(e, "xacro: xacro.arg('" + a + "'): no such argument (declare it with <xacro:arg name=\"" + a + "\" default=...>)");
        }
        if (fn == "error") fail(e, "xacro: xacro.error: " + a);
        fs::path path = a;
        if (a.rfind("package://", 0) == 0 || a.rfind("file://", 0) == 0) {
          std::string error;
          path = resolve_uri(a, fs::path(files_.back()).parent_path(), packages_, error);
          if (!error.empty()) fail(e, "xacro: xacro.abs_filename('" + a + "'): " + error);
        } else if (path.is_relative()) {
          path = fs::path(files_.back()).parent_path() / path;
        }
        return text_value(fs::absolute(path).lexically_normal().string());
      }
      if (name != "load_yaml") return std::nullopt;
      if (args.size() != 1 || args[0].kind != Value::text) fail(e, "xacro: load_yaml() takes one file name");
      return load_yaml(args[0].str, e);
    };
    return cx;
  }

  Value property_value(Prop& p, Scope& holder) {
    if (p.value) return *p.value;
    if (p.busy) throw UrdfError(p.file, p.line, "xacro: property defined by itself (a cycle of properties)");
    if (++eval_depth_ > kMaxNesting) throw UrdfError(p.file, p.line, "xacro: properties nested more than " + std::to_string(kMaxNesting) + " deep");
    p.busy = true;
    files_.push_back(p.file);
    struct Restore {
      Expander& x;
      Prop& p;
      ~Restore() {
        x.files_.pop_back();
        p.busy = false;
        --x.eval_depth_;
      }
    } restore{*this, p};
    // Evaluated where it was defined; `line` from the definition for messages.
    Value v = value_of(p.text, nullptr, holder, p.line);
    p.value = v;
    return v;
  }

  Value load_yaml(const std::string& name, const XMLElement* e) {
    fs::path p = name;
    if (name.rfind("package://", 0) == 0 || name.rfind("file://", 0) == 0) {
      std::string error;
      p = resolve_uri(name, fs::path(files_.back()).parent_path(), packages_, error);
      if (!error.empty()) fail(e, "xacro: load_yaml('" + name + "'): " + error);
    } else if (p.is_relative()) {
      p = fs::path(files_.back()).parent_path() / p;
    }
    Result<std::string> text = collision::read_file_bounded(p.string(), collision::kMaxTextFileBytes);
    if (!text) fail(e, "xacro: load_yaml('" + name + "'): " + text.error().message);
    YAML::Node doc;
    try {
      // yaml-cpp recurses per level: a document that may nest deeper than kMaxNesting is refused
      // first. Over-counted: open brackets, plus per line its indent and its "- " / "? " entries.
      int brackets = 0, deepest = 0, line_depth = 0;
      bool at_start = true;
      for (std::size_t k = 0; k < text->size(); ++k) {
        const char c = (*text)[k];
        const bool entry = (c == '-' || c == '?') && k + 1 < text->size() && (*text)[k + 1] == ' ';
        if (c == '\n') line_depth = 0, at_start = true;
        else if (c == ' ' && at_start) ++line_depth;
        else if (entry) ++line_depth;
        else at_start = false;
        if (c == '[' || c == '{') ++brackets;
        else if ((c == ']' || c == '}') && brackets > 0) --brackets;
        deepest = std::max(deepest, brackets + line_depth);
      }
      if (deepest > 2 * kMaxNesting)
        fail(e, "xacro: load_yaml('" + name + "'): nested more than " + std::to_string(kMaxNesting) + " levels");
      doc = YAML::Load(*text);
    } catch (const YAML::Exception& x) {
      fail(e, "xacro: load_yaml('" + name + "'): " + p.string() + ":" + std::to_string(x.mark.line + 1) + ": " + x.msg);
    }
    const auto yaml_fail = [&](const std::string& m) { fail(e, "xacro: " + m + " in " + p.string()); };
    // As xacro: the tagged text is a Python expression over the math names (no properties).
    const YamlAngle angle = [&](const std::string& expr, bool degrees) {
      ExprContext cx;
      cx.fail = [&](const std::string& m) { yaml_fail("load_yaml: '" + expr + "': " + m); };
      cx.name = [](const std::string&) -> std::optional<Value> { return std::nullopt; };
      cx.call = [](const std::string&, const std::vector<Value>&) -> std::optional<Value> { return std::nullopt; };
      const Value v = Expr(expr, cx).run();
      if (v.kind != Value::number) yaml_fail("load_yaml: " + std::string(degrees ? "!degrees" : "!radians") + " '" + expr + "' is not a number");
      const double r = degrees ? v.num * std::numbers::pi / 180 : v.num;
      if (!std::isfinite(r)) yaml_fail("load_yaml: '" + expr + "' is not a finite angle");
      return r;
    };
    return from_yaml(doc, 0, yaml_fail, angle);
  }

  // The value of a text: one ${expr} spanning all of it keeps the expression's value (a dict, a
  // list, a number); anything else is the substituted text, read back as a number when it is one.
  Value value_of(const std::string& text, const XMLElement* e, Scope& scope, int line = 0) {
    std::string t = text;
    const std::size_t b = t.find_first_not_of(" \t\n\r");
    if (b != std::string::npos && t.compare(b, 2, "${") == 0) {
      const std::size_t close = matching(t, b + 1, '{', '}');
      if (close != std::string::npos && t.find_first_not_of(" \t\n\r", close + 1) == std::string::npos) {
        ExprContext cx = context(e, scope);
        if (line) cx.fail = [this, line](const std::string& m) { throw UrdfError(files_.back(), line, "xacro: " + m); };
        std::string inner = t.substr(b + 2, close - b - 2);
        if (inner.find("$(") != std::string::npos) inner = eval(inner, e, scope, line);  // $(...) first, as xacro
        return Expr(inner, cx).run();
      }
    }
    return from_text(eval(text, e, scope, line));
  }

  // $(...) substitutions and ${expr} in attribute or text values; $${ and $$( stay literal.
  std::string eval(const std::string& text, const XMLElement* e, Scope& scope, int line = 0) {
    if (text.find('$') == std::string::npos) return text;
    std::string out;
    ExprContext cx = context(e, scope);
    if (line) cx.fail = [this, line](const std::string& m) { throw UrdfError(files_.back(), line, "xacro: " + m); };
    for (std::size_t i = 0; i < text.size();) {
      if (text[i] != '$' || i + 1 >= text.size()) {
        out += text[i++];
        continue;
      }
      if (text[i + 1] == '$' && i + 2 < text.size() && (text[i + 2] == '{' || text[i + 2] == '(')) {
        out += '$';
        out += text[i + 2];
        i += 3;
        continue;
      }
      const char open = text[i + 1];
      if (open != '{' && open != '(') {
        out += text[i++];
        continue;
      }
      const std::size_t end = matching(text, i + 1, open, open == '{' ? '}' : ')');
      if (end == std::string::npos) cx.fail(std::string("unterminated ") + (open == '{' ? "${" : "$(") + " in \"" + text + "\"");
      std::string inner = text.substr(i + 2, end - i - 2);
      // As xacro: $(...) inside ${...} is substituted first (${'a' if $(arg flag) else 'b'}).
      if (open == '{' && inner.find("$(") != std::string::npos) inner = eval(inner, e, scope, line);
      if (open == '{') out += format(Expr(inner, cx).run());
      else out += substitution(inner, e, scope, cx);
      i = end + 1;
    }
    return out;
  }

  std::string substitution(const std::string& raw, const XMLElement* e, Scope& scope, const ExprContext& cx) {
    std::string kind, arg;
    {
      std::size_t sp = raw.find_first_of(" \t");
      kind = raw.substr(0, sp);
      if (kind == "eval") return format(eval_substitution(sp == std::string::npos ? "" : raw.substr(sp + 1), cx));
      const std::string s = eval(raw, e, scope);
      sp = s.find_first_of(" \t");
      kind = s.substr(0, sp);
      if (sp != std::string::npos) {
        const std::size_t b = s.find_first_not_of(" \t", sp);
        arg = b == std::string::npos ? "" : s.substr(b);
      }
      while (!arg.empty() && (arg.back() == ' ' || arg.back() == '\t')) arg.pop_back();
    }
    if (kind == "find") {
      if (auto dir = packages_.find(arg)) return fs::absolute(*dir).lexically_normal().string();  // not relative to the includer
      cx.fail("$(find " + arg + "): no package '" + arg + "' on the package path (cell packages:, ROS_PACKAGE_PATH)");
    }
    if (kind == "arg") {
      if (auto it = args_.find(arg); it != args_.end()) return it->second;
      cx.fail("$(arg " + arg + "): no value (give xacro_args: in the cell or <xacro:arg name=\"" + arg + "\" default=...>)");
    }
    if (kind == "env") {
      if (const char* v = std::getenv(arg.c_str())) return v;
      cx.fail("$(env " + arg + "): the environment variable is not set");
    }
    if (kind == "optenv") {
      const std::size_t sp = arg.find_first_of(" \t");
      const std::string var = arg.substr(0, sp);
      if (const char* v = std::getenv(var.c_str())) return v;
      return sp == std::string::npos ? std::string() : arg.substr(arg.find_first_not_of(" \t", sp));
    }
    if (kind == "anon") {
      // roslaunch's anonymous name: the same NAME gives the same value within one expansion, two
      // names two values. Made from NAME and the top file (not host, pid and a random number as
      // roslaunch does) so that a cell loads the same way every run.
      if (arg.empty() || arg.find_first_of(" \t") != std::string::npos) cx.fail("$(anon NAME) takes one name");
      auto [it, fresh] = anon_.try_emplace(arg);
      if (fresh) {
        std::uint64_t h = 1469598103934665603ull;  // FNV-1a
        for (const char ch : files_.front() + '\n' + arg) h = (h ^ static_cast<unsigned char>(ch)) * 1099511628211ull;
        char buf[24];
        std::snprintf(buf, sizeof buf, "_%016llx", static_cast<unsigned long long>(h));
        it->second = arg + buf;
      }
      return it->second;
    }
    if (kind == "dirname") return fs::absolute(fs::path(files_.back()).parent_path()).lexically_normal().string();
    if (kind == "cwd") return fs::current_path().string();
    cx.fail("unsupported substitution $(" + raw + ") (find, arg, env, optenv, eval, anon, dirname, cwd)");
    throw std::logic_error("unreachable");  // fail throws
  }

  // $(eval expr): Python over the args (bare names), with arg(), env(), optenv(), find().
  Value eval_substitution(const std::string& expr, const ExprContext& outer) {
    ExprContext cx;
    cx.fail = outer.fail;
    cx.name = [this](const std::string& n) -> std::optional<Value> {  // args are strings there, as in roslaunch
      if (auto it = args_.find(n); it != args_.end()) return text_value(it->second);
      return std::nullopt;
    };
    cx.call = [this, &cx](const std::string& name, const std::vector<Value>& a) -> std::optional<Value> {
      const auto text_arg = [&](std::size_t k) { return k < a.size() ? format(a[k]) : std::string(); };
      if (name == "arg") {
        if (auto it = args_.find(text_arg(0)); it != args_.end()) return text_value(it->second);
        cx.fail("$(eval arg('" + text_arg(0) + "')): no value");
      }
      if (name == "env" || name == "optenv") {
        if (const char* v = std::getenv(text_arg(0).c_str())) return text_value(v);
        if (name == "optenv") return text_value(text_arg(1));
        cx.fail("$(eval env('" + text_arg(0) + "')): the environment variable is not set");
      }
      if (name == "find") {
        if (auto dir = packages_.find(text_arg(0))) return text_value(fs::absolute(*dir).lexically_normal().string());
        cx.fail("$(eval find('" + text_arg(0) + "')): no package '" + text_arg(0) + "'");
      }
      return std::nullopt;
    };
    return Expr(expr, cx).run();
  }

  std::string attr(const XMLElement* e, const char* name, Scope& scope, bool needed = true) {
    const char* v = e->Attribute(name);
    if (!v) {
      if (needed) fail(e, std::string("<") + e->Name() + "> needs the attribute '" + name + "'");
      return {};
    }
    return eval(v, e, scope);
  }

  void copy_attributes(const XMLElement* from, XMLElement* to, Scope& scope) {
    for (const tinyxml2::XMLAttribute* a = from->FirstAttribute(); a; a = a->Next()) {
      if (std::strncmp(a->Name(), "xmlns", 5) == 0 || std::strncmp(a->Name(), "xacro:", 6) == 0) continue;
      const std::string v = eval(a->Value(), from, scope);
      grow(v.size() + std::strlen(a->Name()) + 4, from);
      to->SetAttribute(a->Name(), v.c_str());
    }
  }

  void children(const XMLElement* parent, XMLNode* out, Scope& scope) {
    for (const XMLNode* n = parent->FirstChild(); n; n = n->NextSibling()) node(n, out, scope);
  }

  void node(const XMLNode* n, XMLNode* out, Scope& scope) {
    if (const XMLElement* e = n->ToElement()) return element(e, out, scope);
    if (const tinyxml2::XMLText* t = n->ToText()) {
      const XMLElement* owner = n->Parent() ? n->Parent()->ToElement() : nullptr;
      const std::string v = eval(t->Value(), owner, scope);
      grow(v.size(), owner);
      out->InsertEndChild(out_.NewText(v.c_str()));
    }
    // comments, declarations: dropped
  }

  // A boolean attribute of an xacro element (remove=, lazy_eval=), as xacro:if reads its value.
  bool is_true(const std::string& text, const XMLElement* e, const char* what) {
    const Value x = value_of(text, e, global_);
    if (x.kind == Value::boolean || x.kind == Value::number) return x.num != 0;
    fail(e, std::string("<xacro:property ") + what + "=\"" + text + "\">: true or false is expected");
  }

  // The scope a scope="parent" / "global" property goes to.
  Scope& target_scope(const XMLElement* e, Scope& scope) {
    const char* s = e->Attribute("scope");
    if (!s || std::strcmp(s, "local") == 0) return scope;
    if (std::strcmp(s, "global") == 0) return global_;
    if (std::strcmp(s, "parent") == 0) return scope.parent ? *scope.parent : scope;
    fail(e, std::string("<xacro:property scope=\"") + s + "\">: local, parent or global");
  }

  void element(const XMLElement* e, XMLNode* out, Scope& scope) {
    if (!is_xacro(e)) {
      XMLElement* copy = out_.NewElement(e->Name());
      grow(std::strlen(e->Name()) * 2 + 5, e);
      copy_attributes(e, copy, scope);
      out->InsertEndChild(copy);
      children(e, copy, scope);
      return;
    }
    const std::string tag = e->Name() + 6;
    if (tag == "property") {
      const std::string name = attr(e, "name", scope);
      Scope& into = target_scope(e, scope);
      // remove="true" deletes the property (ros/xacro 1.14): the nearest one of that name seen
      // from the target scope.
      if (e->Attribute("remove")) {
        if (!is_true(attr(e, "remove", scope), e, "remove")) return;
        if (e->Attribute("value") || e->Attribute("default"))
          fail(e, "<xacro:property name=\"" + name + "\" remove=\"true\">: takes no value");
        for (Scope* s = &into; s; s = s->parent)
          if (s->props.erase(name) + s->blocks.erase(name) > 0) break;
        return;
      }
      // xacro evaluates a property for another scope at once, and one with lazy_eval="false"
      // (so that `value="${x + 1}"` reads the x already defined instead of itself).
      const bool eager = &into != &scope ||
                         (e->Attribute("lazy_eval") && !is_true(attr(e, "lazy_eval", scope), e, "lazy_eval"));
      Prop p;
      p.file = files_.back();
      p.line = e->GetLineNum();
      if (const char* v = e->Attribute("value")) {
        p.text = v;
        if (eager) p.value = value_of(v, e, scope);
        into.props[name] = std::move(p);
      } else if (const char* d = e->Attribute("default")) {
        if (!scope.find(name).first) {
          p.text = d;
          if (eager) p.value = value_of(d, e, scope);
          into.props[name] = std::move(p);
        }
      } else {
        into.blocks[name] = e;  // block property: its children
      }
      return;
    }
    if (tag == "arg") {
      const std::string name = attr(e, "name", scope);
      if (!args_.count(name)) {
        if (!e->Attribute("default")) fail(e, "<xacro:arg name=\"" + name + "\">: no default and no value from the cell (xacro_args:)");
        args_[name] = attr(e, "default", scope);
      }
      return;
    }
    if (tag == "macro") {
      Macro m;
      m.def = e;
      m.file = files_.back();
      const std::string name = ns_ + attr(e, "name", scope);
      m.params = split_params(e->Attribute("params") ? e->Attribute("params") : "");
      macros_[name] = std::move(m);
      return;
    }
    if (tag == "include") return include(e, out, scope);
    if (tag == "if" || tag == "unless") {
      const Value x = value_of(e->Attribute("value") ? e->Attribute("value") : "", e, scope);
      bool b = false;
      if (x.kind == Value::boolean || x.kind == Value::number) b = x.num != 0;
      else fail(e, "<xacro:" + tag + " value=\"" + format(x) + "\">: a boolean or a number is expected");
      if (b == (tag == "if")) children(e, out, scope);
      return;
    }
    if (tag == "insert_block") {
      const std::string name = attr(e, "name", scope);
      const XMLElement* b = scope.block(name);
      if (!b) fail(e, "<xacro:insert_block name=\"" + name + "\">: no such block");
      if (std::strcmp(b->Name(), "xacro:block") == 0) {  // a macro's block parameter, already expanded
        for (const XMLNode* c = b->FirstChild(); c; c = c->NextSibling()) out->InsertEndChild(c->DeepClone(&out_));
        return;
      }
      if (++block_depth_ > kMaxXacroMacroDepth)
        fail(e, "<xacro:insert_block>: nested more than " + std::to_string(kMaxXacroMacroDepth) + " deep");
      children(b, out, scope);  // a block property: its children, here
      --block_depth_;
      return;
    }
    if (tag == "element") {
      const char* n = e->Attribute("xacro:name");
      if (!n) fail(e, "<xacro:element> needs the attribute 'xacro:name'");
      const std::string name = eval(n, e, scope);
      if (name.empty() || name.find_first_of(" <>\"'&") != std::string::npos) fail(e, "<xacro:element>: bad element name '" + name + "'");
      XMLElement* copy = out_.NewElement(name.c_str());
      grow(name.size() * 2 + 5, e);
      copy_attributes(e, copy, scope);
      out->InsertEndChild(copy);
      children(e, copy, scope);
      return;
    }
    if (tag == "attribute") {
      XMLElement* target = out->ToElement();
      if (!target) fail(e, "<xacro:attribute> must be inside an element");
      const std::string name = attr(e, "name", scope), value = attr(e, "value", scope);
      if (name.empty() || name.find_first_of(" <>\"'&=") != std::string::npos) fail(e, "<xacro:attribute>: bad attribute name '" + name + "'");
      grow(name.size() + value.size() + 4, e);
      target->SetAttribute(name.c_str(), value.c_str());
      return;
    }
    if (tag == "call") {
      const std::string name = attr(e, "macro", scope);
      if (auto it = macros_.find(name); it != macros_.end()) return call(e, it->second, out, scope, true);
      fail(e, "<xacro:call macro=\"" + name + "\">: unknown macro");
    }
    if (auto it = macros_.find(tag); it != macros_.end()) return call(e, it->second, out, scope, false);
    fail(e, "<" + std::string(e->Name()) + ">: unsupported xacro construct or unknown macro (docs/robots.md)");
  }

  void include(const XMLElement* e, XMLNode* out, Scope& scope) {
    const std::string name = attr(e, "filename", scope);
    fs::path p = name;
    if (name.rfind("package://", 0) == 0 || name.rfind("file://", 0) == 0) {
      std::string error;
      p = resolve_uri(name, fs::path(files_.back()).parent_path(), packages_, error);
      if (!error.empty()) fail(e, "<xacro:include filename=\"" + name + "\">: " + error);
    } else if (p.is_relative()) {
      p = fs::path(files_.back()).parent_path() / p;
    }
    const std::string file = p.lexically_normal().string();
    if (static_cast<int>(files_.size()) > kMaxXacroIncludeDepth)
      fail(e, "<xacro:include>: includes nested more than " + std::to_string(kMaxXacroIncludeDepth) + " deep");
    std::error_code ec;
    for (const auto& f : files_)
      if (fs::equivalent(f, file, ec)) fail(e, "<xacro:include filename=\"" + name + "\">: include cycle (" + file + " is already being included)");
    const XMLDocument& doc = load(file, e, files_.back());
    const XMLElement* root = doc.RootElement();
    if (!root) throw UrdfError(file, 0, "xacro: no root element");
    // ns="name": the file's macros are called as name.macro and its properties are read as
    // ${name.property} (ros/xacro's PropertyNameSpace: a scope of its own over the includer's).
    const std::string saved_ns = ns_;
    Scope* into = &scope;
    if (const char* ns = e->Attribute("ns")) {
      const std::string name = eval(ns, e, scope);
      if (name.empty() || name.find_first_of(" .${}()") != std::string::npos) fail(e, "<xacro:include ns=\"" + name + "\">: not a name");
      ns_ += name + ".";
      namespaces_.push_back(std::make_unique<Scope>());
      into = namespaces_.back().get();
      into->parent = &scope;
      Prop p;
      p.file = files_.back();
      p.line = e->GetLineNum();
      Value v;
      v.kind = Value::ns;
      v.lookup = std::make_shared<const Lookup>([this, into](const std::string& n) -> std::optional<Value> {
        auto it = into->props.find(n);  // the namespace's own properties only
        if (it == into->props.end()) return std::nullopt;
        return property_value(it->second, *into);
      });
      p.value = v;
      scope.props[name] = std::move(p);
    }
    files_.push_back(file);
    children(root, out, *into);
    files_.pop_back();
    ns_ = saved_ns;
  }

  void call(const XMLElement* e, const Macro& m, XMLNode* out, Scope& caller, bool via_call) {
    if (macro_depth_ >= kMaxXacroMacroDepth)
      fail(e, "<" + std::string(e->Name()) + ">: macros nested more than " + std::to_string(kMaxXacroMacroDepth) + " deep (recursion?)");
    Scope local;
    local.parent = &caller;  // xacro's dynamic scoping: the body sees the caller's properties
    std::vector<const XMLElement*> given;
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) given.push_back(c);
    std::size_t next = 0;
    std::map<std::string, bool> known;
    const auto param = [&](const std::string& name, const Value& v) {
      Prop p;
      p.value = v;
      p.file = files_.back();
      p.line = e->GetLineNum();
      local.props[name] = std::move(p);
    };
    for (const std::string& p : m.params) {
      if (p[0] == '*') {  // *name: the next child element; **name: that element's content
        const bool content = p.rfind("**", 0) == 0;
        if (next >= given.size()) fail(e, "<" + std::string(e->Name()) + ">: missing the block parameter '" + p + "'");
        // Written in the caller's scope: expanded there, before the body.
        XMLElement* tmp = out_.NewElement("xacro:block");  // unlinked; out_ owns it
        if (content) children(given[next], tmp, caller);
        else element(given[next], tmp, caller);
        ++next;
        local.blocks[p.substr(content ? 2 : 1)] = tmp;
        continue;
      }
      const std::size_t d = p.find(":=");
      const std::string name = p.substr(0, d);
      known[name] = true;
      if (const char* v = e->Attribute(name.c_str())) {
        param(name, value_of(v, e, caller));
        continue;
      }
      if (d == std::string::npos) fail(e, "<" + std::string(e->Name()) + ">: missing the parameter '" + name + "'");
      std::string def = p.substr(d + 2);
      if (def.rfind("^", 0) == 0) {  // ^: the caller's property of that name; ^|x: else x
        if (auto [prop, holder] = caller.find(name); prop) {
          param(name, property_value(*prop, *holder));
          continue;
        }
        if (def.rfind("^|", 0) != 0)
          fail(e, "<" + std::string(e->Name()) + ">: parameter '" + p + "': no property '" + name + "' in the caller's scope");
        def = def.substr(2);
      }
      files_.push_back(m.file);
      const Value v = value_of(def, m.def, caller);
      files_.pop_back();
      param(name, v);
    }
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next())
      if (!known.count(a->Name()) && !(via_call && std::strcmp(a->Name(), "macro") == 0))
        fail(e, "<" + std::string(e->Name()) + ">: the macro has no parameter '" + a->Name() + "'");
    ++macro_depth_;
    files_.push_back(m.file);
    children(m.def, out, local);
    files_.pop_back();
    --macro_depth_;
  }

  const PackagePath& packages_;
  std::map<std::string, std::string> args_;
  std::vector<std::unique_ptr<XMLDocument>> docs_;
  std::vector<std::string> files_;  // the include stack: the file whose elements are expanded
  std::map<std::string, Macro> macros_;
  std::string ns_;  // the namespace prefix of an include with ns= ("" or "name.")
  Scope global_;
  std::vector<std::unique_ptr<Scope>> namespaces_;  // the scopes of ns= includes, alive to the end
  std::map<std::string, std::string> anon_;         // $(anon NAME): one value per NAME
  XMLDocument out_;
  std::size_t out_bytes_ = 0;
  int macro_depth_ = 0;
  int block_depth_ = 0;
  int eval_depth_ = 0;
};
}  // namespace

std::string expand_xacro(const std::string& path, const PackagePath& packages, const std::map<std::string, std::string>& args) {
  return Expander(packages, args).run(path);
}

}  // namespace asimov::robots
