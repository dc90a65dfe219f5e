// The HTTP face of `megavox serve` (cpp-httplib): bearer-token auth on every request, the /v1 routes over a
// JobPool, request-size limits, and bounded progress streams.
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "job_pool.h"

namespace httplib {
class Server;
}

namespace mv::serve {

struct HttpOptions {
  std::string host = "127.0.0.1";
  int port = 0;  // 0: a free port
  std::string token;
  uint64_t max_body = uint64_t{64} << 20;  // bytes; larger requests get 413
  double stream_seconds = 30;              // a progress stream ends after this long (poll again after)
  uint32_t threads = 48;                   // HTTP worker threads (one per open connection)
};

class HttpApi {
 public:
  HttpApi(JobPool& pool, const HttpOptions& options);
  ~HttpApi();
  int bind();  // binds host:port (a free port for 0) and returns the port; throws ServeError
  void run();  // serves until stop()
  void stop();

 private:
  void routes();
  JobPool& pool_;
  HttpOptions options_;
  std::unique_ptr<httplib::Server> server_;
  int listen_socket_ = -1;  // the server's socket, seen as it is created (bind() widens its backlog)
};

// The OpenAPI 3 document of the routes (serve/openapi.json, built in).
const char* openapi_json();

}  // namespace mv::serve
