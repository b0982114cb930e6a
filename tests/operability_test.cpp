// Running the service: GET /v1/metrics read by the Prometheus project's own parser
// (tests/metrics_check.py, python3-prometheus-client) and counted against the jobs the test made;
// the structured log read back line by line as JSON (a job's lines in order, even where a worker
// claims it before its submission returns); SIGTERM on the real `lambert serve`: running
// solves finish within --drain-s, and a solve still running after it goes back to the queue and is
// solved after a restart (its energy balance closes, R5).
#pragma GCC diagnostic ignored "-Wunused-function"  // the fixture's helpers this file does not use
#include "tests/service_fixture.h"

#include <fcntl.h>

#include <condition_variable>
#include <cstdio>
#include <mutex>

#include "tests/serve_process.h"

namespace lambert {
namespace {

// The exposition, parsed and checked by tests/metrics_check.py; {} when it refused it.
json parse_metrics(const std::string& text) {
  const TempDir dir;
  const fs::path file = dir.path / "metrics.txt";
  std::ofstream(file) << text;
  const std::string command = "/usr/bin/python3 " + (kSource / "tests/metrics_check.py").string() + " < " +
                              file.string() + " 2>&1";
  FILE* p = ::popen(command.c_str(), "r");
  std::string out;
  char buf[4096];
  while (p && std::fgets(buf, sizeof buf, p)) out += buf;
  const int status = p ? ::pclose(p) : -1;
  EXPECT_EQ(status, 0) << out;
  return status == 0 ? json::parse(out) : json::object();
}

// The value of the sample `name` whose labels include `labels`; NaN if there is none.
double sample(const json& metrics, const std::string& family, const std::string& name, const json& labels = {}) {
  if (!metrics.contains(family)) return NAN;
  for (const auto& s : metrics[family]["samples"]) {
    if (s[0] != name) continue;
    bool match = true;
    for (const auto& [k, v] : labels.items()) match = match && s[1].value(k, "") == v;
    if (match) return s[2].get<double>();
  }
  return NAN;
}

TEST(Operability, MetricsFollowThePrometheusTextFormatAndCountTheJobs) {
  ServiceOptions options;
  options.max_patches = 500;  // the slow scene fails on it at once
  TestServer server(options);
  auto cli = server.client();
  const std::string solved = submit(server, point_scene(100));
  ASSERT_EQ(wait_final(server, solved).value("state", ""), "done");
  const json cached = expect_json(cli->Post("/v1/jobs", point_scene(100).dump(1), "application/json"), 202);
  EXPECT_TRUE(cached.value("cached", false));
  const std::string failed = submit(server, slow_scene(2000));
  ASSERT_EQ(wait_final(server, failed).value("state", ""), "failed");
  ASSERT_EQ(cli->Post("/v1/solve", point_scene(30).dump(), "application/json")->status, 200);

  auto res = cli->Get("/v1/metrics");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(res->get_header_value("Content-Type"), "text/plain; version=0.0.4; charset=utf-8");
  const json m = parse_metrics(res->body);
  EXPECT_EQ(m["lambert_jobs"]["type"], "gauge");
  EXPECT_EQ(sample(m, "lambert_jobs", "lambert_jobs", {{"state", "done"}}), 2);
  EXPECT_EQ(sample(m, "lambert_jobs", "lambert_jobs", {{"state", "failed"}}), 1);
  EXPECT_EQ(sample(m, "lambert_jobs", "lambert_jobs", {{"state", "queued"}}), 0);
  EXPECT_EQ(sample(m, "lambert_queue_depth", "lambert_queue_depth"), 0);
  EXPECT_EQ(m["lambert_solve_seconds"]["type"], "histogram");
  // Solves: the job and the synchronous one done, the slow scene failed; the cached job no solve.
  EXPECT_EQ(sample(m, "lambert_solve_seconds", "lambert_solve_seconds_count", {{"outcome", "done"}}), 2);
  EXPECT_EQ(sample(m, "lambert_solve_seconds", "lambert_solve_seconds_count", {{"outcome", "failed"}}), 1);
  EXPECT_GT(sample(m, "lambert_solve_seconds", "lambert_solve_seconds_sum", {{"outcome", "done"}}), 0);
  EXPECT_EQ(m["lambert_jobs_submitted"]["type"], "counter");
  EXPECT_EQ(sample(m, "lambert_jobs_submitted", "lambert_jobs_submitted_total"), 3);
  EXPECT_EQ(sample(m, "lambert_cache_hits", "lambert_cache_hits_total"), 1);
  EXPECT_EQ(sample(m, "lambert_http_responses", "lambert_http_responses_total", {{"code", "202"}}), 3);
  EXPECT_EQ(sample(m, "lambert_workers", "lambert_workers"), 2);
  EXPECT_EQ(sample(m, "lambert_build_info", "lambert_build_info"), 1);

  // The checker itself refuses what breaks the rules: buckets that are not cumulative.
  std::string broken = res->body;
  const std::string inf = "lambert_solve_seconds_bucket{outcome=\"done\",le=\"1800\"} 2";
  ASSERT_NE(broken.find(inf), std::string::npos);
  broken.replace(broken.find(inf), inf.size(), "lambert_solve_seconds_bucket{outcome=\"done\",le=\"1800\"} 1");
  ::testing::Test::RecordProperty("note", "a broken exposition follows; its failure is expected");
  const std::string command = "/usr/bin/python3 " + (kSource / "tests/metrics_check.py").string() +
                              " > /dev/null 2>&1 <<'EOF'\n" + broken + "EOF\n";
  EXPECT_NE(std::system(command.c_str()), 0);
}

// Waits until `done(status)` on a server process; the last status.
template <typename Pred>
json poll(const ServeProcess& server, const std::string& id, Pred done, std::chrono::duration<double> timeout = 120s) {
  const auto t0 = Clock::now();
  for (;;) {
    auto res = server.client()->Get("/v1/jobs/" + id);
    const json s = res && res->status == 200 ? json::parse(res->body) : json::object();
    if (done(s) || Clock::now() - t0 > timeout) return s;
    std::this_thread::sleep_for(20ms);
  }
}

std::string submit_to(const ServeProcess& server, const json& scene) {
  auto res = server.client()->Post("/v1/jobs", scene.dump(), "application/json");
  EXPECT_TRUE(res && res->status == 202);
  return res && res->status == 202 ? json::parse(res->body).value("id", "") : "";
}

std::vector<std::string> job_states(const ServeProcess& server, const std::string& id) {
  std::vector<std::string> states;
  for (const json& line : server.log_lines())
    if (line.value("event", "") == "job" && line.value("id", "") == id) states.push_back(line.value("state", ""));
  return states;
}

// A store whose claims overtake its submissions: submit() returns only once a worker has claimed a
// job (or after 20 s), so that the worker is ready to log "running" before the submitter has logged
// "queued" (the order in which CI once saw a job's lines). Everything else goes to a FileJobStore;
// idle workers ask every 5 ms.
class ClaimsBeforeSubmitReturns final : public JobStore {
 public:
  SubmitOutcome submit(const std::string& scene_json, const std::string& cache_key, std::size_t queue_limit) override {
    SubmitOutcome out = files_.submit(scene_json, cache_key, queue_limit);
    std::unique_lock lock(mutex_);
    claimed_cv_.wait_for(lock, 20s, [&] { return claimed_; });
    return out;
  }
  std::optional<Claim> claim(const std::string& instance) override {
    std::optional<Claim> c = files_.claim(instance);
    if (c) {
      std::lock_guard lock(mutex_);
      claimed_ = true;
      claimed_cv_.notify_all();
    }
    return c;
  }
  Renewal renew(const Claim& c, double progress) override { return files_.renew(c, progress); }
  bool finish(const Claim& c, const JobOutcome& outcome) override { return files_.finish(c, outcome); }
  void release(const Claim& c) override { files_.release(c); }
  std::optional<JobStatus> status(const std::string& id) override { return files_.status(id); }
  ResultLookup result(const std::string& id) override { return files_.result(id); }
  CancelOutcome cancel_or_remove(const std::string& id) override { return files_.cancel_or_remove(id); }
  std::shared_ptr<const std::string> cached_result(const std::string& key) override { return files_.cached_result(key); }
  StoreCounts counts() override { return files_.counts(); }
  void sweep_expired() override { files_.sweep_expired(); }
  std::chrono::milliseconds renew_interval() const override { return files_.renew_interval(); }
  std::chrono::milliseconds poll_interval() const override { return 5ms; }
  std::string describe() const override { return "claims before submit returns"; }

 private:
  FileJobStore files_{FileJobStoreOptions{}};
  std::mutex mutex_;
  std::condition_variable claimed_cv_;
  bool claimed_ = false;
};

TEST(Operability, AJobsQueuedLineComesBeforeItsRunningLineWhenAWorkerClaimsItAtOnce) {
  // The service's log lines (stderr) go to a file for the test's length.
  const TempDir dir;
  const fs::path log = dir.path / "log.jsonl";
  const int saved = ::dup(STDERR_FILENO);
  const int file = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  ASSERT_GE(saved, 0);
  ASSERT_GE(file, 0);
  ::dup2(file, STDERR_FILENO);
  ::close(file);
  std::string id;
  {
    ServiceOptions options;
    options.workers = 1;
    JobService jobs(std::make_unique<ClaimsBeforeSubmitReturns>(), options.service({}));
    const SubmitOutcome out = jobs.submit(point_scene(100).dump(), "");
    if (const auto* status = std::get_if<JobStatus>(&out)) id = status->id;
    for (int k = 0; k < 2000 && !id.empty(); ++k) {  // until it is done (at most 20 s)
      const auto s = jobs.status(id);
      if (s && s->state != JobState::Queued && s->state != JobState::Running) break;
      std::this_thread::sleep_for(10ms);
    }
  }
  ::dup2(saved, STDERR_FILENO);
  ::close(saved);
  ASSERT_FALSE(id.empty());
  std::vector<std::string> states;
  std::istringstream lines(read_text(log));
  for (std::string line; std::getline(lines, line);) {
    const json j = json::parse(line, nullptr, false);
    if (!j.is_discarded() && j.value("event", "") == "job" && j.value("id", "") == id)
      states.push_back(j.value("state", ""));
  }
  EXPECT_EQ(states, (std::vector<std::string>{"queued", "running", "done"}));
}

TEST(Operability, SigtermLetsARunningSolveFinishWithinTheDrainTime) {
  const TempDir dir;
  const std::vector<std::string> args = {"--threads", "1", "--data-dir", (dir.path / "data").string(),
                                         "--drain-s", "120", "--access-log"};
  std::string id;
  {
    ServeProcess server(args, dir.path / "first.log");
    id = submit_to(server, slow_scene(3000));
    ASSERT_EQ(poll(server, id, [](const json& s) { return s.value("progress", 0.0) > 0; }).value("state", ""),
              "running");
    server.signal(SIGTERM);
    std::this_thread::sleep_for(200ms);
    // Draining: status requests are answered, new work is refused.
    EXPECT_EQ(server.client()->Get("/v1/jobs/" + id)->status, 200);
    auto refused = server.client()->Post("/v1/jobs", point_scene(10).dump(), "application/json");
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->status, 503);
    const int status = server.wait();
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    EXPECT_EQ(job_states(server, id), (std::vector<std::string>{"queued", "running", "done"}));
    // Every request was a JSON line with its method, path, status and duration.
    int requests = 0;
    for (const json& line : server.log_lines())
      if (line.value("event", "") == "request") {
        ++requests;
        EXPECT_TRUE(line.contains("method") && line.contains("path") && line.contains("status") &&
                    line.contains("ms") && line.contains("time"))
            << line;
      }
    EXPECT_GE(requests, 3);
  }
  ServeProcess again(args, dir.path / "second.log");
  const json s = poll(again, id, is_final);
  EXPECT_EQ(s.value("state", ""), "done");
  EXPECT_TRUE(job_states(again, id).empty()) << "solved again after the restart";
}

TEST(Operability, SigtermHandsASolveStillRunningAfterTheDrainTimeBackToTheQueue) {
  const TempDir dir;
  const std::vector<std::string> args = {"--threads", "1", "--data-dir", (dir.path / "data").string(),
                                         "--drain-s", "0.2"};
  std::string id;
  {
    ServeProcess server(args, dir.path / "first.log");
    id = submit_to(server, slow_scene(3000));
    ASSERT_EQ(poll(server, id, [](const json& s) { return s.value("progress", 0.0) > 0; }).value("state", ""),
              "running");
    const auto t0 = Clock::now();
    server.signal(SIGTERM);
    const int status = server.wait();
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 5.0);
    EXPECT_EQ(job_states(server, id), (std::vector<std::string>{"queued", "running", "released"}));
  }
  ServeProcess again(args, dir.path / "second.log");
  const json s = poll(again, id, is_final);
  ASSERT_EQ(s.value("state", ""), "done");
  const json result = json::parse(again.client()->Get("/v1/jobs/" + id + "/result")->body);
  // A closed room: what the source emits is absorbed (REFERENCES R5).
  EXPECT_LT(std::abs(result["stats"]["energy"].value("relative_imbalance", 1.0)), 1e-3);
  EXPECT_EQ(job_states(again, id), (std::vector<std::string>{"running", "done"}));
}

}  // namespace
}  // namespace lambert
