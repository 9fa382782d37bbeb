// Named limits of the dialect and of this implementation (dialect §1, §2, §6).
#pragma once
#include <cstddef>

namespace asimov::interpreter {

constexpr std::size_t kNameLength = 15;        // significant characters of a name
constexpr std::size_t kMaxStringLength = 128;  // characters in a string value
constexpr int kMaxArrayIndex = 65535;          // highest array index
constexpr unsigned kMaxLabel = 65535;          // highest statement label
constexpr int kMaxSubscripts = 3;              // a[i,j,k]
constexpr std::size_t kMaxLoadErrors = 20;     // syntax errors reported per LOAD

}  // namespace asimov::interpreter
