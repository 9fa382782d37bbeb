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
// Array data of all programs of a process (values.hpp, docs/limits.md): ~1 million elements,
// far above a controller's few MB, far below the machine; reached in about a second.
constexpr std::size_t kMaxDataBytes = std::size_t{256} << 20;
// Expressions are parsed, checked, compiled and evaluated by recursion; a statement past these
// limits is refused at load with *Expression too complex* (docs/limits.md): far above what a
// person writes, far below what the stack holds, also under AddressSanitizer.
constexpr int kMaxExpressionNesting = 64;      // parentheses, brackets, calls and signs inside one another
constexpr int kMaxExpressionOperators = 1000;  // operators in one statement (a chain is as deep as it is long)

}  // namespace asimov::interpreter
