// The studio's latency from a command to the arm's new pose on the page's side of the socket:
// a monitor `DO MOVE` (one motion, simulated and checked, the answer carrying the moving bodies'
// world poses: what the page draws) sent over a real WebSocket to an in-process `asimov serve`
// server on 127.0.0.1 and answered; WHERE over the same socket (the server's own cost: JSON,
// the worker thread, the socket); and, as the peer, the same DO MOVE on interpreter::Monitor
// directly (no server). The ratio studio / direct is what serving costs.
// The program debugger's stream (docs/studio.md "Stepping"): the latency from a `debug` step
// command to the first frame of its motion (the arm's poses, streamed as the walker simulates
// the motion), and the frames per second of the pose stream while the arm moves live at x1.
// Run: build/bench/bench_studio --benchmark_repetitions=9 --benchmark_report_aggregates_only=true
#include "app/serve/server.hpp"
#include "asimov/cell/cell_loader.hpp"

#include <benchmark/benchmark.h>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <sstream>
#include <thread>
#include <vector>

namespace {

using namespace asimov;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
namespace net = boost::asio;

// Two joint targets a DO MOVE alternates between (a short move, as a step of a lesson).
const char* const kTargets[] = {"DO MOVE #PPOINT(10, -80, 100, 0, 20, 0)", "DO MOVE #PPOINT(20, -70, 110, 0, 30, 0)"};

struct LiveServer {
  std::filesystem::path dir = std::filesystem::temp_directory_path() / ("asimov-bench-studio-" + std::to_string(::getpid()));
  std::unique_ptr<serve::Server> server;
  std::thread thread;
  net::io_context ioc;
  std::unique_ptr<websocket::stream<net::ip::tcp::socket>> ws;
  LiveServer() {
    std::filesystem::create_directories(dir);
    serve::StudioConfig config{cell::default_cell(), "built-in default cell", "a.v2", "", {}};
    server = std::make_unique<serve::Server>(std::move(config), std::move(serve::Workspace::open(dir).value()),
                                             serve::StudioAssets{"// the bench fetches no page"}, serve::ServerOptions{});
    if (!server->listen()) throw std::runtime_error("listen failed");
    thread = std::thread([this] { server->run(); });
    net::ip::tcp::resolver resolver(ioc);
    ws = std::make_unique<websocket::stream<net::ip::tcp::socket>>(ioc);
    net::connect(ws->next_layer(), resolver.resolve("127.0.0.1", std::to_string(server->port())));
    ws->next_layer().set_option(net::ip::tcp::no_delay(true));  // as browsers do (Chromium sets TCP_NODELAY)
    const std::string host = "127.0.0.1:" + std::to_string(server->port());
    ws->set_option(websocket::stream_base::decorator(
        [host](websocket::request_type& req) { req.set(beast::http::field::origin, "http://" + host); }));
    ws->handshake(host, "/ws?token=" + server->token());
    ws->read_message_max(64 << 20);
    receive();  // hello
  }
  ~LiveServer() {
    beast::error_code ec;
    ws->close(websocket::close_code::normal, ec);
    server->stop();
    thread.join();
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
  }
  nlohmann::json receive() {
    beast::flat_buffer b;
    ws->read(b);
    return nlohmann::json::parse(beast::buffers_to_string(b.data()));
  }
  void send(const nlohmann::json& message) { ws->write(net::buffer(message.dump())); }
  nlohmann::json ask(const std::string& line) {
    ws->write(net::buffer(nlohmann::json{{"type", "monitor"}, {"id", 1}, {"line", line}}.dump()));
    for (;;) {  // the arm's frames come before the answer
      nlohmann::json m = receive();
      if (m["type"] != "frame") return m;
    }
  }
};

void BM_StudioDoMove(benchmark::State& state) {
  LiveServer live;
  std::size_t k = 0;
  for (auto _ : state) {
    const nlohmann::json a = live.ask(kTargets[k++ % 2]);
    if (a.value("status", "") != "ok" || a["poses"].empty()) state.SkipWithError("DO MOVE failed");
    benchmark::DoNotOptimize(a);
  }
}
BENCHMARK(BM_StudioDoMove)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_StudioWhere(benchmark::State& state) {
  LiveServer live;
  for (auto _ : state) benchmark::DoNotOptimize(live.ask("WHERE"));
}
BENCHMARK(BM_StudioWhere)->Unit(benchmark::kMillisecond)->UseRealTime();

// A program of short joint moves back and forth, every step a motion.
std::string swing_program(int moves) {
  std::string text = ".PROGRAM swing()\n    SPEED 100 ALWAYS\n";
  for (int i = 0; i < moves; ++i) text += i % 2 ? "    MOVE #PPOINT(20, -70, 110, 0, 30, 0)\n" : "    MOVE #PPOINT(10, -80, 100, 0, 20, 0)\n";
  return text + ".END\n";
}

nlohmann::json debug_message(const char* action, const std::string& text, double speed) {
  return {{"type", "debug"}, {"id", 2}, {"action", action}, {"file", "swing.v2"}, {"text", text}, {"speed", speed}};
}

// From a step command to the first frame of its motion on the client's side of the socket
// (manual time: only that interval); the rest of the motion streams at x4 and is drained.
void BM_StudioStepToFrame(benchmark::State& state) {
  LiveServer live;
  const std::string text = swing_program(1000);
  live.send(debug_message("start", text, 0));
  live.receive();
  live.send(debug_message("step", text, 0));  // SPEED: no motion
  live.receive();
  std::size_t frames = 0;
  std::vector<double> latencies;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    live.send(debug_message("step", text, 4));
    bool first = true;
    for (;;) {
      const nlohmann::json m = live.receive();
      if (m["type"] == "frame") {
        ++frames;
        if (first) {
          latencies.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
          state.SetIterationTime(latencies.back());
        }
        first = false;
        continue;
      }
      if (m["type"] != "debug" || m["stop"] != "step") state.SkipWithError("the step did not stop at the next one");
      break;
    }
    if (first) state.SkipWithError("no frame");
  }
  std::sort(latencies.begin(), latencies.end());
  if (!latencies.empty()) {
    state.counters["median_ms"] = 1e3 * latencies[latencies.size() / 2];
    state.counters["max_ms"] = 1e3 * latencies.back();
  }
  state.counters["frames_per_step"] = benchmark::Counter(static_cast<double>(frames) / static_cast<double>(state.iterations()));
}
BENCHMARK(BM_StudioStepToFrame)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(15);

// The peer of the step's latency: the same steps on a StudioSession directly (no socket, no
// server thread): from handle() called to the first frame given to the frame sink.
void BM_SessionStepToFrame(benchmark::State& state) {
  const auto dir = std::filesystem::temp_directory_path() / ("asimov-bench-session-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  serve::StudioConfig config{cell::default_cell(), "built-in default cell", "a.v2", "", {}};
  serve::Workspace workspace = std::move(serve::Workspace::open(dir).value());
  serve::StudioSession session(config, workspace);
  std::chrono::steady_clock::time_point first{};
  session.set_frame_sink([&](std::string) {
    if (first == std::chrono::steady_clock::time_point{}) first = std::chrono::steady_clock::now();
  });
  const std::string text = swing_program(1000);
  const auto ask = [&](const char* action, double speed) {
    return session.handle(serve::parse_request(debug_message(action, text, speed).dump()).value());
  };
  ask("start", 0);
  ask("step", 0);
  std::vector<double> latencies;
  for (auto _ : state) {
    first = {};
    const auto start = std::chrono::steady_clock::now();
    const nlohmann::json a = ask("step", 4);
    if (a["stop"] != "step" || first == std::chrono::steady_clock::time_point{}) state.SkipWithError("no frame");
    latencies.push_back(std::chrono::duration<double>(first - start).count());
    state.SetIterationTime(latencies.back());
  }
  std::sort(latencies.begin(), latencies.end());
  if (!latencies.empty()) state.counters["median_ms"] = 1e3 * latencies[latencies.size() / 2];
  std::error_code ignored;
  std::filesystem::remove_all(dir, ignored);
}
BENCHMARK(BM_SessionStepToFrame)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(15);

// The pose stream while the arm moves live at x1: frames received per second of wall time from
// the first frame to the last of a run of motions, and the simulated seconds shown per wall
// second (1 when the stream keeps pace).
void BM_StudioLiveFrameRate(benchmark::State& state) {
  LiveServer live;
  const std::string text = swing_program(6);
  for (auto _ : state) {
    live.send(debug_message("go", text, 1));
    std::size_t frames = 0;
    double t0 = 0, t1 = 0;
    std::chrono::steady_clock::time_point w0, w1;
    for (;;) {
      const nlohmann::json m = live.receive();
      if (m["type"] != "frame") {
        if (m.value("stop", "") != "completed") state.SkipWithError("the run did not complete");
        break;
      }
      w1 = std::chrono::steady_clock::now();
      t1 = m["t"].get<double>();
      if (frames++ == 0) w0 = w1, t0 = t1;
    }
    const double wall = std::chrono::duration<double>(w1 - w0).count();
    state.counters["frames_per_s"] = static_cast<double>(frames - 1) / wall;
    state.counters["sim_s_per_wall_s"] = (t1 - t0) / wall;
    state.counters["frames"] = static_cast<double>(frames);
  }
}
BENCHMARK(BM_StudioLiveFrameRate)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// The peer: the monitor itself, no server, no JSON, no socket.
void BM_DirectDoMove(benchmark::State& state) {
  motion::Simulator sim(cell::default_cell());
  std::ostringstream out;
  interpreter::Interpreter interp(sim, out);
  interpreter::Monitor monitor(interp, sim, out);
  std::size_t k = 0;
  for (auto _ : state) {
    if (monitor.execute(kTargets[k++ % 2]) != interpreter::CommandStatus::ok) state.SkipWithError("DO MOVE failed");
    out.str({});
  }
}
BENCHMARK(BM_DirectDoMove)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
