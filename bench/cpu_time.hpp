// CPU time of the calling thread [us]: the benches compare ratios against a peer in the same run,
// and thread CPU time does not depend on how busy the shared machine is (Lua's os.clock() is CPU
// time too).
#pragma once
#include <ctime>

inline double cpu_us() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e6 + static_cast<double>(t.tv_nsec) / 1e3;
}
