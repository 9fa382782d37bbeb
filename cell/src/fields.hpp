// The cell reader's typed field access (numbers, poses, shapes, key checks; errors with
// file:line:column), as an interface so the workcell keys (workcell.cpp) are read by the same
// rules as the rest of the cell without living in cell_loader.cpp.
#pragma once
#include "asimov/motion/cell.hpp"
#include <yaml-cpp/yaml.h>
#include <initializer_list>
#include <set>
#include <string>
#include <vector>

namespace asimov::cell {

class Fields {
 public:
  virtual ~Fields() = default;
  [[noreturn]] virtual void fail(const YAML::Node& node, const std::string& what) const = 0;
  // "file:line:column" of a node (for warnings and messages naming a second place).
  virtual std::string where(const YAML::Node& node) const = 0;
  virtual double number(const YAML::Node& node, const std::string& what) const = 0;
  virtual double positive(const YAML::Node& node, const std::string& what) const = 0;
  virtual bool boolean(const YAML::Node& node, const std::string& what) const = 0;
  virtual std::string text(const YAML::Node& node, const std::string& what) const = 0;
  virtual std::vector<double> numbers(const YAML::Node& node, std::size_t count, const std::string& what) const = 0;
  virtual motion::Location pose(const YAML::Node& node, const std::string& what) const = 0;
  virtual collision::Polyhedron shape(const YAML::Node& node, const std::string& what,
                                      std::vector<std::string>& warnings) const = 0;
  virtual void expect_keys(const YAML::Node& node, std::initializer_list<const char*> keys,
                           const std::string& what) const = 0;
};

// The top-level keys `parts`, `gripper`, `devices`, `logic` (docs/cell-format.md) into
// cell.workcell; conveyors also become static objects of the cell. `names` holds the body names
// taken so far (parts and conveyors are added).
void read_workcell(const YAML::Node& root, const Fields& f, motion::Cell& cell, std::set<std::string>& names);

}  // namespace asimov::cell
