// Bounded reads and printable text (issue 17): the helpers every loader and message uses.
#include "support/scratch.hpp"
#include "asimov/collision/text_file.hpp"
#include "support/result.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

using namespace asimov::collision;

TEST_CASE("printable: control characters and bad UTF-8 become '?', one per byte", "[text][hostile]") {
  CHECK(printable("x = 1\t; ok") == "x = 1\t; ok");
  CHECK(printable("\x1b[2J\x07") == "?[2J?");
  CHECK(printable(std::string("a\0b", 3)) == "a?b");
  CHECK(printable("\x7f") == "?");
  CHECK(printable("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80") == "caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80");  // é € 😀
  CHECK(printable("\xc2\x9b" "2J") == "??2J");         // C1 CSI
  CHECK(printable("\xff\xfe") == "??");
  CHECK(printable("\xc3") == "?");                      // truncated sequence
  CHECK(printable("\xe0\x80\xaf") == "???");            // overlong
  CHECK(printable("\xed\xa0\x80") == "???");            // surrogate
  CHECK(printable("\xf4\x90\x80\x80") == "????");       // above U+10FFFF
}

TEST_CASE("read_file_bounded: files, folders, devices, the limit", "[text][hostile]") {
  const auto dir = asimov::test::scratch_dir("text-file");
  const auto file = dir / "f.txt";
  std::ofstream(file, std::ios::binary) << std::string(100, 'x');
  CHECK(asimov::test::must(read_file_bounded(file.string(), 100)) == std::string(100, 'x'));
  const auto message = [](const std::string& path, std::size_t limit) {
    return asimov::test::error_message(read_file_bounded(path, limit));
  };
  CHECK(message(file.string(), 99) == "is larger than 99 bytes, the limit for this kind of file");
  CHECK(message(dir.string(), 100) == "is a directory, not a file");
  CHECK(message((dir / "none").string(), 100) == "cannot open the file (No such file or directory)");
  CHECK(message("/dev/zero", 1 << 20) == "is larger than 1 MiB, the limit for this kind of file");
  CHECK(read_file_bounded(dir.string(), 100).error().file == dir.string());
  CHECK(asimov::test::must(read_file_bounded("/dev/null", 10)).empty());
}
