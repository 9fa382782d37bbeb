#include "app/serve/server.hpp"

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <fmt/format.h>

#include <condition_variable>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>
#include <sstream>
#include <thread>

#ifndef ASIMOV_STUDIO_REL
#define ASIMOV_STUDIO_REL "../share/asimov/studio"
#endif

namespace asimov::serve {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

std::string studio_asset_dir() {
  if (const char* env = std::getenv("ASIMOV_STUDIO_DIR"); env && *env) return env;
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  return (exe.parent_path() / ASIMOV_STUDIO_REL).lexically_normal().string();
}

Result<StudioAssets> load_studio_assets() {
  const std::filesystem::path file = std::filesystem::path(studio_asset_dir()) / "studio.js";
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  if (in) s << in.rdbuf();
  if (!in || s.str().empty())
    return Error{fmt::format("{} is missing: install the studio's npm packages with scripts/install-deps.sh "
                             "(npm ci in app/serve/web), then re-run cmake and build; or point ASIMOV_STUDIO_DIR at a "
                             "folder holding studio.js",
                             file.string()),
                 {}, file.string()};
  return StudioAssets{s.str()};
}

std::string random_token() {
  std::random_device rd;  // the system's random source (getrandom / /dev/urandom)
  std::string out;
  for (int i = 0; i < 4; ++i) out += fmt::format("{:08x}", static_cast<std::uint32_t>(rd()));
  return out;
}

bool same_token(const std::string& a, const std::string& b) {
  if (a.size() != b.size() || a.empty()) return false;
  unsigned char diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

std::string query_value(const std::string& target, const std::string& key) {
  const auto q = target.find('?');
  if (q == std::string::npos) return {};
  std::size_t at = q + 1;
  while (at <= target.size()) {
    std::size_t end = target.find('&', at);
    if (end == std::string::npos) end = target.size();
    const std::string pair = target.substr(at, end - at);
    const auto eq = pair.find('=');
    if (pair.substr(0, eq) == key) return eq == std::string::npos ? std::string() : pair.substr(eq + 1);
    at = end + 1;
  }
  return {};
}

namespace {

std::string path_of(const std::string& target) { return target.substr(0, target.find('?')); }

std::string html_page(const std::string& token) {
  // The token is 32 hex digits (nothing to escape); the page reads it from here for the WebSocket.
  return fmt::format(R"(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>asimov studio</title>
</head>
<body>
<div id="studio"></div>
<script>window.ASIMOV_TOKEN = "{0}";</script>
<script src="/studio.js?token={0}"></script>
</body>
</html>
)",
                     token);
}

}  // namespace

// ---------------------------------------------------------------------------------------------

struct Server::Impl : std::enable_shared_from_this<Server::Impl> {
  Impl(StudioConfig c, Workspace w, StudioAssets a, ServerOptions o)
      : config(std::move(c)), workspace(std::move(w)), assets(std::move(a)), options(std::move(o)) {
    if (options.token.empty()) options.token = random_token();
  }
  net::io_context ioc{1};
  tcp::acceptor acceptor{ioc};
  StudioConfig config;
  Workspace workspace;
  StudioAssets assets;
  ServerOptions options;
  std::atomic<int> connections{0}, sessions{0};

  bool wildcard() const {
    boost::system::error_code ec;
    const auto a = net::ip::make_address(options.address, ec);
    return !ec && a.is_unspecified();
  }
  // The Host names the page may be reached by: loopback's and the given address (any when
  // listening on all addresses: the token then decides).
  bool allowed_host(const std::string& host) const {
    if (wildcard()) return !host.empty();
    const std::string port = std::to_string(acceptor.local_endpoint().port());
    for (const std::string& name : {std::string("127.0.0.1"), std::string("localhost"), std::string("[::1]"), options.address,
                                   "[" + options.address + "]"})
      if (host == name + ":" + port) return true;
    return false;
  }
  void accept();
};

namespace {

using ImplPtr = std::shared_ptr<Server::Impl>;

// Counts a live object in one of the Impl's counters for its lifetime.
struct Counted {
  std::atomic<int>& n;
  explicit Counted(std::atomic<int>& n) : n(n) { ++n; }
  ~Counted() { --n; }
  Counted(const Counted&) = delete;
};

// One session's requests, in order, on a thread of its own: the StudioSession lives there.
// Answers go back through `deliver` (posted to the network thread by the WebSocket session).
class Worker {
 public:
  Worker(const StudioConfig& config, const Workspace& workspace, std::size_t max_queued)
      : session_(config, workspace), max_queued_(max_queued) {}
  // False when the queue is full.
  bool push(Request r) {
    std::lock_guard lock(mutex_);
    if (queue_.size() >= max_queued_) return false;
    queue_.push_back(std::move(r));
    cv_.notify_one();
    return true;
  }
  void stop() {
    {
      std::lock_guard lock(mutex_);
      stopped_ = true;
      queue_.clear();
    }
    session_.abort();
    cv_.notify_one();
  }
  void abort() { session_.abort(); }
  void pause() { session_.pause(); }
  nlohmann::json hello() const { return session_.hello(); }
  // The thread's loop; returns after stop(). `deliver(text, droppable)`: the answers (never
  // dropped) and the arm's frames (dropped when the client falls behind).
  void loop(const std::function<void(std::string, bool)>& deliver) {
    session_.set_frame_sink([&](std::string text) { deliver(std::move(text), true); });
    for (;;) {
      Request r;
      {
        std::unique_lock lock(mutex_);
        cv_.wait(lock, [&] { return stopped_ || !queue_.empty(); });
        if (stopped_) return;
        r = std::move(queue_.front());
        queue_.pop_front();
      }
      nlohmann::json answer = session_.handle(r);
      // Program output may hold any bytes: invalid UTF-8 is replaced, never an exception.
      deliver(answer.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), false);
    }
  }

 private:
  StudioSession session_;
  std::size_t max_queued_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Request> queue_;
  bool stopped_ = false;
};

class WsSession : public std::enable_shared_from_this<WsSession> {
  static constexpr std::size_t kMaxFramesWaiting = 8;

 public:
  WsSession(ImplPtr server, tcp::socket socket)
      : server_(std::move(server)), ws_(std::move(socket)), counted_(server_->sessions) {}
  ~WsSession() {
    if (worker_) worker_->stop();
  }

  void start(http::request<http::string_body> req) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(kMaxMessageBytes);
    ws_.async_accept(req, [self = shared_from_this()](beast::error_code ec) { self->on_accept(ec); });
  }

 private:
  void on_accept(beast::error_code ec) {
    if (ec) return;
    worker_ = std::make_shared<Worker>(server_->config, server_->workspace, server_->options.limits.max_queued);
    send(worker_->hello().dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    // The worker thread owns a share of the worker and the server state, not of this session: a
    // closed connection ends here at once, the thread when its request is answered.
    std::weak_ptr<WsSession> weak = shared_from_this();
    auto executor = ws_.get_executor();
    std::thread([worker = worker_, server = server_, weak, executor] {
      worker->loop([&](std::string text, bool droppable) {
        net::post(executor, [weak, text = std::move(text), droppable]() mutable {
          if (auto self = weak.lock()) self->send(std::move(text), droppable);
        });
      });
    }).detach();
    read();
  }

  void read() {
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

  void on_read(beast::error_code ec) {
    if (ec) {  // closed, timed out, a message over the limit, a protocol error: this session ends
      if (worker_) worker_->stop();
      return;
    }
    const bool text = ws_.got_text();
    std::string message = beast::buffers_to_string(buffer_.data());
    buffer_.consume(buffer_.size());
    if (!text) {
      reply_error(0, "*Invalid message*", "binary messages are not accepted");
    } else if (Result<Request> r = parse_request(message); !r) {
      reply_error(0, r.error().message, r.error().detail);
    } else if (r->kind == RequestKind::abort) {
      worker_->abort();  // at once, not behind the run it stops
      send(nlohmann::json{{"type", "abort"}, {"id", r->id}}.dump());
    } else if (r->kind == RequestKind::pause) {
      worker_->pause();  // at once, as abort: the program under way stops resumable
      send(nlohmann::json{{"type", "pause"}, {"id", r->id}}.dump());
    } else {
      const std::int64_t id = r->id;
      if (!worker_->push(std::move(*r))) reply_error(id, "*Busy*", "too many requests waiting; wait for the answers");
    }
    read();
  }

  void reply_error(std::int64_t id, const std::string& message, const std::string& detail) {
    send(nlohmann::json{{"type", "error"}, {"id", id}, {"message", message}, {"detail", detail}}.dump(
        -1, ' ', false, nlohmann::json::error_handler_t::replace));
  }

  void send(std::string text, bool droppable = false) {
    // The arm's frames are dropped while the client is behind (the next one poses it anyway).
    if (droppable && outbox_.size() >= kMaxFramesWaiting) return;
    // A client that reads nothing does not make the server hold its answers without end.
    if (outbox_.size() >= 64) {
      ws_.next_layer().close();
      return;
    }
    outbox_.push_back(std::move(text));
    if (outbox_.size() == 1) write();
  }
  void write() {
    ws_.text(true);
    ws_.async_write(net::buffer(outbox_.front()), [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return;
      self->outbox_.pop_front();
      if (!self->outbox_.empty()) self->write();
    });
  }

  ImplPtr server_;
  websocket::stream<beast::tcp_stream> ws_;
  Counted counted_;
  beast::flat_buffer buffer_;
  std::deque<std::string> outbox_;
  std::shared_ptr<Worker> worker_;
};

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(ImplPtr server, tcp::socket socket)
      : server_(std::move(server)), stream_(std::move(socket)), counted_(server_->connections) {}
  void start() { read(); }

 private:
  void read() {
    parser_.emplace();
    parser_->header_limit(16 * 1024);
    parser_->body_limit(64 * 1024);  // GET only: a body is read (bounded) and ignored
    stream_.expires_after(std::chrono::seconds(server_->options.limits.http_timeout_s));
    http::async_read(stream_, buffer_, *parser_,
                     [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

  void on_read(beast::error_code ec) {
    if (ec) {
      beast::error_code ignored;
      stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
      return;
    }
    http::request<http::string_body> req = parser_->release();
    const std::string target(req.target());
    const std::string host(req[http::field::host]);
    const bool token_ok = same_token(query_value(target, "token"), server_->options.token);
    if (websocket::is_upgrade(req)) {
      const std::string origin(req[http::field::origin]);
      if (path_of(target) != "/ws") return respond(req, http::status::not_found, "text/plain", "not found\n", false);
      if (!token_ok) return respond(req, http::status::forbidden, "text/plain", "forbidden: the URL's token is missing or wrong\n", false);
      // The page's own origin only: a page of another site (or another port) cannot drive the studio.
      if (!server_->allowed_host(host) || origin != "http://" + host)
        return respond(req, http::status::forbidden, "text/plain", "forbidden: WebSocket from another origin\n", false);
      if (server_->sessions.load() >= server_->options.limits.max_sessions)
        return respond(req, http::status::service_unavailable, "text/plain", "too many studio sessions\n", false);
      stream_.expires_never();
      // Small messages (the arm's frames) go out at once, not held for the last one's ACK.
      beast::error_code ignored;
      stream_.socket().set_option(tcp::no_delay(true), ignored);
      std::make_shared<WsSession>(server_, stream_.release_socket())->start(std::move(req));
      return;
    }
    if (req.method() != http::verb::get && req.method() != http::verb::head)
      return respond(req, http::status::method_not_allowed, "text/plain", "GET only\n", req.keep_alive());
    const std::string path = path_of(target);
    if (path == "/favicon.ico") return respond(req, http::status::no_content, "text/plain", "", req.keep_alive());
    if (path != "/" && path != "/index.html" && path != "/studio.js")
      return respond(req, http::status::not_found, "text/plain", "not found\n", req.keep_alive());
    if (!token_ok)
      return respond(req, http::status::forbidden, "text/plain", "forbidden: the URL's token is missing or wrong\n", req.keep_alive());
    if (!server_->allowed_host(host))
      return respond(req, http::status::forbidden, "text/plain", "forbidden: unknown Host\n", req.keep_alive());
    if (path == "/studio.js") return respond(req, http::status::ok, "text/javascript; charset=utf-8", server_->assets.script, req.keep_alive());
    respond(req, http::status::ok, "text/html; charset=utf-8", html_page(server_->options.token), req.keep_alive());
  }

  void respond(const http::request<http::string_body>& req, http::status status, const char* type, std::string body, bool keep) {
    auto res = std::make_shared<http::response<http::string_body>>(status, req.version());
    res->set(http::field::server, "asimov");
    res->set(http::field::content_type, type);
    res->set(http::field::cache_control, "no-store");
    res->set("X-Content-Type-Options", "nosniff");
    res->set("Referrer-Policy", "no-referrer");  // the token stays out of any Referer
    res->set("X-Frame-Options", "DENY");
    res->set("Content-Security-Policy",
             "default-src 'none'; script-src 'self' 'unsafe-inline'; style-src 'self' 'unsafe-inline'; "
             "connect-src 'self'; img-src 'self' data: blob:; frame-ancestors 'none'");
    res->keep_alive(keep);
    if (req.method() != http::verb::head) res->body() = std::move(body);
    res->prepare_payload();
    http::async_write(stream_, *res, [self = shared_from_this(), res](beast::error_code ec, std::size_t) {
      if (ec || !res->keep_alive()) {
        beast::error_code ignored;
        self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
        return;
      }
      self->read();
    });
  }

  ImplPtr server_;
  beast::tcp_stream stream_;
  Counted counted_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
};

}  // namespace

void Server::Impl::accept() {
  acceptor.async_accept(net::make_strand(ioc), [self = shared_from_this()](beast::error_code ec, tcp::socket socket) {
    if (!self->acceptor.is_open()) return;
    if (!ec) {
      if (self->connections.load() < self->options.limits.max_connections)
        std::make_shared<HttpSession>(self, std::move(socket))->start();
      // else: the socket closes here (too many connections at once)
    }
    self->accept();
  });
}

Server::Server(StudioConfig config, Workspace workspace, StudioAssets assets, ServerOptions options)
    : impl_(std::make_shared<Impl>(std::move(config), std::move(workspace), std::move(assets), std::move(options))) {}

Server::~Server() { stop(); }

Result<void> Server::listen() {
  boost::system::error_code ec;
  const auto address = net::ip::make_address(impl_->options.address, ec);
  if (ec) return Error{"*Invalid argument*", fmt::format("--address {}: not an IP address", impl_->options.address), {}, 0, 0};
  const tcp::endpoint endpoint(address, impl_->options.port);
  auto& a = impl_->acceptor;
  a.open(endpoint.protocol(), ec);
  if (!ec) a.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) a.bind(endpoint, ec);
  if (!ec) a.listen(net::socket_base::max_listen_connections, ec);
  if (ec) return Error{"*Cannot listen*", fmt::format("{}:{}: {}", impl_->options.address, impl_->options.port, ec.message()), {}, 0, 0};
  impl_->accept();
  return {};
}

std::uint16_t Server::port() const { return impl_->acceptor.local_endpoint().port(); }

std::string Server::url() const {
  const std::string& a = impl_->options.address;
  const bool v6 = a.find(':') != std::string::npos;
  const std::string host = impl_->wildcard() ? (v6 ? "[::1]" : "127.0.0.1") : v6 ? "[" + a + "]" : a;
  return fmt::format("http://{}:{}/?token={}", host, port(), impl_->options.token);
}

const std::string& Server::token() const { return impl_->options.token; }

void Server::run() { impl_->ioc.run(); }

void Server::stop() {
  net::post(impl_->ioc, [impl = impl_] {
    beast::error_code ignored;
    impl->acceptor.close(ignored);
    impl->ioc.stop();
  });
}

}  // namespace asimov::serve
