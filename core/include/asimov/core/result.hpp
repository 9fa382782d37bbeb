// The one error convention of asimov (docs/design.md "Errors"): across a layer boundary a
// problem is a value, never an exception. A load-time call returns Result<T> (the value, or the
// Error that prevented it); a run-time call returns its layer's result struct with a status
// (motion::MotionResult, interpreter::RunResult) whose failure carries an Error.
#pragma once
#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace asimov {

// What went wrong, in the words the user sees, and where when known.
struct Error {
  std::string message;  // "*Location out of reach*", or a sentence ("robot.urdf:12: joint ...")
  std::string detail;   // short detail after the message, may be empty
  std::string file;     // the file at fault, when there is one
  int line = 0;         // 1-based line in `file`, 0 if unknown
  int column = 0;       // 1-based column in `line`, 0 if unknown
};

// A value or the Error that prevented it: a small std::expected (C++23) for C++20.
template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : v_(std::in_place_index<0>, std::move(value)) {}
  Result(Error error) : v_(std::in_place_index<1>, std::move(error)) {}

  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  // The value; only when ok().
  T& value() & { return std::get<0>(v_); }
  const T& value() const& { return std::get<0>(v_); }
  T&& value() && { return std::get<0>(std::move(v_)); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  // The error; only when !ok().
  const Error& error() const { return std::get<1>(v_); }

 private:
  std::variant<T, Error> v_;
};

// Success, or the Error.
template <>
class [[nodiscard]] Result<void> {
 public:
  Result() = default;
  Result(Error error) : error_(std::move(error)) {}

  bool ok() const { return !error_; }
  explicit operator bool() const { return ok(); }
  const Error& error() const { return *error_; }

 private:
  std::optional<Error> error_;
};

}  // namespace asimov
