// The HTTP service through real HTTP (SPEC §4, docs/API.md), on the fixture of service_fixture.h.
#include "tests/service_fixture.h"

#include <fstream>

namespace lambert {
namespace {
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
  JobService jobs(std::make_unique<FileJobStore>(FileJobStoreOptions{}), job_options().service({}));
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

// The browser viewer's files, byte for byte as they are in the repository and as npm installed
// three.js (tests/viewer_test.mjs runs the page in Chromium).
TEST(Http, ServesTheBrowserViewerAndThreeJsAsNpmShipsIt) {
  TestServer server;
  auto cli = server.client();
  const std::pair<std::string, fs::path> files[] = {
      {"/", kSource / "server/viewer/index.html"},
      {"/viewer/app.js", kSource / "server/viewer/app.js"},
      {"/viewer/three/three.module.js", kSource / "tools/node_modules/three/build/three.module.js"},
      {"/viewer/three/addons/loaders/GLTFLoader.js", kSource / "tools/node_modules/three/examples/jsm/loaders/GLTFLoader.js"}};
  for (const auto& [path, file] : files) {
    SCOPED_TRACE(path);
    auto r = cli->Get(path);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    EXPECT_EQ(r->body, read_text(file));
    EXPECT_EQ(r->get_header_value("Content-Type"),
              path == "/" ? "text/html; charset=utf-8" : "text/javascript; charset=utf-8");
  }
  expect_error(cli->Get("/viewer/"), 404, "not_found");
  expect_error(cli->Get("/viewer/three/build/three.cjs"), 404, "not_found");
  expect_error(cli->Get("/index.html"), 404, "not_found");
  auto r = cli->Post("/", "{}", "application/json");
  expect_error(r, 405, "method_not_allowed");
  EXPECT_EQ(r->get_header_value("Allow"), "GET, HEAD");
  expect_alive(server);
}

TEST(Http, UnknownPathsAre404AndWrongMethods405) {
  TestServer server;
  auto cli = server.client();
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

// output.view_factors and "thermal" surfaces over HTTP: the unit cube's factors (Howell C-11 between
// opposite faces, C-14 between adjacent ones) and, its faces black, the radiant exchange
// q_I = σ T_I⁴ − Σ_J F_IJ σ T_J⁴, and at its centre the mean radiant temperature (Σ T_I⁴ / 6)^¼.
TEST(Http, ViewFactorsAndRadiantExchangeOfTheUnitCube) {
  const double T[] = {320, 290, 300, 310, 305, 295};
  const char* names[] = {"floor", "ceiling", "west", "east", "south", "north"};
  const std::vector<std::vector<std::array<double, 3>>> faces = {
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}},
      {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, {{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}},
      {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}, {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}}};
  json scene = {{"spectrum", {{"mode", "spectral"}, {"wavelengths_nm", {555}}}},
                {"materials", {{"black", {{"reflectance", 0}}}}},
                {"surfaces", json::array()},
                {"probes", json::array({{{"name", "centre"}, {"position", {0.5, 0.5, 0.5}}, {"normal", {0, 0, 1}}}})},
                {"meshing", {{"max_patch_area", 0.02}}},
                {"output", {{"view_factors", true}}}};
  for (int I = 0; I < 6; ++I)
    scene["surfaces"].push_back({{"name", names[I]}, {"material", "black"}, {"polygon", faces[I]},
                                 {"thermal", {{"emissivity", 1}, {"temperature_K", T[I]}}}});
  TestServer server;
  const json result = expect_json(server.client()->Post("/v1/solve", scene.dump(), "application/json"), 200);
  const json& vf = result.at("view_factors");
  const double sigma = 5.670374419e-8;
  double mean_T4 = 0;
  for (int I = 0; I < 6; ++I) {
    double absorbed = 0;
    for (int J = 0; J < 6; ++J) {
      const double F = I == J ? 0 : I / 2 == J / 2 ? 0.1998248957 : 0.2000437761;  // C-11, C-14 (X = Y = 1)
      EXPECT_NEAR(vf["F"][I][J].get<double>(), F, 1e-6);
      absorbed += F * sigma * std::pow(T[J], 4);
    }
    const json& s = result.at("thermal").at("surfaces")[I];
    EXPECT_EQ(s["name"], names[I]);
    EXPECT_NEAR(s["thermal"]["net_flux_W_m2"].get<double>(), sigma * std::pow(T[I], 4) - absorbed, 1e-3);
    mean_T4 += std::pow(T[I], 4) / 6;
  }
  EXPECT_EQ(vf["geometry_hash"], result["thermal"]["geometry_hash"]);
  const json& centre = result["thermal"]["probes"][0];
  EXPECT_NEAR(centre["mean_radiant_temperature_K"].get<double>(), std::pow(mean_T4, 0.25), 1e-9);
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
  http.request_timeout_s = 1;
  TestServer server(job_options(), http);
  const int port = server.port();
  // No Content-Length and not chunked: HTTP/1.1 would read until the client closes.
  std::string r = raw_request(port, "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n\r\n{}");
  EXPECT_EQ(raw_status(r), 411) << r;
  EXPECT_EQ(raw_body(r)["error"]["code"], "length_required");
  // Content-Length says more than arrives. A small body is read before a worker takes the request:
  // it misses the request's deadline (1 s here) and is answered 408.
  auto t0 = Clock::now();
  r = raw_request(port, "POST /v1/solve HTTP/1.1\r\nHost: x\r\nContent-Length: 100\r\n\r\n{\"lambert\"");
  EXPECT_EQ(raw_status(r), 408) << r;
  EXPECT_EQ(raw_body(r)["error"]["code"], "request_timeout");
  EXPECT_LT(Clock::now() - t0, 10s);
  // A large one (beyond the 1 MiB read ahead) is read by a worker, whose read times out (1 s): the
  // request fails alone.
  t0 = Clock::now();
  r = raw_request(port, "POST /v1/solve HTTP/1.1\r\nHost: x\r\nContent-Length: 2000000\r\n\r\n{\"lambert\"");
  EXPECT_EQ(raw_status(r), 400) << r;
  EXPECT_EQ(raw_body(r)["error"]["code"], "invalid_body");
  EXPECT_LT(Clock::now() - t0, 10s);
  // A client that half-closes its socket before its body is complete gets no answer.
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
  ServiceOptions jobs = job_options();
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
  ServiceOptions jobs = job_options();
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
  ServiceOptions jobs = job_options();
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
  ServiceOptions jobs = job_options();
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
  ServiceOptions jobs = job_options();
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
  // 2 s: the slow scene needs about 10 s, and the small one with its worker process well under 1 s
  // even under AddressSanitizer, whose process start alone takes a good part of a second.
  ServiceOptions jobs = job_options();
  jobs.time_limit = 2s;
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
  ServiceOptions jobs = job_options();
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
  ServiceOptions jobs = job_options();
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
  ServiceOptions jobs = job_options();
  jobs.data_dir = dir.path;
  jobs.workers = 1;
  std::string slow, small;
  {
    TestServer server(jobs);
    slow = submit(server, slow_scene());
    small = submit(server, point_scene(30));
    EXPECT_EQ(job_status(server, small).value("state", ""), "queued");
  }  // shut down with one job running and one queued
  jobs.time_limit = 2s;  // so that the slow one (about 10 s) ends soon this time; the small one fits
  TestServer server(jobs);
  const json s = wait_final(server, small);
  ASSERT_EQ(s.value("state", ""), "done") << s;
  const json r = expect_json(server.client()->Get("/v1/jobs/" + small + "/result"), 200);
  EXPECT_NEAR(probe_lx(r, "below"), expected_below(30), 1e-6 * expected_below(30));
  EXPECT_EQ(wait_final(server, slow).value("state", ""), "failed");
}

TEST(Http, FinishedJobsExpire) {
  TempDir dir;
  ServiceOptions jobs = job_options();
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

// A damaged data directory is reported, never silently dropped (issue 37: a corrupted job record
// made its job vanish, 404; a deleted result file left the job "done" with a result answering 404).
TEST(Http, ACorruptedRecordOrALostResultFailsItsJobWithTheReason) {
  TempDir dir;
  ServiceOptions jobs = job_options();
  jobs.data_dir = dir.path;
  std::string corrupted, lost;
  {
    TestServer server(jobs);
    corrupted = submit(server, point_scene(30));
    lost = submit(server, point_scene(40));
    ASSERT_EQ(wait_final(server, corrupted).value("state", ""), "done");
    ASSERT_EQ(wait_final(server, lost).value("state", ""), "done");
  }
  std::ofstream(dir.path / "jobs" / (corrupted + ".job.json"), std::ios::trunc) << "{\"id\": \"" << corrupted << "\", \"sta";
  TestServer server(jobs);
  const json c = job_status(server, corrupted);
  EXPECT_EQ(c.value("state", ""), "failed") << c;
  EXPECT_NE(c.value("error", "").find("record of this job could not be read"), std::string::npos) << c;
  expect_error(server.client()->Get("/v1/jobs/" + corrupted + "/result"), 409, "job_failed");
  // While the server runs, the other job's result file goes.
  fs::remove(dir.path / "jobs" / (lost + ".result.json"));
  expect_error(server.client()->Get("/v1/jobs/" + lost + "/result"), 409, "job_failed");
  const json l = job_status(server, lost);
  EXPECT_EQ(l.value("state", ""), "failed") << l;
  EXPECT_NE(l.value("error", "").find("result of this job was lost"), std::string::npos) << l;
}

TEST(Http, OneDataDirectoryServesOneServer) {
  TempDir dir;
  ServiceOptions jobs = job_options();
  jobs.data_dir = dir.path;
  TestServer server(jobs);
  EXPECT_THROW(FileJobStore second(jobs.files()), std::runtime_error);
  expect_alive(server);
}

TEST(Http, AnUnusableDataDirectoryIsAStartupError) {
  TempDir dir;
  std::ofstream(dir.path / "file") << "x";
  ServiceOptions jobs = job_options();
  jobs.data_dir = dir.path / "file";
  EXPECT_THROW(FileJobStore store(jobs.files()), std::runtime_error);
}

}  // namespace
}  // namespace lambert
