// `asimov serve` without the network: the message parser's bounds, the token helpers, and a
// studio session answering the page's requests (check, monitor, run, files confined to the
// workspace, replay export). The server itself and the page: tests/browser/studio.test.mjs.
#include "app/serve/protocol.hpp"
#include "app/serve/server.hpp"
#include "app/serve/session.hpp"
#include "asimov/cell/cell_loader.hpp"
#include "support/scratch.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <fstream>
#include <set>
#include <thread>

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

TEST_CASE("studio messages: debug and pause requests") {
  auto r = parse_request(R"({"type":"debug","action":"go","breakpoints":[3,7],"speed":0.25,"text":"x"})");
  REQUIRE(r);
  CHECK(r->kind == RequestKind::debug);
  CHECK(r->action == DebugAction::go);
  CHECK(r->breakpoints == std::vector<int>{3, 7});
  CHECK(r->speed == 0.25);
  r = parse_request(R"({"type":"debug","action":"step"})");
  REQUIRE(r);
  CHECK(r->speed == 1);
  CHECK(r->breakpoints.empty());
  CHECK(parse_request(R"({"type":"pause"})"));
  const auto why = [](const std::string& m) {
    auto a = parse_request(m);
    REQUIRE(!a);
    return a.error().detail;
  };
  CHECK(why(R"({"type":"debug"})") == "\"action\" is missing");
  CHECK(why(R"({"type":"debug","action":"jump"})") == "unknown action \"jump\"");
  CHECK(why(R"({"type":"debug","action":"go","breakpoints":3})") == "\"breakpoints\" is not an array");
  CHECK(why(R"({"type":"debug","action":"go","breakpoints":[0]})") == "a breakpoint is not a line number");
  CHECK(why(R"({"type":"debug","action":"go","breakpoints":[1.5]})") == "a breakpoint is not a line number");
  CHECK(why(R"({"type":"debug","action":"go","breakpoints":["2"]})") == "a breakpoint is not a line number");
  CHECK(why(R"({"type":"debug","action":"go","speed":-1})") == "\"speed\" is not a number from 0 to 100");
  CHECK(why(R"({"type":"debug","action":"go","speed":1e300})") == "\"speed\" is not a number from 0 to 100");
  std::string many = R"({"type":"debug","action":"go","breakpoints":[1)";
  for (std::size_t i = 0; i < kMaxBreakpoints; ++i) many += ",1";
  CHECK(why(many + "]}") == "more than 1000 breakpoints");
}

namespace {

// A program of three motions and a CALL, for the debugger (lines in comments).
const char* const kStepped = R"(.PROGRAM walk()
    x = 5
    MOVE #PPOINT(20, -80, 100, 0, 10, 0)
    MOVE #PPOINT(40, -70, 110, 0, 30, 0)
    CALL bump(x)
    MOVE #PPOINT(-20, -90, 90, 0, 0, 0)
    TYPE "x is ", x
.END
.PROGRAM bump(v)
    v = v + 1
.END
)";

nlohmann::json debug_request(const char* action, std::vector<int> breakpoints = {}, double speed = 0) {
  return {{"type", "debug"}, {"action", action}, {"file", "walk.v2"}, {"text", kStepped}, {"breakpoints", breakpoints}, {"speed", speed}};
}

const nlohmann::json* variable(const nlohmann::json& a, const std::string& name) {
  for (const auto& v : a["variables"])
    if (v["name"] == name) return &v;
  return nullptr;
}

}  // namespace

TEST_CASE("studio session: stepping the editor's program, the pointer, the arm and the variables") {
  Studio s("debug");
  std::vector<nlohmann::json> frames;
  s.session.set_frame_sink([&](std::string text) { frames.push_back(nlohmann::json::parse(text)); });
  // Step with nothing stopped: the program starts stopped before its first step.
  auto a = s.ask(debug_request("step").dump());
  REQUIRE(a["type"] == "debug");
  CHECK(a["stopped"] == true);
  CHECK(a["stop"] == "step");
  CHECK(a["place"]["line"] == 2);
  CHECK(a["place"]["program"] == "walk");
  CHECK(a["place"]["text"] == "x = 5");
  CHECK(a["output"].get<std::string>().find("walk, step 1:  x = 5") != std::string::npos);
  REQUIRE(a["tasks"].size() == 1);
  CHECK(a["tasks"][0]["state"] == "stopped at walk, step 1");
  const double j1 = a["joints"][0].get<double>();
  a = s.ask(debug_request("step").dump());  // x = 5
  CHECK(a["place"]["line"] == 3);
  REQUIRE(variable(a, "x"));
  CHECK((*variable(a, "x"))["value"] == "5");
  CHECK(frames.empty());  // no motion yet
  a = s.ask(debug_request("step").dump());  // the first MOVE: the arm there, frames on the way
  CHECK(a["place"]["line"] == 4);
  CHECK(a["joints"][0].get<double>() == Approx(20).margin(1e-6));
  CHECK(j1 != Approx(20));
  REQUIRE(frames.size() >= 1);
  CHECK(frames.back()["joints"][0].get<double>() == Approx(20).margin(1e-6));
  CHECK(frames.back()["poses"].size() == a["poses"].size());
  // A breakpoint in the CALLed program by its file line; a comment-free line with no step refused.
  a = s.ask(debug_request("go", {10, 8}).dump());
  CHECK(a["stop"] == "breakpoint");
  CHECK(a["place"]["program"] == "bump");
  CHECK(a["place"]["line"] == 10);
  CHECK(a["place"]["depth"] == 2);
  CHECK(a["breakpoints"] == nlohmann::json::array({10}));
  CHECK(a["refused"] == nlohmann::json::array({8}));
  CHECK(a["joints"][0].get<double>() == Approx(40).margin(1e-6));
  // The variable changed through the monitor (DO), then seen by the program.
  CHECK(s.ask(R"({"type":"monitor","line":"DO x = 41"})")["status"] == "ok");
  a = s.ask(debug_request("state", {10}).dump());
  CHECK((*variable(a, "x"))["value"] == "41");
  CHECK(a["stopped"] == true);
  a = s.ask(debug_request("go", {}).dump());  // the breakpoint cleared: to the end
  CHECK(a["stopped"] == false);
  CHECK(a["stop"] == "completed");
  CHECK(a["output"].get<std::string>().find("x is 42") != std::string::npos);
  CHECK(a["place"].is_null());
  // Step into the CALL, then abort.
  s.ask(debug_request("start").dump());
  s.ask(debug_request("step").dump());
  s.ask(debug_request("step").dump());
  s.ask(debug_request("step").dump());
  a = s.ask(debug_request("into").dump());
  CHECK(a["place"]["line"] == 10);
  a = s.ask(debug_request("abort").dump());
  CHECK(a["stop"] == "aborted");
  CHECK(a["stopped"] == false);
  // Nothing stopped: abort does nothing; a text with an error does not start.
  CHECK(s.ask(debug_request("abort").dump())["stop"] == "none");
  a = s.ask(nlohmann::json{{"type", "debug"}, {"action", "step"}, {"text", ".PROGRAM w()\n    MOVE (\n.END\n"}}.dump());
  CHECK(a["status"] == "error");
  CHECK(a["stopped"] == false);
  CHECK(a["diagnostics"].size() >= 1);
}

TEST_CASE("studio session: a stepped motion streamed live, paced on the wall clock, and paused") {
  Studio s("live");
  std::vector<std::pair<std::chrono::steady_clock::time_point, double>> frames;
  s.session.set_frame_sink([&](std::string text) {
    frames.emplace_back(std::chrono::steady_clock::now(), nlohmann::json::parse(text)["t"].get<double>());
  });
  s.ask(debug_request("start").dump());
  s.ask(debug_request("step", {}, 4).dump());
  frames.clear();
  auto a = s.ask(debug_request("step", {}, 4).dump());  // the first MOVE at x4
  CHECK(a["place"]["line"] == 4);
  REQUIRE(frames.size() >= 3);
  // Poses every 4/60 s of simulated time, in order; the last the motion's end.
  for (std::size_t i = 1; i < frames.size(); ++i) CHECK(frames[i].second > frames[i - 1].second);
  // On the grid of 4/60 s of simulated time (plus the checked poses): at least one pose a grid step.
  const double sim_s = frames.back().second - frames.front().second;
  CHECK(static_cast<double>(frames.size()) >= sim_s / (4.0 / 60) - 1);
  // A pause from another thread while a slow motion runs: stopped resumable mid-way, Continue ends it.
  std::thread pauser([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    s.session.pause();
  });
  a = s.ask(debug_request("go", {}, 0.25).dump());
  pauser.join();
  CHECK(a["stop"] == "pause");
  CHECK(a["stopped"] == true);
  CHECK(a["place"]["line"].get<int>() >= 4);
  a = s.ask(debug_request("go", {}, 0).dump());
  CHECK(a["stop"] == "completed");
}
