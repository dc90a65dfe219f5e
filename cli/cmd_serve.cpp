// `megavox serve`: the compute service (serve/): jobs over HTTP on loopback by default, bearer-token auth.
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

#include "cli_common.h"
#include "megavox/error.h"
#include "http_api.h"
#include "job_pool.h"
#include "serve_error.h"

namespace mv::cli {

namespace {

struct ServeArgs {
  std::string listen = "127.0.0.1:8080";
  std::string token_file, data_dir = "megavox-data";
  uint32_t max_jobs = 2, max_queue = 0, keep = 256;
  std::string max_body = "64M";
  double job_timeout = 600, stream_seconds = 30;
};

bool loopback(const std::string& host) {
  return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

void split_listen(const std::string& text, std::string& host, int& port) {
  const size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0) throw Error("--listen '" + text + "' wants HOST:PORT (e.g. 127.0.0.1:8080)");
  host = text.substr(0, colon);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  const std::string p = text.substr(colon + 1);
  if (p.empty() || p.size() > 5 || p.find_first_not_of("0123456789") != std::string::npos || std::stoi(p) > 65535)
    throw Error("--listen '" + text + "': the port must be 0 to 65535 (0: a free one)");
  port = std::stoi(p);
}

std::string read_token(const std::string& path) {
  std::ifstream in(path);
  std::string token;
  if (!in || !std::getline(in, token)) throw Error("--token-file " + path + ": cannot read a token from it");
  while (!token.empty() && std::isspace(static_cast<unsigned char>(token.back()))) token.pop_back();
  if (token.size() < 16) throw Error("--token-file " + path + ": the token must be at least 16 characters");
  return token;
}

// A random token in DIR/token, readable by the owner alone.
std::string write_token(const std::string& path) {
  std::random_device rd;
  char hex[65];
  for (int i = 0; i < 32; ++i) std::snprintf(hex + 2 * i, 3, "%02x", rd() & 0xff);
  const std::string token(hex, 64);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  if (fd < 0 || ::fchmod(fd, 0600) != 0 || ::write(fd, (token + "\n").data(), 65) != 65 || ::close(fd) != 0)
    throw Error("cannot write the token to " + path);
  return token;
}

void serve(const GlobalOptions& g, const ServeArgs& a) {
  std::string host;
  int port = 0;
  split_listen(a.listen, host, port);
  if (!loopback(host) && a.token_file.empty())
    throw Error("--listen " + a.listen + " is not a loopback address: give --token-file to listen beyond this machine");
  std::filesystem::create_directories(a.data_dir);
  serve::HttpOptions h;
  h.host = host;
  h.port = port;
  h.max_body = parse_size(a.max_body);
  h.stream_seconds = a.stream_seconds;
  const std::string token_path = (std::filesystem::path(a.data_dir) / "token").string();
  h.token = a.token_file.empty() ? write_token(token_path) : read_token(a.token_file);

  // SIGTERM and SIGINT wait for the thread below: blocked here, before any thread starts, so all inherit it.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  serve::PoolOptions p;
  p.device = g.device;
  p.device_memory = g.device_memory.empty() ? 0 : parse_size(g.device_memory);
  p.workers = a.max_jobs;
  p.max_queue = a.max_queue;
  p.job_timeout = a.job_timeout;
  p.keep_finished = a.keep;
  p.data_dir = a.data_dir;
  serve::JobPool pool(p);
  serve::HttpApi api(pool, h);
  const int bound = api.bind();
  std::printf("listening http://%s:%d\n", host.find(':') != std::string::npos ? ("[" + host + "]").c_str() : host.c_str(), bound);
  if (a.token_file.empty()) std::printf("token in %s\n", token_path.c_str());
  std::fflush(stdout);
  std::fprintf(stderr, "serve: %u jobs at once, %s of device memory each, queue of %u\n", pool.workers(),
               format_bytes(pool.budget_per_context()).c_str(), pool.max_queue());

  std::atomic<bool> done{false};
  std::thread waiter([&] {
    const timespec tick{0, 200'000'000};
    while (!done) {
      const int sig = sigtimedwait(&stop_signals, nullptr, &tick);
      if (sig == SIGTERM || sig == SIGINT) {
        std::fprintf(stderr, "serve: %s: stopping\n", sig == SIGTERM ? "SIGTERM" : "SIGINT");
        api.stop();
        return;
      }
    }
  });
  api.run();
  done = true;
  waiter.join();
  pool.shutdown();  // cancels running jobs, deletes the files of the unfinished
  std::fprintf(stderr, "serve: stopped\n");
}

}  // namespace

void add_serve_command(CLI::App& app, const GlobalOptions& g) {
  auto a = std::make_shared<ServeArgs>();
  CLI::App* c = app.add_subcommand(
      "serve",
      "Run megavox as an HTTP compute service: build and render jobs with progress, ray queries, bearer-token auth.\n"
      "The first stdout line is 'listening http://HOST:PORT'. Routes under /v1 (GET /v1/openapi.json describes them).\n"
      "Examples:\n"
      "  megavox serve --data-dir data                  loopback, port 8080, a fresh token in data/token\n"
      "  megavox serve --listen 127.0.0.1:0             a free port\n"
      "  megavox serve --listen 0.0.0.0:8080 --token-file secret --max-jobs 4   beyond this machine");
  c->add_option("--listen", a->listen, "HOST:PORT to listen on (port 0: a free one); other than loopback only with --token-file")
      ->capture_default_str();
  c->add_option("--token-file", a->token_file, "File whose first line is the bearer token (default: a random one in DIR/token)");
  c->add_option("--data-dir", a->data_dir, "Folder of job inputs (jobs may name files under it, nothing outside) and results")
      ->capture_default_str();
  c->add_option("--max-jobs", a->max_jobs, "Jobs running at once, each on its own device context with an equal share of --device-memory")
      ->capture_default_str()->check(CLI::Range(1, 64));
  c->add_option("--max-queue", a->max_queue, "Jobs waiting at most; beyond, 503 with Retry-After (default: 4 per --max-jobs)");
  c->add_option("--max-body", a->max_body, "Largest request body (uploads, ray batches); larger gets 413")->capture_default_str();
  c->add_option("--job-timeout", a->job_timeout, "Seconds a job may run before it is stopped and failed")->capture_default_str();
  c->add_option("--stream-seconds", a->stream_seconds, "Longest a progress stream stays open (then poll or reconnect)")
      ->capture_default_str();
  c->add_option("--keep", a->keep, "Finished jobs kept; past it the oldest go with their files")->capture_default_str();
  c->callback([&g, a] {
    try {
      serve(g, *a);
    } catch (const serve::ServeError& e) {  // the service's error, reported by the CLI's table of codes
      throw CodedError(static_cast<ErrorCode>(e.code), e.what());
    }
  });
}

}  // namespace mv::cli
