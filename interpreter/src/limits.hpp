// Named limits of the dialect and of this implementation (dialect §1, §2, §6).
#pragma once
#include <cstddef>
#include <cstdint>

namespace asimov::interpreter {

constexpr std::size_t kNameLength = 15;        // significant characters of a name
constexpr std::size_t kMaxStringLength = 128;  // characters in a string value
constexpr int kMaxArrayIndex = 65535;          // highest array index
constexpr unsigned kMaxLabel = 65535;          // highest statement label
constexpr int kMaxSubscripts = 3;              // a[i,j,k]
constexpr std::size_t kMaxIoItems = 1000;      // items of one READ or WRITE
constexpr std::size_t kMaxLoadErrors = 20;     // syntax errors reported per LOAD
// Tasks (dialect §7b): numbers 0 ... 27 (V+ with its extensions); a task that does not give way
// runs one time slice of kSliceStatements steps, which lasts kSliceS on the simulated clock.
constexpr int kMaxTask = 27;
constexpr std::uint64_t kSliceStatements = 1000;
constexpr double kSliceS = 0.001;
// Array data of all programs of a process (values.hpp, docs/limits.md): ~1 million elements,
// far above a controller's few MB, far below the machine; reached in about a second.
constexpr std::size_t kMaxDataBytes = std::size_t{256} << 20;
// Expressions are parsed, checked, compiled and evaluated by recursion per level of nesting
// (a run of binary operators is one n-ary node, walked by loops: code.hpp); a statement past
// these limits is refused at load with *Expression too complex* (docs/limits.md). Nesting: far
// above what a person writes, far below what the stack holds, also under AddressSanitizer.
// Operators: only memory bounds them (about 320 bytes each while loading, docs/limits.md): one
// statement, and one file, stay within about 3 GB, where a 64 MiB file could take 10.
constexpr int kMaxExpressionNesting = 64;            // parentheses, brackets, calls and signs inside one another
constexpr int kMaxExpressionOperators = 10'000'000;  // operators in one statement
// And in one file, all its statements together: a 64 MiB file of many lines took 9.4 GB.
constexpr std::int64_t kMaxFileOperators = 10'000'000;

}  // namespace asimov::interpreter
