// The workers of `lambert serve` (see job_service.h).
//
// One mutex guards the synchronous queue, the table of running solves and the stop flags. Each
// worker thread owns its solve from claim to finish: it waits on the worker process's output in
// short steps, and between them checks cancellation, the time limit and shutdown, and renews the
// claim. The store is called without the mutex held (PostgreSQL: a network round trip).
#include "server/job_service.h"

#include <algorithm>
#include <csignal>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <iostream>
#include <map>
#include <mutex>
#include <shared_mutex>
#include <thread>
#include <vector>

#include "server/log.h"

namespace lambert {
namespace {

using SteadyClock = std::chrono::steady_clock;
using namespace std::chrono_literals;

constexpr auto kWaitStep = 50ms;           // how often a worker looks up from its solve
constexpr auto kSweepInterval = 1s;        // expiry of finished jobs

enum class Stop { None, Cancelled, TimeLimit, Lost, Shutdown };

struct SyncJob {
  std::string scene_json;
  bool finished = false;
  SyncOutcome outcome = ShuttingDown{};
};

// A solve in progress on this instance.
struct Running {
  std::string id;                 // "" for a synchronous solve
  std::atomic<bool> cancel{false};
};

std::string seconds_text(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", s);
  return buf;
}

std::string mebibytes(std::uint64_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f MiB", static_cast<double>(bytes) / (1 << 20));
  return buf;
}

}  // namespace

struct JobService::Impl {
  Impl(std::unique_ptr<JobStore> s, JobServiceOptions o) : store(std::move(s)), options(std::move(o)) {}

  std::unique_ptr<JobStore> store;
  JobServiceOptions options;

  std::mutex mutex;
  // A submission's "queued" line comes before the "running" line of a worker that claims the job:
  // a submission holds this shared from its store call to its log line, and a worker takes it alone
  // to log "running" (a worker polling the store can claim the job before the submitter has logged).
  std::shared_mutex log_order;
  std::condition_variable work_cv;   // workers: new work here, or stopping
  std::condition_variable done_cv;   // solve_now and drain: a solve ended
  std::deque<std::shared_ptr<SyncJob>> sync_queue;
  std::map<Running*, std::shared_ptr<Running>> running;
  std::uint64_t submissions = 0;     // grows with each local submission: wakes an idle worker
  bool draining = false, stopping = false;
  std::map<std::string, Histogram> solve_seconds;  // by outcome: done, failed
  std::uint64_t submitted = 0, cache_hits = 0;
  std::vector<std::thread> workers;
  std::thread sweeper;

  void worker_loop();
  void sweep_loop();
  // What a worker does next: a synchronous solve, a claimed job, or stop (neither).
  struct Work { std::shared_ptr<SyncJob> sync; std::optional<Claim> claim; };
  Work next_work();
  struct Ended { SolveProcessOutcome outcome; Stop stop = Stop::None; double progress = 0; };
  Ended solve(const std::string& scene_json, const Claim* claim, Running& entry);
  std::string failure_text(const Ended& e) const;
  void run_claim(const Claim& claim);
  void run_sync(SyncJob& job);
  void record_solve(const char* outcome, double seconds) {
    std::lock_guard lock(mutex);
    solve_seconds[outcome].observe(seconds);
  }
};

JobService::JobService(std::unique_ptr<JobStore> store, JobServiceOptions options)
    : impl_(std::make_unique<Impl>(std::move(store), std::move(options))) {
  Impl& s = *impl_;
  s.options.workers = std::max<std::size_t>(1, s.options.workers);
  for (std::size_t k = 0; k < s.options.workers; ++k) s.workers.emplace_back([&s] { s.worker_loop(); });
  s.sweeper = std::thread([&s] { s.sweep_loop(); });
}

JobService::~JobService() { shutdown(); }

const JobServiceOptions& JobService::options() const { return impl_->options; }

void JobService::shutdown() {
  Impl& s = *impl_;
  {
    std::lock_guard lock(s.mutex);
    if (s.stopping && s.workers.empty()) return;
    s.stopping = s.draining = true;
    // Synchronous solves still waiting will never run: release their callers.
    for (const auto& job : s.sync_queue) job->finished = true;
    s.sync_queue.clear();
  }
  s.work_cv.notify_all();
  s.done_cv.notify_all();
  for (auto& t : s.workers) t.join();
  s.workers.clear();
  if (s.sweeper.joinable()) s.sweeper.join();
}

void JobService::drain(std::chrono::duration<double> timeout) {
  Impl& s = *impl_;
  {
    std::unique_lock lock(s.mutex);
    s.draining = true;
    s.done_cv.wait_for(lock, timeout, [&] { return s.running.empty() || s.stopping; });
  }
  shutdown();
}

// ---- submissions and queries ------------------------------------------------------------------

SubmitOutcome JobService::submit(const std::string& scene_json, const std::string& cache_key) {
  Impl& s = *impl_;
  {
    std::lock_guard lock(s.mutex);
    if (s.draining) return ShuttingDown{};
  }
  std::shared_lock order(s.log_order);
  SubmitOutcome out = s.store->submit(scene_json, cache_key, s.options.queue_size);
  const auto* status = std::get_if<JobStatus>(&out);
  {
    std::lock_guard lock(s.mutex);
    ++s.submissions;
    if (status) ++s.submitted;
    if (status && status->cached) ++s.cache_hits;
  }
  if (status)
    log_json({{"event", "job"}, {"id", status->id}, {"state", to_string(status->state)},
              {"cached", status->cached}, {"instance", s.options.instance}});
  order.unlock();
  s.work_cv.notify_one();
  return out;
}

SyncOutcome JobService::solve_now(const std::string& scene_json, const std::string& cache_key) {
  Impl& s = *impl_;
  if (auto cached = cache_key.empty() ? nullptr : s.store->cached_result(cache_key)) {
    std::lock_guard lock(s.mutex);
    ++s.cache_hits;
    return JobResult{std::move(cached)};
  }
  const std::size_t queued = s.store->counts().queued;
  auto job = std::make_shared<SyncJob>();
  job->scene_json = scene_json;
  std::unique_lock lock(s.mutex);
  if (s.draining) return ShuttingDown{};
  if (queued + s.sync_queue.size() >= s.options.queue_size) return QueueFull{s.options.queue_size};
  s.sync_queue.push_back(job);
  s.work_cv.notify_one();
  // The time limit bounds the solve, so this wait ends.
  s.done_cv.wait(lock, [&] { return job->finished; });
  return job->outcome;
}

std::optional<JobStatus> JobService::status(const std::string& id) { return impl_->store->status(id); }
ResultLookup JobService::result(const std::string& id) { return impl_->store->result(id); }

CancelOutcome JobService::cancel_or_remove(const std::string& id) {
  Impl& s = *impl_;
  CancelOutcome out = s.store->cancel_or_remove(id);
  if (out.kind == CancelOutcome::Kind::Cancelled) {
    // Running here: stop it now rather than at the next renewal.
    std::lock_guard lock(s.mutex);
    for (auto& [key, entry] : s.running)
      if (entry->id == id) entry->cancel = true;
  }
  return out;
}

JobService::Counts JobService::counts() {
  Impl& s = *impl_;
  Counts c;
  c.store = s.store->counts();
  std::lock_guard lock(s.mutex);
  c.running_here = s.running.size();
  for (const auto& [key, entry] : s.running) c.sync_running += entry->id.empty();
  c.workers = s.options.workers;
  c.queue_size = s.options.queue_size;
  c.draining = s.draining;
  return c;
}

MetricsSnapshot JobService::metrics() {
  Impl& s = *impl_;
  MetricsSnapshot m;
  m.jobs = s.store->counts();
  std::lock_guard lock(s.mutex);
  m.running_here = s.running.size();
  m.workers = s.options.workers;
  m.draining = s.draining;
  m.solve_seconds = s.solve_seconds;
  m.submitted = s.submitted;
  m.cache_hits = s.cache_hits;
  return m;
}

// ---- the workers ----------------------------------------------------------------------------------

JobService::Impl::Work JobService::Impl::next_work() {
  std::unique_lock lock(mutex);
  for (;;) {
    if (stopping) return {};
    if (!sync_queue.empty()) {
      Work w{std::move(sync_queue.front()), std::nullopt};
      sync_queue.pop_front();
      return w;
    }
    const std::uint64_t seen = submissions;
    if (!draining) {
      lock.unlock();
      std::optional<Claim> claim;
      try {
        claim = store->claim(options.instance);
      } catch (const std::exception& e) {
        std::cerr << "lambert serve: cannot take a job from the store: " << e.what() << "\n";
      }
      lock.lock();
      if (claim) {
        if (!stopping) return {nullptr, std::move(claim)};
        lock.unlock();
        store->release(*claim);
        return {};
      }
    }
    work_cv.wait_for(lock, store->poll_interval(),
                     [&] { return stopping || !sync_queue.empty() || submissions != seen; });
  }
}

void JobService::Impl::worker_loop() {
  for (;;) {
    Work w = next_work();
    if (w.sync) run_sync(*w.sync);
    else if (w.claim) run_claim(*w.claim);
    else return;
  }
}

void JobService::Impl::sweep_loop() {
  std::unique_lock lock(mutex);
  while (!stopping) {
    work_cv.wait_for(lock, kSweepInterval, [&] { return stopping; });
    if (stopping) break;
    lock.unlock();
    try {
      store->sweep_expired();
    } catch (const std::exception& e) {
      std::cerr << "lambert serve: cannot remove expired jobs: " << e.what() << "\n";
    }
    lock.lock();
  }
}

// Runs one scene in a worker process until it ends or must stop.
JobService::Impl::Ended JobService::Impl::solve(const std::string& scene_json, const Claim* claim,
                                                Running& entry) {
  Ended ended;
  std::optional<SolveProcess> process;
  try {
    process.emplace(options.worker_executable, scene_json, options.limits);
  } catch (const std::exception& e) {
    std::cerr << "lambert serve: " << e.what() << "\n";
    ended.outcome.kind = SolveProcessOutcome::Kind::Internal;
    ended.outcome.reason = e.what();
    return ended;
  }
  const std::string tag = claim ? "job " + claim->id : std::string("synchronous solve");
  const auto on_stderr = [&](const std::string& line) {
    std::cerr << "lambert serve: " << tag << ": worker: " << line << "\n";
  };
  const auto start = SteadyClock::now();
  auto last_renewal = start;
  while (process->wait(kWaitStep, on_stderr)) {
    if (ended.stop != Stop::None) continue;  // killed: reap it
    const auto now = SteadyClock::now();
    bool shutting_down;
    {
      std::lock_guard lock(mutex);
      shutting_down = stopping;
    }
    Stop stop = Stop::None;
    if (entry.cancel) stop = Stop::Cancelled;
    else if (options.time_limit.count() > 0 && now - start > options.time_limit) stop = Stop::TimeLimit;
    else if (shutting_down) stop = Stop::Shutdown;
    else if (claim && now - last_renewal >= store->renew_interval()) {
      last_renewal = now;
      try {
        if (store->renew(*claim, process->progress()) == Renewal::Lost) stop = Stop::Lost;
      } catch (const std::exception& e) {
        // The store is unreachable: go on; finish() decides whether the claim still holds.
        std::cerr << "lambert serve: " << tag << ": cannot renew the claim: " << e.what() << "\n";
      }
    }
    if (stop != Stop::None) {
      ended.stop = stop;
      process->kill();
    }
  }
  ended.progress = process->progress();
  ended.outcome = process->outcome();
  return ended;
}

std::string JobService::Impl::failure_text(const Ended& e) const {
  using Kind = SolveProcessOutcome::Kind;
  const std::string advice = "; use a larger meshing.max_patch_area";
  if (e.stop == Stop::TimeLimit)
    return "the solve exceeded the time limit of " + seconds_text(options.time_limit.count()) +
           " s and was stopped at " + std::to_string(static_cast<int>(e.progress * 100)) + " % progress" + advice;
  switch (e.outcome.kind) {
    case Kind::Failed: return e.outcome.reason;
    case Kind::OutOfMemory:
      return options.limits.memory_bytes
                 ? "the solve ran out of memory (its limit is " + mebibytes(options.limits.memory_bytes) +
                       ", --job-memory-limit)" + advice
                 : "the solve ran out of memory" + advice;
    case Kind::Crashed:
      if (e.outcome.signal == SIGKILL)
        return "the solve process was killed (SIGKILL), most likely by the system's out-of-memory killer" + advice;
      return e.outcome.reason == "" ? "the solve process crashed" : e.outcome.reason + "; the server is unaffected";
    case Kind::Internal: return "internal error while solving (details are in the server log)";
    case Kind::Done: case Kind::Killed: break;
  }
  return "the solve was stopped";
}

void JobService::Impl::run_claim(const Claim& claim) {
  auto entry = std::make_shared<Running>();
  entry->id = claim.id;
  {
    std::lock_guard lock(mutex);
    running.emplace(entry.get(), entry);
  }
  {
    std::unique_lock order(log_order);
    log_json({{"event", "job"}, {"id", claim.id}, {"state", "running"}, {"attempt", claim.token},
              {"instance", options.instance}});
  }
  const auto start = SteadyClock::now();
  const Ended ended = solve(claim.scene_json, &claim, *entry);
  const double seconds = std::chrono::duration<double>(SteadyClock::now() - start).count();
  if (ended.outcome.kind == SolveProcessOutcome::Kind::Internal)
    std::cerr << "lambert serve: job " << claim.id << " failed: " << ended.outcome.reason << "\n";
  // What became of the job: done, failed, released (back to the queue), cancelled, lost (taken
  // over or removed), or unrecorded (the store could not be reached: the lease runs out and another
  // worker takes the job up).
  nlohmann::json line = {{"event", "job"}, {"id", claim.id}, {"instance", options.instance},
                         {"attempt", claim.token}, {"solve_s", seconds}};
  try {
    if (ended.stop == Stop::Shutdown) {
      store->release(claim);  // not final: it runs again, here after a restart or elsewhere
      line["state"] = "released";
    } else if (ended.stop == Stop::Cancelled || ended.stop == Stop::Lost) {
      line["state"] = ended.stop == Stop::Cancelled ? "cancelled" : "lost";
    } else {
      JobOutcome outcome;
      if (ended.outcome.kind == SolveProcessOutcome::Kind::Done && ended.stop == Stop::None)
        outcome.result = std::make_shared<const std::string>(std::move(ended.outcome.result));
      else
        outcome.error = failure_text(ended);
      const bool recorded = store->finish(claim, outcome);  // false: cancelled or taken over meanwhile
      line["state"] = !recorded ? "lost" : outcome.result ? "done" : "failed";
      if (recorded && !outcome.result) line["error"] = outcome.error;
      record_solve(outcome.result ? "done" : "failed", seconds);
    }
  } catch (const std::exception& e) {
    std::cerr << "lambert serve: job " << claim.id << ": cannot record its outcome: " << e.what() << "\n";
    line["state"] = "unrecorded";
  }
  log_json(line);
  {
    std::lock_guard lock(mutex);
    running.erase(entry.get());
  }
  done_cv.notify_all();
}

void JobService::Impl::run_sync(SyncJob& job) {
  auto entry = std::make_shared<Running>();
  {
    std::lock_guard lock(mutex);
    running.emplace(entry.get(), entry);
  }
  const auto start = SteadyClock::now();
  Ended ended = solve(job.scene_json, nullptr, *entry);
  const double seconds = std::chrono::duration<double>(SteadyClock::now() - start).count();
  if (ended.outcome.kind == SolveProcessOutcome::Kind::Internal)
    std::cerr << "lambert serve: synchronous solve failed: " << ended.outcome.reason << "\n";
  if (ended.stop != Stop::Shutdown) {
    const bool done = ended.outcome.kind == SolveProcessOutcome::Kind::Done && ended.stop == Stop::None;
    record_solve(done ? "done" : "failed", seconds);
    log_json({{"event", "solve"}, {"state", done ? "done" : "failed"}, {"solve_s", seconds},
              {"instance", options.instance}});
  }
  std::lock_guard lock(mutex);
  running.erase(entry.get());
  if (ended.stop == Stop::Shutdown) job.outcome = ShuttingDown{};
  else if (ended.outcome.kind == SolveProcessOutcome::Kind::Done && ended.stop == Stop::None)
    job.outcome = JobResult{std::make_shared<const std::string>(std::move(ended.outcome.result))};
  else job.outcome = SolveFailed{failure_text(ended)};
  job.finished = true;
  done_cv.notify_all();
}

}  // namespace lambert
