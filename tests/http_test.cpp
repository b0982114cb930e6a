// The HTTP service through real HTTP (SPEC §4, docs/API.md): the server runs in-process on a free
// loopback port (bind_to_any_port + listen_after_bind, STACK P5) and is driven by httplib::Client or,
// for requests a well-behaved client cannot send, by a raw socket. Physics checks use the closed form
// of an isotropic point source over a black floor: E = I h / d³ (REFERENCES P1), so each job's
// result tells which scene it came from.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "server/http_server.h"
#include "server/job_store.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

const fs::path kSource = LAMBERT_SOURCE_DIR;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh directory under the system's temporary directory, removed afterwards.
struct TempDir {
  fs::path path = fs::temp_directory_path() / ("lambert_http_test_" + JobStore::new_id());
  TempDir() { fs::create_directories(path); }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// ---- the server under test ------------------------------------------------------------------------

JobStoreOptions job_options() {
  JobStoreOptions o;
  o.workers = 2;
  o.queue_size = 64;
  o.time_limit = 120s;
  o.max_patches = 20000;
  return o;
}

class TestServer {
 public:
  explicit TestServer(JobStoreOptions jobs = job_options(), HttpServerOptions http = {}) {
    jobs.files = http_file_access(http.mesh_root);
    store_ = std::make_unique<JobStore>(std::move(jobs));
    server_ = std::make_unique<HttpServer>(*store_, std::move(http));
    port_ = server_->bind("127.0.0.1", 0);
    EXPECT_GT(port_, 0);
    thread_ = std::thread([this] { server_->listen_after_bind(); });
    for (int k = 0; k < 500 && !server_->is_running(); ++k) std::this_thread::sleep_for(2ms);
  }
  ~TestServer() {  // the order of `lambert serve`: jobs first, then the server
    store_->shutdown();
    server_->stop();
    thread_.join();
  }
  int port() const { return port_; }
  void shutdown_jobs() { store_->shutdown(); }
  std::unique_ptr<httplib::Client> client() const {
    auto c = std::make_unique<httplib::Client>("127.0.0.1", port_);
    c->set_read_timeout(300, 0);
    c->set_write_timeout(60, 0);
    return c;
  }

 private:
  std::unique_ptr<JobStore> store_;
  std::unique_ptr<HttpServer> server_;
  std::thread thread_;
  int port_ = -1;
};

// ---- scenes -----------------------------------------------------------------------------------------

// An isotropic point source of `cd` candela 2 m above a black 2 x 2 m floor; probe "below" right under
// it (E = I/h² = cd/4 lx) and "side" 1 m off (E = I h/d³ = cd · 2/5^1.5 lx).
json point_scene(double cd, const std::string& name = "point") {
  return {{"name", name},
          {"spectrum", {{"mode", "spectral"}, {"from_nm", 380}, {"to_nm", 780}, {"step_nm", 10}}},
          {"materials", {{"black", {{"reflectance", 0}}}}},
          {"surfaces", json::array({{{"name", "floor"},
                                     {"material", "black"},
                                     {"polygon", {{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}}}}})},
          {"lights", json::array({{{"type", "point"},
                                   {"position", {0, 2, 0}},
                                   {"intensity", {{"cie", "A"}}},
                                   {"luminous_intensity_cd", cd}}})},
          {"probes", json::array({{{"name", "below"}, {"position", {0, 0, 0}}, {"normal", {0, 1, 0}}},
                                  {{"name", "side"}, {"position", {1, 0, 0}}, {"normal", {0, 1, 0}}}})},
          {"meshing", {{"max_patch_area", 0.05}}}};
}
double expected_below(double cd) { return cd / 4; }
double expected_side(double cd) { return cd * 2 / std::pow(5.0, 1.5); }

// The closed 4 m room of scenes/reference (reflectance 0.5, a point source inside) cut into about
// `patches` patches: all of them exchange light, so the solve takes seconds.
// Several seconds of solving: a closed room with a floating box (its shadows need rays; an empty
// convex room needs none and solves 3072 patches in about a second).
json slow_scene(int patches = 4096) {
  json scene = json::parse(read_text(kSource / "scenes/reference/closed-room-point.json"));
  scene.erase("expected");
  scene["spectrum"] = {{"mode", "spectral"}, {"from_nm", 400}, {"to_nm", 700}, {"step_nm", 20}};
  scene["meshing"] = {{"max_patch_area", 96.0 / patches}};
  json box = {{"name", "box"}, {"material", scene["surfaces"][0]["material"]}};
  box["mesh"] = {{"vertices", {{0.5, 0.5, 0.5}, {1.5, 0.5, 0.5}, {1.5, 1.5, 0.5}, {0.5, 1.5, 0.5},
                               {0.5, 0.5, 1.5}, {1.5, 0.5, 1.5}, {1.5, 1.5, 1.5}, {0.5, 1.5, 1.5}}},
                 {"triangles", {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {3, 0, 4}, {3, 4, 7}}}};
  scene["surfaces"].push_back(box);
  return scene;
}

double probe_lx(const json& result, const std::string& name) {
  for (const auto& p : result.at("probes"))
    if (p.at("name") == name) return p.at("illuminance_lx").get<double>();
  ADD_FAILURE() << "no probe " << name;
  return NAN;
}

// ---- checks -----------------------------------------------------------------------------------------

// Every error is SPEC §4 JSON, and no exception text ever reaches a header (STACK P8).
json expect_error(const httplib::Result& res, int status, const std::string& code) {
  EXPECT_TRUE(res) << "no response: " << httplib::to_string(res.error());
  if (!res) return {};
  EXPECT_EQ(res->status, status) << res->body;
  EXPECT_FALSE(res->has_header("EXCEPTION_WHAT"));
  EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
  json body = json::parse(res->body, nullptr, false);
  EXPECT_TRUE(body.is_object()) << res->body;
  if (!body.is_object() || !body.contains("error")) return {};
  const json& e = body["error"];
  EXPECT_EQ(e.value("code", ""), code) << res->body;
  EXPECT_TRUE(e.contains("message") && e["message"].is_string() && !e["message"].get<std::string>().empty());
  EXPECT_TRUE(e.contains("pointer") && e["pointer"].is_string());
  return e;
}

json expect_json(const httplib::Result& res, int status) {
  EXPECT_TRUE(res) << "no response: " << httplib::to_string(res.error());
  if (!res) return {};
  EXPECT_EQ(res->status, status) << res->body;
  EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
  json body = json::parse(res->body, nullptr, false);
  EXPECT_FALSE(body.is_discarded()) << res->body;
  return body;
}

void expect_alive(const TestServer& server) {
  auto res = server.client()->Get("/v1/health");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
}

std::string submit(const TestServer& server, const json& scene) {
  auto res = server.client()->Post("/v1/jobs", scene.dump(), "application/json");
  const json body = expect_json(res, 202);
  return body.value("id", "");
}

json job_status(const TestServer& server, const std::string& id) {
  return expect_json(server.client()->Get("/v1/jobs/" + id), 200);
}

// Polls until `done(status)` or the timeout; returns the last status.
template <typename Pred>
json wait_for(const TestServer& server, const std::string& id, Pred done,
              std::chrono::duration<double> timeout = 120s) {
  const auto t0 = Clock::now();
  json s = job_status(server, id);
  while (!done(s) && Clock::now() - t0 < timeout) {
    std::this_thread::sleep_for(10ms);
    s = job_status(server, id);
  }
  return s;
}
bool is_final(const json& s) {
  const std::string st = s.value("state", "");
  return st == "done" || st == "failed" || st == "cancelled";
}
json wait_final(const TestServer& server, const std::string& id) {
  return wait_for(server, id, is_final);
}

// A request a polite client would not send: raw bytes on a socket; returns what came back.
std::string raw_request(int port, const std::string& bytes, bool close_write = false) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  timeval tv{20, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return "";
  }
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) break;
    sent += static_cast<std::size_t>(n);
  }
  if (close_write) ::shutdown(fd, SHUT_WR);
  std::string out;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) break;
    out.append(buf, static_cast<std::size_t>(n));
    // One response is enough: stop once its body (Content-Length) is complete.
    const auto head_end = out.find("\r\n\r\n");
    const auto cl = out.find("Content-Length: ");
    if (head_end != std::string::npos && cl != std::string::npos && cl < head_end) {
      const std::size_t length = std::stoul(out.substr(cl + 16));
      if (out.size() >= head_end + 4 + length) break;
    }
  }
  ::close(fd);
  return out;
}
int raw_status(const std::string& response) {
  return response.size() > 12 && response.rfind("HTTP/1.1 ", 0) == 0 ? std::stoi(response.substr(9, 3)) : -1;
}
json raw_body(const std::string& response) {
  const auto head_end = response.find("\r\n\r\n");
  return head_end == std::string::npos ? json() : json::parse(response.substr(head_end + 4), nullptr, false);
}

// ---- routes, documents, 404/405 ----------------------------------------------------------------------

TEST(Http, HealthReportsLivenessAndVersion) {
  TestServer server;
  auto cli = server.client();
  const json h = expect_json(cli->Get("/v1/health"), 200);
  EXPECT_EQ(h.value("status", ""), "ok");
  EXPECT_FALSE(h.value("version", "").empty());
  EXPECT_EQ(h.value("scene_format", 0), 1);
  EXPECT_EQ(h.value("workers", 0), 2);
  auto head = cli->Head("/v1/health");
  ASSERT_TRUE(head);
  EXPECT_EQ(head->status, 200);
}

TEST(Http, ASecondServerCannotTakeTheSamePort) {
  TestServer server;
  JobStore jobs(job_options());
  HttpServer second(jobs, {});
  EXPECT_EQ(second.bind("127.0.0.1", server.port()), -1);
  expect_alive(server);
}

TEST(Http, ServesTheContractDocumentsFromTheRepository) {
  TestServer server;
  auto cli = server.client();
  auto openapi = cli->Get("/v1/openapi.json");
  ASSERT_TRUE(openapi);
  EXPECT_EQ(openapi->status, 200);
  EXPECT_EQ(openapi->body, read_text(kSource / "docs/openapi.json"));
  EXPECT_EQ(json::parse(openapi->body).value("openapi", ""), "3.1.0");
  auto schema = cli->Get("/v1/schema/scene.json");
  ASSERT_TRUE(schema);
  EXPECT_EQ(schema->status, 200);
  EXPECT_EQ(schema->body, read_text(kSource / "docs/scene.schema.json"));
  EXPECT_EQ(json::parse(schema->body).value("$schema", ""), "https://json-schema.org/draft/2020-12/schema");
}

TEST(Http, UnknownPathsAre404AndWrongMethods405) {
  TestServer server;
  auto cli = server.client();
  expect_error(cli->Get("/"), 404, "not_found");
  expect_error(cli->Get("/v1/healthz"), 404, "not_found");
  expect_error(cli->Get("/v1/health/"), 404, "not_found");
  expect_error(cli->Post("/v2/solve", "{}", "application/json"), 404, "not_found");
  expect_error(cli->Get("/v1/jobs/a/b/c"), 404, "not_found");
  expect_error(cli->Get("/v1/jobs/" + std::string(10000, 'a')), 414, "uri_too_long");

  auto r = cli->Get("/v1/solve");
  expect_error(r, 405, "method_not_allowed");
  EXPECT_EQ(r->get_header_value("Allow"), "POST");
  r = cli->Put("/v1/jobs", "{}", "application/json");
  expect_error(r, 405, "method_not_allowed");
  EXPECT_EQ(r->get_header_value("Allow"), "POST");
  r = cli->Post("/v1/health", "{}", "application/json");
  expect_error(r, 405, "method_not_allowed");
  EXPECT_EQ(r->get_header_value("Allow"), "GET, HEAD");
  r = cli->Patch("/v1/jobs/0123456789abcdef0123456789abcdef", "{}", "application/json");
  expect_error(r, 405, "method_not_allowed");
  EXPECT_EQ(r->get_header_value("Allow"), "GET, HEAD, DELETE");
  expect_error(cli->Delete("/v1/jobs/0123456789abcdef0123456789abcdef/result"), 405, "method_not_allowed");
  expect_error(cli->Delete("/v1/openapi.json"), 405, "method_not_allowed");
  expect_alive(server);
}

TEST(Http, UnknownJobIdsAre404) {
  TestServer server;
  auto cli = server.client();
  for (const std::string id : {"0123456789abcdef0123456789abcdef", "nonexistent", "0123456789ABCDEF0123456789ABCDEF",
                               "..", "%2e%2e%2f%2e%2e%2fetc%2fpasswd", "x%00y"}) {
    expect_error(cli->Get("/v1/jobs/" + id), 404, "not_found");
    expect_error(cli->Get("/v1/jobs/" + id + "/result"), 404, "not_found");
    expect_error(cli->Delete("/v1/jobs/" + id), 404, "not_found");
  }
  expect_alive(server);
}

// ---- synchronous solve ---------------------------------------------------------------------------------

TEST(Http, SolveReturnsTheResultOfTheScene) {
  TestServer server;
  const json result = expect_json(server.client()->Post("/v1/solve", point_scene(100).dump(), "application/json"), 200);
  EXPECT_EQ(result.value("lambert", 0), 1);
  EXPECT_NEAR(probe_lx(result, "below"), expected_below(100), 1e-6 * expected_below(100));
  EXPECT_NEAR(probe_lx(result, "side"), expected_side(100), 1e-6 * expected_side(100));
}

TEST(Http, SolveAcceptsAGzipBody) {
  TestServer server;
  auto cli = server.client();
  cli->set_compress(true);  // Content-Encoding: gzip
  const json result = expect_json(cli->Post("/v1/solve", point_scene(40).dump(), "application/json"), 200);
  EXPECT_NEAR(probe_lx(result, "below"), expected_below(40), 1e-6 * expected_below(40));
}

// ---- hostile bodies ------------------------------------------------------------------------------------

TEST(Http, MalformedBodiesAre400InvalidJson) {
  TestServer server;
  auto cli = server.client();
  const std::string scene = point_scene(10).dump();
  for (const std::string path : {"/v1/solve", "/v1/jobs"}) {
    const json empty = expect_error(cli->Post(path, "", "application/json"), 400, "invalid_json");
    EXPECT_NE(empty.value("message", "").find("empty"), std::string::npos);
    const json cut = expect_error(cli->Post(path, scene.substr(0, scene.size() / 2), "application/json"), 400,
                                  "invalid_json");
    EXPECT_NE(cut.value("message", "").find("line 1"), std::string::npos) << cut;
    expect_error(cli->Post(path, "{\"name\": \"\xff\xfe\", \"materials\": {}}", "application/json"), 400, "invalid_json");
    expect_error(cli->Post(path, "{\"name\": \"\xc0\xaf\"}", "application/json"), 400, "invalid_json");  // overlong '/'
    // RFC 8259 lets a parser ignore a byte order mark: then it is JSON, and {} is no scene.
    expect_error(cli->Post(path, "\xef\xbb\xbf{}", "application/json"), 422, "invalid_scene");
    expect_error(cli->Post(path, "{\"lambert\": NaN}", "application/json"), 400, "invalid_json");
    expect_error(cli->Post(path, "{\"lambert\": Infinity}", "application/json"), 400, "invalid_json");
    expect_error(cli->Post(path, "{\"a\": 1,}", "application/json"), 400, "invalid_json");
    expect_error(cli->Post(path, std::string("{\"a\":\0 1}", 9), "application/json"), 400, "invalid_json");
    expect_error(cli->Post(path, std::string(100000, '['), "application/json"), 400, "invalid_json");
  }
  expect_alive(server);
}

TEST(Http, DeepNestingIsRefusedWithoutRecursion) {
  TestServer server;
  auto cli = server.client();
  // 10^5 levels, balanced: valid JSON, but no scene.
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  const json e = expect_error(cli->Post("/v1/solve", deep, "application/json"), 422, "invalid_scene");
  EXPECT_NE(e.value("message", "").find("nesting"), std::string::npos) << e;
  std::string objects;
  for (int k = 0; k < 100000; ++k) objects += "{\"a\":";
  objects += "1" + std::string(100000, '}');
  expect_error(cli->Post("/v1/jobs", objects, "application/json"), 422, "invalid_scene");
  expect_alive(server);
}

TEST(Http, NumbersBeyondDoubleAre422WithTheirPointer) {
  TestServer server;
  auto cli = server.client();
  std::string text = point_scene(10).dump();
  const std::string key = "\"luminous_intensity_cd\":10";
  ASSERT_NE(text.find(key), std::string::npos);
  text.replace(text.find(key), key.size(), "\"luminous_intensity_cd\":1e400");
  json e = expect_error(cli->Post("/v1/solve", text, "application/json"), 422, "invalid_scene");
  EXPECT_EQ(e.value("pointer", ""), "/lights/0/luminous_intensity_cd");
  text.replace(text.find("1e400"), 5, "-1e400");
  e = expect_error(cli->Post("/v1/jobs", text, "application/json"), 422, "invalid_scene");
  EXPECT_EQ(e.value("pointer", ""), "/lights/0/luminous_intensity_cd");
  // Huge but finite: the decoder's own range checks.
  json scene = point_scene(10);
  scene["lights"][0]["position"] = {0, 1e300, 0};
  e = expect_error(cli->Post("/v1/solve", scene.dump(), "application/json"), 422, "invalid_scene");
  EXPECT_EQ(e.value("pointer", ""), "/lights/0/position/1");
  expect_alive(server);
}

TEST(Http, InvalidScenesGive422WithEveryPointer) {
  TestServer server;
  auto cli = server.client();
  json scene = point_scene(10);
  scene["colour"] = "red";                                     // unknown key
  scene["materials"]["black"]["reflectance"] = 1.2;            // out of range
  scene["lights"][0]["typo_key"] = 1;                          // unknown key
  const json e = expect_error(cli->Post("/v1/jobs", scene.dump(), "application/json"), 422, "invalid_scene");
  ASSERT_TRUE(e.contains("errors"));
  const json& errors = e["errors"];
  ASSERT_GE(errors.size(), 3u) << e;
  EXPECT_EQ(e["pointer"], errors[0]["pointer"]);
  std::set<std::string> pointers;
  for (const auto& x : errors) pointers.insert(x.at("pointer").get<std::string>());
  EXPECT_TRUE(pointers.count("/colour")) << e;
  EXPECT_TRUE(pointers.count("/materials/black/reflectance")) << e;
  EXPECT_TRUE(pointers.count("/lights/0/typo_key")) << e;
  // Valid JSON of the wrong shape.
  expect_error(cli->Post("/v1/solve", "[1, 2, 3]", "application/json"), 422, "invalid_scene");
  expect_error(cli->Post("/v1/solve", "\"scene\"", "application/json"), 422, "invalid_scene");
  expect_error(cli->Post("/v1/solve", "{}", "application/json"), 422, "invalid_scene");
  // Duplicate keys are reported, not silently merged.
  const json dup = expect_error(
      cli->Post("/v1/solve", R"({"name": "a", "name": "b", "materials": {"w": {"reflectance": 0}},
                "surfaces": [{"material": "w", "polygon": [[0,0,0],[1,0,0],[0,0,1]]}]})", "application/json"),
      422, "invalid_scene");
  EXPECT_EQ(dup.value("pointer", ""), "/name");
  // Nothing was queued for any of them.
  const json h = expect_json(cli->Get("/v1/health"), 200);
  EXPECT_EQ(h["jobs"]["stored"], 0);
}

TEST(Http, OversizedBodiesAre413) {
  HttpServerOptions http;
  http.max_body_bytes = 4096;
  TestServer server(job_options(), http);
  auto cli = server.client();
  json scene = point_scene(10);
  scene["description"] = std::string(5000, 'x');
  const json e = expect_error(cli->Post("/v1/solve", scene.dump(), "application/json"), 413, "too_large");
  EXPECT_NE(e.value("message", "").find("4096"), std::string::npos);
  expect_error(server.client()->Post("/v1/jobs", std::string(1 << 20, ' '), "application/json"), 413, "too_large");
  // Chunked, so without a Content-Length for httplib's own limit: ours still holds.
  const std::string big(64 * 1024, ' ');
  auto chunked = server.client()->Post(
      "/v1/jobs",
      [&](std::size_t offset, httplib::DataSink& sink) {
        if (offset < big.size()) sink.write(big.data(), big.size());
        else sink.done();
        return true;
      },
      "application/json");
  if (chunked) expect_error(chunked, 413, "too_large");  // or the server hung up while we sent
  // Gzip: the limit applies to what the body inflates to (1 MB of spaces is a 1 kB upload).
  auto gz = server.client();
  gz->set_compress(true);
  expect_error(gz->Post("/v1/jobs", std::string(1 << 20, ' '), "application/json"), 413, "too_large");
  // A small one still works.
  expect_json(server.client()->Post("/v1/solve", point_scene(10).dump(), "application/json"), 200);
}

TEST(Http, RequestsACarefulClientWouldNotSend) {
  HttpServerOptions http;
  http.read_timeout_s = 1;
  TestServer server(job_options(), http);
  const int port = server.port();
  // No Content-Length and not chunked: HTTP/1.1 would read until the client closes.
  std::string r = raw_request(port, "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n\r\n{}");
  EXPECT_EQ(raw_status(r), 411) << r;
  EXPECT_EQ(raw_body(r)["error"]["code"], "length_required");
  // Content-Length says more than arrives: the read times out (1 s here) and the request fails alone.
  // (A client that half-closes its socket gets no answer at all: httplib 0.11.4 writes nothing to a
  // connection whose peer has sent FIN.)
  auto t0 = Clock::now();
  r = raw_request(port, "POST /v1/solve HTTP/1.1\r\nHost: x\r\nContent-Length: 100\r\n\r\n{\"lambert\"");
  EXPECT_EQ(raw_status(r), 400) << r;
  EXPECT_EQ(raw_body(r)["error"]["code"], "invalid_body");
  EXPECT_LT(Clock::now() - t0, 10s);
  raw_request(port, "POST /v1/solve HTTP/1.1\r\nHost: x\r\nContent-Length: 100\r\n\r\n{\"lambert\"", true);
  // Not HTTP at all.
  r = raw_request(port, "HELLO\r\n\r\n");
  EXPECT_EQ(raw_status(r), 400) << r;
  EXPECT_EQ(raw_body(r)["error"]["code"], "bad_request");
  // A multipart form instead of a JSON body.
  auto cli = server.client();
  httplib::MultipartFormDataItems items = {{"scene", point_scene(10).dump(), "scene.json", "application/json"}};
  expect_error(cli->Post("/v1/solve", items), 415, "unsupported_media_type");
  // A DELETE with no body and no Content-Length is answered at once.
  t0 = Clock::now();
  r = raw_request(port, "DELETE /v1/jobs/0123456789abcdef0123456789abcdef HTTP/1.1\r\nHost: x\r\n\r\n");
  EXPECT_EQ(raw_status(r), 404) << r;
  EXPECT_LT(Clock::now() - t0, 2s);
  expect_alive(server);
}

// ---- files: the mesh root ----------------------------------------------------------------------------------

json file_scene(const std::string& file) {
  return {{"materials", {{"grey", {{"reflectance", 0}}}}},
          {"surfaces", json::array({{{"name", "box"}, {"material", "grey"}, {"file", file}}})}};
}

TEST(Http, FileSurfacesAreRefusedWithoutAMeshRoot) {
  TestServer server;
  auto cli = server.client();
  const std::string existing = (kSource / "tests/data/box.obj").string();
  for (const std::string file : {"box.obj", existing.c_str(), "../tests/data/box.obj", "/etc/passwd"}) {
    const json e = expect_error(cli->Post("/v1/solve", file_scene(file).dump(), "application/json"), 422, "invalid_scene");
    EXPECT_EQ(e.value("pointer", ""), "/surfaces/0/file") << file;
    EXPECT_NE(e.value("message", "").find("--mesh-root"), std::string::npos) << e;
  }
}

TEST(Http, FileSurfacesStayInsideTheMeshRoot) {
  TempDir dir;
  const fs::path root = dir.path / "meshes", outside = dir.path / "outside";
  fs::create_directories(root / "sub");
  fs::create_directories(outside);
  fs::copy_file(kSource / "tests/data/box.obj", root / "box.obj");
  fs::copy_file(kSource / "tests/data/box.obj", root / "sub" / "box.obj");
  fs::copy_file(kSource / "tests/data/box.obj", outside / "secret.obj");
  fs::create_symlink(outside / "secret.obj", root / "link-out.obj");       // a file link out
  fs::create_directory_symlink(outside, root / "dir-out");                 // a directory link out
  fs::create_symlink("box.obj", root / "link-in.obj");                     // a link that stays in

  HttpServerOptions http;
  http.mesh_root = root;
  TestServer server(job_options(), http);
  auto cli = server.client();

  for (const std::string ok : {"box.obj", "sub/box.obj", "link-in.obj", "./box.obj"}) {
    const json r = expect_json(cli->Post("/v1/solve", file_scene(ok).dump(), "application/json"), 200);
    EXPECT_NEAR(r["surfaces"][0].value("area", 0.0), 52.0, 1e-9) << ok;  // REFERENCE: box.obj's area
  }
  const std::vector<std::string> refused = {
      "../outside/secret.obj", "sub/../../outside/secret.obj", "sub/../box.obj", "..", "../",
      (outside / "secret.obj").string(), "/etc/passwd", "//etc/passwd", "link-out.obj", "dir-out/secret.obj",
      "missing.obj", "sub", "", "..\\outside\\secret.obj", "box.obj/", std::string("box.obj\0../x", 12)};
  for (const std::string& bad : refused) {
    auto res = cli->Post("/v1/jobs", file_scene(bad).dump(), "application/json");
    const json e = expect_error(res, 422, "invalid_scene");
    EXPECT_EQ(e.value("pointer", ""), "/surfaces/0/file") << bad;
    // The messages never show where the server keeps its files.
    EXPECT_EQ(res->body.find(root.string()), std::string::npos) << res->body;
  }
  const json h = expect_json(cli->Get("/v1/health"), 200);
  EXPECT_EQ(h["jobs"]["stored"], 0);
}

// ---- jobs ----------------------------------------------------------------------------------------------------

TEST(Http, JobLifecycle) {
  TestServer server;
  auto cli = server.client();
  auto res = cli->Post("/v1/jobs", point_scene(60).dump(), "application/json");
  const json accepted = expect_json(res, 202);
  const std::string id = accepted.value("id", "");
  EXPECT_TRUE(JobStore::is_valid_id(id)) << id;
  EXPECT_EQ(accepted.value("status_url", ""), "/v1/jobs/" + id);
  EXPECT_EQ(res->get_header_value("Location"), "/v1/jobs/" + id);
  const std::string state = accepted.value("state", "");
  EXPECT_TRUE(state == "queued" || state == "running" || state == "done") << accepted;

  const json done = wait_final(server, id);
  ASSERT_EQ(done.value("state", ""), "done") << done;
  EXPECT_EQ(done.value("progress", 0.0), 1.0);
  EXPECT_EQ(done.value("result_url", ""), "/v1/jobs/" + id + "/result");
  EXPECT_TRUE(done.contains("finished") && done.contains("expires"));
  const json result = expect_json(cli->Get("/v1/jobs/" + id + "/result"), 200);
  EXPECT_NEAR(probe_lx(result, "below"), expected_below(60), 1e-6 * expected_below(60));

  // Deleting a finished job removes it and its result.
  const json deleted = expect_json(cli->Delete("/v1/jobs/" + id), 200);
  EXPECT_EQ(deleted.value("deleted", false), true);
  EXPECT_EQ(deleted.value("state", ""), "done");
  expect_error(cli->Get("/v1/jobs/" + id), 404, "not_found");
  expect_error(cli->Get("/v1/jobs/" + id + "/result"), 404, "not_found");
  expect_error(cli->Delete("/v1/jobs/" + id), 404, "not_found");
}

TEST(Http, JobIdsAreRandomAndNeverRepeat) {
  std::set<std::string> ids;
  for (int k = 0; k < 1000; ++k) ids.insert(JobStore::new_id());
  EXPECT_EQ(ids.size(), 1000u);
  for (const auto& id : ids) ASSERT_TRUE(JobStore::is_valid_id(id)) << id;
  // Every hex digit position varies (no counter, no timestamp prefix).
  for (std::size_t pos = 0; pos < 32; ++pos) {
    std::set<char> digits;
    for (const auto& id : ids) digits.insert(id[pos]);
    EXPECT_GT(digits.size(), 8u) << "position " << pos;
  }
}

TEST(Http, TenConcurrentJobsEachGetTheirOwnResult) {
  TestServer server;
  constexpr int kJobs = 10;
  std::vector<std::string> ids(kJobs);
  std::vector<std::thread> clients;
  for (int k = 0; k < kJobs; ++k)
    clients.emplace_back([&, k] { ids[k] = submit(server, point_scene(10.0 * (k + 1), "job" + std::to_string(k))); });
  for (auto& t : clients) t.join();
  EXPECT_EQ(std::set<std::string>(ids.begin(), ids.end()).size(), static_cast<std::size_t>(kJobs));
  clients.clear();
  std::vector<json> results(kJobs);
  for (int k = 0; k < kJobs; ++k)
    clients.emplace_back([&, k] {
      const json s = wait_final(server, ids[k]);
      EXPECT_EQ(s.value("state", ""), "done") << s;
      results[k] = expect_json(server.client()->Get("/v1/jobs/" + ids[k] + "/result"), 200);
    });
  for (auto& t : clients) t.join();
  for (int k = 0; k < kJobs; ++k) {
    const double cd = 10.0 * (k + 1);
    EXPECT_NEAR(probe_lx(results[k], "below"), expected_below(cd), 1e-6 * expected_below(cd)) << "job " << k;
    EXPECT_NEAR(probe_lx(results[k], "side"), expected_side(cd), 1e-6 * expected_side(cd)) << "job " << k;
  }
}

TEST(Http, ProgressMovesAndDeleteCancelsARunningSolvePromptly) {
  JobStoreOptions jobs = job_options();
  jobs.workers = 1;
  TestServer server(jobs);
  auto cli = server.client();
  const std::string id = submit(server, slow_scene());
  wait_for(server, id, [](const json& s) { return s.value("state", "") != "queued"; });
  // The worker is busy: a second job waits.
  const std::string next = submit(server, point_scene(20));
  const json queued = job_status(server, next);
  EXPECT_EQ(queued.value("state", ""), "queued");
  EXPECT_EQ(queued.value("queue_position", 0), 1);

  // Progress moves while it runs, and never goes back.
  std::set<double> seen;
  double last = 0;
  const json running = wait_for(server, id, [&](const json& s) {
    const double p = s.value("progress", 0.0);
    EXPECT_GE(p, last);
    last = p;
    if (s.value("state", "") == "running") seen.insert(p);
    return is_final(s) || (seen.size() >= 3 && p > 0.1);
  });
  ASSERT_EQ(running.value("state", ""), "running") << running;
  EXPECT_GE(seen.size(), 3u);
  EXPECT_LT(running.value("progress", 1.0), 0.9);

  const json not_done = expect_error(cli->Get("/v1/jobs/" + id + "/result"), 409, "not_done");
  EXPECT_EQ(not_done.value("state", ""), "running");

  const auto t0 = Clock::now();
  const json cancelled = expect_json(cli->Delete("/v1/jobs/" + id), 200);
  EXPECT_EQ(cancelled.value("state", ""), "cancelled");
  EXPECT_EQ(job_status(server, id).value("state", ""), "cancelled");
  // The worker is really free: the queued job runs and finishes soon after.
  const json s = wait_final(server, next);
  EXPECT_EQ(s.value("state", ""), "done");
  EXPECT_LT(Clock::now() - t0, 10s);
  expect_error(cli->Get("/v1/jobs/" + id + "/result"), 409, "job_cancelled");
  EXPECT_EQ(job_status(server, id).value("state", ""), "cancelled");  // still visible
  // A second DELETE removes the cancelled job.
  EXPECT_EQ(expect_json(cli->Delete("/v1/jobs/" + id), 200).value("deleted", false), true);
  expect_error(cli->Get("/v1/jobs/" + id), 404, "not_found");
}

TEST(Http, DeleteCancelsAQueuedJob) {
  JobStoreOptions jobs = job_options();
  jobs.workers = 1;
  TestServer server(jobs);
  auto cli = server.client();
  const std::string slow = submit(server, slow_scene());
  const std::string queued = submit(server, point_scene(20));
  EXPECT_EQ(expect_json(cli->Delete("/v1/jobs/" + queued), 200).value("state", ""), "cancelled");
  EXPECT_EQ(job_status(server, queued).value("state", ""), "cancelled");
  expect_json(cli->Delete("/v1/jobs/" + slow), 200);
  const json h = expect_json(cli->Get("/v1/health"), 200);
  EXPECT_EQ(h["jobs"]["queued"], 0);
}

TEST(Http, AFullQueueAnswers503WithRetryAfter) {
  JobStoreOptions jobs = job_options();
  jobs.workers = 1;
  jobs.queue_size = 1;
  TestServer server(jobs);
  auto cli = server.client();
  const std::string running = submit(server, slow_scene());
  wait_for(server, running, [](const json& s) { return s.value("state", "") != "queued"; });
  const std::string waiting = submit(server, point_scene(10));  // fills the queue
  auto res = cli->Post("/v1/jobs", point_scene(10).dump(), "application/json");
  expect_error(res, 503, "queue_full");
  EXPECT_FALSE(res->get_header_value("Retry-After").empty());
  res = cli->Post("/v1/solve", point_scene(10).dump(), "application/json");
  expect_error(res, 503, "queue_full");
  EXPECT_FALSE(res->get_header_value("Retry-After").empty());
  expect_json(cli->Delete("/v1/jobs/" + running), 200);
  EXPECT_EQ(wait_final(server, waiting).value("state", ""), "done");
  submit(server, point_scene(10));  // room again
}

TEST(Http, SynchronousSolvesLeaveThreadsForStatusRequests) {
  JobStoreOptions jobs = job_options();
  jobs.workers = 1;
  jobs.time_limit = 2s;
  HttpServerOptions http;
  http.http_threads = 3;  // one may wait for a solve, two stay free
  TestServer server(jobs, http);
  std::thread waiting([&] {
    expect_error(server.client()->Post("/v1/solve", slow_scene().dump(), "application/json"), 422, "solve_failed");
  });
  const auto t0 = Clock::now();
  while (expect_json(server.client()->Get("/v1/health"), 200)["jobs"]["running"] != 1 && Clock::now() - t0 < 30s)
    std::this_thread::sleep_for(5ms);
  auto res = server.client()->Post("/v1/solve", point_scene(10).dump(), "application/json");
  expect_error(res, 503, "busy");
  EXPECT_FALSE(res->get_header_value("Retry-After").empty());
  expect_json(server.client()->Post("/v1/jobs", point_scene(10).dump(), "application/json"), 202);  // jobs still go
  waiting.join();
}

TEST(Http, ShutdownAnswersWhoIsWaitingAndRefusesNewWork) {
  JobStoreOptions jobs = job_options();
  jobs.workers = 1;
  TestServer server(jobs);
  std::thread waiting([&] {
    expect_error(server.client()->Post("/v1/solve", slow_scene().dump(), "application/json"), 503, "shutting_down");
  });
  const auto t0 = Clock::now();
  while (expect_json(server.client()->Get("/v1/health"), 200)["jobs"]["running"] != 1 && Clock::now() - t0 < 30s)
    std::this_thread::sleep_for(5ms);
  server.shutdown_jobs();
  waiting.join();
  EXPECT_LT(Clock::now() - t0, 30s);
  expect_error(server.client()->Post("/v1/jobs", point_scene(10).dump(), "application/json"), 503, "shutting_down");
  expect_error(server.client()->Post("/v1/solve", point_scene(10).dump(), "application/json"), 503, "shutting_down");
  expect_alive(server);
}

TEST(Http, TheTimeLimitFailsAJobWithTheReason) {
  JobStoreOptions jobs = job_options();
  jobs.time_limit = 0.3s;
  TestServer server(jobs);
  auto cli = server.client();
  const std::string id = submit(server, slow_scene());
  const json s = wait_final(server, id);
  EXPECT_EQ(s.value("state", ""), "failed") << s;
  EXPECT_NE(s.value("error", "").find("time limit"), std::string::npos) << s;
  const json e = expect_error(cli->Get("/v1/jobs/" + id + "/result"), 409, "job_failed");
  EXPECT_NE(e.value("message", "").find("time limit"), std::string::npos) << e;
  // The synchronous route has the same limit.
  const json sync = expect_error(cli->Post("/v1/solve", slow_scene().dump(), "application/json"), 422, "solve_failed");
  EXPECT_NE(sync.value("message", "").find("time limit"), std::string::npos) << sync;
  // And a small scene still fits in it.
  expect_json(cli->Post("/v1/solve", point_scene(10).dump(), "application/json"), 200);
}

TEST(Http, ThePatchLimitFailsWithTheReason) {
  JobStoreOptions jobs = job_options();
  jobs.max_patches = 500;
  TestServer server(jobs);
  auto cli = server.client();
  const json sync = expect_error(cli->Post("/v1/solve", slow_scene(2000).dump(), "application/json"), 422, "solve_failed");
  EXPECT_NE(sync.value("message", "").find("500"), std::string::npos) << sync;
  const std::string id = submit(server, slow_scene(2000));
  const json s = wait_final(server, id);
  EXPECT_EQ(s.value("state", ""), "failed");
  EXPECT_NE(s.value("error", "").find("max_patches"), std::string::npos) << s;
  // A patch size that would exhaust memory is refused before meshing, at once.
  json absurd = point_scene(10);
  absurd["meshing"] = {{"max_patch_area", 1e-12}};
  const auto t0 = Clock::now();
  expect_error(cli->Post("/v1/solve", absurd.dump(), "application/json"), 422, "solve_failed");
  EXPECT_LT(Clock::now() - t0, 5s);
  expect_json(cli->Post("/v1/solve", slow_scene(200).dump(), "application/json"), 200);
}

// ---- the data directory ------------------------------------------------------------------------------------

std::size_t files_in(const fs::path& dir) {  // not counting the lock file
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir))
    n += e.is_regular_file() && e.path().filename().string()[0] != '.';
  return n;
}

TEST(Http, FinishedResultsSurviveARestart) {
  TempDir dir;
  JobStoreOptions jobs = job_options();
  jobs.data_dir = dir.path;
  jobs.max_patches = 500;
  std::string done_id, failed_id, result_text;
  {
    TestServer server(jobs);
    done_id = submit(server, point_scene(80));
    failed_id = submit(server, slow_scene(2000));  // over the patch limit
    ASSERT_EQ(wait_final(server, done_id).value("state", ""), "done");
    ASSERT_EQ(wait_final(server, failed_id).value("state", ""), "failed");
    auto res = server.client()->Get("/v1/jobs/" + done_id + "/result");
    ASSERT_TRUE(res);
    result_text = res->body;
  }
  // Files only: the scene went away once the job was final; no temporary file is left.
  for (const auto& e : fs::directory_iterator(dir.path / "jobs"))
    EXPECT_TRUE(e.path().string().ends_with(".job.json") || e.path().string().ends_with(".result.json") ||
                e.path().filename() == ".lock")
        << e.path();
  {
    TestServer server(jobs);
    auto cli = server.client();
    EXPECT_EQ(job_status(server, done_id).value("state", ""), "done");
    auto res = cli->Get("/v1/jobs/" + done_id + "/result");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 200);
    EXPECT_EQ(res->body, result_text);
    EXPECT_NEAR(probe_lx(json::parse(res->body), "below"), expected_below(80), 1e-6 * expected_below(80));
    const json f = job_status(server, failed_id);
    EXPECT_EQ(f.value("state", ""), "failed");
    EXPECT_NE(f.value("error", "").find("max_patches"), std::string::npos) << f;
    // Deleting removes the files too, so a third start does not bring it back.
    expect_json(cli->Delete("/v1/jobs/" + done_id), 200);
  }
  {
    TestServer server(jobs);
    expect_error(server.client()->Get("/v1/jobs/" + done_id), 404, "not_found");
    EXPECT_EQ(job_status(server, failed_id).value("state", ""), "failed");
  }
}

TEST(Http, UnfinishedJobsRunAgainAfterARestart) {
  TempDir dir;
  JobStoreOptions jobs = job_options();
  jobs.data_dir = dir.path;
  jobs.workers = 1;
  std::string slow, small;
  {
    TestServer server(jobs);
    slow = submit(server, slow_scene());
    small = submit(server, point_scene(30));
    EXPECT_EQ(job_status(server, small).value("state", ""), "queued");
  }  // shut down with one job running and one queued
  jobs.time_limit = 0.3s;  // so that the slow one ends quickly this time
  TestServer server(jobs);
  const json s = wait_final(server, small);
  ASSERT_EQ(s.value("state", ""), "done") << s;
  const json r = expect_json(server.client()->Get("/v1/jobs/" + small + "/result"), 200);
  EXPECT_NEAR(probe_lx(r, "below"), expected_below(30), 1e-6 * expected_below(30));
  EXPECT_EQ(wait_final(server, slow).value("state", ""), "failed");
}

TEST(Http, FinishedJobsExpire) {
  TempDir dir;
  JobStoreOptions jobs = job_options();
  jobs.data_dir = dir.path;
  jobs.result_ttl = 1s;
  TestServer server(jobs);
  const std::string id = submit(server, point_scene(10));
  ASSERT_EQ(wait_final(server, id).value("state", ""), "done");
  EXPECT_EQ(files_in(dir.path / "jobs"), 2u);
  const auto t0 = Clock::now();
  while (server.client()->Get("/v1/jobs/" + id)->status == 200 && Clock::now() - t0 < 10s)
    std::this_thread::sleep_for(50ms);
  expect_error(server.client()->Get("/v1/jobs/" + id), 404, "not_found");
  EXPECT_EQ(files_in(dir.path / "jobs"), 0u);
}

TEST(Http, OneDataDirectoryServesOneServer) {
  TempDir dir;
  JobStoreOptions jobs = job_options();
  jobs.data_dir = dir.path;
  TestServer server(jobs);
  EXPECT_THROW(JobStore second(jobs), std::runtime_error);
  expect_alive(server);
}

TEST(Http, AnUnusableDataDirectoryIsAStartupError) {
  TempDir dir;
  std::ofstream(dir.path / "file") << "x";
  JobStoreOptions jobs = job_options();
  jobs.data_dir = dir.path / "file";
  EXPECT_THROW(JobStore store(jobs), std::runtime_error);
}

}  // namespace
}  // namespace lambert
