// The studio's latency from a command to the arm's new pose on the page's side of the socket:
// a monitor `DO MOVE` (one motion, simulated and checked, the answer carrying the moving bodies'
// world poses: what the page draws) sent over a real WebSocket to an in-process `asimov serve`
// server on 127.0.0.1 and answered; WHERE over the same socket (the server's own cost: JSON,
// the worker thread, the socket); and, as the peer, the same DO MOVE on interpreter::Monitor
// directly (no server). The ratio studio / direct is what serving costs.
// Run: build/bench/bench_studio --benchmark_repetitions=9 --benchmark_report_aggregates_only=true
#include "app/serve/server.hpp"
#include "asimov/cell/cell_loader.hpp"

#include <benchmark/benchmark.h>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>
#include <sstream>
#include <thread>

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
  nlohmann::json ask(const std::string& line) {
    ws->write(net::buffer(nlohmann::json{{"type", "monitor"}, {"id", 1}, {"line", line}}.dump()));
    return receive();
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
