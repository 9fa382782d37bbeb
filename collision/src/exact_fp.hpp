// Include FIRST in a translation unit that computes exact signs (predicates, face test):
// forbids FMA contraction and fast-math, and insists on SSE2-style double evaluation.
// CMake also builds those files with -ffp-contract=off; the pragmas keep that true for other
// builds (a fused a*b-c breaks Dekker's split and Shewchuk's error bounds).
#pragma once
#include <cfloat>

#if defined(__clang__)
#pragma clang fp contract(off)
#elif defined(__GNUC__)
#pragma GCC optimize("fp-contract=off")
#endif
#if defined(__FAST_MATH__)
#error "exact predicates must not be built with fast-math: the error bounds need IEEE arithmetic"
#endif
#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
#error "exact predicates need FLT_EVAL_METHOD == 0 (SSE2 doubles, not x87 extended precision)"
#endif
