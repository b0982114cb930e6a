// `lambert serve`: the HTTP service (SPEC §4, docs/API.md) from the command line. Parses the options,
// starts the job store and the server, prints the bound address and runs until SIGINT or SIGTERM.
// Exit status: 0 after a clean shutdown, 1 when the service cannot start, 2 on bad usage.
#include "server/serve_command.h"

#include <pthread.h>
#include <signal.h>

#include <atomic>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "server/cli_common.h"
#include "server/http_server.h"
#include "server/job_store.h"

namespace lambert {
namespace {

constexpr const char* kServeUsage =
    "usage: lambert serve [options]\n"
    "  --host ADDR            address to bind (default 127.0.0.1; 0.0.0.0 for every interface)\n"
    "  --port N               TCP port (default 8080; 0 picks a free one)\n"
    "  --threads N            solver workers: scenes solved at once (default 2)\n"
    "  --http-threads N       connections served at once (default 8)\n"
    "  --data-dir DIR         keep jobs and results in DIR (kept across restarts)\n"
    "  --mesh-root DIR        allow \"file\" surfaces, relative to DIR and never outside it\n"
    "  --max-body-bytes N     largest request body (default 67108864)\n"
    "  --max-patches N        largest patch count of a solve (default 10000)\n"
    "  --job-time-limit-s S   running time limit per solve, 0 for none (default 300)\n"
    "  --queue-size N         jobs waiting for a worker before 503 (default 64)\n"
    "  --result-ttl-s S       keep finished jobs for S seconds, 0 for ever (default 604800)\n"
    "  --access-log           one line per request on stderr\n";

int usage_error(const std::string& message) { return lambert::usage_error("lambert serve", message, kServeUsage); }

template <typename T>
std::optional<T> parse_number(const std::string& text, T lo, T hi) {
  T value{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  if constexpr (std::is_floating_point_v<T>)
    if (!std::isfinite(value)) return std::nullopt;
  if (value < lo || value > hi) return std::nullopt;
  return value;
}

struct ServeOptions {
  std::string host = "127.0.0.1";
  int port = 8080;
  JobStoreOptions jobs;
  HttpServerOptions http;
};

// Returns the options, or the exit status of a usage error (already printed).
std::variant<ServeOptions, int> parse(const std::vector<std::string>& args) {
  ServeOptions o;
  o.jobs.workers = 2;
  o.jobs.queue_size = 64;
  o.jobs.max_patches = 10000;
  o.jobs.time_limit = std::chrono::seconds(300);
  o.jobs.result_ttl = std::chrono::seconds(604800);
  constexpr double kMaxSeconds = 1e9;
  for (std::size_t k = 0; k < args.size(); ++k) {
    const std::string& a = args[k];
    if (a == "-h" || a == "--help") {
      std::cout << kServeUsage;
      return 0;
    }
    if (a == "--access-log") {
      o.http.access_log = true;
      continue;
    }
    if (k + 1 >= args.size()) return usage_error(a.rfind("--", 0) == 0 ? a + " needs a value" : "unexpected argument " + a);
    const std::string& v = args[++k];
    auto bad = [&](const std::string& what) { return usage_error(a + ": '" + v + "' is not " + what); };
    if (a == "--host") {
      if (v.empty()) return bad("an address");
      o.host = v;
    } else if (a == "--port") {
      auto n = parse_number<int>(v, 0, 65535);
      if (!n) return bad("a port number (0-65535)");
      o.port = *n;
    } else if (a == "--threads") {
      auto n = parse_number<std::size_t>(v, 1, 256);
      if (!n) return bad("a number of workers (1-256)");
      o.jobs.workers = *n;
    } else if (a == "--http-threads") {
      auto n = parse_number<std::size_t>(v, 2, 1024);
      if (!n) return bad("a number of threads (2-1024)");
      o.http.http_threads = *n;
    } else if (a == "--data-dir") {
      if (v.empty()) return bad("a directory");
      o.jobs.data_dir = std::filesystem::path(v);
    } else if (a == "--mesh-root") {
      std::error_code ec;
      if (v.empty() || !std::filesystem::is_directory(v, ec)) return bad("an existing directory");
      o.http.mesh_root = std::filesystem::canonical(v, ec);
      if (ec) return bad("a usable directory");
    } else if (a == "--max-body-bytes") {
      auto n = parse_number<std::size_t>(v, 1, std::size_t{1} << 40);
      if (!n) return bad("a size in bytes");
      o.http.max_body_bytes = *n;
    } else if (a == "--max-patches") {
      auto n = parse_number<std::size_t>(v, 1, std::numeric_limits<std::size_t>::max());
      if (!n) return bad("a positive patch count");
      o.jobs.max_patches = *n;
    } else if (a == "--job-time-limit-s") {
      auto s = parse_number<double>(v, 0, kMaxSeconds);
      if (!s) return bad("a number of seconds");
      o.jobs.time_limit = std::chrono::duration<double>(*s);
    } else if (a == "--queue-size") {
      auto n = parse_number<std::size_t>(v, 1, 1000000);
      if (!n) return bad("a queue length (1-1000000)");
      o.jobs.queue_size = *n;
    } else if (a == "--result-ttl-s") {
      auto s = parse_number<double>(v, 0, kMaxSeconds);
      if (!s) return bad("a number of seconds");
      o.jobs.result_ttl = std::chrono::duration<double>(*s);
    } else {
      return usage_error("unknown option " + a);
    }
  }
  o.jobs.files = http_file_access(o.http.mesh_root);
  return o;
}

}  // namespace

int run_serve(const std::vector<std::string>& args) {
  auto parsed = parse(args);
  if (auto* status = std::get_if<int>(&parsed)) return *status;
  ServeOptions& o = std::get<ServeOptions>(parsed);

  // SIGINT and SIGTERM are taken by one thread with sigwait(); blocked before any other thread
  // starts, so every thread inherits the mask and none is interrupted.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  std::optional<JobStore> jobs;
  try {
    jobs.emplace(o.jobs);
  } catch (const std::exception& e) {
    std::cerr << "lambert serve: " << e.what() << "\n";
    return 1;
  }
  HttpServer server(*jobs, o.http);
  const int port = server.bind(o.host, o.port);
  if (port < 0) {
    std::cerr << "lambert serve: cannot listen on " << o.host << ":" << o.port << "\n";
    return 1;
  }
  const bool ipv6 = o.host.find(':') != std::string::npos;
  std::cout << "lambert " << LAMBERT_VERSION << " listening on http://" << (ipv6 ? "[" : "") << o.host
            << (ipv6 ? "]" : "") << ":" << port << " (" << o.jobs.workers << " solver workers"
            << (o.jobs.data_dir ? ", data in " + o.jobs.data_dir->string() : std::string(", results in memory"))
            << (o.http.mesh_root ? ", mesh root " + o.http.mesh_root->string() : std::string())
            << ")" << std::endl;

  // Shutdown order: first the jobs (running solves are cancelled, and requests waiting for a
  // synchronous solve are answered 503), then the server, whose stop() waits for its handlers.
  // Jobs that did not finish stay in --data-dir and run again after a restart.
  std::atomic<bool> listening_ended{false};
  std::thread signal_waiter([&] {
    int sig = 0;
    sigwait(&signals, &sig);
    if (!listening_ended)
      std::cerr << "lambert serve: " << (sig == SIGINT ? "SIGINT" : "SIGTERM") << ", shutting down\n";
    jobs->shutdown();
    server.stop();
  });
  const bool ok = server.listen_after_bind();
  listening_ended = true;
  pthread_kill(signal_waiter.native_handle(), SIGTERM);  // if listening ended by itself
  signal_waiter.join();
  std::cerr << "lambert serve: stopped\n";
  return ok ? 0 : 1;
}

}  // namespace lambert
