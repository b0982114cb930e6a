// The HTTP service (SPEC §4): JSON over HTTP/1.1 in front of a JobService. cpp-httplib is used only in
// http_server.cpp; this header does not expose it.
//
// Routes: POST /v1/solve, POST /v1/jobs, GET|DELETE /v1/jobs/{id}, GET /v1/jobs/{id}/result,
// GET /v1/health, GET /v1/metrics (Prometheus text, server/metrics.h), GET /v1/openapi.json,
// GET /v1/schema/scene.json (docs/openapi.json is the full contract). Every error is {"error": {"code", "message", "pointer"}}; handler exceptions become a
// 500 without their text.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "server/job_service.h"
#include "server/scene_codec.h"

namespace lambert {

struct HttpServerOptions {
  std::size_t max_body_bytes = 64u << 20;       // larger request bodies get 413 too_large
  std::optional<std::filesystem::path> mesh_root;  // none: scenes may not name files at all
  std::size_t http_threads = 8;                 // requests handled at once (server/connection_front.h)
  std::size_t max_connections = 512;            // open connections; beyond: 503 and closed
  std::size_t max_connections_per_client = 64;  // open connections of one IP address; beyond: 503
  double request_timeout_s = 10;                // a request's line and headers must arrive within it: else 408
  int read_timeout_s = 30, write_timeout_s = 30;  // a worker's single read or write
  int keep_alive_timeout_s = 5;
  int retry_after_s = 5;                        // advertised with 503 queue_full
  bool access_log = false;                      // one JSON line per request on stderr (server/log.h)
};

// How scenes sent over HTTP may name "file" surfaces: not at all without a mesh root, and then
// only relative paths that stay inside it once symbolic links are followed.
FileAccess http_file_access(const std::optional<std::filesystem::path>& mesh_root);

class HttpServer {
 public:
  HttpServer(JobService& jobs, HttpServerOptions options);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // Binds host:port (port 0: any free port) and returns the port, or -1 when binding failed.
  int bind(const std::string& host, int port);
  // Serves until stop(); returns false if the server could not run.
  bool listen_after_bind();
  // Stops listening and closes the connections; safe from another thread (not from a signal
  // handler: use a thread that waits for the signal).
  void stop();
  bool is_running() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The contract documents served by the API, embedded from docs/ at build time.
const std::string& openapi_document();
const std::string& scene_schema_document();

}  // namespace lambert
