// Result<T> in tests: the value, or a failed test that names the Error; the error's message.
#pragma once
#include "asimov/core/result.hpp"

#include <catch2/catch.hpp>

#include <string>
#include <utility>

namespace asimov::test {

template <class T>
T must(Result<T> r) {
  if (!r) FAIL("unexpected error: " << r.error().message);
  return std::move(r).value();
}

// "no error" when `r` holds a value.
template <class T>
std::string error_message(const Result<T>& r) {
  return r ? std::string("no error") : r.error().message;
}

}  // namespace asimov::test
