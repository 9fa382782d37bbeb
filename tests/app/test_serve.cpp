// `asimov serve` without the network: the message parser's bounds, the token helpers, and a
// studio session answering the page's requests (check, monitor, run, files confined to the
// workspace, replay export). The server itself and the page: tests/browser/studio.test.mjs.
#include "app/serve/protocol.hpp"
#include "app/serve/server.hpp"
#include "app/serve/session.hpp"
#include "asimov/cell/cell_loader.hpp"
#include "support/scratch.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <set>

using namespace asimov;
using namespace asimov::serve;

TEST_CASE("studio messages: valid requests parse with their fields") {
  auto r = parse_request(R"({"type":"check","id":7,"text":".PROGRAM a()\n.END\n","file":"a.v2"})");
  REQUIRE(r);
  CHECK(r->kind == RequestKind::check);
  CHECK(r->id == 7);
  CHECK(r->file == "a.v2");
  r = parse_request(R"({"type":"monitor","line":"WHERE","extra":[1,2]})");
  REQUIRE(r);
  CHECK(r->kind == RequestKind::monitor);
  CHECK(r->id == 0);
  CHECK(r->line == "WHERE");
  CHECK(parse_request(R"({"type":"abort"})"));
  CHECK(parse_request(R"({"type":"run","text":"","main":"x"})"));
}

TEST_CASE("studio messages: bad ones are *Invalid message* with the reason") {
  const auto why = [](std::string_view m) {
    auto r = parse_request(m);
    REQUIRE(!r);
    CHECK(r.error().message == "*Invalid message*");
    return r.error().detail;
  };
  CHECK(why("") == "not JSON (or not UTF-8)");
  CHECK(why("not json") == "not JSON (or not UTF-8)");
  CHECK(why("[1]") == "not a JSON object");
  CHECK(why(R"({"id":1})") == "\"type\" is missing");
  CHECK(why(R"({"type":"rm -rf"})") == "unknown type \"rm -rf\"");
  CHECK(why(R"({"type":5})") == "\"type\" is not a string");
  CHECK(why(R"({"type":"check"})") == "\"text\" is missing");
  CHECK(why(R"({"type":"open"})") == "\"file\" is missing");
  CHECK(why(R"({"type":"check","text":"","id":"1"})") == "\"id\" is not an integer");
  CHECK(why(R"({"type":"check","text":"","id":1.5})") == "\"id\" is not an integer");
  CHECK(why(R"({"type":"monitor","line":"a\nb"})") == "\"line\" holds a line break");
  CHECK(why("{\"type\":\"check\",\"text\":\"\xff\xfe\"}") == "not JSON (or not UTF-8)");
  // Deep nesting is refused before the JSON parser starts (it recurses).
  CHECK(why(std::string(200000, '[')) == "nested deeper than 4");
  CHECK(json_depth(R"({"a":"[[[[[[[[[[","b":[{}]})") == 3);  // brackets in strings do not count
  // Every string within its bound.
  CHECK(why(R"({"type":"monitor","line":")" + std::string(kMaxLineBytes + 1, 'x') + "\"}") ==
        "\"line\" is longer than 4096 bytes");
  CHECK(why(R"({"type":"open","file":")" + std::string(kMaxNameBytes + 1, 'x') + "\"}") ==
        "\"file\" is longer than 255 bytes");
  CHECK(why(R"({"type":"check","text":")" + std::string(kMaxTextBytes + 1, 'x') + "\"}") ==
        "\"text\" is longer than 524288 bytes");
  CHECK(why(std::string(kMaxMessageBytes + 1, ' ')) == "longer than 1048576 bytes");
}

TEST_CASE("studio token: random, 128 bits in hex, compared whole") {
  std::set<std::string> seen;
  for (int i = 0; i < 50; ++i) {
    const std::string t = random_token();
    CHECK(t.size() == 32);
    CHECK(t.find_first_not_of("0123456789abcdef") == std::string::npos);
    seen.insert(t);
  }
  CHECK(seen.size() == 50);
  CHECK(same_token("abc", "abc"));
  CHECK(!same_token("abc", "abd"));
  CHECK(!same_token("abc", "ab"));
  CHECK(!same_token("", ""));  // an empty token never matches
  CHECK(query_value("/?token=abc", "token") == "abc");
  CHECK(query_value("/ws?x=1&token=abc&y", "token") == "abc");
  CHECK(query_value("/ws?tokens=abc", "token").empty());
  CHECK(query_value("/ws", "token").empty());
  CHECK(query_value("/?token", "token").empty());
}

namespace {

struct Studio {
  std::filesystem::path dir;
  Workspace workspace;
  StudioConfig config;
  StudioSession session;
  explicit Studio(const std::string& name)
      : dir(test::scratch_dir("studio-" + name)),
        workspace(std::move(Workspace::open(dir).value())),
        config{cell::default_cell(), "built-in default cell", "a.v2", ".PROGRAM a()\n.END\n", {}},
        session(config, workspace) {}
  nlohmann::json ask(const std::string& message) {
    auto r = parse_request(message);
    REQUIRE(r);
    return session.handle(*r);
  }
};

std::string read(const std::filesystem::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST_CASE("studio session: check's diagnostics with line and column, as the editor shows them") {
  Studio s("check");
  auto a = s.ask(R"({"type":"check","id":3,"file":"t.v2","text":".PROGRAM t()\n    MOVE #PPOINT(0, -90, 90, 0, 0, 0)\n    MOVE nowhere(\n.END\n"})");
  CHECK(a["type"] == "check");
  CHECK(a["id"] == 3);
  REQUIRE(a["diagnostics"].size() >= 1);
  CHECK(a["diagnostics"][0]["line"] == 3);
  CHECK(a["diagnostics"][0]["column"].get<int>() > 0);
  CHECK(a["diagnostics"][0]["text"].get<std::string>().find("t.v2:3") != std::string::npos);
  a = s.ask(R"({"type":"check","text":".PROGRAM t()\n    MOVE #PPOINT(0, -90, 90, 0, 0, 0)\n.END\n"})");
  CHECK(a["diagnostics"].empty());
}

TEST_CASE("studio session: a run's status, messages, report and replay data") {
  Studio s("run");
  const std::string crash = read(ASIMOV_SOURCE_DIR "/programs/demo/crash.v2");
  auto a = s.ask(nlohmann::json{{"type", "run"}, {"id", 9}, {"file", "crash.v2"}, {"text", crash}}.dump());
  CHECK(a["status"] == "collision");
  CHECK(a["line"] == 12);
  CHECK(a["messages"].get<std::string>().find("*Collision*  link4 / box") != std::string::npos);
  CHECK(a["report"]["collision"]["bodies"].size() == 2);
  CHECK(a["replay"]["frames"]["count"].get<int>() > 100);
  CHECK(a["replay"].contains("collision"));
  // Its replay page goes into the workspace, an .html name only.
  CHECK(s.ask(R"({"type":"replay","file":"crash.txt"})")["message"] == "*Illegal file name*");
  a = s.ask(R"({"type":"replay","file":"crash.html"})");
  if (a["type"] == "replay") CHECK(read(s.dir / "crash.html").find("asimov-replay-data") != std::string::npos);
  else CHECK(a["message"] == "*Cannot write replay*");  // a build without three.js
  // A program that does not load: its diagnostics, nothing ran.
  a = s.ask(R"({"type":"run","text":".PROGRAM x()\n    MOVE (\n.END\n"})");
  CHECK(a["status"] == "error");
  CHECK(!a.contains("replay"));
  CHECK(s.ask(R"({"type":"run","text":"; nothing\n"})")["message"] == "*Undefined program or variable name*");
}

TEST_CASE("studio session: files stay in the workspace") {
  Studio s("files");
  CHECK(s.ask(R"({"type":"save","file":"p.v2","text":".PROGRAM p()\n    TYPE 42\n.END\n"})")["type"] == "save");
  CHECK(read(s.dir / "p.v2").find("TYPE 42") != std::string::npos);
  CHECK(s.ask(R"({"type":"open","file":"p.v2"})")["text"].get<std::string>().find("TYPE 42") != std::string::npos);
  CHECK(s.ask(R"({"type":"list"})")["files"] == nlohmann::json::array({"p.v2"}));
  for (const char* bad : {"../p.v2", "/etc/passwd", "sub/../../p.v2", ""}) {
    const auto a = s.ask(nlohmann::json{{"type", "open"}, {"file", bad}}.dump());
    CHECK(a["type"] == "error");
    const auto w = s.ask(nlohmann::json{{"type", "save"}, {"file", bad}, {"text", "x"}}.dump());
    CHECK(w["type"] == "error");
  }
  CHECK(!std::filesystem::exists(s.dir.parent_path() / "p.v2"));
  // A link leading out is not followed.
  std::filesystem::create_symlink("/etc/hostname", s.dir / "out.v2");
  CHECK(s.ask(R"({"type":"open","file":"out.v2"})")["type"] == "error");
  // The monitor's LOAD and STORE name files of the workspace only.
  auto m = s.ask(R"({"type":"monitor","line":"LOAD p"})");
  CHECK(m["status"] == "ok");
  m = s.ask(R"({"type":"monitor","line":"EXECUTE p"})");
  CHECK(m["output"].get<std::string>().find("42") != std::string::npos);
  m = s.ask(R"({"type":"monitor","line":"STORE q.v2"})");
  CHECK(m["status"] == "ok");
  CHECK(read(s.dir / "q.v2").find(".PROGRAM p()") != std::string::npos);
  for (const char* bad : {"LOAD /etc/passwd", "LOAD ../p", "STORE /tmp/x.v2", "STOREL ../x", "lo ../../etc/hosts"}) {
    m = s.ask(nlohmann::json{{"type", "monitor"}, {"line", bad}}.dump());
    INFO(bad);
    CHECK(m["status"] == "failed");
    CHECK(m["output"].get<std::string>().rfind("*Illegal file name*", 0) == 0);
  }
}

TEST_CASE("studio session: the monitor keeps its state and poses the arm") {
  Studio s("monitor");
  auto m = s.ask(R"j({"type":"monitor","line":"DO MOVE #PPOINT(40, -60, 120, 0, 30, 0)"})j");
  CHECK(m["status"] == "ok");
  CHECK(m["joints"][0].get<double>() == Approx(40));
  CHECK(m["poses"].size() >= 7);  // the links and the tool
  m = s.ask(R"({"type":"monitor","line":"WHERE"})");
  CHECK(m["output"].get<std::string>().find("40.000") != std::string::npos);
  m = s.ask(R"({"type":"monitor","line":"NOSUCH"})");
  CHECK(m["status"] == "failed");
  // A program typed at the prompt: the prompt shows the step.
  m = s.ask(R"j({"type":"monitor","line":".PROGRAM typed()"})j");
  CHECK(m["prompt"] == "1? ");
}
