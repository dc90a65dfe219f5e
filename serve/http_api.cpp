#include "http_api.h"

#include <httplib.h>
#include <sys/socket.h>

#include <bit>
#include <chrono>
#include <cstring>
#include <fstream>
#include <memory>

#include "serve_error.h"

namespace mv::serve {

namespace {

using nlohmann::json;

void send_json(httplib::Response& res, int status, const json& body) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}

// The kind of a refusal told by its HTTP status, in the C API's terms (one table for the CLI, the C API and
// the service).
MvError code_of_status(int status) {
  if (status == 409) return MV_ERROR_INVALID_OPERATION;
  if (status == 429 || status == 503) return MV_ERROR_OUT_OF_MEMORY;  // the queue or the uploads are full
  return status >= 500 ? MV_ERROR_UNKNOWN : MV_ERROR_INVALID_ARGUMENT;
}

// {"error": MESSAGE, "code": "MV_ERROR_..."}, as the CLI prints an error with --json.
void send_error(httplib::Response& res, int status, const std::string& message, int retry_after = 0,
                MvError code = MV_ERROR_NONE) {
  if (retry_after) res.set_header("Retry-After", std::to_string(retry_after));
  if (code == MV_ERROR_NONE) code = code_of_status(status);
  send_json(res, status, {{"error", message}, {"code", mvGetErrorString(code)}});
}

// Equal strings take the same time whatever the first differing byte.
bool same_token(const std::string& a, const std::string& b) {
  unsigned char diff = a.size() != b.size();
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0 && !b.empty();
}

// Runs a handler, turning HttpError and ServeError (400) into a JSON error response.
template <class F>
void handle(httplib::Response& res, F&& body) {
  try {
    body();
  } catch (const HttpError& e) {
    send_error(res, e.status, e.what(), e.retry_after);
  } catch (const ServeError& e) {
    // What a request names (its fields, its files under --data-dir) are the client's arguments.
    send_error(res, 400, e.what(), 0, e.code == MV_ERROR_INPUT || e.code == MV_ERROR_IO ? MV_ERROR_INVALID_ARGUMENT : e.code);
  } catch (const std::exception& e) {
    send_error(res, 500, std::string("internal error: ") + message_of(e), 0, code_of(e));
  }
}

bool is_json(const httplib::Request& req) {
  return req.get_header_value("Content-Type").rfind("application/json", 0) == 0;
}

}  // namespace

HttpApi::HttpApi(JobPool& pool, const HttpOptions& options)
    : pool_(pool), options_(options), server_(std::make_unique<httplib::Server>()) {
  const uint32_t threads = options_.threads;
  server_->new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  server_->set_payload_max_length(options_.max_body);
  server_->set_tcp_nodelay(true);  // small JSON answers: no 40 ms wait on delayed ACKs (Nagle)
  // Connections stay open for many requests: reconnecting clients would overflow the listen backlog
  // (cpp-httplib listens with 5) and wait out a SYN retransmit.
  server_->set_keep_alive_max_count(1000);
  server_->set_socket_options([this](socket_t sock) {
    httplib::default_socket_options(sock);
    listen_socket_ = sock;
  });
  server_->set_read_timeout(10, 0);
  server_->set_write_timeout(10, 0);
  routes();
}

HttpApi::~HttpApi() = default;

int HttpApi::bind() {
  int port = options_.port;
  if (port == 0) {
    port = server_->bind_to_any_port(options_.host);
    if (port <= 0) throw ServeError("serve: cannot listen on " + options_.host, MV_ERROR_IO);
  } else if (!server_->bind_to_port(options_.host, port)) {
    throw ServeError("serve: cannot listen on " + options_.host + ":" + std::to_string(port) + " (in use?)", MV_ERROR_IO);
  }
  // Debian's compiled cpp-httplib listens with a backlog of 5: a burst of new connections (32 clients
  // starting at once) overflowed it, and a dropped handshake became a client's read error. Listening again
  // on the bound socket only raises the backlog.
  if (listen_socket_ >= 0 && ::listen(listen_socket_, SOMAXCONN) != 0)
    throw ServeError("serve: cannot listen on " + options_.host + ":" + std::to_string(port) + ": " + std::strerror(errno), MV_ERROR_IO);
  return port;
}

void HttpApi::run() { server_->listen_after_bind(); }

void HttpApi::stop() { server_->stop(); }

void HttpApi::routes() {
  httplib::Server& s = *server_;
  s.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    const std::string auth = req.get_header_value("Authorization");
    if (auth.rfind("Bearer ", 0) != 0 || !same_token(auth.substr(7), options_.token)) {
      res.set_header("WWW-Authenticate", "Bearer");
      send_error(res, 401, "a valid Authorization: Bearer TOKEN header is required");
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  s.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return;  // a handler's own error
    const char* what = res.status == 413 ? "the request body is over the server's limit"
                       : res.status == 404 ? "no such route (see /v1/openapi.json)"
                       : res.status == 400 ? "malformed request (a POST without a body needs Content-Length: 0)"
                                           : "the request was refused";
    send_error(res, res.status, what);
  });

  s.Get("/v1/openapi.json", [](const httplib::Request&, httplib::Response& res) {
    res.set_content(openapi_json(), "application/json");
  });

  // Submit: a JSON job naming its input under --data-dir, or the input itself (options in the query).
  s.Post("/v1/jobs", [this](const httplib::Request& req, httplib::Response& res) {
    handle(res, [&] {
      json status;
      if (is_json(req)) {
        status = pool_.submit(parse_job_request(req.body), nullptr, "");
      } else {
        if (req.body.empty()) throw HttpError(400, "an upload needs the input in the body (or send a JSON job)");
        const JobRequest r = job_request_from_query(req.params);
        status = pool_.submit(r, &req.body, req.get_param_value("name"));
      }
      res.set_header("Location", "/v1/jobs/" + status["id"].get<std::string>());
      send_json(res, 201, status);
    });
  });
  s.Get("/v1/jobs", [this](const httplib::Request&, httplib::Response& res) {
    handle(res, [&] { send_json(res, 200, pool_.list()); });
  });
  s.Get(R"(/v1/jobs/([0-9a-f]{1,32}))", [this](const httplib::Request& req, httplib::Response& res) {
    handle(res, [&] { send_json(res, 200, pool_.status(req.matches[1])); });
  });
  s.Delete(R"(/v1/jobs/([0-9a-f]{1,32}))", [this](const httplib::Request& req, httplib::Response& res) {
    handle(res, [&] {
      pool_.remove(req.matches[1]);
      res.status = 204;
    });
  });
  s.Post(R"(/v1/jobs/([0-9a-f]{1,32})/cancel)", [this](const httplib::Request& req, httplib::Response& res) {
    handle(res, [&] { send_json(res, 202, pool_.cancel(req.matches[1])); });
  });
  // Server-sent events: the status now and at each change, until the job ends or the stream's time is up.
  s.Get(R"(/v1/jobs/([0-9a-f]{1,32})/events)", [this](const httplib::Request& req, httplib::Response& res) {
    handle(res, [&] {
      const std::string id = req.matches[1];
      pool_.status(id);  // 404 now rather than inside the stream
      const auto end = std::chrono::steady_clock::now() +
                       std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                           std::chrono::duration<double>(options_.stream_seconds));
      auto last = std::make_shared<std::string>();
      auto seen = std::make_shared<uint64_t>(0);  // the pool's change count when the stream last looked
      res.set_header("Cache-Control", "no-cache");
      res.set_chunked_content_provider("text/event-stream", [this, id, end, last, seen](size_t, httplib::DataSink& sink) {
        bool over = false;
        std::string event;
        try {
          if (*seen) *seen = pool_.wait_change(*seen, end);  // asleep until some job changes (or time is up)
          else *seen = pool_.wait_change(0, std::chrono::steady_clock::now());
          const std::string now = pool_.status(id).dump();
          over = pool_.ended(id);
          if (now != *last) event = "event: status\ndata: " + now + "\n\n";
          *last = now;
        } catch (const HttpError&) {
          event = "event: gone\ndata: {}\n\n";
          over = true;
        }
        if (!event.empty() && !sink.write(event.data(), event.size())) return false;
        if (over || std::chrono::steady_clock::now() >= end) {
          sink.done();
          return true;
        }
        return true;
      });
    });
  });
  s.Get(R"(/v1/jobs/([0-9a-f]{1,32})/result)", [this](const httplib::Request& req, httplib::Response& res) {
    handle(res, [&] {
      const JobPool::Result r = pool_.result(req.matches[1]);
      auto in = std::make_shared<std::ifstream>(r.path, std::ios::binary | std::ios::ate);
      if (!*in) throw HttpError(410, "the result file is gone");
      const auto size = static_cast<size_t>(in->tellg());
      in->seekg(0);
      // streamed from the file in pieces: memory stays bounded whatever the result's size
      res.set_content_provider(size, r.content_type, [in](size_t offset, size_t length, httplib::DataSink& sink) {
        char buf[1 << 16];
        in->seekg(static_cast<std::streamoff>(offset));
        const size_t n = std::min(length, sizeof buf);
        in->read(buf, static_cast<std::streamsize>(n));
        return in->gcount() > 0 && sink.write(buf, static_cast<size_t>(in->gcount()));
      });
    });
  });
  // Rays in: 7 little-endian f32 each (origin, direction, t_max); out: the 32-byte MvTraceHit per ray, then with
  // ?colour=rgba 4 bytes of colour per ray.
  s.Post(R"(/v1/jobs/([0-9a-f]{1,32})/rays)", [this](const httplib::Request& req, httplib::Response& res) {
    handle(res, [&] {
      static_assert(sizeof(MvTraceRay) == 28 && sizeof(MvTraceHit) == 32);
      static_assert(std::endian::native == std::endian::little, "the wire format is the host layout");
      if (req.body.size() % sizeof(MvTraceRay))
        throw HttpError(400, "the body must hold whole rays of 28 bytes (7 little-endian f32); got " +
                                 std::to_string(req.body.size()) + " bytes");
      std::vector<MvTraceRay> rays(req.body.size() / sizeof(MvTraceRay));
      if (!rays.empty()) std::memcpy(rays.data(), req.body.data(), req.body.size());
      const std::string colour = req.has_param("colour") ? req.get_param_value("colour") : "none";
      if (colour != "none" && colour != "rgba")
        throw HttpError(400, "colour must be none or rgba (4 bytes per ray after the hits); got '" + colour + "'");
      std::vector<uint8_t> rgba;
      const std::vector<MvTraceHit> hits =
          pool_.trace(req.matches[1], rays.data(), rays.size(), colour == "rgba" ? &rgba : nullptr);
      std::string body(reinterpret_cast<const char*>(hits.data()), hits.size() * sizeof(MvTraceHit));
      body.append(reinterpret_cast<const char*>(rgba.data()), rgba.size());
      res.set_content(std::move(body), "application/octet-stream");
    });
  });
}

}  // namespace mv::serve
