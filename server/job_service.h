// The solves of `lambert serve`: a fixed number of workers that take jobs from a JobStore
// (server/job_store.h) and run each in its own process (server/solve_process.h), under a time limit
// and a memory limit, with progress, cancellation and the claim's renewal, and the synchronous
// POST /v1/solve on the same workers.
//
// At most `workers` scenes are solved at once, by this instance; synchronous solves go first (a
// client is waiting on the connection). Cancellation: a DELETE answered here kills this instance's
// solve of the job at once; a job cancelled through another instance is stopped at the next
// renewal of its claim. The time limit kills the worker process.
//
// Each job's start and end is a structured log line (server/log.h), and each solve's time goes into
// the histogram of GET /v1/metrics (server/metrics.h).
//
// shutdown() stops at once: running solves are killed and their jobs handed back to the queue (a
// durable store runs them again, here after a restart or on another instance). drain() first stops
// taking work and waits for the running solves to finish.
#pragma once

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <variant>

#include "server/job_store.h"
#include "server/metrics.h"
#include "server/solve_process.h"

namespace lambert {

struct JobServiceOptions {
  std::size_t workers = 1;                   // solves at once (>= 1)
  std::size_t queue_size = 64;               // queued jobs beyond which submissions are refused
  std::chrono::duration<double> time_limit = std::chrono::seconds(600);  // per solve; <= 0: none
  SolveLimits limits;                        // mesh root, patch limit, memory limit per solve
  std::filesystem::path worker_executable;   // the lambert binary that runs `solve-worker`
  std::string instance = "local";            // this instance's name in the store
};

// A synchronous solve: the result, or why there is none.
struct SolveFailed { std::string reason; };
using SyncOutcome = std::variant<JobResult, SolveFailed, QueueFull, ShuttingDown>;

class JobService {
 public:
  JobService(std::unique_ptr<JobStore> store, JobServiceOptions options);
  ~JobService();  // shutdown()
  JobService(const JobService&) = delete;
  JobService& operator=(const JobService&) = delete;

  // `scene_json` has been decoded once already (a valid scene); the worker decodes it again.
  SubmitOutcome submit(const std::string& scene_json, const std::string& cache_key);
  // Solves on the workers and waits for the outcome; nothing of it is stored.
  SyncOutcome solve_now(const std::string& scene_json, const std::string& cache_key);

  std::optional<JobStatus> status(const std::string& id);
  ResultLookup result(const std::string& id);
  CancelOutcome cancel_or_remove(const std::string& id);

  struct Counts {
    StoreCounts store;
    std::size_t running_here = 0, sync_running = 0, workers = 0, queue_size = 0;
    bool draining = false;
  };
  Counts counts();
  // The store's counts and this instance's record (the HTTP counters are the server's to add).
  MetricsSnapshot metrics();

  // Stops taking work and waits up to `timeout` for the running solves, then shutdown().
  void drain(std::chrono::duration<double> timeout);
  // Stops taking work, kills the running solves and hands their jobs back. Idempotent.
  void shutdown();

  const JobServiceOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lambert
