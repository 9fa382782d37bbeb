// Hostile URDF (issue 17): folders, joint loops, chains deeper than the walks allow, entity
// expansion and element nesting all end with an Error naming file and line.
#include "support/scratch.hpp"
#include "asimov/robots/urdf_loader.hpp"
#include "support/result.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <ctime>
#include <filesystem>
#include <string>

using namespace asimov::robots;

namespace {

std::string urdf_error(const std::string& xml) {
  return asimov::test::error_message(load_urdf_text(xml, "bad.urdf"));
}

std::string numbered(const char* prefix, int i) {
  std::string s = prefix;
  s += std::to_string(i);
  return s;
}

std::string fixed_joint(const std::string& name, const std::string& parent, const std::string& child) {
  return "<joint name=\"" + name + "\" type=\"fixed\"><parent link=\"" + parent + "\"/><child link=\"" + child +
         "\"/></joint>\n";
}

}  // namespace

TEST_CASE("URDF that is a folder or a device", "[urdf][hostile]") {
  const auto dir = asimov::test::scratch_dir("hostile.urdf");
  CHECK_THAT(asimov::test::error_message(load_urdf(dir.string())), Catch::Equals(dir.string() + ":0: is a directory, not a file"));
  CHECK_THAT(asimov::test::error_message(load_urdf("/dev/zero")), Catch::Equals("/dev/zero:0: is larger than 64 MiB, the limit for this kind of file"));
}

TEST_CASE("URDF joint loops away from the root are reported, not ignored", "[urdf][hostile]") {
  const std::string xml = "<robot name=\"t\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n<link name=\"c\"/>\n" +
                          fixed_joint("bc", "b", "c") + fixed_joint("cb", "c", "b") + "</robot>\n";
  CHECK(urdf_error(xml) == "bad.urdf:5: joint 'bc': link 'c' is not connected to the root link 'a' (the joints form a loop)");
  const std::string all = "<robot name=\"t\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n" + fixed_joint("ab", "a", "b") +
                          fixed_joint("ba", "b", "a") + "</robot>\n";
  CHECK(urdf_error(all) == "bad.urdf:1: the joints form a loop (no root link)");
}

TEST_CASE("a chain deeper than the limit ends with a message, not a stack overflow", "[urdf][hostile]") {
  std::string xml = "<robot name=\"t\">\n";
  const int n = 100000;
  for (int i = 0; i <= n; ++i) xml += "<link name=\"" + numbered("l", i) + "\"/>\n";
  for (int i = 0; i < n; ++i) xml += fixed_joint(numbered("j", i), numbered("l", i), numbered("l", i + 1));
  xml += "</robot>\n";
  // CPU time, not wall: the bound is on the work (1.3 s under ASan), not on a shared machine's load.
  const std::clock_t t0 = std::clock();
  CHECK_THAT(urdf_error(xml), Catch::EndsWith("joint 'j1000': the chain is more than 1000 joints deep"));
  CHECK(static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC < 10);
}

TEST_CASE("XML entities are never expanded, element nesting is bounded", "[urdf][hostile]") {
  std::string lol = "<?xml version=\"1.0\"?>\n<!DOCTYPE lolz [\n<!ENTITY lol \"lol\">\n";
  for (int i = 1; i < 10; ++i) {
    lol += "<!ENTITY lol" + std::to_string(i) + " \"";
    for (int k = 0; k < 10; ++k) lol += "&lol" + std::string(i > 1 ? std::to_string(i - 1) : "") + ";";
    lol += "\">\n";
  }
  lol += "]>\n<robot name=\"&lol9;\">\n<link name=\"a\"/>\n</robot>\n";
  const auto t0 = std::chrono::steady_clock::now();
  CHECK(urdf_error(lol).find("bad.urdf:") == 0);  // a message, at once
  CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 5);
  std::string deep = "<robot name=\"t\">";
  for (int i = 0; i < 100000; ++i) deep += "<a>";
  CHECK_THAT(urdf_error(deep), Catch::StartsWith("bad.urdf:1: XML error") && Catch::Contains("DEPTH"));
}
