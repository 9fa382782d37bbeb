// The docs/api.md examples (engine_query.cpp, ik.cpp, run_program.cpp); main.cpp checks them.
#pragma once
#include <string>

bool cubes_touch(double gap_mm);                 // asimov::collision
double ik_round_trip_error_mm();                 // asimov::robots
std::string run_and_name_contact(const std::string& v2_file);  // asimov::interpreter + asimov::cell
