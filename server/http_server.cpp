// The HTTP service (SPEC §4) on cpp-httplib 0.11.4, the only file that uses it.
//
// Hardening against cpp-httplib's defaults (STACK P4-P8):
//   - connections are accepted and their requests read by our own front (server/connection_front.h):
//     a request reaches one of the `http_threads` workers only once its head (and a small body) has
//     arrived within its deadline, so slow or stalled clients hold no worker; httplib only parses and
//     answers the request (Server::process_request, reached through a subclass);
//   - request bodies are read through a content reader with our own size limit, which also holds
//     for chunked and gzip-encoded bodies (httplib's payload limit, P7, covers only Content-Length);
//   - solves run on the JobStore's workers, never on these threads (P6);
//   - handler exceptions are logged and answered with a bare 500 (P8: no EXCEPTION_WHAT header);
//   - JSON is dumped with invalid UTF-8 replaced, so no message can turn into an exception (P10).
#include "server/http_server.h"

#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <ctime>
#include <map>
#include <optional>
#include <iostream>
#include <mutex>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "server/cache_key.h"
#include "server/connection_front.h"
#include "server/log.h"
#include "server/metrics.h"
#include "server/result_views.h"
#include "server/viewer_assets.h"

#ifndef LAMBERT_VERSION
#define LAMBERT_VERSION "unknown"
#endif

namespace lambert {

// ---- the embedded contract documents ----------------------------------------------------------

namespace {
#include "contract_documents.inc"  // kOpenApiJson, kSceneSchemaJson (tools/embed_files.cmake)
}  // namespace

const std::string& openapi_document() {
  static const std::string text(reinterpret_cast<const char*>(kOpenApiJson), sizeof kOpenApiJson - 1);
  return text;
}
const std::string& scene_schema_document() {
  static const std::string text(reinterpret_cast<const char*>(kSceneSchemaJson),
                                sizeof kSceneSchemaJson - 1);
  return text;
}

FileAccess http_file_access(const std::optional<std::filesystem::path>& mesh_root) {
  FileAccess files;
  if (mesh_root) {
    files.policy = FileAccess::Policy::UnderRoot;
    files.root = *mesh_root;
  } else {
    files.policy = FileAccess::Policy::Deny;
  }
  return files;
}

namespace {

using json = nlohmann::json;

// When the request this thread serves arrived (set before routing, read by the request's log line).
thread_local std::optional<std::chrono::steady_clock::time_point> request_start;

// ---- responses ----------------------------------------------------------------------------------

constexpr const char* kJsonType = "application/json";

std::string dump(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

void send_json(httplib::Response& res, int status, const json& body) {
  res.status = status;
  res.set_content(dump(body) + "\n", kJsonType);
}

// SPEC §4: {"error": {"code", "message", "pointer"}}, plus any `extra` members inside "error".
void send_error(httplib::Response& res, int status, const std::string& code,
                const std::string& message, const std::string& pointer = "",
                json extra = json::object()) {
  json error = {{"code", code}, {"message", message}, {"pointer", pointer}};
  for (auto& [k, v] : extra.items()) error[k] = std::move(v);
  send_json(res, status, {{"error", std::move(error)}});
}

std::string rfc3339(std::chrono::system_clock::time_point t) {
  const std::time_t secs = std::chrono::system_clock::to_time_t(t);
  std::tm tm{};
  gmtime_r(&secs, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string job_url(const std::string& id) { return "/v1/jobs/" + id; }

json status_json(const JobStatus& s) {
  json j = {{"id", s.id}, {"state", to_string(s.state)}, {"progress", s.progress},
            {"created", rfc3339(s.created)}};
  if (s.state == JobState::Queued) j["queue_position"] = s.queue_position;
  if (s.state == JobState::Done || s.state == JobState::Failed || s.state == JobState::Cancelled)
    j["finished"] = rfc3339(s.finished);
  if (s.expires) j["expires"] = rfc3339(*s.expires);
  if (s.state == JobState::Failed) j["error"] = s.error;
  if (s.state == JobState::Done) j["result_url"] = job_url(s.id) + "/result";
  if (s.cached) j["cached"] = true;
  j["status_url"] = job_url(s.id);
  return j;
}

// ---- routes -------------------------------------------------------------------------------------

// The served paths, for 404 and 405 before any handler runs. A "*" segment matches one non-empty
// path segment (a job id).
struct Route {
  std::vector<std::string> segments;
  std::vector<std::string> methods;  // GET implies HEAD
  std::string allow;                 // the Allow header for 405
};

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> parts;
  std::size_t start = 1;  // paths start with '/'
  for (;;) {
    const std::size_t slash = path.find('/', start);
    parts.push_back(path.substr(start, slash == std::string::npos ? std::string::npos : slash - start));
    if (slash == std::string::npos) return parts;
    start = slash + 1;
  }
}

bool route_matches(const Route& route, const std::string& path) {
  if (path.empty() || path[0] != '/') return false;
  const auto parts = split_path(path);
  if (parts.size() != route.segments.size()) return false;
  for (std::size_t k = 0; k < parts.size(); ++k)
    if (route.segments[k] == "*" ? parts[k].empty() : parts[k] != route.segments[k]) return false;
  return true;
}

// A file name as a regular expression that matches only itself.
std::string escape_dots(const std::string& name) {
  std::string out;
  for (char c : name) out += c == '.' ? std::string("\\.") : std::string(1, c);
  return out;
}

std::vector<Route> make_routes() {
  auto route = [](const std::string& path, std::vector<std::string> methods) {
    std::string allow;
    for (const auto& m : methods) allow += (allow.empty() ? "" : ", ") + m + (m == "GET" ? ", HEAD" : "");
    return Route{split_path(path), std::move(methods), std::move(allow)};
  };
  std::vector<Route> routes = {route("/v1/solve", {"POST"}),
                               route("/v1/jobs", {"POST"}),
                               route("/v1/jobs/*", {"GET", "DELETE"}),
                               route("/v1/jobs/*/result", {"GET"}),
                               route("/v1/health", {"GET"}),
                               route("/v1/metrics", {"GET"}),
                               route("/v1/openapi.json", {"GET"}),
                               route("/v1/schema/scene.json", {"GET"})};
  for (const ResultView& view : result_views()) routes.push_back(route("/v1/jobs/*/" + view.file, {"GET"}));
  for (const ViewerAsset& asset : viewer_assets()) routes.push_back(route(asset.path, {"GET"}));
  return routes;
}

std::optional<std::size_t> content_length(const httplib::Request& req) {
  if (!req.has_header("Content-Length")) return std::nullopt;
  const std::string v = req.get_header_value("Content-Length");
  std::size_t n = 0;
  const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
  if (ec != std::errc() || end != v.data() + v.size()) return std::nullopt;
  return n;
}

bool has_chunked_body(const httplib::Request& req) {
  std::string te = req.get_header_value("Transfer-Encoding");
  std::transform(te.begin(), te.end(), te.begin(), [](unsigned char c) { return std::tolower(c); });
  return te.find("chunked") != std::string::npos;
}

// A request whose body we leave unread (or read only in part) must not be followed by another on the
// same connection: its remaining bytes would be taken for the next request.
bool has_body(const httplib::Request& req) {
  const auto length = content_length(req);
  return (length && *length > 0) || has_chunked_body(req);
}
void close_after(const httplib::Request& req, httplib::Response& res) {
  if (req.get_header_value("Connection") != "close" && !res.has_header("Connection"))
    res.set_header("Connection", "close");
}

// httplib's request processing on a connection of the front: a Stream over it, and the protected
// Server::process_request made reachable.
class FrontStream final : public httplib::Stream {
 public:
  explicit FrontStream(Connection& c) : c_(c) {}
  bool is_readable() const override { return c_.readable(); }
  bool is_writable() const override { return c_.writable(); }
  ssize_t read(char* ptr, size_t size) override { return c_.read(ptr, size); }
  ssize_t write(const char* ptr, size_t size) override { return c_.write(ptr, size); }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = c_.remote_ip();
    port = c_.remote_port();
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    ip = c_.local_ip();
    port = c_.local_port();
  }
  socket_t socket() const override { return c_.fd(); }

 private:
  Connection& c_;
};

class RequestServer final : public httplib::Server {
 public:
  // One request on `strm`; false when none could be read or the answer not written.
  bool serve(httplib::Stream& strm, bool close_connection, bool& connection_closed) {
    return process_request(strm, close_connection, connection_closed, nullptr);
  }
};

// Set by the post-routing handler when the answer closes the connection (a body left unread).
thread_local bool answer_closes = false;

FrontOptions front_options(const HttpServerOptions& o) {
  FrontOptions f;
  f.workers = std::max<std::size_t>(2, o.http_threads);
  f.max_connections = o.max_connections;
  f.max_connections_per_client = o.max_connections_per_client;
  f.request_timeout = std::chrono::milliseconds(static_cast<long long>(o.request_timeout_s * 1000));
  f.keep_alive_timeout = std::chrono::seconds(o.keep_alive_timeout_s);
  f.read_timeout = std::chrono::seconds(o.read_timeout_s);
  f.write_timeout = std::chrono::seconds(o.write_timeout_s);
  return f;
}

}  // namespace

// ---- the server -----------------------------------------------------------------------------------

struct HttpServer::Impl {
  Impl(JobService& j, HttpServerOptions o)
      : jobs(j), options(std::move(o)), files(http_file_access(options.mesh_root)),
        routes(make_routes()),
        max_sync_waiters(std::max<std::size_t>(1, options.http_threads > 2 ? options.http_threads - 2 : 1)) {}

  JobService& jobs;
  HttpServerOptions options;
  FileAccess files;
  std::vector<Route> routes;
  RequestServer server;
  ConnectionFront front{front_options(options), [this](Connection& c, bool last, bool& close) {
                          return handle(c, last, close);
                        }};
  // Synchronous solves wait on HTTP threads: keep two threads free for status and health requests.
  const std::size_t max_sync_waiters;
  std::atomic<std::size_t> sync_waiters{0};
  std::mutex responses_mutex;
  std::map<int, std::uint64_t> responses;  // by status code, for GET /v1/metrics

  void install();
  bool handle(Connection& c, bool last, bool& close) {
    FrontStream strm(c);
    bool closed = false;
    answer_closes = false;
    const bool ok = server.serve(strm, last, closed);
    close = closed || answer_closes;
    return ok;
  }

  enum class Body { Ok, Sent };
  Body read_body(const httplib::Request& req, httplib::Response& res,
                 const httplib::ContentReader& reader, std::string& body) const;
  // Decodes a request's scene; on failure sends the 400/422 answer and returns nullopt.
  std::optional<Scene> decode(const std::string& body, httplib::Response& res) const;

  void post_solve(const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& reader);
  void post_job(const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& reader);
  void get_job(const httplib::Request& req, httplib::Response& res);
  // The result as JSON, or (with `view`) in one of the exchange formats of result_views.h.
  void get_result(const httplib::Request& req, httplib::Response& res, const ResultView* view = nullptr);
  void delete_job(const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& reader);
  void health(httplib::Response& res);
  void metrics(httplib::Response& res);
  void log_request(const httplib::Request& req, const httplib::Response& res);

  void queue_full(httplib::Response& res, std::size_t queue_size, const std::string& what) {
    res.set_header("Retry-After", std::to_string(options.retry_after_s));
    send_error(res, 503, "queue_full",
               what + ": the job queue is full (" + std::to_string(queue_size) +
                   " jobs waiting); retry later");
  }
};

HttpServer::HttpServer(JobService& jobs, HttpServerOptions options)
    : impl_(std::make_unique<Impl>(jobs, std::move(options))) {
  impl_->install();
}

HttpServer::~HttpServer() { stop(); }

int HttpServer::bind(const std::string& host, int port) { return impl_->front.bind(host, port); }
bool HttpServer::listen_after_bind() { return impl_->front.run(); }
void HttpServer::stop() { impl_->front.stop(); }
bool HttpServer::is_running() const { return impl_->front.is_running(); }

void HttpServer::Impl::install() {
  // Connections, timeouts and threads are the front's (front_options); httplib sees one request at a time.
  server.set_payload_max_length(options.max_body_bytes);
  server.set_keep_alive_timeout(options.keep_alive_timeout_s);  // advertised in Keep-Alive
  server.set_keep_alive_max_count(FrontOptions{}.max_requests_per_connection);
  server.set_post_routing_handler([](const httplib::Request&, httplib::Response& res) {
    answer_closes = res.get_header_value("Connection") == "close";
  });
  server.set_default_headers({{"Cache-Control", "no-store"}, {"X-Content-Type-Options", "nosniff"}});

  // 404 for unknown paths and 405 (with Allow) for known paths with another method, decided before
  // any body is read.
  server.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    request_start = std::chrono::steady_clock::now();
    for (const Route& route : routes) {
      if (!route_matches(route, req.path)) continue;
      const bool allowed =
          std::find(route.methods.begin(), route.methods.end(), req.method) != route.methods.end() ||
          (req.method == "HEAD" &&
           std::find(route.methods.begin(), route.methods.end(), "GET") != route.methods.end());
      if (allowed) return httplib::Server::HandlerResponse::Unhandled;
      res.set_header("Allow", route.allow);
      if (has_body(req)) close_after(req, res);
      send_error(res, 405, "method_not_allowed",
                 req.method + " is not allowed on " + req.path + "; allowed: " + route.allow);
      return httplib::Server::HandlerResponse::Handled;
    }
    if (has_body(req)) close_after(req, res);
    send_error(res, 404, "not_found", "no such resource: " + req.path + " (see /v1/openapi.json)");
    return httplib::Server::HandlerResponse::Handled;
  });

  // Statuses httplib sets by itself (400 unreadable request, 413, 414, ...) get a JSON body too.
  server.set_error_handler(httplib::Server::HandlerWithResponse(
      [](const httplib::Request&, httplib::Response& res) -> httplib::Server::HandlerResponse {
    if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
    switch (res.status) {
      case 400: send_error(res, 400, "bad_request", "the request could not be read"); break;
      case 404: send_error(res, 404, "not_found", "no such resource"); break;
      case 413: send_error(res, 413, "too_large", "the request body is too large"); break;
      case 414: send_error(res, 414, "uri_too_long", "the request URI is too long"); break;
      default:
        send_error(res, res.status, res.status >= 500 ? "internal" : "bad_request",
                   "the request failed (HTTP " + std::to_string(res.status) + ")");
    }
    return httplib::Server::HandlerResponse::Handled;
  }));

  server.set_exception_handler([](const httplib::Request& req, httplib::Response& res,
                                  std::exception_ptr ep) {
    std::string what = "unknown exception";
    try {
      std::rethrow_exception(ep);
    } catch (const std::exception& e) {
      what = e.what();
    } catch (...) {
    }
    std::cerr << "lambert serve: " << req.method << " " << req.path << ": " << what << "\n";
    res.headers.clear();
    send_error(res, 500, "internal", "internal server error (details are in the server log)");
  });

  server.set_logger([this](const httplib::Request& req, const httplib::Response& res) { log_request(req, res); });

  server.Post("/v1/solve", [this](const httplib::Request& req, httplib::Response& res,
                                  const httplib::ContentReader& reader) { post_solve(req, res, reader); });
  server.Post("/v1/jobs", [this](const httplib::Request& req, httplib::Response& res,
                                 const httplib::ContentReader& reader) { post_job(req, res, reader); });
  server.Get(R"(/v1/jobs/([^/]+))",
             [this](const httplib::Request& req, httplib::Response& res) { get_job(req, res); });
  server.Delete(R"(/v1/jobs/([^/]+))", [this](const httplib::Request& req, httplib::Response& res,
                                              const httplib::ContentReader& reader) {
    delete_job(req, res, reader);
  });
  server.Get(R"(/v1/jobs/([^/]+)/result)",
             [this](const httplib::Request& req, httplib::Response& res) { get_result(req, res); });
  for (const ResultView& view : result_views())
    server.Get(R"(/v1/jobs/([^/]+)/)" + escape_dots(view.file),
               [this, &view](const httplib::Request& req, httplib::Response& res) { get_result(req, res, &view); });
  // The browser viewer (viewer_assets.h): each file at its own path, nothing else under /viewer/.
  for (const ViewerAsset& asset : viewer_assets())
    server.Get(escape_dots(asset.path), [&asset](const httplib::Request&, httplib::Response& res) {
      res.set_content(asset.bytes.data(), asset.bytes.size(), asset.media_type.c_str());
    });
  server.Get("/v1/health", [this](const httplib::Request&, httplib::Response& res) { health(res); });
  server.Get("/v1/metrics", [this](const httplib::Request&, httplib::Response& res) { metrics(res); });
  server.Get("/v1/openapi.json", [](const httplib::Request&, httplib::Response& res) {
    res.set_content(openapi_document(), kJsonType);
  });
  server.Get("/v1/schema/scene.json", [](const httplib::Request&, httplib::Response& res) {
    res.set_content(scene_schema_document(), "application/schema+json");
  });
}

// Reads the body with our own limit. Sends the error itself (and returns Sent) when it cannot.
HttpServer::Impl::Body HttpServer::Impl::read_body(const httplib::Request& req, httplib::Response& res,
                                                   const httplib::ContentReader& reader,
                                                   std::string& body) const {
  const std::string limit = std::to_string(options.max_body_bytes) + " bytes";
  if (req.is_multipart_form_data()) {
    close_after(req, res);
    send_error(res, 415, "unsupported_media_type",
               "send the scene as the request body (application/json), not as a multipart form");
    return Body::Sent;
  }
  const auto length = content_length(req);
  if (!length && !has_chunked_body(req)) {
    // Without either, HTTP/1.1 would read until the client closes the connection.
    close_after(req, res);
    send_error(res, 411, "length_required", "the request needs a Content-Length header (or chunked encoding)");
    return Body::Sent;
  }
  if (length && *length > options.max_body_bytes) {
    // Read and discard a body of reasonable size (httplib does that for payload_max_length), so that
    // the client, still sending, does not lose our answer to a connection reset; a huge one is not
    // worth the traffic.
    constexpr std::size_t kAlwaysDrain = 16u << 20;
    if (*length <= kAlwaysDrain || *length / 2 <= options.max_body_bytes)
      reader([](const char*, std::size_t) { return true; });
    close_after(req, res);
    send_error(res, 413, "too_large",
               "the request body has " + std::to_string(*length) + " bytes; this server accepts at most " + limit);
    return Body::Sent;
  }
  if (length) body.reserve(*length);
  bool too_large = false;
  const bool ok = reader([&](const char* data, std::size_t n) {
    if (body.size() + n > options.max_body_bytes) {
      too_large = true;
      return false;
    }
    body.append(data, n);
    return true;
  });
  if (too_large || res.status == 413) {
    close_after(req, res);
    send_error(res, 413, "too_large", "the request body is larger than this server's limit of " + limit);
    return Body::Sent;
  }
  if (!ok) {
    close_after(req, res);
    send_error(res, 400, "invalid_body",
               "the request body could not be read completely (truncated, badly encoded or too slow)");
    return Body::Sent;
  }
  return Body::Ok;
}

std::optional<Scene> HttpServer::Impl::decode(const std::string& body, httplib::Response& res) const {
  DecodeResult decoded = decode_scene(body, files, jobs.options().limits.scene);
  if (decoded.ok()) return std::move(decoded.scene);
  const DecodeError& first = decoded.errors.front();
  // Errors without a pointer concern the whole document; it is "invalid JSON" only if the text is
  // not JSON at all (RFC 8259: also invalid UTF-8). Valid JSON that is no scene (too deeply nested,
  // not an object, a number out of the double range) is an invalid scene.
  if (first.pointer.empty() && decoded.errors.size() == 1 && !json::accept(body)) {
    send_error(res, 400, "invalid_json",
               body.empty() ? std::string("the request body is empty; send a scene (JSON)") : first.message);
    return std::nullopt;
  }
  // Bounded (scene_codec.h): the first kMaxListedErrors errors, each shortened, and the count of all.
  json errors = json::array();
  for (const DecodeError& e : decoded.errors) errors.push_back({{"pointer", e.pointer}, {"message", e.message}});
  std::string message = (first.pointer.empty() ? std::string("(document)") : first.pointer) + ": " + first.message;
  if (decoded.error_count() > 1)
    message += " (and " + std::to_string(decoded.error_count() - 1) + " more; see \"errors\")";
  send_error(res, 422, "invalid_scene", message, first.pointer,
             {{"errors", std::move(errors)}, {"error_count", decoded.error_count()}});
  return std::nullopt;
}

void HttpServer::Impl::post_solve(const httplib::Request& req, httplib::Response& res,
                                  const httplib::ContentReader& reader) {
  std::string body;
  if (read_body(req, res, reader, body) == Body::Sent) return;
  auto scene = decode(body, res);
  if (!scene) return;
  // Bounded: at most max_sync_waiters HTTP threads wait for a solve.
  if (sync_waiters.fetch_add(1) >= max_sync_waiters) {
    sync_waiters.fetch_sub(1);
    res.set_header("Retry-After", std::to_string(options.retry_after_s));
    send_error(res, 503, "busy",
               "too many synchronous solves in progress; retry later or use POST /v1/jobs");
    return;
  }
  SyncOutcome outcome = jobs.solve_now(body, scene_cache_key(body, LAMBERT_VERSION));
  sync_waiters.fetch_sub(1);
  if (auto* r = std::get_if<JobResult>(&outcome)) {
    res.status = 200;
    res.set_content(*r->json, kJsonType);
  } else if (auto* f = std::get_if<SolveFailed>(&outcome)) {
    send_error(res, 422, "solve_failed", f->reason);
  } else if (auto* q = std::get_if<QueueFull>(&outcome)) {
    queue_full(res, q->queue_size, "cannot solve now");
  } else {
    send_error(res, 503, "shutting_down", "the server is shutting down");
  }
}

void HttpServer::Impl::post_job(const httplib::Request& req, httplib::Response& res,
                                const httplib::ContentReader& reader) {
  std::string body;
  if (read_body(req, res, reader, body) == Body::Sent) return;
  auto scene = decode(body, res);
  if (!scene) return;
  SubmitOutcome outcome = jobs.submit(body, scene_cache_key(body, LAMBERT_VERSION));
  if (auto* s = std::get_if<JobStatus>(&outcome)) {
    json j = status_json(*s);
    res.set_header("Location", job_url(s->id));
    send_json(res, 202, j);
  } else if (auto* q = std::get_if<QueueFull>(&outcome)) {
    queue_full(res, q->queue_size, "job not accepted");
  } else if (auto* e = std::get_if<StorageError>(&outcome)) {
    send_error(res, 500, "internal", e->message);
  } else {
    send_error(res, 503, "shutting_down", "the server is shutting down");
  }
}

void HttpServer::Impl::get_job(const httplib::Request& req, httplib::Response& res) {
  const std::string id = req.matches[1];
  const auto status = JobStore::is_valid_id(id) ? jobs.status(id) : std::nullopt;
  if (!status) return send_error(res, 404, "not_found", "no job " + id);
  send_json(res, 200, status_json(*status));
}

void HttpServer::Impl::get_result(const httplib::Request& req, httplib::Response& res, const ResultView* view) {
  const std::string id = req.matches[1];
  if (!JobStore::is_valid_id(id)) return send_error(res, 404, "not_found", "no job " + id);
  ResultLookup lookup = jobs.result(id);
  if (auto* r = std::get_if<JobResult>(&lookup); r && view) {
    ResultViewOutcome out = view->render(*r->json, req.params);
    if (!out.error.empty()) return send_error(res, 400, "invalid_parameter", out.error);
    res.status = 200;
    res.set_content(std::move(out.body), view->media_type);
  } else if (r) {
    res.status = 200;
    res.set_content(*r->json, kJsonType);
  } else if (auto* n = std::get_if<JobNotDone>(&lookup)) {
    res.set_header("Retry-After", "1");
    send_error(res, 409, "not_done",
               std::string("the job is ") + to_string(n->status.state) + "; its result is not ready",
               "", {{"state", to_string(n->status.state)}, {"progress", n->status.progress}});
  } else if (auto* f = std::get_if<JobFailed>(&lookup)) {
    const bool failed = f->status.state == JobState::Failed;
    send_error(res, 409, failed ? "job_failed" : "job_cancelled",
               failed ? "the job failed: " + f->status.error : std::string("the job was cancelled"), "",
               {{"state", to_string(f->status.state)}});
  } else {
    send_error(res, 404, "not_found", "no job " + id);
  }
}

void HttpServer::Impl::delete_job(const httplib::Request& req, httplib::Response& res,
                                  const httplib::ContentReader& reader) {
  // A DELETE has no body; read one only if announced, so that the connection stays in step.
  if (const auto length = content_length(req); (length && *length > 0) || has_chunked_body(req)) {
    std::string ignored;
    if (read_body(req, res, reader, ignored) == Body::Sent) return;
  }
  const std::string id = req.matches[1];
  const CancelOutcome out = JobStore::is_valid_id(id) ? jobs.cancel_or_remove(id) : CancelOutcome{};
  switch (out.kind) {
    case CancelOutcome::Kind::NotFound: return send_error(res, 404, "not_found", "no job " + id);
    case CancelOutcome::Kind::Cancelled: return send_json(res, 200, status_json(out.status));
    case CancelOutcome::Kind::Removed:
      return send_json(res, 200, {{"id", id}, {"deleted", true}, {"state", to_string(out.status.state)}});
  }
}

void HttpServer::Impl::health(httplib::Response& res) {
  const JobService::Counts c = jobs.counts();
  send_json(res, 200,
            {{"status", "ok"},
             {"version", LAMBERT_VERSION},
             {"scene_format", 1},
             {"workers", c.workers},
             {"jobs", {{"queued", c.store.queued}, {"running", c.store.running + c.sync_running}, {"stored", c.store.stored()}}},
             {"queue_size", c.queue_size}});
}

}  // namespace lambert

namespace lambert {

void HttpServer::Impl::metrics(httplib::Response& res) {
  MetricsSnapshot m = jobs.metrics();
  m.version = LAMBERT_VERSION;
  {
    std::lock_guard lock(responses_mutex);
    m.http_responses = responses;
  }
  res.status = 200;
  res.set_content(prometheus_text(m), kPrometheusMediaType);
}

// Counts every response for GET /v1/metrics and, with --access-log, writes its log line.
void HttpServer::Impl::log_request(const httplib::Request& req, const httplib::Response& res) {
  {
    std::lock_guard lock(responses_mutex);
    ++responses[res.status];
  }
  std::optional<double> ms;
  if (request_start)
    ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - *request_start).count();
  request_start.reset();
  if (!options.access_log) return;
  json line = {{"event", "request"}, {"remote", req.remote_addr}, {"method", req.method}, {"path", req.path},
               {"status", res.status}, {"bytes", res.body.size()}};
  if (ms) line["ms"] = std::round(*ms * 1000) / 1000;
  if (req.matches.size() > 1 && JobStore::is_valid_id(req.matches[1])) line["job"] = req.matches[1].str();
  log_json(line);
}

}  // namespace lambert
