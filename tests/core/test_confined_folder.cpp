// core::ConfinedFolder: every route out of a folder is refused, by the kernel (openat2) and by
// the walk alike; only regular files are opened; whole writes and in-place appends lose nothing.
#include "asimov/core/confined_folder.hpp"
#include "support/scratch.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

using asimov::core::ConfinedFolder;
using asimov::core::FsRefusal;
namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string read_fd(int fd) {
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) > 0;) out.append(buf, static_cast<std::size_t>(n));
  return out;
}

// scratch/N/p is the folder; scratch/N/o lies outside it, with links from p leading there.
struct Tree {
  fs::path top, p, o;
  Tree() {
    static int count = 0;
    top = asimov::test::scratch_dir("confined" + std::to_string(++count));
    fs::remove_all(top);
    p = top / "p";
    o = top / "o";
    fs::create_directories(p / "sub");
    fs::create_directories(o);
    std::ofstream(o / "secret") << "secret\n";
    std::ofstream(p / "in.txt") << "inside\n";
    std::ofstream(p / "sub" / "deep.txt") << "deep\n";
    fs::create_symlink("../o", p / "out");                   // relative, leads out
    fs::create_symlink(o, p / "absout");                     // absolute, leads out
    fs::create_symlink("/etc/hostname", p / "host");         // absolute, a system file
    fs::create_symlink("/dev/zero", p / "zero");             // a device outside
    fs::create_symlink("sub/deep.txt", p / "inlink");        // stays inside
    fs::create_symlink("sub/../in.txt", p / "updown");       // stays inside through ..
    fs::create_symlink("../in.txt", p / "sub" / "back");     // sub/.. is p: inside
    fs::create_symlink("../../o/secret", p / "sub" / "far");  // leads out from below
    fs::create_symlink("loop", p / "loop");                  // a link to itself
    fs::create_symlink("missing.txt", p / "dangling");       // inside, to nothing
    REQUIRE(::mkfifo((p / "fifo").c_str(), 0600) == 0);
  }
  ConfinedFolder open(ConfinedFolder::Resolver r) const {
    auto f = ConfinedFolder::open(p, r);
    REQUIRE(f);
    return std::move(*f.value);
  }
};

const auto kResolvers = {ConfinedFolder::Resolver::kernel, ConfinedFolder::Resolver::walk};

}  // namespace

TEST_CASE("reads stay beneath the folder, by the kernel and by the walk", "[confined]") {
  Tree t;
  for (auto r : kResolvers) {
    INFO((r == ConfinedFolder::Resolver::kernel ? "kernel" : "walk"));
    const ConfinedFolder f = t.open(r);
    const std::pair<const char*, const char*> inside[] = {
        {"in.txt", "inside\n"}, {"./in.txt", "inside\n"}, {"sub/../in.txt", "inside\n"}, {"inlink", "deep\n"},
        {"updown", "inside\n"}, {"sub/back", "inside\n"}, {"sub//deep.txt", "deep\n"}};
    for (const auto& [name, text] : inside) {
      INFO(name);
      auto fd = f.open_read(name);
      REQUIRE(fd);
      CHECK(read_fd(fd.value->get()) == text);
    }
    // Out by `..`, by a relative or absolute link, by a link below, by an absolute name.
    for (const char* out : {"../o/secret", "sub/../../o/secret", "out/secret", "absout/secret", "host", "zero",
                            "sub/far", "sub/../out/secret", "/etc/hostname", "..", "sub/../.."}) {
      INFO(out);
      auto fd = f.open_read(out);
      CHECK_FALSE(fd);
      CHECK(fd.error.kind == FsRefusal::outside);
    }
    // Through a folder that does not exist and back: the kernel walks `x` first, so it is not
    // found, and nothing is read.
    auto ghost = f.open_read("x/../out/secret");
    CHECK_FALSE(ghost);
    CHECK(ghost.error.kind == FsRefusal::not_found);
    // Only regular files: a FIFO is refused without blocking, a folder and a loop by name.
    auto fifo = f.open_read("fifo");
    CHECK(fifo.error.kind == FsRefusal::not_regular);
    CHECK(fifo.error.why == "is a FIFO, not a regular file");
    CHECK(f.open_read("sub").error.kind == FsRefusal::is_folder);
    CHECK(f.open_read("loop").error.kind == FsRefusal::bad_name);
    CHECK(f.open_read("dangling").error.kind == FsRefusal::not_found);
    CHECK(f.open_read("").error.kind == FsRefusal::bad_name);
    CHECK(f.open_read(std::string("in.txt\0x", 8)).error.kind == FsRefusal::bad_name);
    CHECK(f.open_read(std::string(5000, 'a')).error.kind == FsRefusal::bad_name);
    CHECK(f.is_file("inlink"));
    CHECK_FALSE(f.is_file("out/secret"));
    CHECK_FALSE(f.is_file("fifo"));
  }
}

TEST_CASE("writes, appends, truncation, removal and listing never reach outside", "[confined]") {
  for (auto r : kResolvers) {
    INFO((r == ConfinedFolder::Resolver::kernel ? "kernel" : "walk"));
    Tree t;
    const ConfinedFolder f = t.open(r);
    for (const char* out : {"out/new.txt", "x/../out/new.txt", "absout/new.txt", "sub/../../o/new.txt"}) {
      INFO(out);
      auto created = f.create(out);
      CHECK_FALSE(created);
      CHECK((created.error.kind == FsRefusal::outside || created.error.kind == FsRefusal::not_found));
      CHECK_FALSE(f.open_append(out));
    }
    CHECK(f.open_append("out/secret").error.kind == FsRefusal::outside);
    CHECK(f.truncate("out/secret").error.kind == FsRefusal::outside);
    CHECK(f.truncate("sub/far").error.kind == FsRefusal::outside);
    CHECK(f.remove("out/secret").error.kind == FsRefusal::outside);
    CHECK(f.list("out", 100).error.kind == FsRefusal::outside);
    CHECK(f.list("..", 100).error.kind == FsRefusal::outside);
    CHECK(f.open_append("fifo").error.kind == FsRefusal::not_regular);
    CHECK(f.truncate("fifo").error.kind == FsRefusal::not_regular);
    CHECK(f.remove("sub").error.kind == FsRefusal::is_folder);
    CHECK(f.remove("fifo").error.kind == FsRefusal::not_regular);
    CHECK(f.open_append("dangling").error.kind == FsRefusal::not_regular);
    CHECK(slurp(t.o / "secret") == "secret\n");
    CHECK(fs::directory_iterator(t.o) != fs::directory_iterator());
    CHECK(std::distance(fs::directory_iterator(t.o), fs::directory_iterator()) == 1);
    // Removing the link that leads out removes the link, never what it points to.
    REQUIRE(f.remove("out"));
    CHECK_FALSE(fs::is_symlink(t.p / "out"));
    CHECK(slurp(t.o / "secret") == "secret\n");
    // Inside, everything works; the listing is sorted and holds the links as names.
    auto names = f.list(".", 100);
    REQUIRE(names);
    CHECK(names.value->front() == "absout");
    CHECK(f.list(".", 3).error.kind == FsRefusal::io);
    REQUIRE(f.truncate("in.txt"));
    CHECK(slurp(t.p / "in.txt").empty());
    REQUIRE(f.remove("in.txt"));
    CHECK_FALSE(fs::exists(t.p / "in.txt"));
    CHECK(f.remove("in.txt").error.kind == FsRefusal::not_found);
  }
}

TEST_CASE("a new file appears whole, under its name only if the name is still free", "[confined]") {
  for (auto r : kResolvers) {
    Tree t;
    const ConfinedFolder f = t.open(r);
    CHECK(f.create("in.txt").error.kind == FsRefusal::exists);
    CHECK(f.create("dangling").error.kind == FsRefusal::exists);  // a link is a taken name
    CHECK(f.create("sub/").error.kind == FsRefusal::bad_name);
    CHECK(f.create("sub/..").error.kind == FsRefusal::bad_name);
    auto created = f.create("sub/new.txt");
    REQUIRE(created);
    REQUIRE(asimov::core::write_all(created.value->fd(), "whole\n"));
    CHECK_FALSE(fs::exists(t.p / "sub" / "new.txt"));  // not there until committed
    REQUIRE(created.value->commit());
    CHECK(slurp(t.p / "sub" / "new.txt") == "whole\n");
    // The name taken meanwhile: commit refuses and the other file stays as it is.
    auto second = f.create("race.txt");
    REQUIRE(second);
    std::ofstream(t.p / "race.txt") << "first\n";
    auto done = second.value->commit();
    CHECK(done.error.kind == FsRefusal::exists);
    CHECK(slurp(t.p / "race.txt") == "first\n");
    // Discarded (or destroyed) without commit: nothing is left.
    { auto gone = f.create("gone.txt"); REQUIRE(gone); }
    int temporaries = 0;
    for (const auto& e : fs::recursive_directory_iterator(t.p)) temporaries += e.path().filename().string()[0] == '.';
    CHECK(temporaries == 0);
    // replace = true replaces a regular file, never a link or a FIFO.
    auto again = f.create("race.txt", true);
    REQUIRE(again);
    REQUIRE(asimov::core::write_all(again.value->fd(), "second\n"));
    REQUIRE(again.value->commit());
    CHECK(slurp(t.p / "race.txt") == "second\n");
    CHECK(f.create("inlink", true).error.kind == FsRefusal::not_regular);
    CHECK(f.create("fifo", true).error.kind == FsRefusal::not_regular);
  }
}

TEST_CASE("appends from many writers at once keep every record", "[confined]") {
  Tree t;
  const ConfinedFolder f = t.open(ConfinedFolder::Resolver::kernel);
  constexpr int kWriters = 4, kRecords = 2000;
  std::vector<std::thread> writers;
  std::atomic<int> failures{0};
  for (int w = 0; w < kWriters; ++w)
    writers.emplace_back([&, w] {
      auto fd = f.open_append("log.txt");  // each its own open file, as separate runs have
      if (!fd) { ++failures; return; }
      for (int i = 0; i < kRecords; ++i)
        if (!asimov::core::append_whole(fd.value->get(), "writer " + std::to_string(w) + " record " + std::to_string(i) + "\r\n")) ++failures;
    });
  for (auto& w : writers) w.join();
  CHECK(failures == 0);
  std::ifstream in(t.p / "log.txt");
  int lines = 0;
  for (std::string line; std::getline(in, line);) {
    CHECK(line.rfind("writer ", 0) == 0);
    ++lines;
  }
  CHECK(lines == kWriters * kRecords);
}

TEST_CASE("an append that does not fit is taken back whole", "[confined]") {
  // A full disk, made with RLIMIT_FSIZE in a child process: the write fails (EFBIG) after part
  // of the record, and the file is cut back to what it held.
  Tree t;
  std::ofstream(t.p / "log.txt", std::ios::binary) << "old record\r\n";
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    auto f = ConfinedFolder::open(t.p);
    if (!f) ::_exit(10);
    auto fd = f.value->open_append("log.txt");
    if (!fd) ::_exit(11);
    rlimit lim{20, 20};
    ::setrlimit(RLIMIT_FSIZE, &lim);
    auto done = asimov::core::append_whole(fd.value->get(), std::string(100, 'x') + "\r\n");
    ::_exit(done ? 12 : 0);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  CHECK(slurp(t.p / "log.txt") == "old record\r\n");
}

TEST_CASE("a folder that cannot be opened is an error, not a crash", "[confined]") {
  Tree t;
  CHECK(ConfinedFolder::open(t.p / "in.txt").error.kind == FsRefusal::not_found);  // ENOTDIR
  CHECK(ConfinedFolder::open(t.p / "nothing").error.kind == FsRefusal::not_found);
}
