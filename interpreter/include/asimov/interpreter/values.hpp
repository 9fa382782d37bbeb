// Runtime values and variables (dialect §2) and the default number format (§3).
#pragma once
#include "asimov/motion/location.hpp"
#include "asimov/robots/robot.hpp"
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace asimov::interpreter {

enum class Kind : unsigned char { real, string, trans, ppoint };

// A real, a string, a transformation or a precision point (display joint values).
using Value = std::variant<double, std::string, motion::Location, robots::JointVector>;

inline Kind kind_of(const Value& v) { return static_cast<Kind>(v.index()); }
const char* kind_name(Kind kind);

// The value as a real; anything else is an *Illegal value* naming `what`.
double to_real(const Value& v, const char* what = "number expected");
const std::string& to_string_value(const Value& v);
// The checked result of arithmetic: non-finite is an *Illegal value*.
[[noreturn]] void raise_not_finite();
inline double finite(double x) {
  if (!std::isfinite(x)) raise_not_finite();
  return x;
}
// Integer contexts (indices, counts): nearest, halves away from zero.
int to_index(double x);

using Index = std::array<int, 3>;

// The elements of an array, sorted by index (listings, STORE, LAST). Elements of the form
// a[i] (i.e. [i,0,0]) are also found in O(1) through a dense table of pointers into the map
// (its nodes never move); other indices take the map lookup.
class Elements {
 public:
  using Map = std::map<Index, Value>;
  Elements() = default;
  Elements(const Elements& other) : map_(other.map_) { reindex(); }
  Elements(Elements&&) noexcept = default;  // map nodes move with the map
  Elements& operator=(const Elements& other) {
    if (this != &other) map_ = other.map_, reindex();
    return *this;
  }
  Elements& operator=(Elements&&) noexcept = default;

  bool empty() const { return map_.empty(); }
  std::size_t size() const { return map_.size(); }
  Map::const_iterator begin() const { return map_.begin(); }
  Map::const_iterator end() const { return map_.end(); }
  Map::iterator begin() { return map_.begin(); }
  Map::iterator end() { return map_.end(); }
  Map::const_reverse_iterator rbegin() const { return map_.rbegin(); }
  Map::const_reverse_iterator rend() const { return map_.rend(); }

  // The element, or null.
  Value* get(const Index& i) {
    if (i[1] == 0 && i[2] == 0 && i[0] >= 0) return static_cast<std::size_t>(i[0]) < dense_.size() ? dense_[static_cast<std::size_t>(i[0])] : nullptr;
    const auto it = map_.find(i);
    return it == map_.end() ? nullptr : &it->second;
  }
  std::size_t count(const Index& i) const { return const_cast<Elements*>(this)->get(i) ? 1 : 0; }
  // Inserts or assigns.
  Value& set(const Index& i, Value v) {
    if (Value* e = get(i)) return *e = std::move(v);
    // Filling an array in index order appends: the hint skips the search from the root.
    const auto hint = map_.empty() || map_.rbegin()->first < i ? map_.end() : map_.lower_bound(i);
    Value& e = map_.emplace_hint(hint, i, std::move(v))->second;
    note(i, &e);
    return e;
  }
  Value& operator[](const Index& i) {
    if (Value* e = get(i)) return *e;
    return set(i, Value{});
  }

 private:
  void note(const Index& i, Value* e) {
    if (i[1] != 0 || i[2] != 0 || i[0] < 0) return;
    const auto k = static_cast<std::size_t>(i[0]);
    if (k >= dense_.size()) dense_.resize(k + 1, nullptr);
    dense_[k] = e;
  }
  void reindex() {
    dense_.clear();
    for (auto& [i, v] : map_) note(i, &v);
  }

  Map map_;
  std::vector<Value*> dense_;  // [i] -> the element a[i], or null
};

// One named variable: a scalar or an array, never both. Elements grow on assignment.
struct Variable {
  std::optional<Value> scalar;            // scalar value, when assigned
  Elements elements;                      // array elements, when assigned
  bool is_array() const { return !elements.empty(); }
};

// Default number format of TYPE (dialect §3).
std::string format_number(double x);

}  // namespace asimov::interpreter
