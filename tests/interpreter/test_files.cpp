// Confined file I/O (dialect §7a): ATTACH / FOPENR ... / READ / WRITE / GETC / IOSTAT on a
// disk unit, paths kept inside the files folder, atomic writes, end of file through IOSTAT.
#include "interpreter/src/files.hpp"
#include "interpreter_fixture.hpp"
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <sys/stat.h>

using asimov::test::InterpreterFixture;
using asimov::interpreter::RunStatus;
namespace fs = std::filesystem;

namespace {

// A fresh folder for one case (under the tests' scratch folder), removed at the end.
struct Folder {
  fs::path path;
  Folder() {
    static int count = 0;
    path = asimov::test::scratch_dir("files" + std::to_string(++count));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~Folder() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  void write(const std::string& name, const std::string& text) const { std::ofstream(path / name, std::ios::binary) << text; }
  std::string read(const std::string& name) const { return asimov::test::slurp(path / name); }
};

std::string slurp_or_none(const fs::path& p) { return fs::exists(p) ? asimov::test::slurp(p) : "<none>"; }

std::string program(const std::string& body) { return ".PROGRAM main()\n" + body + "\n.END\n"; }

// Runs `body` with the files in `folder`: the output, or the error after "ERROR ".
std::string outcome(const Folder& folder, const std::string& body) {
  InterpreterFixture f;
  f.interp.limits().files_root = folder.path.string();
  return asimov::test::outcome_of(f, program(body));
}

}  // namespace

TEST_CASE("a program writes a file and reads its values back", "[files]") {
  Folder d;
  const std::string out = outcome(d,
      "ATTACH (lun, 4) \"DISK\"\n"
      "FOPENW (lun) \"points.txt\"\n"
      "FOR i = 1 TO 3\n"
      "  WRITE (lun) i * 10, \",\", i / 4, \" \", -i\n"
      "END\n"
      "WRITE (lun) \"last line\"\n"
      "FCLOSE (lun)\n"
      "FOPENR (lun) \"points.txt\"\n"
      "FOR i = 1 TO 3\n"
      "  READ (lun) x, y, z\n"
      "  TYPE x, y, z, IOSTAT(lun)\n"
      "END\n"
      "READ (lun) $s\n"
      "TYPE $s\n"
      "READ (lun) $s\n"
      "TYPE IOSTAT(lun), \" \", $ERROR(IOSTAT(lun)), \" \", $s\n"
      "c = GETC(lun)\n"
      "TYPE c\n"
      "DETACH (lun)");
  CHECK(out == "10 0.25 -1 1\n20 0.5 -2 1\n30 0.75 -3 1\nlast line\n-504 *Unexpected end of file* last line\n-504\n");
  CHECK(d.read("points.txt") == "10,0.25 -1\r\n20,0.5 -2\r\n30,0.75 -3\r\nlast line\r\n");
}

TEST_CASE("records end at LF, CR LF, CR CR LF or CR, GETC reads bytes", "[files]") {
  Folder d;
  d.write("in.txt", "a\nb\r\nc\r\r\nd\re");
  CHECK(outcome(d, "ATTACH (5) \"DISK\"\nFOPENR (5) \"in.txt\"\nDO\n  READ (5) $s\n  IF IOSTAT(5) == 1 THEN\n    TYPE $s, \"|\", /S\n"
                   "  END\nUNTIL IOSTAT(5) < 0\nTYPE\nFCLOSE (5)\nFOPENR (5) \"in.txt\"\nTYPE GETC(5), GETC(5)")
        == "a|b|c|d|e|\n97 10\n");
}

TEST_CASE("FOPENR of a missing file and FOPENW of an existing one set IOSTAT", "[files]") {
  Folder d;
  d.write("old.txt", "keep\n");
  CHECK(outcome(d, "ATTACH (5)\nFOPENR (5) \"none.txt\"\nTYPE IOSTAT(5), \" \", $ERROR(IOSTAT(5))\n"
                   "FOPENW (5) \"old.txt\"\nTYPE IOSTAT(5), \" \", $ERROR(IOSTAT(5))")
        == "-500 *File not found*\n-503 *File already exists*\n");
  CHECK(d.read("old.txt") == "keep\n");
  // FOPENA appends; FDELETE removes; FEMPTY empties.
  CHECK(outcome(d, "ATTACH (5)\nFOPENA (5) \"old.txt\"\nWRITE (5) \"more\"\nFCLOSE (5)\nFDELETE (5) \"old.txt\"\n"
                   "TYPE IOSTAT(5)\nFDELETE (5) \"old.txt\"\nTYPE IOSTAT(5)") == "1\n-500\n");
  CHECK_FALSE(fs::exists(d.path / "old.txt"));
  d.write("e.txt", "x\n");
  CHECK(outcome(d, "ATTACH (5)\nFEMPTY (5) \"e.txt\"\nTYPE IOSTAT(5)") == "1\n");
  CHECK(d.read("e.txt").empty());
}

TEST_CASE("paths stay inside the files folder", "[files]") {
  Folder d;
  fs::create_directories(d.path / "sub");
  d.write("sub/in.txt", "inside\n");
  CHECK(outcome(d, "ATTACH (5)\nFOPENR (5) \"sub\\in.txt\"\nREAD (5) $s\nTYPE $s") == "inside\n");
  CHECK(outcome(d, "ATTACH (5)\nFOPENR (5) \"sub/../sub/in.txt\"\nREAD (5) $s\nTYPE $s") == "inside\n");
  for (const char* bad : {"../x.txt", "/etc/passwd", "sub/../../x.txt", "C:\\\\x.txt", "D>x.txt"}) {
    INFO(bad);
    const std::string r = outcome(d, std::string("ATTACH (5)\nFOPENR (5) \"") + bad + "\"");
    CHECK(r.rfind("ERROR *Illegal value* FOPENR: ", 0) == 0);
  }
  CHECK(outcome(d, "ATTACH (5)\nFOPENW (5) \"../out.txt\"") == "ERROR *Illegal value* FOPENW: \"../out.txt\" leaves the program's folder");
  // A link that leads out of the folder is refused as well.
  Folder outside;
  outside.write("secret.txt", "no\n");
  fs::create_symlink(outside.path / "secret.txt", d.path / "link.txt");
  CHECK(outcome(d, "ATTACH (5)\nFOPENR (5) \"link.txt\"") == "ERROR *Illegal value* FOPENR: \"link.txt\" leaves the program's folder");
}

TEST_CASE("writes replace the file atomically when it is closed, also when the run stops", "[files]") {
  Folder d;
  InterpreterFixture f;
  f.interp.limits().files_root = d.path.string();
  // The run ends at PAUSE, before FCLOSE: what was written is committed, no temporary is left.
  REQUIRE(f.load(program("ATTACH (5)\nFOPENW (5) \"a.txt\"\nWRITE (5) \"one\"\nPAUSE\nWRITE (5) \"two\"\nFCLOSE (5)")).empty());
  REQUIRE(f.interp.run("main").status == RunStatus::paused);
  CHECK(d.read("a.txt") == "one\r\n");
  int temporaries = 0;
  for (const auto& e : fs::directory_iterator(d.path)) temporaries += e.path().filename().string()[0] == '.';
  CHECK(temporaries == 0);
  // Until FCLOSE the file is not there for a reader: it appears whole.
  CHECK(outcome(d, "ATTACH (5)\nATTACH (6)\nFOPENW (5) \"c.txt\"\nWRITE (5) \"1\"\nFOPENR (6) \"c.txt\"\nTYPE IOSTAT(6)\n"
                   "FCLOSE (5)\nFOPENR (6) \"c.txt\"\nREAD (6) $s\nTYPE IOSTAT(6), \" \", $s")
        == "-500\n1 1\n");
  // An error after a WRITE still commits it.
  const auto r = f.run(program("ATTACH (6)\nFOPENW (6) \"b.txt\"\nWRITE (6) \"x\"\ny = 1 / 0"));
  CHECK(r.error.message == "*Division by zero*");
  CHECK(d.read("b.txt") == "x\r\n");
}

TEST_CASE("units used wrongly stop the program, network devices stop with a hint", "[files]") {
  Folder d;
  CHECK(outcome(d, "READ (5) $s") == "ERROR *Illegal value* READ: logical unit 5 is not attached");
  CHECK(outcome(d, "ATTACH (5)\nREAD (5) $s") == "ERROR *Illegal value* READ: logical unit 5 has no file open for reading");
  CHECK(outcome(d, "ATTACH (5)\nATTACH (5)") == "ERROR *Illegal value* ATTACH: logical unit 5 is attached already");
  const std::string tcp = outcome(d, "ATTACH (lun, 4) \"TCP\"");
  CHECK(tcp.rfind("ERROR *Not supported in simulation* ATTACH \"TCP\"; network and serial I/O are not simulated", 0) == 0);
  CHECK(tcp.find("--main") != std::string::npos);
  CHECK(outcome(d, "FCMND (lun, 600) \"x\"").find("FCMND; network and serial I/O") != std::string::npos);
  CHECK(outcome(d, "FOPEN (lun, 16) \"/LOCAL_PORT 11000\"").find("FOPEN; network") != std::string::npos);
  InterpreterFixture f;
  CHECK_FALSE(f.load(program("READ (5)")).empty());          // READ needs variables
  CHECK_FALSE(f.load(program("FOPENR (5)")).empty());        // a file name
  CHECK_FALSE(f.load(program("READ (5) 1 + 2")).empty());
  CHECK_FALSE(f.load(program("FCLOSE (5) \"x\"")).empty());
  CHECK_FALSE(f.load(program("FOPENR \"x\"")).empty());       // the unit
}

TEST_CASE("V+ file names become relative names, absolute ones and drives are refused", "[files]") {
  std::string why;
  CHECK(asimov::interpreter::relative_name(" a\\b.txt ", why) == "a/b.txt");
  CHECK_FALSE(asimov::interpreter::relative_name("  ", why));
  CHECK(why == "empty file name");
  CHECK_FALSE(asimov::interpreter::relative_name("/etc/passwd", why));
  CHECK_FALSE(asimov::interpreter::relative_name("D>x", why));
  CHECK(why == "\"D>x\" is not inside the program's folder (absolute path or drive)");
}

// Issue 29: with `ln -s ../o p/out`, a program in p/ read, created, emptied and deleted files in o/.
TEST_CASE("no route leads a program out of its folder", "[files][confinement]") {
  Folder top;
  const fs::path p = top.path / "p", o = top.path / "o";
  fs::create_directories(p / "sub");
  fs::create_directories(o);
  std::ofstream(o / "secret") << "secret\n";
  fs::create_symlink("../o", p / "out");
  fs::create_symlink("/etc/hostname", p / "host");
  fs::create_symlink("/dev/zero", p / "zero");
  REQUIRE(::mkfifo((p / "fifo").c_str(), 0600) == 0);
  auto run = [&](const std::string& body) {
    InterpreterFixture f;
    f.interp.limits().files_root = p.string();
    std::string text = "ATTACH (5)\n";
    return asimov::test::outcome_of(f, program(text.append(body)));
  };
  // Through a folder that does not exist and back: not found, nothing read.
  CHECK(run("FOPENR (5) \"x/../out/secret\"\nTYPE IOSTAT(5)") == "-500\n");
  const std::string leaves = "\" leaves the program's folder";
  CHECK(run("FOPENR (5) \"out/secret\"") == "ERROR *Illegal value* FOPENR: \"out/secret" + leaves);
  CHECK(run("FOPENR (5) \"sub/../out/secret\"") == "ERROR *Illegal value* FOPENR: \"sub/../out/secret" + leaves);
  CHECK(run("FOPENW (5) \"out/new\"") == "ERROR *Illegal value* FOPENW: \"out/new" + leaves);
  CHECK(run("FOPENW (5) \"x/../out/new\"\nTYPE IOSTAT(5)") == "-500\n");
  CHECK(run("FOPENA (5) \"out/secret\"") == "ERROR *Illegal value* FOPENA: \"out/secret" + leaves);
  CHECK(run("FEMPTY (5) \"out/secret\"") == "ERROR *Illegal value* FEMPTY: \"out/secret" + leaves);
  CHECK(run("FDELETE (5) \"out/secret\"") == "ERROR *Illegal value* FDELETE: \"out/secret" + leaves);
  CHECK(run("FDELETE (5) \"out\\..\\out\\secret\"") == "ERROR *Illegal value* FDELETE: \"out\\..\\out\\secret" + leaves);
  CHECK(run("FOPEND (5) \"out\"") == "ERROR *Illegal value* FOPEND: \"out" + leaves);
  CHECK(run("FOPENR (5) \"host\"") == "ERROR *Illegal value* FOPENR: \"host" + leaves);
  CHECK(run("FOPENR (5) \"zero\"") == "ERROR *Illegal value* FOPENR: \"zero" + leaves);
  CHECK(slurp_or_none(o / "secret") == "secret\n");
  CHECK(std::distance(fs::directory_iterator(o), fs::directory_iterator()) == 1);
  // Regular files only, each refusal said as what it is (a FIFO is not opened: no blocking).
  CHECK(run("FOPENR (5) \"fifo\"") == "ERROR *Illegal value* FOPENR: \"fifo\" is a FIFO, not a regular file");
  CHECK(run("FOPENA (5) \"fifo\"") == "ERROR *Illegal value* FOPENA: \"fifo\" is a FIFO, not a regular file");
  CHECK(run("FOPENR (5) \"sub\"") == "ERROR *Illegal value* FOPENR: \"sub\" is a folder, not a file");
  CHECK(run("FDELETE (5) \"sub\"") == "ERROR *Illegal value* FDELETE: \"sub\" is a folder, not a file");
  // Deleting the link removes the link, inside the folder.
  CHECK(run("FDELETE (5) \"out\"\nTYPE IOSTAT(5)") == "1\n");
  CHECK(slurp_or_none(o / "secret") == "secret\n");
}

TEST_CASE("records and what a run writes are bounded", "[files][limits]") {
  Folder d;
  d.write("big.txt", std::string(100'000, 'a') + "\n");
  const std::string big = outcome(d, "ATTACH (5)\nFOPENR (5) \"big.txt\"\nREAD (5) x");
  CHECK(big == "ERROR *Illegal value* READ: a record of \"big.txt\" is longer than 65536 bytes");
  InterpreterFixture f;
  f.interp.limits().files_root = d.path.string();
  f.interp.limits().max_file_bytes = 1000;
  const std::string flood = asimov::test::outcome_of(f, program(
      "ATTACH (5)\nFOPENW (5) \"flood.txt\"\nFOR i = 1 TO 100000\n  WRITE (5) \"012345678901234567\"\nEND"));
  CHECK(flood == "ERROR *Illegal value* WRITE: the run's files would pass 1000 bytes in all (docs/limits.md)");
  CHECK(d.read("flood.txt").size() == 1000);  // 50 records of 20 bytes, committed at the end of the run
  InterpreterFixture g;
  g.interp.limits().files_root = d.path.string();
  g.interp.limits().max_record_bytes = 10;
  CHECK(asimov::test::outcome_of(g, program("ATTACH (5)\nFOPENW (5) \"r.txt\"\nWRITE (5) \"0123456789\""))
        == "ERROR *Illegal value* WRITE: a record of 12 bytes is longer than 10 bytes");
}

TEST_CASE("FOPENA appends each record in place, after what the file held", "[files]") {
  Folder d;
  d.write("log.txt", "old\r\n");
  InterpreterFixture f;
  f.interp.limits().files_root = d.path.string();
  // Until the run ends the record is in the file already (in place, not a copy renamed later).
  REQUIRE(f.load(program("ATTACH (5)\nFOPENA (5) \"log.txt\"\nWRITE (5) \"new\"\nPAUSE\nFCLOSE (5)")).empty());
  REQUIRE(f.interp.run("main").status == RunStatus::paused);
  CHECK(d.read("log.txt") == "old\r\nnew\r\n");
  CHECK(outcome(d, "ATTACH (5)\nFOPENA (5) \"fresh.txt\"\nWRITE (5) \"a\", /S\nWRITE (5) \"b\"") == "");
  CHECK(d.read("fresh.txt") == "ab\r\n");
}
