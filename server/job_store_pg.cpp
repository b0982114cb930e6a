// The PostgreSQL job store (see job_store_pg.h for the schema, the claims and the leases).
//
// Every time is the database's (clock_timestamp()), and every statement that changes a claimed job
// names its token, so an instance whose lease ran out can no longer change the job.
#include "server/job_store_pg.h"

#include <algorithm>
#include <iostream>
#include <mutex>

#include "server/pg_connection.h"

namespace lambert {
namespace {

using SystemClock = std::chrono::system_clock;
using pg::Param;

constexpr const char* kForeignKeyViolation = "23503";
constexpr const char* kUniqueViolation = "23505";

// Version 1 of the schema (see job_store_pg.h). Each later version adds one step to kMigrations.
constexpr const char* kSchemaV1 = R"sql(
CREATE TABLE lambert_results (
  key text PRIMARY KEY,
  result bytea NOT NULL,
  created timestamptz NOT NULL DEFAULT clock_timestamp()
);
CREATE TABLE lambert_jobs (
  id text PRIMARY KEY,
  seq bigserial NOT NULL,
  state text NOT NULL CHECK (state IN ('queued', 'running', 'done', 'failed', 'cancelled')),
  created timestamptz NOT NULL DEFAULT clock_timestamp(),
  finished timestamptz,
  progress double precision NOT NULL DEFAULT 0,
  error text NOT NULL DEFAULT '',
  token bigint NOT NULL DEFAULT 0,
  owner text,
  lease_until timestamptz,
  scene bytea,
  cache_key text NOT NULL DEFAULT '',
  result_key text REFERENCES lambert_results (key),
  cached boolean NOT NULL DEFAULT false,
  CHECK ((state = 'done') = (result_key IS NOT NULL)),
  CHECK ((state IN ('queued', 'running')) = (scene IS NOT NULL))
);
CREATE INDEX lambert_jobs_open ON lambert_jobs (seq) WHERE state IN ('queued', 'running');
CREATE INDEX lambert_jobs_result ON lambert_jobs (result_key) WHERE result_key IS NOT NULL;
CREATE INDEX lambert_jobs_finished ON lambert_jobs (finished) WHERE finished IS NOT NULL;
)sql";
constexpr const char* kMigrations[] = {kSchemaV1};
static_assert(std::size(kMigrations) == kPgSchemaVersion);

// The columns status_from() reads, in its order.
constexpr const char* kStatusColumns =
    "j.id, j.state, j.progress, j.error, extract(epoch from j.created)::float8, "
    "coalesce(extract(epoch from j.finished)::float8, 0), j.cached, "
    "CASE WHEN j.state = 'queued' THEN (SELECT count(*) FROM lambert_jobs q "
    "WHERE q.state = 'queued' AND q.seq <= j.seq) ELSE 0 END, coalesce(j.result_key, '')";

}  // namespace

bool is_postgresql_uri(const std::string& store) {
  return store.rfind("postgresql://", 0) == 0 || store.rfind("postgres://", 0) == 0;
}

struct PgJobStore::Impl {
  explicit Impl(PgJobStoreOptions o) : options(std::move(o)), pool(options.conninfo, options.max_connections) {}

  PgJobStoreOptions options;
  pg::Pool pool;
  std::string description;
  std::mutex sweep_mutex;
  std::chrono::steady_clock::time_point last_sweep{};

  Param lease_seconds() const { return pg::number(options.lease.count()); }

  JobStatus status_from(const pg::Rows& rows, int r) const {
    JobStatus s;
    s.id = rows.text(r, 0);
    s.state = job_state_from_string(rows.text(r, 1)).value_or(JobState::Failed);
    s.progress = s.state == JobState::Done ? 1.0 : rows.real(r, 2);
    s.error = rows.text(r, 3);
    s.created = from_unix_seconds(rows.real(r, 4));
    s.finished = from_unix_seconds(rows.real(r, 5));
    s.cached = rows.boolean(r, 6);
    s.queue_position = static_cast<std::size_t>(rows.integer(r, 7));
    if (is_final(s.state) && options.result_ttl.count() > 0)
      s.expires = s.finished + std::chrono::duration_cast<SystemClock::duration>(options.result_ttl);
    return s;
  }

  std::optional<JobStatus> status_of(pg::Connection& c, const std::string& id) {
    const pg::Rows rows =
        c.exec(std::string("SELECT ") + kStatusColumns + " FROM lambert_jobs j WHERE j.id = $1", {Param::text(id)});
    if (rows.size() == 0) return std::nullopt;
    return status_from(rows, 0);
  }

  void migrate();
  bool mark_cached(pg::Connection& c, const std::string& id, std::int64_t token, const std::string& key);
  bool finish_done(pg::Connection& c, const Claim& claim, const std::string& result);
};

void PgJobStore::Impl::migrate() {
  auto c = pool.lease();
  description = c->describe();
  pg::in_transaction(*c, [&](pg::Connection& t) {
    // One instance at a time creates or migrates; the others wait here and find it done.
    t.exec("SELECT pg_advisory_xact_lock(7478353268)");
    t.exec("CREATE TABLE IF NOT EXISTS lambert_schema (version integer NOT NULL)");
    const pg::Rows rows = t.exec("SELECT version FROM lambert_schema");
    const int version = rows.size() == 0 ? 0 : static_cast<int>(rows.integer(0, 0));
    if (version > kPgSchemaVersion)
      throw std::runtime_error("the store's schema is version " + std::to_string(version) +
                               ", newer than this lambert's (" + std::to_string(kPgSchemaVersion) +
                               "): upgrade lambert");
    for (int v = version; v < kPgSchemaVersion; ++v) t.exec(kMigrations[v]);
    if (rows.size() == 0) t.exec("INSERT INTO lambert_schema (version) VALUES ($1)", {pg::number(std::int64_t{kPgSchemaVersion})});
    else t.exec("UPDATE lambert_schema SET version = $1", {pg::number(std::int64_t{kPgSchemaVersion})});
  });
}

PgJobStore::PgJobStore(PgJobStoreOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {
  impl_->migrate();
}

PgJobStore::~PgJobStore() = default;

std::string PgJobStore::describe() const { return "jobs in PostgreSQL, " + impl_->description; }

std::chrono::milliseconds PgJobStore::renew_interval() const {
  const auto quarter = std::chrono::duration_cast<std::chrono::milliseconds>(impl_->options.lease / 4);
  return std::clamp(quarter, std::chrono::milliseconds(50), std::chrono::milliseconds(5000));
}

// ---- submit and the worker's side -----------------------------------------------------------------

SubmitOutcome PgJobStore::submit(const std::string& scene_json, const std::string& cache_key,
                                 std::size_t queue_limit) {
  Impl& s = *impl_;
  try {
    auto c = s.pool.lease();
    for (int attempt = 0;; ++attempt) {
      const std::string id = JobStore::new_id();
      try {
        if (!cache_key.empty()) {
          // Done on arrival when the result is stored (a concurrent removal of that result makes
          // the foreign key fail: then it is solved like any other).
          try {
            const pg::Rows cached = c->exec(
                "INSERT INTO lambert_jobs (id, state, progress, finished, cache_key, result_key, cached) "
                "SELECT $1, 'done', 1, clock_timestamp(), $2, $2, true "
                "WHERE EXISTS (SELECT 1 FROM lambert_results WHERE key = $2)",
                {Param::text(id), Param::text(cache_key)});
            if (cached.changed() == 1) return *s.status_of(*c, id);
          } catch (const pg::Error& e) {
            if (e.sqlstate() != kForeignKeyViolation) throw;
          }
        }
        // Across instances the count and the insert race; the limit is a bound, not an exact one.
        const pg::Rows queued = c->exec("SELECT count(*) FROM lambert_jobs WHERE state = 'queued'");
        if (static_cast<std::size_t>(queued.integer(0, 0)) >= queue_limit) return QueueFull{queue_limit};
        c->exec("INSERT INTO lambert_jobs (id, state, scene, cache_key) VALUES ($1, 'queued', $2, $3)",
                {Param::text(id), Param::bytes(scene_json), Param::text(cache_key)});
        return *s.status_of(*c, id);
      } catch (const pg::Error& e) {
        if (e.sqlstate() != kUniqueViolation || attempt > 3) throw;  // an id collision: draw again
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "lambert serve: cannot store a job: " << e.what() << "\n";
    return StorageError{"the job could not be stored"};
  }
}

bool PgJobStore::Impl::mark_cached(pg::Connection& c, const std::string& id, std::int64_t token,
                                   const std::string& key) {
  try {
    return c.exec("UPDATE lambert_jobs SET state = 'done', progress = 1, finished = clock_timestamp(), "
                  "result_key = $3, cached = true, scene = NULL, owner = NULL, lease_until = NULL "
                  "WHERE id = $1 AND token = $2 AND state = 'running' "
                  "AND EXISTS (SELECT 1 FROM lambert_results WHERE key = $3)",
                  {Param::text(id), pg::number(token), Param::text(key)})
               .changed() == 1;
  } catch (const pg::Error& e) {
    if (e.sqlstate() == kForeignKeyViolation) return false;  // the result went meanwhile: solve it
    throw;
  }
}

std::optional<Claim> PgJobStore::claim(const std::string& instance) {
  Impl& s = *impl_;
  auto c = s.pool.lease();
  for (;;) {
    // Binary results: the scene comes as its bytes, not as hex text.
    const pg::Rows rows = c->exec(
        "UPDATE lambert_jobs SET state = 'running', token = token + 1, owner = $1, progress = 0, "
        "lease_until = clock_timestamp() + make_interval(secs => $2::float8) "
        "WHERE id = (SELECT id FROM lambert_jobs "
        "            WHERE state = 'queued' OR (state = 'running' AND lease_until < clock_timestamp()) "
        "            ORDER BY seq LIMIT 1 FOR UPDATE SKIP LOCKED) "
        "RETURNING id, token, scene, cache_key, "
        "  cache_key <> '' AND EXISTS (SELECT 1 FROM lambert_results r WHERE r.key = lambert_jobs.cache_key)",
        {Param::text(instance), s.lease_seconds()}, pg::Format::Binary);
    if (rows.size() == 0) return std::nullopt;
    Claim claim{rows.text(0, 0), rows.integer(0, 1), rows.text(0, 2), rows.text(0, 3)};
    // Solved meanwhile under the same key: answered from the store.
    if (rows.boolean(0, 4) && s.mark_cached(*c, claim.id, claim.token, claim.cache_key)) continue;
    return claim;
  }
}

Renewal PgJobStore::renew(const Claim& claim, double progress) {
  Impl& s = *impl_;
  auto c = s.pool.lease();
  const pg::Rows rows = c->exec(
      "UPDATE lambert_jobs SET lease_until = clock_timestamp() + make_interval(secs => $3::float8), "
      "progress = greatest(progress, $4::float8) WHERE id = $1 AND token = $2 AND state = 'running'",
      {Param::text(claim.id), pg::number(claim.token), s.lease_seconds(), pg::number(std::clamp(progress, 0.0, 1.0))});
  return rows.changed() == 1 ? Renewal::Held : Renewal::Lost;
}

bool PgJobStore::Impl::finish_done(pg::Connection& c, const Claim& claim, const std::string& result) {
  const std::string key = claim.cache_key.empty() ? "job:" + claim.id : claim.cache_key;
  return pg::in_transaction(c, [&](pg::Connection& t) {
    const pg::Rows held = t.exec(
        "SELECT 1 FROM lambert_jobs WHERE id = $1 AND token = $2 AND state = 'running' FOR UPDATE",
        {Param::text(claim.id), pg::number(claim.token)});
    if (held.size() == 0) return false;
    // Another instance may have stored the same key's result already: the same bytes, kept once.
    t.exec("INSERT INTO lambert_results (key, result) VALUES ($1, $2) ON CONFLICT (key) DO NOTHING",
           {Param::text(key), Param::bytes(result)});
    t.exec("UPDATE lambert_jobs SET state = 'done', progress = 1, finished = clock_timestamp(), "
           "result_key = $2, scene = NULL, owner = NULL, lease_until = NULL WHERE id = $1",
           {Param::text(claim.id), Param::text(key)});
    return true;
  });
}

bool PgJobStore::finish(const Claim& claim, const JobOutcome& outcome) {
  Impl& s = *impl_;
  auto c = s.pool.lease();
  std::string error = outcome.error;
  if (outcome.result && outcome.result->size() > s.options.max_result_bytes) {
    error = "the result has " + std::to_string(outcome.result->size()) +
            " bytes, more than the PostgreSQL store holds (max_result_bytes = " +
            std::to_string(s.options.max_result_bytes) +
            ", bytea's limit); ask for less output (output.spectral: false, fewer probes)";
  } else if (outcome.result) {
    try {
      return s.finish_done(*c, claim, *outcome.result);
    } catch (const pg::Error& e) {
      // The result row was removed between our insert and the job's update: once more.
      if (e.sqlstate() != kForeignKeyViolation) throw;
      return s.finish_done(*c, claim, *outcome.result);
    }
  }
  return c->exec("UPDATE lambert_jobs SET state = 'failed', error = $3, finished = clock_timestamp(), "
                 "scene = NULL, owner = NULL, lease_until = NULL "
                 "WHERE id = $1 AND token = $2 AND state = 'running'",
                 {Param::text(claim.id), pg::number(claim.token), Param::text(error)})
             .changed() == 1;
}

void PgJobStore::release(const Claim& claim) {
  auto c = impl_->pool.lease();
  c->exec("UPDATE lambert_jobs SET state = 'queued', progress = 0, owner = NULL, lease_until = NULL "
          "WHERE id = $1 AND token = $2 AND state = 'running'",
          {Param::text(claim.id), pg::number(claim.token)});
}

// ---- queries -----------------------------------------------------------------------------------------

std::optional<JobStatus> PgJobStore::status(const std::string& id) {
  auto c = impl_->pool.lease();
  return impl_->status_of(*c, id);
}

ResultLookup PgJobStore::result(const std::string& id) {
  auto c = impl_->pool.lease();
  const auto status = impl_->status_of(*c, id);
  if (!status) return JobNotFound{};
  if (!is_final(status->state)) return JobNotDone{*status};
  if (status->state != JobState::Done) return JobFailed{*status};
  const pg::Rows rows = c->exec(
      "SELECT r.result FROM lambert_jobs j JOIN lambert_results r ON r.key = j.result_key WHERE j.id = $1",
      {Param::text(id)}, pg::Format::Binary);
  if (rows.size() == 0) return JobNotFound{};  // removed or expired meanwhile
  return JobResult{std::make_shared<const std::string>(rows.text(0, 0))};
}

std::shared_ptr<const std::string> PgJobStore::cached_result(const std::string& cache_key) {
  if (cache_key.empty()) return nullptr;
  auto c = impl_->pool.lease();
  const pg::Rows rows = c->exec("SELECT result FROM lambert_results WHERE key = $1", {Param::text(cache_key)},
                                pg::Format::Binary);
  return rows.size() == 0 ? nullptr : std::make_shared<const std::string>(rows.text(0, 0));
}

CancelOutcome PgJobStore::cancel_or_remove(const std::string& id) {
  Impl& s = *impl_;
  auto c = s.pool.lease();
  return pg::in_transaction(*c, [&](pg::Connection& t) -> CancelOutcome {
    const pg::Rows rows = t.exec(std::string("SELECT ") + kStatusColumns +
                                     " FROM lambert_jobs j WHERE j.id = $1 FOR UPDATE OF j",
                                 {Param::text(id)});
    if (rows.size() == 0) return {};
    const JobStatus before = s.status_from(rows, 0);
    if (is_final(before.state)) {
      const std::string result_key = rows.text(0, 8);
      t.exec("DELETE FROM lambert_jobs WHERE id = $1", {Param::text(id)});
      if (!result_key.empty())
        t.exec("DELETE FROM lambert_results r WHERE r.key = $1 AND NOT EXISTS "
               "(SELECT 1 FROM lambert_jobs j WHERE j.result_key = $1)",
               {Param::text(result_key)});
      return {CancelOutcome::Kind::Removed, before};
    }
    // Running elsewhere: its instance finds the claim lost at its next renewal and stops.
    t.exec("UPDATE lambert_jobs SET state = 'cancelled', finished = clock_timestamp(), scene = NULL, "
           "owner = NULL, lease_until = NULL WHERE id = $1",
           {Param::text(id)});
    return {CancelOutcome::Kind::Cancelled, *s.status_of(t, id)};
  });
}

StoreCounts PgJobStore::counts() {
  auto c = impl_->pool.lease();
  const pg::Rows rows = c->exec("SELECT state, count(*) FROM lambert_jobs GROUP BY state");
  StoreCounts counts;
  for (int r = 0; r < rows.size(); ++r) {
    const auto n = static_cast<std::size_t>(rows.integer(r, 1));
    switch (job_state_from_string(rows.text(r, 0)).value_or(JobState::Failed)) {
      case JobState::Queued: counts.queued = n; break;
      case JobState::Running: counts.running = n; break;
      case JobState::Done: counts.done = n; break;
      case JobState::Failed: counts.failed = n; break;
      case JobState::Cancelled: counts.cancelled = n; break;
    }
  }
  return counts;
}

void PgJobStore::sweep_expired() {
  Impl& s = *impl_;
  if (s.options.result_ttl.count() <= 0) return;
  {
    // Every instance sweeps; each at most every 10 s is plenty for a TTL of hours.
    std::lock_guard lock(s.sweep_mutex);
    const auto now = std::chrono::steady_clock::now();
    if (now - s.last_sweep < std::chrono::seconds(10)) return;
    s.last_sweep = now;
  }
  auto c = s.pool.lease();
  pg::in_transaction(*c, [&](pg::Connection& t) {
    t.exec("CREATE TEMP TABLE IF NOT EXISTS lambert_swept (key text) ON COMMIT DELETE ROWS");
    t.exec("WITH gone AS (DELETE FROM lambert_jobs WHERE finished IS NOT NULL "
           "AND finished < clock_timestamp() - make_interval(secs => $1::float8) RETURNING result_key) "
           "INSERT INTO lambert_swept SELECT result_key FROM gone WHERE result_key IS NOT NULL",
           {pg::number(s.options.result_ttl.count())});
    t.exec("DELETE FROM lambert_results r WHERE r.key IN (SELECT key FROM lambert_swept) "
           "AND NOT EXISTS (SELECT 1 FROM lambert_jobs j WHERE j.result_key = r.key)");
  });
}

}  // namespace lambert
