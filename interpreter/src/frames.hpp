// The statement VM's call stack (value types): a frame per CALL, and the stack that reuses
// popped frames. The scheduler keeps one stack per task and swaps it with the running one.
#pragma once
#include "code.hpp"
#include "asimov/interpreter/values.hpp"

#include <cstddef>
#include <iterator>
#include <vector>

namespace asimov::interpreter {

struct Frame {
  const Program* program = nullptr;              // kept alive by Memory or Stopped::pinned
  std::vector<Variable*> params;                 // by reference or into `owned`
  std::vector<Variable> owned;                   // by value, omitted, AUTO (reserved: stable)
  std::vector<double> temps;                     // FOR limits and steps
  int pc = 0;                                    // next instruction
  int restore_priority = -1;                     // a reaction's frame: the priority its RETURN restores
  bool trap = false;                             // the REACTE program's frame
};

// The call stack. Popped frames stay allocated and are reused by the next CALL, with their
// vectors' capacity and their (emptied) variables: no construction, move or allocation per
// CALL. back() is valid until the next next().
class FrameStack {
 public:
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  Frame& back() { return frames_[size_ - 1]; }
  // The frame above the top, cleared (its owned variables are emptied as they are taken),
  // filled by the caller, then pushed by commit().
  Frame& next() {
    if (size_ == frames_.size()) frames_.emplace_back();
    Frame& f = frames_[size_];
    f.program = nullptr;
    f.params.clear();
    f.temps.clear();
    f.pc = 0;
    f.restore_priority = -1;
    f.trap = false;
    return f;
  }
  // A frame that runs `program` from its start with every parameter omitted (a run, a task).
  Frame& push_top(const Program& program) {
    Frame& top = next();
    top.program = &program;
    top.owned.clear();
    top.owned.resize(program.params.size() + program.autos.size());
    for (Variable& v : top.owned) top.params.push_back(&v);
    top.temps.resize(static_cast<std::size_t>(program.temps));
    commit();
    return top;
  }
  void commit() { ++size_; }
  void pop() { --size_; }
  void clear() { size_ = 0; }
  std::vector<Frame> take() {  // the frames, for a stopped execution
    std::vector<Frame> out(std::make_move_iterator(frames_.begin()),
                           std::make_move_iterator(frames_.begin() + static_cast<std::ptrdiff_t>(size_)));
    frames_.clear();
    size_ = 0;
    return out;
  }
  void assign(std::vector<Frame> frames) {
    frames_ = std::move(frames);
    size_ = frames_.size();
  }

 private:
  std::vector<Frame> frames_;
  std::size_t size_ = 0;
};

}  // namespace asimov::interpreter
