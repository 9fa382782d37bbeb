// Path strings against core::ConfinedFolder (docs/design.md "Confinement"). A fixed tree with
// links that lead out (relative, absolute, from below, through `..`), links that stay inside,
// a FIFO and a loop; each input is one name. The kernel's resolution (openat2) and the walk must
// give the same answer, and whatever opens must be a regular file inside the folder: its inode
// one of the tree's own files (the files outside are never among them).
#include "asimov/core/confined_folder.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <utility>

#include <sys/stat.h>
#include <unistd.h>

namespace fs = std::filesystem;
using asimov::core::ConfinedFolder;

namespace {

struct Tree {
  fs::path p;
  std::set<std::pair<dev_t, ino_t>> inside;  // the regular files beneath p
  Tree() {
    const fs::path top = fs::temp_directory_path() / ("asimov-fuzz-paths-" + std::to_string(::getpid()));
    fs::remove_all(top);
    p = top / "p";
    const fs::path o = top / "o";
    fs::create_directories(p / "a" / "b");
    fs::create_directories(o / "sub");
    for (const fs::path& f : {p / "f", p / "a" / "f", p / "a" / "b" / "f"}) std::ofstream(f) << "in\n";
    for (const fs::path& f : {o / "f", o / "sub" / "f", top / "f"}) std::ofstream(f) << "out\n";
    fs::create_symlink("../o", p / "out");
    fs::create_symlink(o, p / "abs");
    fs::create_symlink("/etc", p / "etc");
    fs::create_symlink("../../../o", p / "a" / "b" / "up3");
    fs::create_symlink("../..", p / "a" / "b" / "up2");  // p itself: inside
    fs::create_symlink("b/up2/f", p / "a" / "in");
    fs::create_symlink("loop", p / "loop");
    fs::create_symlink("nothing", p / "dangling");
    ::mkfifo((p / "fifo").c_str(), 0600);
    for (const auto& e : fs::recursive_directory_iterator(p)) {
      struct stat st {};
      if (!e.is_symlink() && e.is_regular_file() && ::stat(e.path().c_str(), &st) == 0) inside.insert({st.st_dev, st.st_ino});
    }
  }
  ~Tree() {
    std::error_code ec;
    fs::remove_all(p.parent_path(), ec);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Tree tree;
  static auto kernel = ConfinedFolder::open(tree.p, ConfinedFolder::Resolver::kernel);
  static auto walk = ConfinedFolder::open(tree.p, ConfinedFolder::Resolver::walk);
  if (!kernel || !walk) std::abort();
  const std::string name(reinterpret_cast<const char*>(data), size);

  auto a = kernel.value->open_read(name);
  auto b = walk.value->open_read(name);
  if (static_cast<bool>(a) != static_cast<bool>(b)) std::abort();
  if (!a && a.error.kind != b.error.kind) std::abort();
  if (a) {
    struct stat st {};
    if (::fstat(a.value->get(), &st) != 0 || !S_ISREG(st.st_mode)) std::abort();
    if (!tree.inside.count({st.st_dev, st.st_ino})) std::abort();  // a file outside was opened
  }
  auto la = kernel.value->list(name, 1000);
  auto lb = walk.value->list(name, 1000);
  if (static_cast<bool>(la) != static_cast<bool>(lb) || (la && *la.value != *lb.value)) std::abort();
  // A new file is only ever made beneath the folder; it is discarded, the tree stays as it is.
  auto created = kernel.value->create(name);
  auto created_walk = walk.value->create(name);
  if (static_cast<bool>(created) != static_cast<bool>(created_walk)) std::abort();
  return 0;
}
