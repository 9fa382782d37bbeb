// Runs the docs/api.md examples against the installed asimov and checks their answers.
// usage: consumer PREFIX/share/asimov/programs
#include "examples.hpp"

#include "asimov/version.hpp"

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer PROGRAMS_DIR\n");
    return 1;
  }
  const std::string programs = argv[1];
  int failures = 0;
  const auto expect = [&](bool ok, const char* what) {
    std::printf("%s: %s\n", ok ? "ok" : "FAILED", what);
    failures += ok ? 0 : 1;
  };
  std::printf("asimov %s\n", asimov::kVersion);
  expect(!cubes_touch(1.0), "cubes 1 mm apart do not touch");
  expect(cubes_touch(0.0), "cubes face to face touch");
  expect(cubes_touch(-10.0), "overlapping cubes touch");
  const double ik_error = ik_round_trip_error_mm();
  expect(ik_error >= 0 && ik_error < 1e-6, "PUMA 560 IK reproduces the FK pose");
  expect(run_and_name_contact(programs + "/demo/crash.v2") == "link4 / box", "crash.v2 stops on link4 / box");
  expect(run_and_name_contact(programs + "/demo/pick_place.v2") == "completed", "pick_place.v2 completes");
  expect(run_and_name_contact(programs + "/no-such-file.v2").find("*File not found*") != std::string::npos,
         "a missing file is a VAL diagnostic");
  return failures == 0 ? 0 : 1;
}
