// Issue 37's acceptance test: two real `lambert serve` processes on one PostgreSQL store, 24 jobs,
// one instance SIGKILLed while it solves. Every job must end done exactly once (counted in the
// structured logs of every instance that ever ran), with its own scene's answer, readable from any
// instance, and still there after every instance has been restarted.
//
// Each job is a furnace (REFERENCES R1) of its own: a closed convex 4 x 3 x 2.5 m room whose every
// surface emits M_k and reflects rho_k, so its radiosity is B = M_k / (1 - rho_k) everywhere, exactly
// (a convex room needs no visibility; the dense solve is exact to 1e-6, README's accuracy table).
#pragma GCC diagnostic ignored "-Wunused-function"  // the fixture's helpers this file does not use
#include "tests/service_fixture.h"

#include <map>

#include "tests/pg_fixture.h"
#include "tests/serve_process.h"

namespace lambert {
namespace {

struct Furnace {
  double exitance, reflectance;
  double radiosity() const { return exitance / (1 - reflectance); }  // R1: B = M/(1 - rho)
};

Furnace furnace(int k) { return {1.0 + 0.25 * k, 0.30 + 0.02 * k}; }

json furnace_scene(int k) {
  json scene = json::parse(read_text(kSource / "scenes/reference/furnace-obstacle.json"));
  scene.erase("expected");
  scene["name"] = "furnace-" + std::to_string(k);
  scene["surfaces"].erase(1);  // the floating box: the room alone is convex
  scene["surfaces"][0]["emission"] = {{"exitance", furnace(k).exitance}};
  scene["materials"]["grey"]["reflectance"] = furnace(k).reflectance;
  scene["meshing"] = {{"max_patch_area", 0.04}};  // about 1500 patches: a fraction of a second each
  return scene;
}

// Checks a result against its furnace; "" when it holds, otherwise what is wrong.
std::string check_furnace(const std::string& body, int k) {
  const json result = json::parse(body, nullptr, false);
  if (!result.is_object() || !result.contains("surfaces")) return "not a result";
  const double expected = furnace(k).radiosity();
  for (const json& b : result["surfaces"][0]["radiosity_mean"])
    if (std::abs(b.get<double>() - expected) > 1e-6 * expected)
      return "radiosity " + b.dump() + " instead of M/(1 - rho) = " + std::to_string(expected);
  return "";
}

std::vector<std::string> serve_args(const std::string& uri) {
  return {"--store", uri, "--threads", "1", "--store-lease-s", "2", "--queue-size", "100", "--drain-s", "30"};
}

// Every job line of every log: job id -> the states it went through on each instance.
std::map<std::string, std::vector<std::string>> job_lines(const std::vector<const ServeProcess*>& instances) {
  std::map<std::string, std::vector<std::string>> states;
  for (const ServeProcess* p : instances)
    for (const json& line : p->log_lines())
      if (line.value("event", "") == "job") states[line.value("id", "")].push_back(line.value("state", ""));
  return states;
}

json status_of(const ServeProcess& p, const std::string& id) {
  auto res = p.client()->Get("/v1/jobs/" + id);
  return res && res->status == 200 ? json::parse(res->body) : json::object();
}

TEST(PgInstances, TwoInstancesOneKilledEveryJobDoneOnceWithItsOwnAnswer) {
  LAMBERT_FRESH_DATABASE(uri);
  const TempDir dir;
  auto a = std::make_unique<ServeProcess>(serve_args(uri), dir.path / "a.log");
  auto b = std::make_unique<ServeProcess>(serve_args(uri), dir.path / "b.log");
  ASSERT_GT(a->port(), 0);
  ASSERT_GT(b->port(), 0);

  constexpr int kJobs = 24;
  std::vector<std::string> ids;
  for (int k = 0; k < kJobs; ++k) {
    auto res = (k % 2 ? *a : *b).client()->Post("/v1/jobs", furnace_scene(k).dump(), "application/json");
    ASSERT_TRUE(res && res->status == 202) << (res ? res->body : "no answer");
    ids.push_back(json::parse(res->body).value("id", ""));
  }

  // Kill `a` while it solves: once it has finished a few jobs and started another.
  std::string killed_job;
  const auto t0 = Clock::now();
  while (killed_job.empty() && Clock::now() - t0 < 60s) {
    std::size_t finished = 0;
    std::map<std::string, std::string> last;
    for (const json& line : a->log_lines())
      if (line.value("event", "") == "job" && line.value("instance", "") != "") {
        last[line.value("id", "")] = line.value("state", "");
        finished += line.value("state", "") == "done";
      }
    for (const auto& [id, state] : last)
      if (state == "running" && finished >= 3) killed_job = id;
    if (killed_job.empty()) std::this_thread::sleep_for(5ms);
  }
  ASSERT_FALSE(killed_job.empty()) << "instance a never ran a job";
  a->signal(SIGKILL);
  a->wait();
  const auto killed_at = Clock::now();
  EXPECT_EQ(status_of(*b, killed_job).value("state", ""), "running");  // under a's lease until it runs out

  // A new instance joins, as a restarted pod would.
  auto c = std::make_unique<ServeProcess>(serve_args(uri), dir.path / "c.log");
  std::optional<double> taken_up_s;
  for (const auto deadline = Clock::now() + 120s; Clock::now() < deadline;) {
    if (!taken_up_s) {
      const auto seen = job_lines({b.get(), c.get()});
      if (seen.count(killed_job) &&
          std::count(seen.at(killed_job).begin(), seen.at(killed_job).end(), "running") > 0)
        taken_up_s = std::chrono::duration<double>(Clock::now() - killed_at).count();
    }
    std::size_t final = 0;
    for (const auto& id : ids) final += is_final(status_of(*c, id));
    if (final == ids.size()) break;
    std::this_thread::sleep_for(50ms);
  }
  ASSERT_TRUE(taken_up_s);
  EXPECT_LT(*taken_up_s, 60.0) << "the killed instance's job waited more than a minute";
  std::cerr << "the killed instance's job was taken up after " << *taken_up_s << " s (lease 2 s)\n";

  // Done exactly once each, with its own furnace's answer, from either living instance.
  const auto states = job_lines({a.get(), b.get(), c.get()});
  for (int k = 0; k < kJobs; ++k) {
    const std::string& id = ids[k];
    EXPECT_EQ(status_of(*b, id).value("state", ""), "done") << id;
    const auto& seen = states.count(id) ? states.at(id) : std::vector<std::string>{};
    EXPECT_EQ(std::count(seen.begin(), seen.end(), "done"), 1) << id << " (job " << k << ")";
    for (const ServeProcess* p : {b.get(), c.get()}) {
      auto res = p->client()->Get("/v1/jobs/" + id + "/result");
      ASSERT_TRUE(res && res->status == 200) << id;
      EXPECT_EQ(check_furnace(res->body, k), "") << "job " << k;
    }
  }
  const auto& killed_states = states.at(killed_job);
  EXPECT_GE(std::count(killed_states.begin(), killed_states.end(), "running"), 2)
      << "the killed instance's job ran once more elsewhere";

  // Every instance stops; a new one still has every result.
  b->signal(SIGTERM);
  c->signal(SIGTERM);
  EXPECT_EQ(b->wait(), 0);
  EXPECT_EQ(c->wait(), 0);
  ServeProcess after(serve_args(uri), dir.path / "after.log");
  for (int k = 0; k < kJobs; ++k) {
    auto res = after.client()->Get("/v1/jobs/" + ids[k] + "/result");
    ASSERT_TRUE(res && res->status == 200) << ids[k];
    EXPECT_EQ(check_furnace(res->body, k), "") << "job " << k << " after the restart";
  }
}

}  // namespace
}  // namespace lambert
