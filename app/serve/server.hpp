// `asimov serve`: the studio's HTTP + WebSocket server (Boost.Beast on one Asio thread; each
// WebSocket session's requests run on that session's own worker thread, so a long run never
// stalls the others). Security (docs/studio.md "Security"): it listens on loopback unless an
// address is given; every HTTP request and the WebSocket upgrade must carry the random token of
// the printed URL (403 without it); the WebSocket's Origin must be the page's own (403
// otherwise); headers, messages and queues are bounded; a broken client closes only its own
// connection.
#pragma once
#include "app/serve/session.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace asimov::serve {

struct ServerLimits {
  int max_sessions = 8;               // WebSocket sessions at once (more: 503)
  int max_connections = 64;           // TCP connections at once (more: closed at accept)
  std::size_t max_queued = 32;        // requests waiting per session (more: *Busy*)
  int http_timeout_s = 30;            // a request must arrive whole within this
};

struct ServerOptions {
  std::string address = "127.0.0.1";  // loopback unless given
  std::uint16_t port = 0;              // 0: any free port
  std::string token;                   // the URL's secret; empty: a random one
  ServerLimits limits;
};

// The page and its script: index.html is written per request (the token inlined), studio.js
// (the esbuild bundle, app/serve/web/) is read from the studio asset folder at start.
struct StudioAssets {
  std::string script;  // studio.js
};
// $ASIMOV_STUDIO_DIR, else share/asimov/studio beside the executable's folder (as the replay
// assets: app/README.md).
std::string studio_asset_dir();
Result<StudioAssets> load_studio_assets();

// A random token: 32 hex digits (128 bits from the system's random source).
std::string random_token();
// Constant-time comparison (the token check must not leak how much of a guess was right).
bool same_token(const std::string& a, const std::string& b);
// The value of `key` in a request target's query ("/?token=abc" -> "abc"); "" when absent.
std::string query_value(const std::string& target, const std::string& key);

class Server {
 public:
  Server(StudioConfig config, Workspace workspace, StudioAssets assets, ServerOptions options);
  ~Server();
  // Binds and listens; the error says why not (address in use, bad address).
  Result<void> listen();
  std::uint16_t port() const;
  // http://ADDRESS:PORT/?token=TOKEN
  std::string url() const;
  const std::string& token() const;
  // Serves until stop() (from any thread or a signal handler through it).
  void run();
  void stop();

  struct Impl;  // public for the connection classes of server.cpp; defined there only

 private:
  std::shared_ptr<Impl> impl_;
};

}  // namespace asimov::serve
