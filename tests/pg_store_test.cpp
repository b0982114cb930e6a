// The PostgreSQL job store (server/job_store_pg.h) on a real, throw-away PostgreSQL (pg_fixture.h).
// Two PgJobStore objects on one database stand for two instances. The checks are the store's
// promises, counted: every job claimed exactly once however the claims interleave; a lease that ran
// out is taken over and the stale worker can change nothing; a cancel through one instance is seen
// by the other's next renewal; a result is shared by its cache key and removed with its last job.
// Over HTTP, each job's result is its own scene's closed form E = I/h² (REFERENCES P1), whichever
// instance solved it and whichever answers.
#pragma GCC diagnostic ignored "-Wunused-function"  // the fixture's helpers this file does not use
#include "tests/service_fixture.h"

#include <mutex>

#include "server/cache_key.h"
#include "server/job_store_pg.h"
#include "tests/pg_fixture.h"

namespace lambert {
namespace {

PgJobStoreOptions pg_options(const std::string& uri, double lease_s = 30) {
  PgJobStoreOptions o;
  o.conninfo = uri;
  o.lease = std::chrono::duration<double>(lease_s);
  return o;
}

std::string submitted_id(const SubmitOutcome& out) {
  const auto* s = std::get_if<JobStatus>(&out);
  EXPECT_TRUE(s) << "the job was not accepted";
  return s ? s->id : "";
}

JobOutcome done_with(const std::string& text) {
  JobOutcome o;
  o.result = std::make_shared<const std::string>(text);
  return o;
}

std::string result_text(JobStore& store, const std::string& id) {
  const ResultLookup r = store.result(id);
  const auto* done = std::get_if<JobResult>(&r);
  return done ? *done->json : "(no result)";
}

TEST(PgStore, TheSchemaIsCreatedOnceAndANewerOneIsRefused) {
  LAMBERT_FRESH_DATABASE(uri);
  { PgJobStore a(pg_options(uri)); }
  PgJobStore b(pg_options(uri));  // finds the schema made: nothing to do
  pg::Connection c(uri);
  EXPECT_EQ(c.exec("SELECT version FROM lambert_schema").integer(0, 0), kPgSchemaVersion);
  EXPECT_EQ(c.exec("SELECT count(*) FROM lambert_schema").integer(0, 0), 1);
  c.exec("UPDATE lambert_schema SET version = 99");
  try {
    PgJobStore newer(pg_options(uri));
    ADD_FAILURE() << "a schema of version 99 was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("version 99"), std::string::npos) << e.what();
  }
  EXPECT_THROW(PgJobStore(pg_options("postgresql://lambert@/nonexistent_db?host=/nonexistent")), std::exception);
}

TEST(PgStore, ConcurrentClaimsFromTwoInstancesTakeEachJobExactlyOnce) {
  LAMBERT_FRESH_DATABASE(uri);
  PgJobStore a(pg_options(uri)), b(pg_options(uri));
  std::set<std::string> submitted;
  for (int k = 0; k < 40; ++k) submitted.insert(submitted_id((k % 2 ? a : b).submit("{}", "", 1000)));
  EXPECT_EQ(a.counts().queued, 40u);
  std::mutex mutex;
  std::multiset<std::string> claimed;
  std::vector<std::thread> workers;
  for (int t = 0; t < 6; ++t)
    workers.emplace_back([&, t] {
      JobStore& store = t % 2 ? a : b;
      while (auto c = store.claim("worker" + std::to_string(t))) {
        EXPECT_EQ(c->token, 1);
        EXPECT_TRUE(store.finish(*c, done_with("result of " + c->id)));
        std::lock_guard lock(mutex);
        claimed.insert(c->id);
      }
    });
  for (auto& w : workers) w.join();
  EXPECT_EQ(claimed.size(), 40u);
  for (const auto& id : submitted) {
    EXPECT_EQ(claimed.count(id), 1u) << id;
    EXPECT_EQ(result_text(b, id), "result of " + id);
  }
  EXPECT_EQ(a.counts().done, 40u);
}

TEST(PgStore, AnExpiredLeaseIsTakenOverAndTheStaleWorkerIsFenced) {
  LAMBERT_FRESH_DATABASE(uri);
  PgJobStore a(pg_options(uri, 1)), b(pg_options(uri, 1));
  const std::string id = submitted_id(a.submit("{}", "", 10));
  const auto first = a.claim("a");
  ASSERT_TRUE(first);
  EXPECT_FALSE(b.claim("b"));                       // held under a's lease
  EXPECT_EQ(a.renew(*first, 0.3), Renewal::Held);
  std::this_thread::sleep_for(1300ms);              // a stops renewing: its lease of 1 s runs out
  const auto second = b.claim("b");
  ASSERT_TRUE(second);
  EXPECT_EQ(second->id, id);
  EXPECT_EQ(second->token, first->token + 1);
  EXPECT_EQ(a.renew(*first, 0.5), Renewal::Lost);
  EXPECT_FALSE(a.finish(*first, done_with("stale")));
  a.release(*first);                                // changes nothing either
  EXPECT_EQ(a.status(id)->state, JobState::Running);
  EXPECT_TRUE(b.finish(*second, done_with("fresh")));
  EXPECT_FALSE(b.finish(*second, done_with("twice")));  // done once
  EXPECT_EQ(result_text(a, id), "fresh");
}

TEST(PgStore, ACancelThroughOneInstanceReachesTheOneThatRunsTheJob) {
  LAMBERT_FRESH_DATABASE(uri);
  PgJobStore a(pg_options(uri)), b(pg_options(uri));
  const std::string id = submitted_id(a.submit("{}", "", 10));
  const auto c = a.claim("a");
  ASSERT_TRUE(c);
  EXPECT_EQ(b.status(id)->state, JobState::Running);
  const CancelOutcome out = b.cancel_or_remove(id);
  EXPECT_EQ(out.kind, CancelOutcome::Kind::Cancelled);
  EXPECT_EQ(out.status.state, JobState::Cancelled);
  EXPECT_EQ(a.renew(*c, 0.5), Renewal::Lost);       // a's worker stops here
  EXPECT_FALSE(a.finish(*c, done_with("late")));
  EXPECT_EQ(a.status(id)->state, JobState::Cancelled);
  EXPECT_EQ(b.cancel_or_remove(id).kind, CancelOutcome::Kind::Removed);  // finished: removed
  EXPECT_FALSE(a.status(id));
}

TEST(PgStore, AReleasedJobGoesBackToTheFrontOfTheQueue) {
  LAMBERT_FRESH_DATABASE(uri);
  PgJobStore a(pg_options(uri)), b(pg_options(uri));
  const std::string first = submitted_id(a.submit("{\"n\": 1}", "", 10));
  const std::string second = submitted_id(a.submit("{\"n\": 2}", "", 10));
  EXPECT_EQ(a.status(second)->queue_position, 2u);
  const auto c = a.claim("a");
  ASSERT_TRUE(c && c->id == first);
  EXPECT_EQ(c->scene_json, "{\"n\": 1}");
  EXPECT_EQ(a.status(second)->queue_position, 1u);
  a.release(*c);
  const auto again = b.claim("b");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->id, first);
  EXPECT_EQ(again->token, 2);
  EXPECT_EQ(a.submit("{}", "", 1).index(), 1u);     // QueueFull: one job (the second) is queued
}

TEST(PgStore, ResultsAreSharedByCacheKeyAndGoWithTheirLastJob) {
  LAMBERT_FRESH_DATABASE(uri);
  PgJobStore a(pg_options(uri)), b(pg_options(uri));
  const std::string key(64, 'a');
  const std::string first = submitted_id(a.submit("{}", key, 10));
  const std::string twin = submitted_id(b.submit("{}", key, 10));  // queued before the result exists
  const auto c = a.claim("a");
  ASSERT_TRUE(c && c->id == first);
  ASSERT_TRUE(a.finish(*c, done_with("shared result")));
  EXPECT_FALSE(b.claim("b"));  // the twin was answered from the store when its turn came
  EXPECT_TRUE(b.status(twin)->cached);
  EXPECT_EQ(result_text(b, twin), "shared result");
  const SubmitOutcome late = b.submit("{}", key, 10);
  const auto* s = std::get_if<JobStatus>(&late);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->state, JobState::Done);
  EXPECT_TRUE(s->cached);
  ASSERT_TRUE(b.cached_result(key));
  EXPECT_EQ(*b.cached_result(key), "shared result");
  pg::Connection sql(uri);
  EXPECT_EQ(sql.exec("SELECT count(*) FROM lambert_results").integer(0, 0), 1);  // stored once
  a.cancel_or_remove(first);
  a.cancel_or_remove(twin);
  EXPECT_EQ(result_text(a, s->id), "shared result");
  a.cancel_or_remove(s->id);
  EXPECT_EQ(sql.exec("SELECT count(*) FROM lambert_results").integer(0, 0), 0);
  EXPECT_FALSE(b.cached_result(key));
}

TEST(PgStore, FinishedJobsExpireWithTheirResults) {
  LAMBERT_FRESH_DATABASE(uri);
  PgJobStoreOptions o = pg_options(uri);
  o.result_ttl = 300ms;
  PgJobStore a(o);
  const std::string id = submitted_id(a.submit("{}", "", 10));
  const std::string waiting = submitted_id(a.submit("{}", "", 10));
  const auto c = a.claim("a");
  ASSERT_TRUE(c && a.finish(*c, done_with("soon gone")));
  ASSERT_TRUE(a.status(id)->expires);
  std::this_thread::sleep_for(500ms);
  a.sweep_expired();
  EXPECT_FALSE(a.status(id));
  EXPECT_TRUE(a.status(waiting));  // queued jobs do not expire
  pg::Connection sql(uri);
  EXPECT_EQ(sql.exec("SELECT count(*) FROM lambert_results").integer(0, 0), 0);
}

TEST(PgStore, AResultOverTheStoresLimitFailsItsJobWithTheLimitNamed) {
  // The same check as bytea's 1 GiB (kPgMaxResultBytes), at a limit of 64 bytes: a result of
  // exactly 64 bytes is stored, one of 65 fails its job with the limit named and stores nothing.
  LAMBERT_FRESH_DATABASE(uri);
  PgJobStoreOptions o = pg_options(uri);
  o.max_result_bytes = 64;
  PgJobStore a(o);
  const std::string fits = submitted_id(a.submit("{}", "", 10));
  const std::string over = submitted_id(a.submit("{}", "", 10));
  const auto first = a.claim("a");
  ASSERT_TRUE(first && first->id == fits);
  ASSERT_TRUE(a.finish(*first, done_with(std::string(64, 'x'))));
  EXPECT_EQ(result_text(a, fits), std::string(64, 'x'));
  const auto second = a.claim("a");
  ASSERT_TRUE(second && second->id == over);
  ASSERT_TRUE(a.finish(*second, done_with(std::string(65, 'x'))));
  const auto status = a.status(over);
  ASSERT_TRUE(status);
  EXPECT_EQ(status->state, JobState::Failed);
  EXPECT_NE(status->error.find("65 bytes"), std::string::npos) << status->error;
  EXPECT_NE(status->error.find("max_result_bytes = 64"), std::string::npos) << status->error;
  EXPECT_TRUE(std::holds_alternative<JobFailed>(a.result(over)));
  pg::Connection sql(uri);
  EXPECT_EQ(sql.exec("SELECT count(*) FROM lambert_results").integer(0, 0), 1);
}

// ---- two in-process services on one database, over HTTP ---------------------------------------------

TEST(PgHttp, AnyInstanceAnswersForAnyJobWithItsOwnScenesAnswer) {
  LAMBERT_FRESH_DATABASE(uri);
  ServiceOptions options;
  options.workers = 1;
  TestServer a(std::make_unique<PgJobStore>(pg_options(uri)), options);
  TestServer b(std::make_unique<PgJobStore>(pg_options(uri)), options);
  std::vector<std::pair<std::string, double>> jobs;  // id, candela
  for (int k = 0; k < 8; ++k) {
    const double cd = 40 + 10 * k;
    jobs.emplace_back(submit(k % 2 ? a : b, point_scene(cd)), cd);
  }
  for (const auto& [id, cd] : jobs) {
    ASSERT_EQ(wait_final(a, id).value("state", ""), "done");
    for (TestServer* server : {&a, &b}) {
      auto res = server->client()->Get("/v1/jobs/" + id + "/result");
      ASSERT_TRUE(res && res->status == 200);
      const json result = json::parse(res->body);
      EXPECT_NEAR(probe_lx(result, "below"), expected_below(cd), 1e-9 * expected_below(cd));  // E = I/h²
      EXPECT_NEAR(probe_lx(result, "side"), expected_side(cd), 1e-9 * expected_side(cd));     // E = I h/d³
    }
  }
  // The same scene through the other instance: answered from the store.
  const json cached = expect_json(b.client()->Post("/v1/jobs", point_scene(40).dump(2), "application/json"), 202);
  EXPECT_TRUE(cached.value("cached", false));
  EXPECT_EQ(json::parse(a.client()->Get("/v1/health")->body)["jobs"].value("stored", 0), 9);
}

TEST(PgHttp, ADeleteThroughAnotherInstanceStopsTheRunningSolvePromptly) {
  LAMBERT_FRESH_DATABASE(uri);
  ServiceOptions options;
  options.workers = 1;
  TestServer a(std::make_unique<PgJobStore>(pg_options(uri, 2)), options);  // renews every 0.5 s
  PgJobStore elsewhere(pg_options(uri, 2));  // an instance without workers
  const std::string id = submit(a, slow_scene());
  const json running = wait_for(a, id, [](const json& s) { return s.value("progress", 0.0) > 0; });
  ASSERT_EQ(running.value("state", ""), "running");
  const auto t0 = Clock::now();
  EXPECT_EQ(elsewhere.cancel_or_remove(id).kind, CancelOutcome::Kind::Cancelled);
  while (a.jobs().counts().running_here > 0 && Clock::now() - t0 < 10s) std::this_thread::sleep_for(10ms);
  const double stopped_s = std::chrono::duration<double>(Clock::now() - t0).count();
  EXPECT_EQ(a.jobs().counts().running_here, 0u);
  EXPECT_LT(stopped_s, 2.0) << "the renewal every 0.5 s should have stopped it";
  EXPECT_EQ(job_status(a, id).value("state", ""), "cancelled");
}

}  // namespace
}  // namespace lambert
