// Confined file I/O (dialect §7a): ATTACH / FOPENR ... / READ / WRITE / GETC / IOSTAT on a
// disk unit, paths kept inside the files folder, atomic writes, end of file through IOSTAT.
#include "interpreter/src/files.hpp"
#include "interpreter_fixture.hpp"
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

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

TEST_CASE("records end at LF, CR LF, CR CR LF or CR; GETC reads bytes", "[files]") {
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

TEST_CASE("units used wrongly stop the program; network devices stop with a hint", "[files]") {
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

TEST_CASE("resolve_inside", "[files]") {
  Folder d;
  std::string why;
  CHECK(asimov::interpreter::resolve_inside(d.path, "a/b.txt", why) == fs::weakly_canonical(d.path) / "a" / "b.txt");
  CHECK_FALSE(asimov::interpreter::resolve_inside(d.path, "", why));
  CHECK(why == "empty file name");
  CHECK_FALSE(asimov::interpreter::resolve_inside(d.path, "..", why));
  CHECK_FALSE(asimov::interpreter::resolve_inside(d.path, ".", why));
}
