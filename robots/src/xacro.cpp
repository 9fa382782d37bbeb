// xacro -> URDF text, on the tinyxml2 DOM. Properties are evaluated when defined (document
// order), macros expand in a scope holding their parameters over the global one.
#include "xacro.hpp"

#include "asimov/collision/text_file.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <sstream>
#include <memory>
#include <numbers>
#include <vector>

namespace asimov::robots {
namespace {
using tinyxml2::XMLDocument;
using tinyxml2::XMLElement;
using tinyxml2::XMLNode;
namespace fs = std::filesystem;

struct Value {
  enum Kind { number, text, boolean } kind = number;
  double num = 0;
  bool integer = false;
  std::string str;
};

std::string format(const Value& v) {
  if (v.kind == Value::text) return v.str;
  if (v.kind == Value::boolean) return v.num != 0 ? "True" : "False";
  if (v.integer && std::abs(v.num) < 1e15) return std::to_string(static_cast<long long>(v.num));
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v.num);  // shortest round trip
  return std::string(buf, r.ptr);
}

// A property's text read back in an expression: a number when it is one, else a string.
Value from_text(const std::string& s) {
  Value v;
  const char* b = s.data();
  const char* e = b + s.size();
  while (b < e && *b == ' ') ++b;
  while (e > b && e[-1] == ' ') --e;
  double d = 0;
  auto r = std::from_chars(b, e, d);
  if (b != e && r.ec == std::errc() && r.ptr == e && std::isfinite(d)) {
    v.num = d;
    v.integer = std::none_of(b, e, [](char c) { return c == '.' || c == 'e' || c == 'E'; });
    return v;
  }
  if (s == "True" || s == "true") return {Value::boolean, 1, false, {}};
  if (s == "False" || s == "false") return {Value::boolean, 0, false, {}};
  v.kind = Value::text;
  v.str = s;
  return v;
}

struct Macro {
  const XMLElement* def = nullptr;
  std::string file;
  std::vector<std::string> params;  // "name", "name:=default", "*block", "**block"
};

struct Scope {
  std::map<std::string, std::string> props;
  std::map<std::string, const XMLElement*> blocks;
  const Scope* parent = nullptr;
  const std::string* find(const std::string& n) const {
    for (const Scope* s = this; s; s = s->parent)
      if (auto it = s->props.find(n); it != s->props.end()) return &it->second;
    return nullptr;
  }
  const XMLElement* block(const std::string& n) const {
    for (const Scope* s = this; s; s = s->parent)
      if (auto it = s->blocks.find(n); it != s->blocks.end()) return it->second;
    return nullptr;
  }
};

class Expander;

// Recursive descent over one ${...} expression (Python's precedence for the subset).
class Expr {
 public:
  Expr(const std::string& text, const Scope& scope, const std::function<void(const std::string&)>& fail)
      : s_(text), scope_(scope), fail_(fail) {}
  Value run() {
    Value v = disjunction();
    skip();
    if (i_ != s_.size()) die("unexpected '" + s_.substr(i_) + "' in ${" + s_ + "}");
    return v;
  }

 private:
  [[noreturn]] void die(const std::string& m) const {
    fail_(m);  // throws UrdfError
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
    if (n == 1 && (o[0] == '*' || o[0] == '/' || o[0] == '<' || o[0] == '>') && i_ + 1 < s_.size() &&
        (s_[i_ + 1] == o[0] || s_[i_ + 1] == '='))
      return false;  // '**', '//', '<=' are other operators
    i_ += n;
    return true;
  }
  double num(const Value& v, const char* what) {
    if (v.kind == Value::text) die(std::string("'") + v.str + "' is not a number (" + what + ") in ${" + s_ + "}");
    return v.num;
  }
  static bool truth(const Value& v) { return v.kind == Value::text ? !v.str.empty() : v.num != 0; }
  static Value boolean(bool b) { return {Value::boolean, b ? 1.0 : 0.0, false, {}}; }
  static Value number(double d, bool integer = false) { return {Value::number, d, integer, {}}; }

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
    if (word("not")) return boolean(!truth(negation()));
    return comparison();
  }
  Value comparison() {
    Value a = sum();
    for (const char* o : {"==", "!=", "<=", ">=", "<", ">"}) {
      if (!op(o)) continue;
      Value b = sum();
      const std::string so = o;
      if (a.kind == Value::text || b.kind == Value::text) {
        const std::string x = format(a), y = format(b);
        if (so == "==") return boolean(x == y);
        if (so == "!=") return boolean(x != y);
        die("'" + so + "' between strings in ${" + s_ + "}");
      }
      const double x = a.num, y = b.num;
      if (so == "==") return boolean(x == y);
      if (so == "!=") return boolean(x != y);
      if (so == "<=") return boolean(x <= y);
      if (so == ">=") return boolean(x >= y);
      if (so == "<") return boolean(x < y);
      return boolean(x > y);
    }
    return a;
  }
  Value sum() {
    Value v = product();
    for (;;) {
      if (op("+")) {
        Value r = product();
        if (v.kind == Value::text && r.kind == Value::text) v.str += r.str;
        else v = number(num(v, "+") + num(r, "+"), v.integer && r.integer);
      } else if (op("-")) {
        Value r = product();
        v = number(num(v, "-") - num(r, "-"), v.integer && r.integer);
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
        v = number(num(v, "*") * num(r, "*"), v.integer && r.integer);
      } else if (op("/")) {
        Value r = unary();
        const double d = num(r, "/");
        if (d == 0) die("division by zero in ${" + s_ + "}");
        v = number(num(v, "/") / d);
      } else if (op("%")) {
        Value r = unary();
        const double d = num(r, "%");
        if (d == 0) die("modulo by zero in ${" + s_ + "}");
        const double x = num(v, "%");
        v = number(x - d * std::floor(x / d), v.integer && r.integer);
      } else {
        return v;
      }
    }
  }
  Value unary() {
    if (op("-")) {
      Value v = unary();
      return number(-num(v, "-"), v.integer);
    }
    if (op("+")) return number(num(unary(), "+"));
    return power();
  }
  Value power() {
    Value v = primary();
    if (op("**")) {
      Value r = unary();  // right associative, binds tighter than a unary minus on its left
      const double p = std::pow(num(v, "**"), num(r, "**"));
      if (!std::isfinite(p)) die("'**' gives no finite number in ${" + s_ + "}");
      return number(p, v.integer && r.integer && r.num >= 0);
    }
    return v;
  }
  Value primary() {
    skip();
    if (i_ >= s_.size()) die("incomplete expression ${" + s_ + "}");
    const char c = s_[i_];
    if (c == '(') {
      ++i_;
      if (++depth_ > 200) die("expression nested too deeply");
      Value v = disjunction();
      --depth_;
      if (!op(")")) die("missing ')' in ${" + s_ + "}");
      return v;
    }
    if (c == '\'' || c == '"') {
      const std::size_t end = s_.find(c, i_ + 1);
      if (end == std::string::npos) die("unterminated string in ${" + s_ + "}");
      Value v{Value::text, 0, false, s_.substr(i_ + 1, end - i_ - 1)};
      i_ = end + 1;
      return v;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      double d = 0;
      auto r = std::from_chars(s_.data() + i_, s_.data() + s_.size(), d);
      if (r.ec != std::errc() || !std::isfinite(d)) die("bad number in ${" + s_ + "}");
      const bool integer = std::none_of(s_.data() + i_, r.ptr, [](char ch) { return ch == '.' || ch == 'e' || ch == 'E'; });
      i_ = static_cast<std::size_t>(r.ptr - s_.data());
      return number(d, integer);
    }
    if (!(std::isalpha(static_cast<unsigned char>(c)) || c == '_')) die(std::string("unexpected '") + c + "' in ${" + s_ + "}");
    std::size_t j = i_;
    while (j < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[j])) || s_[j] == '_' || s_[j] == '.')) ++j;
    std::string name = s_.substr(i_, j - i_);
    i_ = j;
    if (name.rfind("math.", 0) == 0) name = name.substr(5);
    skip();
    if (i_ < s_.size() && s_[i_] == '(') return call(name);
    if (name == "pi") return number(std::numbers::pi);
    if (name == "e") return number(std::numbers::e);
    if (name == "True" || name == "true") return boolean(true);
    if (name == "False" || name == "false") return boolean(false);
    if (const std::string* p = scope_.find(name)) return from_text(*p);
    die("unknown property '" + name + "' in ${" + s_ + "}");
  }
  Value call(const std::string& name) {
    ++i_;  // '('
    std::vector<Value> args;
    skip();
    if (!op(")")) {
      do args.push_back(disjunction());
      while (op(","));
      if (!op(")")) die("missing ')' after the arguments of " + name + "() in ${" + s_ + "}");
    }
    if (name == "xacro.load_yaml" || name == "load_yaml")
      die("load_yaml is not supported (docs/robots.md): write the values as xacro:property");
    auto one = [&](const char* what) {
      if (args.size() != 1) die(name + "() takes one argument in ${" + s_ + "}");
      return num(args[0], what);
    };
    auto checked = [&](double v) {
      if (!std::isfinite(v)) die(name + "() gives no finite number in ${" + s_ + "}");
      return number(v);
    };
    if (name == "radians") return number(one("radians") * std::numbers::pi / 180);
    if (name == "degrees") return number(one("degrees") * 180 / std::numbers::pi);
    if (name == "sin") return number(std::sin(one("sin")));
    if (name == "cos") return number(std::cos(one("cos")));
    if (name == "tan") return checked(std::tan(one("tan")));
    if (name == "asin") return checked(std::asin(one("asin")));
    if (name == "acos") return checked(std::acos(one("acos")));
    if (name == "atan") return number(std::atan(one("atan")));
    if (name == "sqrt") return checked(std::sqrt(one("sqrt")));
    if (name == "abs" || name == "fabs") {
      Value v = args.size() == 1 ? args[0] : Value{};
      return number(std::abs(one("abs")), v.integer);
    }
    if (name == "floor") return number(std::floor(one("floor")), true);
    if (name == "ceil") return number(std::ceil(one("ceil")), true);
    if (name == "atan2" || name == "pow" || name == "min" || name == "max") {
      if (args.size() != 2) die(name + "() takes two arguments in ${" + s_ + "}");
      const double a = num(args[0], name.c_str()), b = num(args[1], name.c_str());
      if (name == "atan2") return number(std::atan2(a, b));
      if (name == "pow") return checked(std::pow(a, b));
      const bool integer = args[0].integer && args[1].integer;
      return number(name == "min" ? std::min(a, b) : std::max(a, b), integer);
    }
    die("unsupported function " + name + "() in ${" + s_ + "}");
  }

  const std::string& s_;
  const Scope& scope_;
  const std::function<void(const std::string&)>& fail_;
  std::size_t i_ = 0;
  int depth_ = 0;
};

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
    copy_attributes(root, out_root, path);
    files_.push_back(path);
    children(root, out_root, global_);
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

  // $(find pkg), $(arg name) and ${expr} in attribute or text values; $${ and $$( stay literal.
  std::string eval(const std::string& text, const XMLElement* e, const Scope& scope) {
    if (text.find('$') == std::string::npos) return text;
    std::string out;
    const std::function<void(const std::string&)> f = [&](const std::string& m) { fail(e, "xacro: " + m); };
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
      const std::size_t end = text.find(open == '{' ? '}' : ')', i + 2);
      if (end == std::string::npos) f(std::string("unterminated ") + (open == '{' ? "${" : "$(") + " in \"" + text + "\"");
      const std::string inner = text.substr(i + 2, end - i - 2);
      if (open == '{') {
        out += format(Expr(inner, scope, f).run());
      } else {
        out += substitution(inner, e, scope);
      }
      i = end + 1;
    }
    return out;
  }

  std::string substitution(const std::string& inner, const XMLElement* e, const Scope& scope) {
    std::string kind, arg;
    {
      const std::string s = eval(inner, e, scope);
      const std::size_t sp = s.find(' ');
      kind = s.substr(0, sp);
      if (sp != std::string::npos) arg = s.substr(s.find_first_not_of(' ', sp) == std::string::npos ? s.size() : s.find_first_not_of(' ', sp));
      while (!arg.empty() && arg.back() == ' ') arg.pop_back();
    }
    if (kind == "find") {
      if (auto dir = packages_.find(arg)) return fs::absolute(*dir).lexically_normal().string();  // not relative to the includer
      fail(e, "xacro: $(find " + arg + "): no package '" + arg + "' on the package path (cell packages:, ROS_PACKAGE_PATH)");
    }
    if (kind == "arg") {
      if (auto it = args_.find(arg); it != args_.end()) return it->second;
      fail(e, "xacro: $(arg " + arg + "): no value (give xacro_args: in the cell or <xacro:arg name=\"" + arg +
                  "\" default=...>)");
    }
    fail(e, "xacro: unsupported substitution $(" + inner + ") (find, arg)");
  }

  std::string attr(const XMLElement* e, const char* name, const Scope& scope, bool needed = true) {
    const char* v = e->Attribute(name);
    if (!v) {
      if (needed) fail(e, std::string("<") + e->Name() + "> needs the attribute '" + name + "'");
      return {};
    }
    return eval(v, e, scope);
  }

  void copy_attributes(const XMLElement* from, XMLElement* to, const std::string&) {
    for (const tinyxml2::XMLAttribute* a = from->FirstAttribute(); a; a = a->Next()) {
      if (std::strncmp(a->Name(), "xmlns", 5) == 0) continue;
      const std::string v = eval(a->Value(), from, global_);
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

  void element(const XMLElement* e, XMLNode* out, Scope& scope) {
    if (!is_xacro(e)) {
      XMLElement* copy = out_.NewElement(e->Name());
      grow(std::strlen(e->Name()) * 2 + 5, e);
      for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
        const std::string v = eval(a->Value(), e, scope);
        grow(v.size() + std::strlen(a->Name()) + 4, e);
        copy->SetAttribute(a->Name(), v.c_str());
      }
      out->InsertEndChild(copy);
      children(e, copy, scope);
      return;
    }
    const std::string tag = e->Name() + 6;
    if (tag == "property") {
      const std::string name = attr(e, "name", scope);
      if (e->Attribute("value")) {
        scope.props[name] = attr(e, "value", scope);
      } else if (e->Attribute("default")) {
        if (!scope.find(name)) scope.props[name] = attr(e, "default", scope);
      } else {
        scope.blocks[name] = e;  // block property: its children
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
      const std::string name = attr(e, "name", scope);
      std::string params = e->Attribute("params") ? e->Attribute("params") : "";
      std::istringstream in(params);
      for (std::string p; in >> p;) {
        if (p.find(":=^") != std::string::npos || p.find("^|") != std::string::npos)
          fail(e, "<xacro:macro name=\"" + name + "\">: parameter '" + p + "': ^ (outer scope) defaults are not supported");
        m.params.push_back(p);
      }
      macros_[name] = std::move(m);
      return;
    }
    if (tag == "include") return include(e, out, scope);
    if (tag == "if" || tag == "unless") {
      const std::string v = attr(e, "value", scope);
      bool b = false;
      if (v == "true" || v == "True") b = true;
      else if (v == "false" || v == "False") b = false;
      else {
        const Value x = from_text(v);
        if (x.kind == Value::text) fail(e, "<xacro:" + tag + " value=\"" + v + "\">: a boolean or a number is expected");
        b = x.num != 0;
      }
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
    if (auto it = macros_.find(tag); it != macros_.end()) return call(e, it->second, out, scope);
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
    files_.push_back(file);
    children(root, out, scope);
    files_.pop_back();
  }

  void call(const XMLElement* e, const Macro& m, XMLNode* out, Scope& caller) {
    if (macro_depth_ >= kMaxXacroMacroDepth)
      fail(e, "<" + std::string(e->Name()) + ">: macros nested more than " + std::to_string(kMaxXacroMacroDepth) + " deep (recursion?)");
    Scope local;
    local.parent = &global_;
    std::vector<const XMLElement*> given;
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) given.push_back(c);
    std::size_t next = 0;
    std::map<std::string, bool> known;
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
        local.props[name] = eval(v, e, caller);
      } else if (d != std::string::npos) {
        local.props[name] = eval(p.substr(d + 2), m.def, global_);
      } else {
        fail(e, "<" + std::string(e->Name()) + ">: missing the parameter '" + name + "'");
      }
    }
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next())
      if (!known.count(a->Name())) fail(e, "<" + std::string(e->Name()) + ">: the macro has no parameter '" + a->Name() + "'");
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
  Scope global_;
  XMLDocument out_;
  std::size_t out_bytes_ = 0;
  int macro_depth_ = 0;
  int block_depth_ = 0;
};
}  // namespace

std::string expand_xacro(const std::string& path, const PackagePath& packages, const std::map<std::string, std::string>& args) {
  return Expander(packages, args).run(path);
}

}  // namespace asimov::robots
