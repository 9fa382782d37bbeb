#include "app/serve/cmd_serve.hpp"

#include "app/exit_codes.hpp"
#include "app/replay.hpp"
#include "app/serve/server.hpp"
#include "asimov/cell/cell_loader.hpp"

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>

#include <fmt/format.h>

#include <csignal>
#include <ostream>
#include <thread>

namespace asimov::serve {

int serve_command(const ServeOptions& opt, std::ostream& out, std::ostream& err) {
  Result<Workspace> workspace = Workspace::open(opt.workspace);
  if (!workspace) {
    err << workspace.error().message << "  " << workspace.error().detail << '\n';
    return app::kExitUsage;
  }
  Result<StudioAssets> assets = load_studio_assets();
  if (!assets) {
    err << "*Cannot serve*  " << assets.error().message << '\n';
    return app::kExitUsage;
  }
  auto cell = cell::load_cell_for_command(opt.cell, err);
  if (!cell) return app::kExitUsage;
  StudioConfig config{std::move(*cell), opt.cell.empty() ? "built-in default cell" : opt.cell, kSampleName, kSampleText, {}};
  if (!opt.file.empty()) {
    Result<std::string> text = workspace->read(opt.file);
    if (!text) {
      err << text.error().message << "  " << text.error().detail << '\n';
      return app::kExitUsage;
    }
    config.first_file = opt.file;
    config.first_text = std::move(*text);
  }
  if (auto replay = app::load_replay_assets(); !replay) config.replay_assets_error = replay.error().message;
  if (opt.port < 0 || opt.port > 65535) {
    err << fmt::format("*Invalid argument*  --port {}: 0 to 65535\n", opt.port);
    return app::kExitUsage;
  }
  ServerOptions options;
  options.address = opt.address;
  options.port = static_cast<std::uint16_t>(opt.port);
  Server server(std::move(config), std::move(*workspace), std::move(*assets), options);
  if (auto listening = server.listen(); !listening) {
    err << listening.error().message << "  " << listening.error().detail << '\n';
    return app::kExitUsage;
  }
  out << fmt::format("asimov studio: {}\n", server.url())
      << fmt::format("  workspace {}; Ctrl-C stops the server\n", std::filesystem::absolute(opt.workspace).lexically_normal().string());
  out.flush();
  // Ctrl-C and SIGTERM stop the server (exit 0): the usual way to end it.
  boost::asio::io_context signals_ctx;
  boost::asio::signal_set signals(signals_ctx, SIGINT, SIGTERM);
  signals.async_wait([&server](const boost::system::error_code&, int) { server.stop(); });
  std::thread waiter([&signals_ctx] { signals_ctx.run(); });
  server.run();
  signals_ctx.stop();
  waiter.join();
  out << "asimov studio: stopped\n";
  return app::kExitCompleted;
}

}  // namespace asimov::serve
