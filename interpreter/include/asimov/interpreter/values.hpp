// Runtime values and variables (dialect §2) and the default number format (§3).
#pragma once
#include "asimov/motion/location.hpp"
#include "asimov/robots/robot.hpp"
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <utility>
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

// Memory of a program's data (docs/limits.md): every array element, the worst case of its
// string and the index tables are charged against kMaxDataBytes (limits.hpp) for all
// interpreters of the process, so a program filling a huge array stops with *Out of memory*
// within seconds instead of ending in std::bad_alloc or being killed by the OS.
std::size_t data_bytes();  // charged now
// Charges `bytes` or raises *Out of memory* (nothing charged); release() gives them back.
void charge_data(std::size_t bytes);
void release_data(std::size_t bytes) noexcept;

// The elements of an array, sorted by index (listings, STORE, LAST). Elements of the form
// a[i] (i.e. [i,0,0]) are also found in O(1) through a dense table of pointers into the map
// (its nodes never move); other indices take the map lookup. What the elements hold is
// charged (charge_data) and given back when they go.
class Elements {
 public:
  using Map = std::map<Index, Value>;
  // An element's bytes: the map node and, for a string, the largest heap a string value can
  // have (128 characters), so reassigning a string never needs a new charge.
  static std::size_t element_bytes(const Value& v);

  Elements() = default;
  Elements(const Elements& other);
  Elements(Elements&& other) noexcept  // map nodes move with the map
      : map_(std::move(other.map_)), dense_(std::move(other.dense_)), bytes_(std::exchange(other.bytes_, 0)) {
    other.clear();
  }
  Elements& operator=(const Elements& other) {
    if (this != &other) *this = Elements(other);
    return *this;
  }
  Elements& operator=(Elements&& other) noexcept {
    if (this == &other) return *this;
    clear();
    map_ = std::move(other.map_);
    dense_ = std::move(other.dense_);
    bytes_ = std::exchange(other.bytes_, 0);
    other.clear();
    return *this;
  }
  ~Elements() { release_data(bytes_); }

  bool empty() const { return map_.empty(); }
  std::size_t size() const { return map_.size(); }
  std::size_t bytes() const { return bytes_; }
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
  // Inserts or assigns; *Out of memory* past kMaxDataBytes.
  Value& set(const Index& i, Value v);
  // Empties the array and gives its bytes back.
  void clear() noexcept;

 private:
  void reserve_dense(std::size_t size);  // charged
  void note(std::size_t k, Value* e);    // dense_[k] = e, within the reserved size

  Map map_;
  std::vector<Value*> dense_;  // [i] -> the element a[i], or null
  std::size_t bytes_ = 0;      // charged for map_ and dense_
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
