// Where the HTTP service keeps its jobs: one interface, two backends.
//   FileJobStore (server/job_store_fs.h)  one machine: in memory, or durable in a data directory
//   PgJobStore   (server/job_store_pg.h)  any number of instances sharing one PostgreSQL database
// The store owns the queue, the job records and the results; server/job_service.h runs the solves.
//
// Life of a job: queued -> running -> done | failed | cancelled. A worker takes a queued job with
// claim(), which hands it a Claim: the job's scene and a fencing token. While it solves it calls
// renew() (PostgreSQL: the lease's heartbeat); renew() answers Lost once the job was cancelled,
// removed, or taken over by another instance after its lease ran out, and the worker then stops.
// finish() records the outcome only if the claim still holds, so a job is finished once, by the
// last worker that claimed it, and a stale worker's result is discarded. release() hands a job back
// to the queue (a server that shuts down without finishing it).
//
// Results are content-addressed: each job carries a cache key (server/cache_key.h); a job submitted
// or claimed while a result for its key is stored is done at once, without a solve.
//
// No HTTP here: server/http_server.cpp maps these outcomes onto status codes.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>

namespace lambert {

enum class JobState { Queued, Running, Done, Failed, Cancelled };
const char* to_string(JobState state);
std::optional<JobState> job_state_from_string(const std::string& text);
inline bool is_final(JobState s) {
  return s == JobState::Done || s == JobState::Failed || s == JobState::Cancelled;
}

// A job's times as the stores keep them (a JSON record, a PostgreSQL double): seconds since 1970.
inline double to_unix_seconds(std::chrono::system_clock::time_point t) {
  return std::chrono::duration<double>(t.time_since_epoch()).count();
}
inline std::chrono::system_clock::time_point from_unix_seconds(double s) {
  return std::chrono::system_clock::time_point(
      std::chrono::duration_cast<std::chrono::system_clock::duration>(std::chrono::duration<double>(s)));
}

struct JobStatus {
  std::string id;
  JobState state = JobState::Queued;
  double progress = 0;                       // 0..1; 1 once done
  std::string error;                         // failed: the reason
  std::chrono::system_clock::time_point created, finished;  // finished: only in a final state
  std::optional<std::chrono::system_clock::time_point> expires;  // finished and a TTL is set
  std::size_t queue_position = 0;            // queued: 1 = next to run
  bool cached = false;                       // done from a stored result, without a solve
};

// What a request about one job can get back.
struct JobNotFound {};
struct JobNotDone { JobStatus status; };                      // queued or running
struct JobFailed { JobStatus status; };                       // failed or cancelled
struct JobResult { std::shared_ptr<const std::string> json; };  // the result document
using ResultLookup = std::variant<JobNotFound, JobNotDone, JobFailed, JobResult>;

struct QueueFull { std::size_t queue_size; };
struct ShuttingDown {};
struct StorageError { std::string message; };
using SubmitOutcome = std::variant<JobStatus, QueueFull, ShuttingDown, StorageError>;

struct CancelOutcome {
  enum class Kind { NotFound, Cancelled, Removed } kind = Kind::NotFound;
  JobStatus status;                          // the job's status after the call
};

// A job taken by a worker. `token` grows with every claim of the job: the fencing token.
struct Claim {
  std::string id;
  std::int64_t token = 0;
  std::string scene_json;
  std::string cache_key;
};

enum class Renewal { Held, Lost };

// How a solve ended, for finish(): a result, or the reason there is none.
struct JobOutcome {
  std::shared_ptr<const std::string> result;  // set: done
  std::string error;                          // failed: the reason, for the client
  bool cancelled = false;                     // stopped by a user's DELETE (already recorded)
};

struct StoreCounts {
  std::size_t queued = 0, running = 0, done = 0, failed = 0, cancelled = 0;
  std::size_t stored() const { return queued + running + done + failed + cancelled; }
};

class JobStore {
 public:
  virtual ~JobStore() = default;

  // Accepts a job (durable before it returns, where the backend is) unless `queue_limit` jobs are
  // already queued. A stored result under `cache_key` makes it done at once (status.cached).
  virtual SubmitOutcome submit(const std::string& scene_json, const std::string& cache_key,
                               std::size_t queue_limit) = 0;
  // The oldest queued job (PostgreSQL: or one whose lease ran out), now running for `instance`.
  virtual std::optional<Claim> claim(const std::string& instance) = 0;
  virtual Renewal renew(const Claim& claim, double progress) = 0;
  // Records the outcome; false when the claim no longer holds (nothing recorded).
  virtual bool finish(const Claim& claim, const JobOutcome& outcome) = 0;
  virtual void release(const Claim& claim) = 0;

  virtual std::optional<JobStatus> status(const std::string& id) = 0;
  virtual ResultLookup result(const std::string& id) = 0;
  // Queued or running: cancelled (and kept, visible as such). Finished: removed with its result.
  virtual CancelOutcome cancel_or_remove(const std::string& id) = 0;
  // The stored result for a cache key, if any.
  virtual std::shared_ptr<const std::string> cached_result(const std::string& cache_key) = 0;
  virtual StoreCounts counts() = 0;
  // Removes finished jobs older than the TTL (and results no job refers to any more).
  virtual void sweep_expired() = 0;

  // How often a running job's claim is renewed, and how often idle workers ask for work that
  // another instance submitted (the local ones are woken at once).
  virtual std::chrono::milliseconds renew_interval() const = 0;
  virtual std::chrono::milliseconds poll_interval() const = 0;
  virtual std::string describe() const = 0;  // for the startup line: "data in DIR", ...

  // A fresh job id: 128 random bits from the OS, as 32 lowercase hex digits.
  static std::string new_id();
  static bool is_valid_id(const std::string& id);
};

}  // namespace lambert
