// Jobs for the HTTP service (see job_store.h for the life of a job and the data directory's layout).
//
// One mutex guards the job table, the queue and every job's state; the solver runs without it and
// talks to its job only through two atomics (progress and the cancel token). Result files, which can
// be large, are written outside the lock; the small commit record (<id>.job.json) is written under
// it, so that a job's files and its state in memory never disagree about whether it was removed.
#include "server/job_store.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <deque>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <new>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>

#include "server/result_codec.h"
#include "solver/radiosity.h"
#include "solver/report.h"

namespace lambert {

const char* to_string(JobState state) {
  switch (state) {
    case JobState::Queued: return "queued";
    case JobState::Running: return "running";
    case JobState::Done: return "done";
    case JobState::Failed: return "failed";
    case JobState::Cancelled: return "cancelled";
  }
  return "unknown";
}

namespace {

namespace fs = std::filesystem;
using SystemClock = std::chrono::system_clock;
using SteadyClock = std::chrono::steady_clock;
using json = nlohmann::json;

constexpr auto kWatchdogTick = std::chrono::milliseconds(50);
constexpr auto kExpirySweepInterval = std::chrono::seconds(1);

bool is_final(JobState s) {
  return s == JobState::Done || s == JobState::Failed || s == JobState::Cancelled;
}

std::optional<JobState> state_from_string(const std::string& s) {
  for (JobState state : {JobState::Queued, JobState::Running, JobState::Done, JobState::Failed,
                         JobState::Cancelled})
    if (s == to_string(state)) return state;
  return std::nullopt;
}

double to_unix_seconds(SystemClock::time_point t) {
  return std::chrono::duration<double>(t.time_since_epoch()).count();
}
SystemClock::time_point from_unix_seconds(double s) {
  return SystemClock::time_point(
      std::chrono::duration_cast<SystemClock::duration>(std::chrono::duration<double>(s)));
}

std::string errno_text(int err) { return std::strerror(err); }

// Writes `content` to `path` so that readers see the old file or the complete new one: a temporary
// file beside it, fsync, rename over, fsync of the directory. Throws std::runtime_error.
void write_file_atomically(const fs::path& path, const std::string& content) {
  const fs::path tmp = path.string() + "." + JobStore::new_id().substr(0, 8) + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) throw std::runtime_error("cannot create " + tmp.string() + ": " + errno_text(errno));
  const char* data = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, data, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = errno;
      ::close(fd);
      ::unlink(tmp.c_str());
      throw std::runtime_error("cannot write " + tmp.string() + ": " + errno_text(err));
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw std::runtime_error("cannot flush " + tmp.string() + ": " + errno_text(err));
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw std::runtime_error("cannot rename " + tmp.string() + ": " + errno_text(err));
  }
  const int dir = ::open(path.parent_path().c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
}

std::optional<std::string> read_whole_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) return std::nullopt;
  return s.str();
}

void remove_quietly(const fs::path& path) {
  std::error_code ec;
  fs::remove(path, ec);
}

std::string seconds_text(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", s);
  return buf;
}

}  // namespace

// ---- the job ----------------------------------------------------------------------------------

namespace {

enum class StopReason { None, User, TimeLimit, Shutdown };

struct Job {
  std::string id;
  bool stored = true;                  // false: a synchronous solve (no id visible, nothing persisted)
  std::shared_ptr<const Scene> scene;  // released once the job is final
  // Guarded by Impl::mutex:
  JobState state = JobState::Queued;
  StopReason stop = StopReason::None;
  std::string error;
  SystemClock::time_point created, finished;
  SteadyClock::time_point started;
  std::shared_ptr<const std::string> result;  // in memory: sync solves and stores without data_dir
  bool result_on_disk = false;
  bool removed = false;
  // Shared with the solver's threads:
  std::atomic<double> progress{0};
  std::atomic<bool> cancel{false};
};

}  // namespace

struct JobStore::Impl {
  explicit Impl(JobStoreOptions o) : options(std::move(o)) {}
  ~Impl() {
    if (lock_fd >= 0) ::close(lock_fd);
  }

  JobStoreOptions options;
  std::optional<fs::path> jobs_dir;

  mutable std::mutex mutex;
  std::condition_variable work_cv;      // workers: the queue has work, or stopping
  std::condition_variable done_cv;      // solve_now: a job became final
  std::condition_variable watchdog_cv;  // watchdog: stopping
  std::map<std::string, std::shared_ptr<Job>> jobs;  // stored jobs by id
  std::deque<std::shared_ptr<Job>> queue;
  std::vector<std::shared_ptr<Job>> running;
  bool stopping = false;
  std::vector<std::thread> workers;
  std::thread watchdog;
  int lock_fd = -1;  // flock on <data_dir>/jobs/.lock: one server per data directory

  fs::path scene_path(const std::string& id) const { return *jobs_dir / (id + ".scene.json"); }
  fs::path result_path(const std::string& id) const { return *jobs_dir / (id + ".result.json"); }
  fs::path record_path(const std::string& id) const { return *jobs_dir / (id + ".job.json"); }

  std::optional<SystemClock::time_point> expiry(const Job& job) const {
    if (!is_final(job.state) || options.result_ttl.count() <= 0) return std::nullopt;
    return job.finished + std::chrono::duration_cast<SystemClock::duration>(options.result_ttl);
  }

  JobStatus status_locked(const Job& job) const {
    JobStatus s;
    s.id = job.id;
    s.state = job.state;
    s.progress = job.state == JobState::Done ? 1.0 : job.progress.load(std::memory_order_relaxed);
    s.error = job.error;
    s.created = job.created;
    s.finished = job.finished;
    s.expires = expiry(job);
    if (job.state == JobState::Queued) {
      const auto it = std::find_if(queue.begin(), queue.end(),
                                   [&](const auto& q) { return q.get() == &job; });
      s.queue_position = it == queue.end() ? 0 : static_cast<std::size_t>(it - queue.begin()) + 1;
    }
    return s;
  }

  // The commit record of a final job; replaces the scene file. Logged, not thrown: the state in
  // memory is right even when the disk is not, and the next restart re-runs the job.
  void persist_final_locked(const Job& job) {
    if (!jobs_dir || !job.stored || job.removed) return;
    json record = {{"id", job.id},
                   {"state", to_string(job.state)},
                   {"created", to_unix_seconds(job.created)},
                   {"finished", to_unix_seconds(job.finished)}};
    if (!job.error.empty()) record["error"] = job.error;
    try {
      write_file_atomically(record_path(job.id),
                            record.dump(1, ' ', false, json::error_handler_t::replace) + "\n");
      remove_quietly(scene_path(job.id));
    } catch (const std::exception& e) {
      std::cerr << "lambert serve: job " << job.id << ": " << e.what() << "\n";
    }
  }

  void remove_files_locked(const std::string& id) {
    if (!jobs_dir) return;
    remove_quietly(record_path(id));
    remove_quietly(result_path(id));
    remove_quietly(scene_path(id));
  }

  void worker_loop();
  void run(const std::shared_ptr<Job>& job, tbb::task_arena& arena);
  void watchdog_loop();
  void sweep_expired_locked();
  void reload();
  std::string unused_id_locked() const;
};

// ---- construction, reload, shutdown -------------------------------------------------------------

JobStore::JobStore(JobStoreOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {
  Impl& s = *impl_;
  s.options.workers = std::max<std::size_t>(1, s.options.workers);
  if (s.options.data_dir) {
    const fs::path dir = *s.options.data_dir / "jobs";
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
      throw std::runtime_error("cannot use data directory " + dir.string() + ": " + ec.message());
    // Two servers on one directory would run and delete each other's jobs.
    s.lock_fd = ::open((dir / ".lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
    if (s.lock_fd < 0 || ::flock(s.lock_fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      if (s.lock_fd >= 0) ::close(s.lock_fd);
      s.lock_fd = -1;
      throw std::runtime_error("data directory " + dir.string() +
                               (err == EWOULDBLOCK ? " is in use by another lambert serve"
                                                   : ": " + errno_text(err)));
    }
    // A probe write: a read-only or full directory is a startup error, not a lost result later.
    const fs::path probe = dir / ".write-test";
    write_file_atomically(probe, "ok\n");
    remove_quietly(probe);
    s.jobs_dir = dir;
    s.reload();
  }
  for (std::size_t k = 0; k < s.options.workers; ++k) s.workers.emplace_back([&s] { s.worker_loop(); });
  s.watchdog = std::thread([&s] { s.watchdog_loop(); });
}

JobStore::~JobStore() { shutdown(); }

void JobStore::shutdown() {
  Impl& s = *impl_;
  {
    std::lock_guard lock(s.mutex);
    if (s.stopping && s.workers.empty()) return;
    s.stopping = true;
    for (const auto& job : s.running) {
      if (job->stop == StopReason::None) job->stop = StopReason::Shutdown;
      job->cancel = true;
    }
    // Synchronous solves still waiting will never run: release their callers.
    for (const auto& job : s.queue)
      if (!job->stored) {
        job->state = JobState::Failed;
        job->stop = StopReason::Shutdown;
      }
  }
  s.work_cv.notify_all();
  s.watchdog_cv.notify_all();
  s.done_cv.notify_all();
  for (auto& t : s.workers) t.join();
  s.workers.clear();
  if (s.watchdog.joinable()) s.watchdog.join();
  if (s.lock_fd >= 0) {
    ::close(s.lock_fd);  // releases the flock
    s.lock_fd = -1;
  }
}

// Reads the data directory back (see job_store.h). Runs before the workers start.
void JobStore::Impl::reload() {
  struct Files { bool record = false, result = false, scene = false; };
  std::map<std::string, Files> found;
  for (const auto& entry : fs::directory_iterator(*jobs_dir)) {
    const std::string name = entry.path().filename().string();
    if (name.size() > 4 && name.ends_with(".tmp")) {  // an interrupted write
      remove_quietly(entry.path());
      continue;
    }
    const auto dot = name.find('.');
    if (dot == std::string::npos) continue;
    const std::string id = name.substr(0, dot), kind = name.substr(dot);
    if (!JobStore::is_valid_id(id)) continue;
    if (kind == ".job.json") found[id].record = true;
    else if (kind == ".result.json") found[id].result = true;
    else if (kind == ".scene.json") found[id].scene = true;
  }
  const auto now = SystemClock::now();
  std::vector<std::shared_ptr<Job>> requeued;
  for (const auto& [id, files] : found) {
    auto job = std::make_shared<Job>();
    job->id = id;
    if (files.record) {
      json record;
      try {
        const auto text = read_whole_file(record_path(id));
        record = json::parse(text.value_or(""));
        const auto state = state_from_string(record.at("state").get<std::string>());
        if (record.at("id").get<std::string>() != id || !state || !is_final(*state))
          throw std::runtime_error("inconsistent record");
        job->state = *state;
        job->created = from_unix_seconds(record.at("created").get<double>());
        job->finished = from_unix_seconds(record.at("finished").get<double>());
        job->error = record.value("error", std::string());
      } catch (const std::exception& e) {
        std::cerr << "lambert serve: ignoring unreadable job record " << record_path(id) << ": "
                  << e.what() << "\n";
        continue;
      }
      if (files.scene) remove_quietly(scene_path(id));  // crashed between commit and clean-up
      if (const auto exp = expiry(*job); exp && *exp <= now) {
        remove_files_locked(id);
        continue;
      }
      if (job->state == JobState::Done) {
        if (files.result) {
          job->result_on_disk = true;
          job->progress = 1;
        } else {
          job->state = JobState::Failed;
          job->error = "the stored result of this job was lost";
        }
      } else if (files.result) {
        remove_quietly(result_path(id));
      }
      jobs.emplace(id, std::move(job));
      continue;
    }
    if (!files.scene) {  // a result without its commit record, and nothing to re-run: debris
      remove_quietly(result_path(id));
      continue;
    }
    // Accepted but never finished: decode again and queue it.
    std::error_code ec;
    const auto mtime = fs::last_write_time(scene_path(id), ec);
    job->created = ec ? now : std::chrono::file_clock::to_sys(mtime);
    const auto text = read_whole_file(scene_path(id));
    DecodeResult decoded = decode_scene(text.value_or(""), options.files);
    if (!decoded.ok()) {
      job->state = JobState::Failed;
      job->error = "the scene stored for this job no longer decodes: " +
                   (decoded.errors.empty() ? std::string("unreadable")
                                           : decoded.errors.front().pointer + ": " +
                                                 decoded.errors.front().message);
      job->finished = now;
      persist_final_locked(*job);
      jobs.emplace(id, std::move(job));
      continue;
    }
    job->scene = std::make_shared<const Scene>(std::move(*decoded.scene));
    requeued.push_back(job);
    jobs.emplace(id, std::move(job));
  }
  // Oldest first, as they were accepted.
  std::sort(requeued.begin(), requeued.end(),
            [](const auto& a, const auto& b) { return a->created < b->created; });
  for (auto& job : requeued) queue.push_back(std::move(job));
  if (!found.empty())
    std::cerr << "lambert serve: reloaded " << jobs.size() << " jobs from " << jobs_dir->string()
              << " (" << queue.size() << " queued again)\n";
}

// ---- ids ----------------------------------------------------------------------------------------

std::string JobStore::new_id() {
  unsigned char bytes[16];
  std::size_t got = 0;
  while (got < sizeof bytes) {
    const ssize_t n = ::getrandom(bytes + got, sizeof bytes - got, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    got += static_cast<std::size_t>(n);
  }
  if (got < sizeof bytes) {  // no getrandom: the library's non-deterministic source
    std::random_device rd;
    for (auto& b : bytes) b = static_cast<unsigned char>(rd());
  }
  static constexpr char kHex[] = "0123456789abcdef";
  std::string id(32, '0');
  for (std::size_t k = 0; k < 16; ++k) {
    id[2 * k] = kHex[bytes[k] >> 4];
    id[2 * k + 1] = kHex[bytes[k] & 15];
  }
  return id;
}

bool JobStore::is_valid_id(const std::string& id) {
  return id.size() == 32 && std::all_of(id.begin(), id.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

// 2^-128 per pair makes a collision absurd; checking costs nothing and makes "never reused" a fact
// for the ids this store knows about (including removed ones that left files behind).
std::string JobStore::Impl::unused_id_locked() const {
  for (;;) {
    std::string id = JobStore::new_id();
    if (jobs.count(id)) continue;
    if (jobs_dir) {
      std::error_code ec;
      if (fs::exists(scene_path(id), ec) || fs::exists(record_path(id), ec) ||
          fs::exists(result_path(id), ec))
        continue;
    }
    return id;
  }
}

// ---- submit, solve_now --------------------------------------------------------------------------

SubmitOutcome JobStore::submit(Scene scene, const std::string& scene_json) {
  Impl& s = *impl_;
  auto job = std::make_shared<Job>();
  job->scene = std::make_shared<const Scene>(std::move(scene));
  job->created = SystemClock::now();
  {
    std::unique_lock lock(s.mutex);
    if (s.stopping) return ShuttingDown{};
    if (s.queue.size() >= s.options.queue_size) return QueueFull{s.options.queue_size};
    job->id = s.unused_id_locked();
    if (s.jobs_dir) {
      // Durable before it is acknowledged. Scenes are bounded by the request size limit.
      try {
        write_file_atomically(s.scene_path(job->id), scene_json);
      } catch (const std::exception& e) {
        std::cerr << "lambert serve: " << e.what() << "\n";
        return StorageError{"the job could not be stored"};
      }
    }
    s.jobs.emplace(job->id, job);
    s.queue.push_back(job);
  }
  s.work_cv.notify_one();
  std::lock_guard lock(s.mutex);
  return s.status_locked(*job);
}

SyncOutcome JobStore::solve_now(Scene scene) {
  Impl& s = *impl_;
  auto job = std::make_shared<Job>();
  job->stored = false;
  job->scene = std::make_shared<const Scene>(std::move(scene));
  job->created = SystemClock::now();
  std::unique_lock lock(s.mutex);
  if (s.stopping) return ShuttingDown{};
  if (s.queue.size() >= s.options.queue_size) return QueueFull{s.options.queue_size};
  s.queue.push_back(job);
  s.work_cv.notify_one();
  // The watchdog bounds the running time, so this wait ends.
  s.done_cv.wait(lock, [&] { return is_final(job->state); });
  if (job->stop == StopReason::Shutdown) return ShuttingDown{};
  if (job->state == JobState::Done) return JobResult{job->result};
  return SolveFailed{job->error};
}

// ---- workers --------------------------------------------------------------------------------------

void JobStore::Impl::worker_loop() {
  // The solver's parallel loops run in this worker's own arena: a thread that waits for one job's
  // loop never picks up another job's tasks, so a small job is not held up behind a large one.
  tbb::task_arena arena;
  for (;;) {
    std::shared_ptr<Job> job;
    {
      std::unique_lock lock(mutex);
      work_cv.wait(lock, [&] { return stopping || !queue.empty(); });
      if (stopping) return;
      job = std::move(queue.front());
      queue.pop_front();
      job->state = JobState::Running;
      job->started = SteadyClock::now();
      running.push_back(job);
    }
    run(job, arena);
  }
}

void JobStore::Impl::run(const std::shared_ptr<Job>& job, tbb::task_arena& arena) {
  SolveControl control;
  Job* j = job.get();
  // Called from the solver's TBB threads: keep the largest value reported (never moves back).
  control.progress = [j](double f) {
    f = std::clamp(std::isfinite(f) ? f : 0.0, 0.0, 1.0);
    double current = j->progress.load(std::memory_order_relaxed);
    while (f > current && !j->progress.compare_exchange_weak(current, f, std::memory_order_relaxed)) {
    }
  };
  control.cancel = &job->cancel;
  control.max_patches = options.max_patches;

  std::shared_ptr<const std::string> result;
  std::string failure;
  bool cancelled = false;
  try {
    arena.execute([&] {
      const Solution solution = solve(*job->scene, control);
      const Report report = make_report(*job->scene, solution);
      result = std::make_shared<const std::string>(encode_result(*job->scene, solution, report));
    });
  } catch (const SolveCancelled&) {
    cancelled = true;
  } catch (const SolveError& e) {
    failure = e.what();  // written for the scene's author
  } catch (const std::bad_alloc&) {
    failure = "the solve ran out of memory; use a larger meshing.max_patch_area";
  } catch (const std::exception& e) {
    // Environment or bug: the details go to the server's log, not to the client.
    std::cerr << "lambert serve: job " << (job->stored ? job->id : std::string("(sync)"))
              << " failed: " << e.what() << "\n";
    failure = "internal error while solving (details are in the server log)";
  }

  // Large result files are written before taking the lock.
  bool result_written = false;
  if (result && job->stored && jobs_dir) {
    try {
      write_file_atomically(result_path(job->id), *result);
      result_written = true;
    } catch (const std::exception& e) {
      std::cerr << "lambert serve: job " << job->id << ": " << e.what() << "\n";
      failure = "the result could not be stored on the server";
      result.reset();
    }
  }

  {
    std::lock_guard lock(mutex);
    running.erase(std::find(running.begin(), running.end(), job));
    const StopReason stop = job->stop;
    if (job->removed || stop == StopReason::User) {
      // Cancelled (state and record already written by cancel_or_remove) or removed meanwhile.
      if (result_written) remove_quietly(result_path(job->id));
    } else if (stop == StopReason::Shutdown) {
      // Not final: with a data directory the scene file stays and the job runs after a restart.
      if (result_written) remove_quietly(result_path(job->id));
      job->state = JobState::Failed;
      job->error = "the server shut down before the job finished";
    } else {
      job->finished = SystemClock::now();
      if (result) {
        job->state = JobState::Done;
        job->progress = 1;
        if (result_written) job->result_on_disk = true;
        else job->result = std::move(result);
      } else {
        job->state = JobState::Failed;
        if (cancelled && stop == StopReason::TimeLimit)
          job->error = "the solve exceeded the time limit of " +
                       seconds_text(options.time_limit.count()) + " s and was stopped at " +
                       std::to_string(static_cast<int>(job->progress.load() * 100)) +
                       " % progress; use a larger meshing.max_patch_area";
        else if (cancelled)
          job->error = "the solve was cancelled";
        else
          job->error = failure;
      }
      persist_final_locked(*job);
    }
    job->scene.reset();
  }
  done_cv.notify_all();
}

// ---- watchdog ----------------------------------------------------------------------------------------

void JobStore::Impl::watchdog_loop() {
  std::unique_lock lock(mutex);
  auto last_sweep = SteadyClock::now();
  while (!stopping) {
    watchdog_cv.wait_for(lock, kWatchdogTick, [&] { return stopping; });
    if (stopping) break;
    const auto now = SteadyClock::now();
    if (options.time_limit.count() > 0)
      for (const auto& job : running)
        if (job->stop == StopReason::None && now - job->started > options.time_limit) {
          job->stop = StopReason::TimeLimit;
          job->cancel = true;
        }
    if (now - last_sweep >= kExpirySweepInterval) {
      sweep_expired_locked();
      last_sweep = now;
    }
  }
}

void JobStore::Impl::sweep_expired_locked() {
  if (options.result_ttl.count() <= 0) return;
  const auto now = SystemClock::now();
  for (auto it = jobs.begin(); it != jobs.end();) {
    const auto exp = expiry(*it->second);
    if (exp && *exp <= now) {
      it->second->removed = true;
      remove_files_locked(it->first);
      it = jobs.erase(it);
    } else {
      ++it;
    }
  }
}

// ---- queries ----------------------------------------------------------------------------------------

std::optional<JobStatus> JobStore::status(const std::string& id) const {
  const Impl& s = *impl_;
  std::lock_guard lock(s.mutex);
  const auto it = s.jobs.find(id);
  if (it == s.jobs.end()) return std::nullopt;
  return s.status_locked(*it->second);
}

ResultLookup JobStore::result(const std::string& id) const {
  const Impl& s = *impl_;
  fs::path file;
  {
    std::lock_guard lock(s.mutex);
    const auto it = s.jobs.find(id);
    if (it == s.jobs.end()) return JobNotFound{};
    const Job& job = *it->second;
    if (!is_final(job.state)) return JobNotDone{s.status_locked(job)};
    if (job.state != JobState::Done) return JobFailed{s.status_locked(job)};
    if (!job.result_on_disk) return JobResult{job.result};
    file = s.result_path(id);
  }
  // Read outside the lock; a concurrent DELETE unlinks the file, which an open reader survives.
  auto text = read_whole_file(file);
  if (!text) return JobNotFound{};  // removed or expired meanwhile
  return JobResult{std::make_shared<const std::string>(std::move(*text))};
}

CancelOutcome JobStore::cancel_or_remove(const std::string& id) {
  Impl& s = *impl_;
  std::lock_guard lock(s.mutex);
  const auto it = s.jobs.find(id);
  if (it == s.jobs.end()) return {};
  const std::shared_ptr<Job> job = it->second;
  if (is_final(job->state)) {
    CancelOutcome out{CancelOutcome::Kind::Removed, s.status_locked(*job)};
    job->removed = true;
    s.remove_files_locked(id);
    s.jobs.erase(it);
    return out;
  }
  if (job->state == JobState::Queued) {
    s.queue.erase(std::find(s.queue.begin(), s.queue.end(), job));
    job->scene.reset();
  }
  // Running: the solver stops at its next check of the token and the worker then discards
  // whatever it has; the job is cancelled from now on.
  job->stop = StopReason::User;
  job->cancel = true;
  job->state = JobState::Cancelled;
  job->finished = SystemClock::now();
  s.persist_final_locked(*job);
  return {CancelOutcome::Kind::Cancelled, s.status_locked(*job)};
}

JobStore::Counts JobStore::counts() const {
  const Impl& s = *impl_;
  std::lock_guard lock(s.mutex);
  return {s.queue.size(), s.running.size(), s.jobs.size(), s.options.workers, s.options.queue_size};
}

}  // namespace lambert
