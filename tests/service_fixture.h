// The HTTP service under test, shared by the service's test files: the server runs in-process on a
// free loopback port (bind_to_any_port + listen_after_bind, STACK P5) and is driven by httplib::Client
// or, for requests a well-behaved client cannot send, by a raw socket. Scenes whose answers are closed
// forms: an isotropic point source over a black floor, E = I h / d³ (REFERENCES P1), so each job's
// result tells which scene it came from.
#pragma once

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
#include "server/job_service.h"
#include "server/job_store_fs.h"

namespace lambert {
// The helpers are inline: each test file uses some of them, and an unused inline function does not warn.
namespace {


namespace fs = std::filesystem;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

const fs::path kSource = LAMBERT_SOURCE_DIR;

inline std::string read_text(const fs::path& path) {
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

// The job service and its file store, as the tests set them up.
struct ServiceOptions {
  std::size_t workers = 2, queue_size = 64, max_patches = 20000;
  std::chrono::duration<double> time_limit = 120s;
  std::uint64_t memory_bytes = 0;
  SceneLimits scene_limits;  // probe points, spectral values, result size (server/scene_limits.h)
  std::optional<fs::path> data_dir;
  std::chrono::duration<double> result_ttl = std::chrono::hours(24 * 7);
  FileJobStoreOptions files() const { return {data_dir, result_ttl}; }
  JobServiceOptions service(const std::optional<fs::path>& mesh_root) const {
    JobServiceOptions o;
    o.workers = workers;
    o.queue_size = queue_size;
    o.time_limit = time_limit;
    o.limits = {mesh_root, max_patches, memory_bytes, {}, scene_limits};
    o.worker_executable = LAMBERT_BINARY;
    return o;
  }
};
inline ServiceOptions job_options() { return {}; }

class TestServer {
 public:
  explicit TestServer(const ServiceOptions& jobs = job_options(), HttpServerOptions http = {})
      : TestServer(std::make_unique<FileJobStore>(jobs.files()), jobs, std::move(http)) {}
  // The same on another store (server/job_store_pg.h in pg_store_test).
  TestServer(std::unique_ptr<JobStore> store, const ServiceOptions& jobs, HttpServerOptions http = {}) {
    store_ = std::make_unique<JobService>(std::move(store), jobs.service(http.mesh_root));
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
  JobService& jobs() { return *store_; }
  std::unique_ptr<httplib::Client> client() const {
    auto c = std::make_unique<httplib::Client>("127.0.0.1", port_);
    c->set_read_timeout(300, 0);
    c->set_write_timeout(60, 0);
    return c;
  }

 private:
  std::unique_ptr<JobService> store_;
  std::unique_ptr<HttpServer> server_;
  std::thread thread_;
  int port_ = -1;
};

// ---- scenes -----------------------------------------------------------------------------------------

// An isotropic point source of `cd` candela 2 m above a black 2 x 2 m floor; probe "below" right under
// it (E = I/h² = cd/4 lx) and "side" 1 m off (E = I h/d³ = cd · 2/5^1.5 lx).
inline json point_scene(double cd, const std::string& name = "point") {
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
inline double expected_below(double cd) { return cd / 4; }
inline double expected_side(double cd) { return cd * 2 / std::pow(5.0, 1.5); }

// The closed 4 m room of scenes/reference (reflectance 0.5, a point source inside) cut into about
// `patches` patches: all of them exchange light, so the solve takes seconds.
// Several seconds of solving: a closed room with a floating box (its shadows need rays; an empty
// convex room needs none and solves 3072 patches in about a second).
inline json slow_scene(int patches = 4096) {
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

inline double probe_lx(const json& result, const std::string& name) {
  for (const auto& p : result.at("probes"))
    if (p.at("name") == name) return p.at("illuminance_lx").get<double>();
  ADD_FAILURE() << "no probe " << name;
  return NAN;
}

// ---- checks -----------------------------------------------------------------------------------------

// Every error is SPEC §4 JSON, and no exception text ever reaches a header (STACK P8).
inline json expect_error(const httplib::Result& res, int status, const std::string& code) {
  EXPECT_TRUE(res) << "no response: " << httplib::to_string(res.error());
  if (!res) return {};
  EXPECT_EQ(res->status, status) << res->body.substr(0, 2000);
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

inline json expect_json(const httplib::Result& res, int status) {
  EXPECT_TRUE(res) << "no response: " << httplib::to_string(res.error());
  if (!res) return {};
  EXPECT_EQ(res->status, status) << res->body.substr(0, 2000);
  EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
  json body = json::parse(res->body, nullptr, false);
  EXPECT_FALSE(body.is_discarded()) << res->body.substr(0, 2000);
  return body;
}

inline void expect_alive(const TestServer& server) {
  auto res = server.client()->Get("/v1/health");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
}

inline std::string submit(const TestServer& server, const json& scene) {
  auto res = server.client()->Post("/v1/jobs", scene.dump(), "application/json");
  const json body = expect_json(res, 202);
  return body.value("id", "");
}

inline json job_status(const TestServer& server, const std::string& id) {
  return expect_json(server.client()->Get("/v1/jobs/" + id), 200);
}

// Polls until `done(status)` or the timeout; returns the last status.
template <typename Pred>
inline json wait_for(const TestServer& server, const std::string& id, Pred done,
              std::chrono::duration<double> timeout = 120s) {
  const auto t0 = Clock::now();
  json s = job_status(server, id);
  while (!done(s) && Clock::now() - t0 < timeout) {
    std::this_thread::sleep_for(10ms);
    s = job_status(server, id);
  }
  return s;
}
inline bool is_final(const json& s) {
  const std::string st = s.value("state", "");
  return st == "done" || st == "failed" || st == "cancelled";
}
inline json wait_final(const TestServer& server, const std::string& id) {
  return wait_for(server, id, is_final);
}

// A request a polite client would not send: raw bytes on a socket; returns what came back.
inline std::string raw_request(int port, const std::string& bytes, bool close_write = false) {
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
inline int raw_status(const std::string& response) {
  return response.size() > 12 && response.rfind("HTTP/1.1 ", 0) == 0 ? std::stoi(response.substr(9, 3)) : -1;
}
inline json raw_body(const std::string& response) {
  const auto head_end = response.find("\r\n\r\n");
  return head_end == std::string::npos ? json() : json::parse(response.substr(head_end + 4), nullptr, false);
}

}  // namespace
}  // namespace lambert
