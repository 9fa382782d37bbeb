#include "duplicate_keys.hpp"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/exceptions.h>
#include <yaml-cpp/parser.h>

#include <map>
#include <sstream>
#include <vector>

namespace asimov::cell {
namespace {

// One open collection: for a map, whether the next node is a key and the keys seen so far.
struct Frame {
  bool map = false;
  bool expect_key = true;
  std::map<std::string, int> keys;  // key -> line it was first given
};

class KeyCheck : public YAML::EventHandler {
 public:
  std::optional<DuplicateKey> found;

  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t) override { node(mark, nullptr); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override { node(mark, nullptr); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t, const std::string& value) override {
    node(mark, &value);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    node(mark, nullptr);
    stack_.push_back({});
  }
  void OnSequenceEnd() override { stack_.pop_back(); }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    node(mark, nullptr);
    stack_.push_back({true, true, {}});
  }
  void OnMapEnd() override { stack_.pop_back(); }

 private:
  // A node starts inside the innermost open collection: in a map it is a key or a value, in turn.
  void node(const YAML::Mark& mark, const std::string* scalar) {
    if (stack_.empty() || !stack_.back().map) return;
    Frame& f = stack_.back();
    const bool is_key = f.expect_key;
    f.expect_key = !f.expect_key;
    if (!is_key || !scalar || found) return;
    const auto [it, inserted] = f.keys.emplace(*scalar, mark.line + 1);
    if (!inserted) found = DuplicateKey{*scalar, mark.line + 1, mark.column + 1, it->second};
  }

  std::vector<Frame> stack_;
};

}  // namespace

std::optional<DuplicateKey> first_duplicate_key(const std::string& yaml) {
  std::istringstream in(yaml);
  KeyCheck check;
  try {
    YAML::Parser parser(in);
    parser.HandleNextDocument(check);
  } catch (const YAML::Exception&) {
    // A syntax error: YAML::Load reports it with its place. Keys before it were checked.
  }
  return check.found;
}

}  // namespace asimov::cell
