// Solve jobs for the HTTP service: a bounded queue, a fixed pool of solver workers, a per-job time
// limit, progress, cancellation, and durable results.
//
// Life of a job: queued -> running -> done | failed | cancelled. Every solve (asynchronous jobs and
// the synchronous POST /v1/solve alike) runs on one of the `workers` threads, never on an HTTP
// thread, so at most `workers` scenes are solved at once and a huge scene holds one worker, not the
// service. Each worker solves inside its own TBB arena, so the solver's parallel loops of one job
// never run another job's tasks. Cancellation and the time limit both go through the solver's cancel
// token (checked between work items); a watchdog thread raises the token when a job's time is up.
//
// With a data directory, a job is durable from the moment it is accepted:
//   <data_dir>/jobs/<id>.scene.json   the scene, written before submit() returns; removed when the
//                                     job reaches a final state
//   <data_dir>/jobs/<id>.result.json  the result of a done job
//   <data_dir>/jobs/<id>.job.json     the final state (done, failed with its reason, cancelled),
//                                     written last: it is the commit record of a finished job
// Every file is written to a temporary name, flushed and renamed, so a crash leaves either the old
// state or the new one. On start the directory is read back: finished jobs are served again (until
// they expire) and jobs that were accepted but not finished are queued again.
//
// No HTTP here: server/http_server.cpp maps these outcomes onto status codes.
#pragma once

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "server/scene_codec.h"
#include "solver/scene.h"

namespace lambert {

enum class JobState { Queued, Running, Done, Failed, Cancelled };
const char* to_string(JobState state);

struct JobStoreOptions {
  std::size_t workers = 1;                   // solver threads (>= 1)
  std::size_t queue_size = 64;               // jobs waiting for a worker, beyond which submit refuses
  std::chrono::duration<double> time_limit = std::chrono::seconds(600);  // per solve, running time
  std::size_t max_patches = 0;               // passed to the solver; 0: the solver's own limit only
  std::optional<std::filesystem::path> data_dir;  // none: results live in memory only
  std::chrono::duration<double> result_ttl = std::chrono::hours(24 * 7);  // <= 0: keep forever
  FileAccess files;                          // how scenes re-read from data_dir resolve "file"
};

struct JobStatus {
  std::string id;
  JobState state = JobState::Queued;
  double progress = 0;                       // 0..1; 1 once done
  std::string error;                         // failed: the reason
  std::chrono::system_clock::time_point created, finished;  // finished: only in a final state
  std::optional<std::chrono::system_clock::time_point> expires;  // finished and a TTL is set
  std::size_t queue_position = 0;            // queued: 1 = next to run
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

// A synchronous solve: the result, or why there is none.
struct SolveFailed { std::string reason; };
using SyncOutcome = std::variant<JobResult, SolveFailed, QueueFull, ShuttingDown>;

struct CancelOutcome {
  enum class Kind { NotFound, Cancelled, Removed } kind = Kind::NotFound;
  JobStatus status;                          // the job's status after the call
};

class JobStore {
 public:
  // Starts the workers and the watchdog. With a data_dir, creates it if needed and reloads it;
  // throws std::runtime_error when it cannot be used.
  explicit JobStore(JobStoreOptions options);
  ~JobStore();  // shutdown()
  JobStore(const JobStore&) = delete;
  JobStore& operator=(const JobStore&) = delete;

  // Queues a decoded scene; `scene_json` is what gets persisted (and decoded again after a restart).
  SubmitOutcome submit(Scene scene, const std::string& scene_json);

  // Solves on the worker pool (same queue, limits and time limit) and waits for the outcome.
  // Nothing of it is stored.
  SyncOutcome solve_now(Scene scene);

  std::optional<JobStatus> status(const std::string& id) const;
  ResultLookup result(const std::string& id) const;

  // Queued or running: cancels (promptly: a running solve stops at its next check of the token)
  // and the job stays visible as "cancelled". Already finished: removes the job and its files.
  CancelOutcome cancel_or_remove(const std::string& id);

  struct Counts { std::size_t queued = 0, running = 0, stored = 0, workers = 0, queue_size = 0; };
  Counts counts() const;

  // Stops taking work, raises every running job's cancel token and joins the threads. Jobs that did
  // not finish stay in data_dir (if any) and run again after a restart. Idempotent.
  void shutdown();

  // A fresh job id: 128 random bits from the OS, as 32 lowercase hex digits.
  static std::string new_id();
  static bool is_valid_id(const std::string& id);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lambert
