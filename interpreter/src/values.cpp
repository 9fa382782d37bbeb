#include "asimov/interpreter/values.hpp"

#include "errors.hpp"
#include "limits.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>

namespace asimov::interpreter {
namespace {

std::atomic<std::size_t> g_data_bytes{0};

// A map node: the element, the tree's three links and colour, the allocator's header.
constexpr std::size_t kNodeBytes = sizeof(Elements::Map::value_type) + 4 * sizeof(void*) + 16;
// The heap of the longest string value (kMaxStringLength characters and the terminator).
constexpr std::size_t kStringHeapBytes = kMaxStringLength + 1 + 16;
constexpr std::size_t kDenseLimit = kMaxArrayIndex + 1;  // a[0]..a[65535]

}  // namespace

std::size_t data_bytes() { return g_data_bytes.load(std::memory_order_relaxed); }

void charge_data(std::size_t bytes) {
  if (bytes == 0) return;
  const std::size_t before = g_data_bytes.fetch_add(bytes, std::memory_order_relaxed);
  if (before + bytes <= kMaxDataBytes) return;
  g_data_bytes.fetch_sub(bytes, std::memory_order_relaxed);
  raise(Message::out_of_memory, fmt::format("the program's data would exceed {} MiB", kMaxDataBytes >> 20));
}

void release_data(std::size_t bytes) noexcept { g_data_bytes.fetch_sub(bytes, std::memory_order_relaxed); }

std::size_t Elements::element_bytes(const Value& v) {
  return kNodeBytes + (std::holds_alternative<std::string>(v) ? kStringHeapBytes : 0);
}

Value& Elements::set(const Index& i, Value v) {
  if (Value* e = get(i)) {
    // Only a caller mixing kinds in one array changes an element's charge (the evaluator never does).
    const std::size_t before = element_bytes(*e), after = element_bytes(v);
    if (after > before) charge_data(after - before);
    *e = std::move(v);
    if (before > after) release_data(before - after);
    bytes_ += after - before;  // modular: a decrease wraps back
    return *e;
  }
  const bool dense = i[1] == 0 && i[2] == 0 && i[0] >= 0;
  if (dense) reserve_dense(static_cast<std::size_t>(i[0]) + 1);  // first: nothing to undo if it fails
  const std::size_t cost = element_bytes(v);
  charge_data(cost);
  Value* e = nullptr;
  try {
    // Filling an array in index order appends: the hint skips the search from the root.
    const auto hint = map_.empty() || map_.rbegin()->first < i ? map_.end() : map_.lower_bound(i);
    e = &map_.emplace_hint(hint, i, std::move(v))->second;
  } catch (...) {
    release_data(cost);
    throw;
  }
  bytes_ += cost;
  if (dense) note(static_cast<std::size_t>(i[0]), e);
  return *e;
}

// The dense table grows by doubling (up to the highest index) and is charged as it grows: one
// a[65535] costs a 512 KB table, so many arrays of one high element count too.
void Elements::reserve_dense(std::size_t size) {
  if (size <= dense_.capacity()) return;
  const std::size_t capacity = std::max(size, std::min(2 * dense_.capacity(), kDenseLimit));
  const std::size_t more = (capacity - dense_.capacity()) * sizeof(Value*);
  charge_data(more);
  try {
    dense_.reserve(capacity);
  } catch (...) {
    release_data(more);
    throw;
  }
  bytes_ += more;
}

void Elements::note(std::size_t k, Value* e) {
  if (k >= dense_.size()) dense_.resize(k + 1, nullptr);  // within the reserved capacity
  dense_[k] = e;
}

Elements::Elements(const Elements& other) {
  charge_data(other.bytes_);
  bytes_ = other.bytes_;
  try {
    map_ = other.map_;
    dense_.reserve(other.dense_.capacity());  // what other's charge covers
  } catch (...) {
    clear();
    throw;
  }
  for (auto& [i, v] : map_)
    if (i[1] == 0 && i[2] == 0 && i[0] >= 0) note(static_cast<std::size_t>(i[0]), &v);
}

void Elements::clear() noexcept {
  map_.clear();
  dense_ = {};
  release_data(bytes_);
  bytes_ = 0;
}

const char* kind_name(Kind kind) {
  switch (kind) {
    case Kind::real: return "real";
    case Kind::string: return "string";
    case Kind::trans: return "transformation";
    case Kind::ppoint: return "precision point";
  }
  return "?";
}

double to_real(const Value& v, const char* what) {
  if (const double* d = std::get_if<double>(&v)) return *d;
  raise(Message::illegal_value, fmt::format("{}, not a {}", what, kind_name(kind_of(v))));
}

const std::string& to_string_value(const Value& v) {
  if (const std::string* s = std::get_if<std::string>(&v)) return *s;
  raise(Message::illegal_value, fmt::format("string expected, not a {}", kind_name(kind_of(v))));
}

void raise_not_finite() { raise(Message::illegal_value, "result is not a finite number"); }

int to_index(double x) {
  const double r = std::round(x);  // halves away from zero
  if (!(r >= -2e9 && r <= 2e9)) raise(Message::illegal_value, fmt::format("{} is outside the integers -2e9..2e9", x));
  return static_cast<int>(r);
}

std::string format_number(double x) {
  if (x == 0) return "0";  // also -0
  const double a = std::fabs(x);
  if (a < 1e15 && x == std::trunc(x)) return fmt::format("{:.0f}", x);
  if (a >= 1e-6 && a < 1e15) {
    std::string s = fmt::format("{:.6f}", x);
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
    if (s == "-0") return "0";
    return s;
  }
  return fmt::format("{:.6g}", x);
}

}  // namespace asimov::interpreter
