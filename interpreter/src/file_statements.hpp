// Stage 3, file I/O (dialect §7a): ATTACH / DETACH, FOPENR ... / FCLOSE, READ / WRITE on disk
// units, IOSTAT() and GETC(), over the logical units of files.hpp. All units are closed (what
// was written committed) at the end of every run.
#pragma once
#include "code.hpp"
#include "files.hpp"

namespace asimov::interpreter {

class Evaluator;

class FileStatements {
 public:
  explicit FileStatements(Evaluator& vm) : vm_(vm) {}
  void begin_run(const Limits& limits);       // the files' folder and size limits of this run
  void end_run() { units_.close_all(); }
  void execute(const Instr& in);              // the io instruction (Instr::io says which)
  double function(const Node& n);             // IOSTAT(lun [, mode]), GETC(lun [, mode])

 private:
  int unit_number(const Instr& in);

  Evaluator& vm_;                             // the items' values and the variables READ sets
  FileUnits units_;                           // logical units; all closed at the end of a run
};

}  // namespace asimov::interpreter
