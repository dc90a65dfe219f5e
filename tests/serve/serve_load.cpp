// A bounded load test of `megavox serve` on loopback: CLIENTS threads each make REQUESTS requests, a mix of
// status polls, submits (64^3 builds of an uploaded tetrahedron), ray queries against a finished build and,
// given BIG (a .mvx under the server's data folder, larger than its query share), ray queries against it opened
// as a scene: streamed through the page cache.
// Every submit must be accepted (201) or refused with 429/503 and Retry-After; every accepted job must then
// end done (none lost); every other answer must be 200. Prints p50/p99 latencies per kind. Exit 0 when all
// of that holds within the time limit.
// Usage: serve_load URL TOKEN [CLIENTS REQUESTS SECONDS [BIG]]
#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

const char* kTetra =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
    "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

struct Shared {
  std::mutex lock;
  std::vector<std::string> accepted;
  std::vector<double> ms[4];  // status, submit, rays, big rays
  int rejected = 0, errors = 0;
  std::string first_error;
  void error(const std::string& what) {
    std::lock_guard<std::mutex> g(lock);
    if (errors++ == 0) first_error = what;
  }
};

httplib::Headers auth(const std::string& token) { return {{"Authorization", "Bearer " + token}}; }

std::string submit_path() { return "/v1/jobs?kind=build&resolution=64&name=tetra.ply"; }

double pct(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(p * double(v.size())))];
}

// Waits until job `id` ends; its final status ("" when it could not be read).
std::string wait_for(httplib::Client& c, const std::string& token, const std::string& id, Clock::time_point deadline) {
  while (Clock::now() < deadline) {
    auto r = c.Get(("/v1/jobs/" + id).c_str(), auth(token));
    if (!r || r->status != 200) return r ? "http " + std::to_string(r->status) : "no answer";
    const std::string s = json::parse(r->body)["status"];
    if (s != "queued" && s != "running") return s;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return "timeout";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: serve_load URL TOKEN [CLIENTS REQUESTS SECONDS [BIG]]\n");
    return 2;
  }
  const std::string url = argv[1], token = argv[2];
  const int clients = argc > 3 ? std::atoi(argv[3]) : 32, requests = argc > 4 ? std::atoi(argv[4]) : 50;
  const double seconds = argc > 5 ? std::atof(argv[5]) : 110;
  const std::string big_file = argc > 6 ? argv[6] : "";
  const auto start = Clock::now();
  const auto deadline = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));

  // One finished build to poll and to trace rays at.
  httplib::Client setup(url);
  auto first = setup.Post(submit_path().c_str(), auth(token), kTetra, std::strlen(kTetra), "application/octet-stream");
  if (!first || first->status != 201) {
    std::fprintf(stderr, "serve_load: the first submit failed (%d)\n", first ? first->status : -1);
    return 1;
  }
  const std::string scene = json::parse(first->body)["id"];
  if (wait_for(setup, token, scene, deadline) != "done") {
    std::fprintf(stderr, "serve_load: the first build did not finish\n");
    return 1;
  }
  std::string big;  // the open job of big_file
  if (!big_file.empty()) {
    const std::string body = json{{"kind", "open"}, {"input", big_file}}.dump();
    auto r = setup.Post("/v1/jobs", auth(token), body, "application/json");
    if (!r || r->status != 201) {
      std::fprintf(stderr, "serve_load: opening %s failed (%d)\n", big_file.c_str(), r ? r->status : -1);
      return 1;
    }
    big = json::parse(r->body)["id"];
    if (wait_for(setup, token, big, deadline) != "done") {
      std::fprintf(stderr, "serve_load: %s did not open\n", big_file.c_str());
      return 1;
    }
    // a picture of it on a worker, whose share it passes as well: streamed, it converges
    const auto t0 = Clock::now();
    const std::string job = json{{"kind", "render"}, {"scene", big}, {"width", 160}, {"height", 120}}.dump();
    auto p = setup.Post("/v1/jobs", auth(token), job, "application/json");
    const std::string render = p && p->status == 201 ? json::parse(p->body)["id"].get<std::string>() : "";
    const std::string ended = render.empty() ? "refused" : wait_for(setup, token, render, deadline);
    if (ended != "done") {
      auto st = setup.Get(("/v1/jobs/" + render).c_str(), auth(token));
      std::fprintf(stderr, "serve_load: the render of %s ended %s: %s\n", big_file.c_str(), ended.c_str(),
                   st ? st->body.c_str() : "");
      return 1;
    }
    std::printf("render of %s (160 x 120, streamed on a worker): %.2f s\n", big_file.c_str(),
                std::chrono::duration<double>(Clock::now() - t0).count());
  }
  std::vector<float> rays;
  for (int i = 0; i < 64; ++i) rays.insert(rays.end(), {0.05f + 0.9f * float(i % 8) / 8, 0.05f + 0.9f * float(i / 8) / 8, 5, 0, 0, -1, INFINITY});
  const std::string ray_body(reinterpret_cast<const char*>(rays.data()), rays.size() * 4);

  Shared shared;
  std::vector<std::thread> threads;
  for (int t = 0; t < clients; ++t)
    threads.emplace_back([&, t] {
      httplib::Client c(url);
      c.set_keep_alive(true);
      c.set_tcp_nodelay(true);
      c.set_read_timeout(60, 0);
      for (int i = 0; i < requests && Clock::now() < deadline; ++i) {
        // 20 % submits, 40 % status, 40 % rays (half of them at the big scene when there is one)
        const int kind = (t + i) % 5 == 0 ? 1 : (t + i) % 5 < 3 ? 0 : (t + i) % 5 == 4 && !big.empty() ? 3 : 2;
        const auto t0 = Clock::now();
        httplib::Result r = kind == 0 ? c.Get(("/v1/jobs/" + scene).c_str(), auth(token))
                            : kind == 1 ? c.Post(submit_path().c_str(), auth(token), kTetra, std::strlen(kTetra), "application/octet-stream")
                                        : c.Post(("/v1/jobs/" + (kind == 3 ? big : scene) + "/rays").c_str(), auth(token), ray_body,
                                                 "application/octet-stream");
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        if (!r) {
          shared.error("no answer (" + httplib::to_string(r.error()) + ") to request " + std::to_string(i) + " of client " +
                       std::to_string(t) + ", a " + (kind == 0 ? "status" : kind == 1 ? "submit" : "rays") + " request");
          continue;
        }
        std::lock_guard<std::mutex> g(shared.lock);
        shared.ms[kind].push_back(ms);
        if (kind == 1 && r->status == 201) {
          shared.accepted.push_back(json::parse(r->body)["id"]);
        } else if (kind == 1 && (r->status == 429 || r->status == 503)) {
          ++shared.rejected;
          if (!r->has_header("Retry-After") && shared.errors++ == 0) shared.first_error = "a refusal without Retry-After";
        } else if (r->status != 200 || (kind >= 2 && r->body.size() != 64 * 32)) {
          if (shared.errors++ == 0) shared.first_error = "status " + std::to_string(r->status) + ": " + r->body.substr(0, 200);
        }
      }
    });
  for (auto& th : threads) th.join();
  const double load_seconds = std::chrono::duration<double>(Clock::now() - start).count();

  int done = 0, lost = 0;
  for (const auto& id : shared.accepted) {
    const std::string s = wait_for(setup, token, id, deadline);
    if (s == "done") ++done;
    else if (++lost == 1) std::fprintf(stderr, "serve_load: job %s ended %s\n", id.c_str(), s.c_str());
  }
  const double total = std::chrono::duration<double>(Clock::now() - start).count();
  const char* names[4] = {"status", "submit", "rays", "big"};
  size_t made = 0;
  for (int k = 0; k < 4; ++k) {
    if (k == 3 && big.empty()) continue;
    made += shared.ms[k].size();
    std::printf("%-6s %5zu requests  p50 %8.2f ms  p99 %8.2f ms\n", names[k], shared.ms[k].size(), pct(shared.ms[k], 0.5),
                pct(shared.ms[k], 0.99));
  }
  std::vector<double> all;
  for (auto& v : shared.ms) all.insert(all.end(), v.begin(), v.end());
  std::printf("all    %5zu requests  p50 %8.2f ms  p99 %8.2f ms  (%d clients x %d, %.1f s of load, %.1f s in all)\n", made,
              pct(all, 0.5), pct(all, 0.99), clients, requests, load_seconds, total);
  std::printf("submits: %zu accepted, %d refused (429/503), %d done, %d lost; %d other errors\n", shared.accepted.size(),
              shared.rejected, done, lost, shared.errors);
  if (shared.errors) std::fprintf(stderr, "serve_load: first error: %s\n", shared.first_error.c_str());
  const bool ok = lost == 0 && shared.errors == 0 && made == size_t(clients) * size_t(requests) && total < seconds;
  return ok ? 0 : 1;
}
