// The job store that many `lambert serve` instances, on any number of machines, share: one queue
// and one result store in a PostgreSQL database (`lambert serve --store postgresql://...`).
//
//   lambert_schema   one row: the schema's version. Each instance creates or migrates the schema on
//                    start, under an advisory lock, and refuses a database of a newer version.
//   lambert_jobs     one row per job: its state, the scene until it is final, the claim (a fencing
//                    token that grows with each claim, the owning instance and the lease's end), the
//                    cache key, and for a done job the key of its result.
//   lambert_results  the results, as bytea under their key: the scene's cache key
//                    (server/cache_key.h), or "job:<id>" for a scene without one. Jobs answered from
//                    the cache share their result's row; a result goes when no job refers to it.
//
// Claims: the oldest job that is queued, or running under a lease that ran out (its instance died
// or lost the database), is taken with SELECT ... FOR UPDATE SKIP LOCKED, so concurrent instances
// never take the same row; the token grows, and the lease runs `lease` from the database's clock
// (never the instances': their clocks may differ). A worker renews the lease every lease/4, at
// most every 5 s (the heartbeat); a renewal that finds the job cancelled, removed or taken over
// answers Lost, and the worker stops its solve: that is how a DELETE on any instance reaches the one
// that runs the job.
// finish() commits a result only while the job is still running under the worker's token, in one
// transaction with the result's row, so no job is done twice and a stale worker's result is dropped.
//
// Results are bytea, not large objects: a row and its result are written, read and deleted in one
// transaction (large objects need their own clean-up), and PostgreSQL compresses them (TOAST). A
// bytea value holds at most 1 GiB; a larger result fails its job with that limit named.
#pragma once

#include <chrono>
#include <memory>
#include <string>

#include "server/job_store.h"

namespace lambert {

// The largest result the store accepts: bytea's 1 GiB, less room for the row.
constexpr std::size_t kPgMaxResultBytes = (std::size_t{1} << 30) - (std::size_t{1} << 20);

struct PgJobStoreOptions {
  std::string conninfo;  // a libpq connection URI or string: postgresql://user@host:5432/db
  std::chrono::duration<double> result_ttl = std::chrono::hours(24 * 7);  // <= 0: keep forever
  std::chrono::duration<double> lease = std::chrono::seconds(30);  // a dead instance's jobs wait this long
  std::size_t max_connections = 8;  // per instance
  std::size_t max_result_bytes = kPgMaxResultBytes;  // a larger result fails its job, naming this limit
};

// The schema this build writes; older ones are migrated on start.
constexpr int kPgSchemaVersion = 1;

class PgJobStore final : public JobStore {
 public:
  // Connects, creates or migrates the schema; throws std::runtime_error when it cannot.
  explicit PgJobStore(PgJobStoreOptions options);
  ~PgJobStore() override;

  SubmitOutcome submit(const std::string& scene_json, const std::string& cache_key,
                       std::size_t queue_limit) override;
  std::optional<Claim> claim(const std::string& instance) override;
  Renewal renew(const Claim& claim, double progress) override;
  bool finish(const Claim& claim, const JobOutcome& outcome) override;
  void release(const Claim& claim) override;
  std::optional<JobStatus> status(const std::string& id) override;
  ResultLookup result(const std::string& id) override;
  CancelOutcome cancel_or_remove(const std::string& id) override;
  std::shared_ptr<const std::string> cached_result(const std::string& cache_key) override;
  StoreCounts counts() override;
  void sweep_expired() override;
  std::chrono::milliseconds renew_interval() const override;
  std::chrono::milliseconds poll_interval() const override { return std::chrono::milliseconds(500); }
  std::string describe() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// True when `store` names a PostgreSQL database (postgresql:// or postgres://).
bool is_postgresql_uri(const std::string& store);

}  // namespace lambert
