#include "examples.hpp"

#include "asimov/cell/cell_loader.hpp"
#include "asimov/interpreter/interpreter.hpp"

#include <iostream>

using namespace asimov;

// Loads a .v2 file into the built-in cell and runs its first program: "a / b" when the run
// stopped on a contact, the VAL error text when it failed, "completed" otherwise.
std::string run_and_name_contact(const std::string& v2_file) {
  motion::Simulator sim(cell::default_cell());  // or the value of a checked cell::load_cell_file("cell.yaml")
  interpreter::Interpreter interp(sim, std::cout);  // TYPE output goes to std::cout
  for (const interpreter::Diagnostic& d : interp.load_file(v2_file))
    if (!d.warning) return interpreter::format_diagnostic(d);  // "*Syntax error* ..." with file:line
  const interpreter::RunResult r = interp.run(interp.program_names().front());
  switch (r.status) {
    case interpreter::RunStatus::collision: return r.collision.body_a + " / " + r.collision.body_b;
    case interpreter::RunStatus::error: return interpreter::format_diagnostic(r.error);
    default: return "completed";
  }
}
