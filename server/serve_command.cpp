// `lambert serve`: the HTTP service (SPEC §4, docs/API.md) from the command line. Parses the options,
// starts the job store and the server, prints the bound address and runs until SIGINT or SIGTERM.
// Exit status: 0 after a clean shutdown, 1 when the service cannot start, 2 on bad usage.
#include "server/serve_command.h"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "server/cli_common.h"
#include "server/cli_parser.h"
#include "server/http_server.h"
#include "server/job_service.h"
#include "server/job_store_fs.h"
#include "server/job_store_pg.h"

namespace lambert {
namespace {

// What `lambert serve` is started with: the values as given, checked by the parser.
struct ServeArgs {
  std::string host = "127.0.0.1";
  int port = 8080;
  std::size_t workers = 2;
  std::size_t http_threads = HttpServerOptions{}.http_threads;
  std::size_t max_connections = HttpServerOptions{}.max_connections;
  std::size_t max_connections_per_client = HttpServerOptions{}.max_connections_per_client;
  double request_timeout_s = HttpServerOptions{}.request_timeout_s;
  std::string data_dir, mesh_root;  // empty: none
  std::string store;                // a PostgreSQL URI; empty: the data directory or memory
  double store_lease_s = 30;
  double drain_s = 20;
  std::size_t max_body_bytes = HttpServerOptions{}.max_body_bytes;
  std::size_t max_patches = 10000;
  double job_time_limit_s = 300;
  std::size_t queue_size = 64;
  double result_ttl_s = 604800;
  std::string job_memory_limit;  // empty: the machine's memory divided by the workers
  SceneLimits scene_limits;
  bool access_log = false;
};

constexpr double kMaxSeconds = 1e9;

void define_options(cli::Options& o, ServeArgs& a) {
  o.text("--host", a.host, "address to bind (0.0.0.0 for every interface)");
  o.integer("--port", a.port, 0, 65535, "TCP port; 0 picks a free one");
  o.count("--threads", a.workers, 1, 256, "solver workers: scenes solved at once");
  o.count("--http-threads", a.http_threads, 2, 1024, "requests handled at once (connections wait without a thread)");
  o.count("--max-connections", a.max_connections, 1, 100000, "open connections; beyond: 503 and closed");
  o.count("--max-connections-per-client", a.max_connections_per_client, 1, 100000,
          "open connections of one IP address; beyond: 503 and closed");
  o.number("--request-timeout-s", a.request_timeout_s, 0.1, 3600,
           "a request's line and headers must arrive within S seconds (else 408)");
  o.text("--data-dir", a.data_dir, "keep jobs and results in DIR (kept across restarts)", "DIR");
  o.text("--store", a.store,
         "keep jobs and results in PostgreSQL, shared by every instance started with the same URI "
         "(postgresql://user@host:5432/db; docs/SCALING.md)", "URI");
  o.number("--store-lease-s", a.store_lease_s, 1, 3600,
           "with --store: a running job whose instance stopped renewing its lease for S seconds is "
           "taken up by another");
  o.number("--drain-s", a.drain_s, 0, kMaxSeconds,
           "on SIGTERM: let running solves finish for up to S seconds, then hand the rest back to the "
           "queue (SIGINT or a second signal: at once)");
  o.directory("--mesh-root", a.mesh_root, "allow \"file\" surfaces, relative to DIR and never outside it");
  o.count("--max-body-bytes", a.max_body_bytes, 1, std::size_t{1} << 40, "largest request body in bytes");
  o.count("--max-patches", a.max_patches, 1, std::numeric_limits<std::size_t>::max(),
          "largest patch count of a solve");
  o.number("--job-time-limit-s", a.job_time_limit_s, 0, kMaxSeconds, "running time limit per solve, 0 for none");
  o.count("--queue-size", a.queue_size, 1, 1000000, "jobs waiting for a worker before 503");
  o.number("--result-ttl-s", a.result_ttl_s, 0, kMaxSeconds, "keep finished jobs for S seconds, 0 for ever");
  o.text("--job-memory-limit", a.job_memory_limit,
         "address space of each solve's process: 4G, 512M or bytes, 0 for none "
         "(default: the machine's memory divided by --threads)", "SIZE");
  scene_limit_options(o, a.scene_limits);
  o.flag("--access-log", a.access_log, "one JSON line per request on stderr (jobs are always logged)");
}

// "4G", "512M", "65536K" or plain bytes (binary multiples).
std::optional<std::uint64_t> parse_size(std::string text) {
  std::uint64_t unit = 1;
  if (!text.empty()) switch (text.back()) {
      case 'K': case 'k': unit = 1ull << 10; break;
      case 'M': case 'm': unit = 1ull << 20; break;
      case 'G': case 'g': unit = 1ull << 30; break;
      case 'T': case 't': unit = 1ull << 40; break;
      default: break;
    }
  if (unit != 1) text.pop_back();
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text.size() > 15)
    return std::nullopt;
  const std::uint64_t n = std::stoull(text);
  if (n > (std::uint64_t{1} << 50) / unit) return std::nullopt;
  return n * unit;
}

std::uint64_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page) : 0;
}

struct ServeOptions {
  std::string host;
  int port = 0;
  JobServiceOptions jobs;
  FileJobStoreOptions files;
  std::optional<PgJobStoreOptions> postgres;
  HttpServerOptions http;
  std::chrono::duration<double> drain{0};
};

// The service's options from the parsed arguments, or the exit status of a usage error (printed).
std::variant<ServeOptions, int> serve_options(const ServeArgs& a) {
  ServeOptions o;
  o.host = a.host;
  o.port = a.port;
  if (a.host.empty()) return cli::usage_error("serve", "--host: expected an address");
  o.jobs.workers = a.workers;
  o.jobs.queue_size = a.queue_size;
  o.jobs.limits.max_patches = a.max_patches;
  o.jobs.limits.scene = a.scene_limits;
  o.jobs.time_limit = std::chrono::duration<double>(a.job_time_limit_s);
  o.files.result_ttl = std::chrono::duration<double>(a.result_ttl_s);
  if (!a.data_dir.empty()) o.files.data_dir = std::filesystem::path(a.data_dir);
  if (!a.store.empty()) {
    if (!is_postgresql_uri(a.store))
      return cli::usage_error("serve", "--store: '" + a.store + "' is not a postgresql:// URI");
    if (!a.data_dir.empty()) return cli::usage_error("serve", "--store and --data-dir exclude each other");
    PgJobStoreOptions pg;
    pg.conninfo = a.store;
    pg.result_ttl = o.files.result_ttl;
    pg.lease = std::chrono::duration<double>(a.store_lease_s);
    o.postgres = pg;
  }
  o.drain = std::chrono::duration<double>(a.drain_s);
  o.jobs.limits.memory_bytes = physical_memory_bytes() / a.workers;
  if (!a.job_memory_limit.empty()) {
    const auto bytes = parse_size(a.job_memory_limit);
    if (!bytes || (*bytes > 0 && *bytes < (std::uint64_t{64} << 20)))
      return cli::usage_error("serve", "--job-memory-limit: '" + a.job_memory_limit +
                                           "' is not a size of at least 64M (or 0 for none)");
    o.jobs.limits.memory_bytes = *bytes;
  }
  // The worker processes run this very binary, even if its file was replaced since it started.
  o.jobs.worker_executable = "/proc/self/exe";
  char host[256] = "localhost";
  ::gethostname(host, sizeof host - 1);
  o.jobs.instance = std::string(host) + "/" + std::to_string(::getpid());
  o.http.http_threads = a.http_threads;
  o.http.max_connections = a.max_connections;
  o.http.max_connections_per_client = a.max_connections_per_client;
  o.http.request_timeout_s = a.request_timeout_s;
  o.http.max_body_bytes = a.max_body_bytes;
  o.http.access_log = a.access_log;
  if (!a.mesh_root.empty()) {
    std::error_code ec;
    o.http.mesh_root = std::filesystem::canonical(a.mesh_root, ec);
    if (ec) return cli::usage_error("serve", "--mesh-root: '" + a.mesh_root + "' is not a usable directory");
  }
  o.jobs.limits.mesh_root = o.http.mesh_root;
  return o;
}

int run_serve(const ServeArgs& args) {
  auto parsed = serve_options(args);
  if (auto* status = std::get_if<int>(&parsed)) return *status;
  ServeOptions& o = std::get<ServeOptions>(parsed);

  // SIGINT and SIGTERM are taken by one thread with sigwait(); blocked before any other thread
  // starts, so every thread inherits the mask and none is interrupted.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  std::optional<JobService> jobs;
  std::string where;
  try {
    std::unique_ptr<JobStore> store;
    if (o.postgres) store = std::make_unique<PgJobStore>(*o.postgres);
    else store = std::make_unique<FileJobStore>(o.files);
    where = store->describe();
    jobs.emplace(std::move(store), o.jobs);
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
            << ", " << where
            << (o.http.mesh_root ? ", mesh root " + o.http.mesh_root->string() : std::string())
            << ")" << std::endl;

  // SIGTERM drains: no new work is taken, running solves may finish for up to --drain-s, and the
  // jobs still running then are handed back to the queue (another instance, or this one after a
  // restart, runs them). SIGINT, or a second signal while draining, hands them back at once. The
  // server answers status and result requests throughout, and stops last (its stop() waits for its
  // handlers).
  std::atomic<bool> listening_ended{false};
  std::thread drainer;
  std::thread signal_waiter([&] {
    for (bool draining = false;;) {
      int sig = 0;
      sigwait(&signals, &sig);
      if (listening_ended) break;
      const bool at_once = sig == SIGINT || draining || o.drain.count() <= 0;
      std::cerr << "lambert serve: " << (sig == SIGINT ? "SIGINT" : "SIGTERM");
      if (at_once) std::cerr << ", handing running jobs back to the queue and stopping\n";
      else std::cerr << ", draining (running solves may finish for up to " << o.drain.count() << " s)\n";
      if (at_once) {
        jobs->shutdown();
        server.stop();
        break;
      }
      draining = true;
      drainer = std::thread([&] {
        jobs->drain(o.drain);
        server.stop();
      });
    }
  });
  const bool ok = server.listen_after_bind();
  listening_ended = true;
  pthread_kill(signal_waiter.native_handle(), SIGTERM);  // if listening ended by itself
  signal_waiter.join();
  if (drainer.joinable()) drainer.join();
  jobs->shutdown();
  std::cerr << "lambert serve: stopped\n";
  return ok ? 0 : 1;
}

}  // namespace

cli::CommandSpec command_serve() {
  return {"serve", "the HTTP service (docs/API.md): solves and jobs over HTTP", [](cli::Options& o) {
            auto args = std::make_shared<ServeArgs>();
            define_options(o, *args);
            return [args] { return run_serve(*args); };
          }};
}

int run_serve(const std::vector<std::string>& args) { return cli::run_one(command_serve(), args); }

}  // namespace lambert
