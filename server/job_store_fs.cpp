// The job store of one machine (see job_store_fs.h for the data directory's layout).
//
// One mutex guards the job table, the queue and every job's state. Result files, which can be
// large, are written and read outside the lock; the small commit record (<id>.job.json) is written
// under it, so that a job's files and its state in memory never disagree about whether it was
// removed.
#include "server/job_store_fs.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <deque>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

namespace lambert {
namespace {

namespace fs = std::filesystem;
using SystemClock = std::chrono::system_clock;
using json = nlohmann::json;

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

struct Job {
  std::string id;
  JobState state = JobState::Queued;
  std::string error;
  SystemClock::time_point created, finished;
  double progress = 0;
  std::int64_t token = 0;                     // claims so far (the fencing token)
  std::string scene_json;                     // until the job is final
  std::string cache_key;                      // "" for jobs queued again after a restart
  std::shared_ptr<const std::string> result;  // in memory (no data directory)
  bool result_on_disk = false;
  bool cached = false;
};

}  // namespace

struct FileJobStore::Impl {
  explicit Impl(FileJobStoreOptions o) : options(std::move(o)) {}
  ~Impl() {
    if (lock_fd >= 0) ::close(lock_fd);  // releases the flock
  }

  FileJobStoreOptions options;
  std::optional<fs::path> jobs_dir;
  std::mutex mutex;
  std::map<std::string, std::shared_ptr<Job>> jobs;
  std::deque<std::shared_ptr<Job>> queue;
  std::map<std::string, std::string> done_by_key;  // cache key -> a done job holding that result
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
    s.progress = job.state == JobState::Done ? 1.0 : job.progress;
    s.error = job.error;
    s.created = job.created;
    s.finished = job.finished;
    s.expires = expiry(job);
    s.cached = job.cached;
    if (job.state == JobState::Queued) {
      const auto it = std::find_if(queue.begin(), queue.end(),
                                   [&](const auto& q) { return q.get() == &job; });
      s.queue_position = it == queue.end() ? 0 : static_cast<std::size_t>(it - queue.begin()) + 1;
    }
    return s;
  }

  // The commit record of a final job; replaces the scene file. Logged, not thrown: the state in
  // memory is right even when the disk is not, and the next restart runs the job again.
  void persist_final_locked(const Job& job) {
    if (!jobs_dir) return;
    json record = {{"id", job.id},
                   {"state", to_string(job.state)},
                   {"created", to_unix_seconds(job.created)},
                   {"finished", to_unix_seconds(job.finished)}};
    if (!job.error.empty()) record["error"] = job.error;
    if (!job.cache_key.empty()) record["cache_key"] = job.cache_key;
    if (job.cached) record["cached"] = true;
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

  // Forgets a job (removed or expired) and, if it held the cache's copy of a result, hands that
  // role to another done job with the same key.
  void erase_locked(std::map<std::string, std::shared_ptr<Job>>::iterator it) {
    const std::shared_ptr<Job> job = it->second;
    remove_files_locked(job->id);
    jobs.erase(it);
    const auto key = done_by_key.find(job->cache_key);
    if (key == done_by_key.end() || key->second != job->id) return;
    done_by_key.erase(key);
    for (const auto& [id, other] : jobs)
      if (other->state == JobState::Done && other->cache_key == job->cache_key) {
        done_by_key[job->cache_key] = id;
        break;
      }
  }

  // A done job for `key`, if the cache has one.
  std::shared_ptr<Job> cached_locked(const std::string& key) const {
    if (key.empty()) return nullptr;
    const auto it = done_by_key.find(key);
    if (it == done_by_key.end()) return nullptr;
    const auto job = jobs.find(it->second);
    return job == jobs.end() ? nullptr : job->second;
  }

  // Makes `job` done with the result of `source` (a done job with the same cache key): shares the
  // string in memory, or hard-links the result file (a copy where links are not possible).
  bool share_result_locked(Job& job, const Job& source) {
    if (jobs_dir) {
      std::error_code ec;
      fs::create_hard_link(result_path(source.id), result_path(job.id), ec);
      if (ec) fs::copy_file(result_path(source.id), result_path(job.id), ec);
      if (ec) return false;
      job.result_on_disk = true;
    } else {
      job.result = source.result;
    }
    job.state = JobState::Done;
    job.progress = 1;
    job.cached = true;
    job.finished = SystemClock::now();
    job.scene_json.clear();
    return true;
  }

  std::string unused_id_locked() const;
  void reload();
  void reload_record(const std::string& id, bool has_scene, bool has_result, SystemClock::time_point now);
  std::shared_ptr<Job> running_locked(const Claim& claim) const {
    const auto it = jobs.find(claim.id);
    if (it == jobs.end() || it->second->state != JobState::Running || it->second->token != claim.token)
      return nullptr;
    return it->second;
  }
};

// ---- construction and reload ----------------------------------------------------------------------

FileJobStore::FileJobStore(FileJobStoreOptions options)
    : impl_(std::make_unique<Impl>(std::move(options))) {
  Impl& s = *impl_;
  if (!s.options.data_dir) return;
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

FileJobStore::~FileJobStore() = default;

std::string FileJobStore::describe() const {
  return impl_->options.data_dir ? "data in " + impl_->options.data_dir->string()
                                 : std::string("results in memory");
}

// Reads the data directory back (see job_store_fs.h).
void FileJobStore::Impl::reload() {
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
    if (files.record) {
      reload_record(id, files.scene, files.result, now);
      continue;
    }
    if (!files.scene) {  // a result without its commit record, and nothing to run again: debris
      remove_quietly(result_path(id));
      continue;
    }
    // Accepted but never finished: queued again. Its cache key is not kept on disk, so its
    // result is stored without one (and not offered to later submissions).
    auto job = std::make_shared<Job>();
    job->id = id;
    std::error_code ec;
    const auto mtime = fs::last_write_time(scene_path(id), ec);
    job->created = ec ? now : std::chrono::file_clock::to_sys(mtime);
    job->scene_json = read_whole_file(scene_path(id)).value_or("");
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

void FileJobStore::Impl::reload_record(const std::string& id, bool has_scene, bool has_result,
                                       SystemClock::time_point now) {
  auto job = std::make_shared<Job>();
  job->id = id;
  try {
    const json record = json::parse(read_whole_file(record_path(id)).value_or(""));
    const auto state = job_state_from_string(record.at("state").get<std::string>());
    if (record.at("id").get<std::string>() != id || !state || !is_final(*state))
      throw std::runtime_error("inconsistent record");
    job->state = *state;
    job->created = from_unix_seconds(record.at("created").get<double>());
    job->finished = from_unix_seconds(record.at("finished").get<double>());
    job->error = record.value("error", std::string());
    job->cache_key = record.value("cache_key", std::string());
    job->cached = record.value("cached", false);
  } catch (const std::exception& e) {
    // Reported, not dropped (issue 37: a corrupted record made its job vanish, 404): the job stays,
    // failed with the reason, until it expires like any other failed job from now on.
    std::cerr << "lambert serve: unreadable job record " << record_path(id) << ": " << e.what() << "\n";
    job->state = JobState::Failed;
    job->error = std::string("the stored record of this job could not be read (") + e.what() + ")";
    job->created = job->finished = now;
    if (has_scene) remove_quietly(scene_path(id));
    if (has_result) remove_quietly(result_path(id));
    persist_final_locked(*job);
    jobs.emplace(id, std::move(job));
    return;
  }
  if (has_scene) remove_quietly(scene_path(id));  // crashed between commit and clean-up
  if (const auto exp = expiry(*job); exp && *exp <= now) {
    remove_files_locked(id);
    return;
  }
  if (job->state == JobState::Done) {
    if (has_result) {
      job->result_on_disk = true;
      job->progress = 1;
      if (!job->cache_key.empty()) done_by_key.emplace(job->cache_key, id);
    } else {
      job->state = JobState::Failed;
      job->error = "the stored result of this job was lost";
    }
  } else if (has_result) {
    remove_quietly(result_path(id));
  }
  jobs.emplace(id, std::move(job));
}

// 2^-128 per pair makes a collision absurd; checking costs nothing and makes "never reused" a fact
// for the ids this store knows about (including removed ones that left files behind).
std::string FileJobStore::Impl::unused_id_locked() const {
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

// ---- submit and the worker's side -----------------------------------------------------------------

SubmitOutcome FileJobStore::submit(const std::string& scene_json, const std::string& cache_key,
                                   std::size_t queue_limit) {
  Impl& s = *impl_;
  auto job = std::make_shared<Job>();
  job->created = SystemClock::now();
  job->cache_key = cache_key;
  std::lock_guard lock(s.mutex);
  job->id = s.unused_id_locked();
  if (const auto source = s.cached_locked(cache_key); source && s.share_result_locked(*job, *source)) {
    s.persist_final_locked(*job);
    s.jobs.emplace(job->id, job);
    return s.status_locked(*job);
  }
  if (s.queue.size() >= queue_limit) return QueueFull{queue_limit};
  if (s.jobs_dir) {
    // Durable before it is acknowledged. Scenes are bounded by the request size limit.
    try {
      write_file_atomically(s.scene_path(job->id), scene_json);
    } catch (const std::exception& e) {
      std::cerr << "lambert serve: " << e.what() << "\n";
      return StorageError{"the job could not be stored"};
    }
  }
  job->scene_json = scene_json;
  s.jobs.emplace(job->id, job);
  s.queue.push_back(job);
  return s.status_locked(*job);
}

std::optional<Claim> FileJobStore::claim(const std::string&) {
  Impl& s = *impl_;
  std::lock_guard lock(s.mutex);
  while (!s.queue.empty()) {
    const std::shared_ptr<Job> job = std::move(s.queue.front());
    s.queue.pop_front();
    // Solved meanwhile under the same key: answered from the cache.
    if (const auto source = s.cached_locked(job->cache_key); source && s.share_result_locked(*job, *source)) {
      s.persist_final_locked(*job);
      continue;
    }
    job->state = JobState::Running;
    job->progress = 0;
    ++job->token;
    return Claim{job->id, job->token, job->scene_json, job->cache_key};
  }
  return std::nullopt;
}

Renewal FileJobStore::renew(const Claim& claim, double progress) {
  Impl& s = *impl_;
  std::lock_guard lock(s.mutex);
  const auto job = s.running_locked(claim);
  if (!job) return Renewal::Lost;
  job->progress = std::max(job->progress, progress);
  return Renewal::Held;
}

bool FileJobStore::finish(const Claim& claim, const JobOutcome& outcome) {
  Impl& s = *impl_;
  // Large result files are written before taking the lock (and removed if the job went meanwhile).
  bool written = false;
  std::string error = outcome.error;
  if (outcome.result && s.jobs_dir) {
    try {
      write_file_atomically(s.result_path(claim.id), *outcome.result);
      written = true;
    } catch (const std::exception& e) {
      std::cerr << "lambert serve: job " << claim.id << ": " << e.what() << "\n";
      error = "the result could not be stored on the server";
    }
  }
  std::lock_guard lock(s.mutex);
  const auto job = s.running_locked(claim);
  if (!job) {
    if (written) remove_quietly(s.result_path(claim.id));
    return false;
  }
  job->finished = SystemClock::now();
  job->scene_json.clear();
  if (outcome.result && (written || !s.jobs_dir)) {
    job->state = JobState::Done;
    job->progress = 1;
    job->result_on_disk = written;
    if (!written) job->result = outcome.result;
    if (!job->cache_key.empty()) s.done_by_key.emplace(job->cache_key, job->id);
  } else {
    job->state = JobState::Failed;
    job->error = error;
  }
  s.persist_final_locked(*job);
  return true;
}

void FileJobStore::release(const Claim& claim) {
  Impl& s = *impl_;
  std::lock_guard lock(s.mutex);
  const auto job = s.running_locked(claim);
  if (!job) return;
  job->state = JobState::Queued;
  job->progress = 0;
  s.queue.push_front(job);  // its scene file is still there: it runs again after a restart too
}

// ---- queries -----------------------------------------------------------------------------------------

std::optional<JobStatus> FileJobStore::status(const std::string& id) {
  Impl& s = *impl_;
  std::lock_guard lock(s.mutex);
  const auto it = s.jobs.find(id);
  if (it == s.jobs.end()) return std::nullopt;
  return s.status_locked(*it->second);
}

ResultLookup FileJobStore::result(const std::string& id) {
  Impl& s = *impl_;
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
  if (text) return JobResult{std::make_shared<const std::string>(std::move(*text))};
  std::lock_guard lock(s.mutex);
  const auto it = s.jobs.find(id);
  if (it == s.jobs.end()) return JobNotFound{};  // deleted or expired meanwhile
  // The job is there and its result file is not: lost outside the server. Said so, not "done" with
  // a result that answers 404 (issue 37).
  Job& job = *it->second;
  if (job.state == JobState::Done && job.result_on_disk) {
    std::cerr << "lambert serve: job " << id << ": its result file " << file << " is gone\n";
    job.state = JobState::Failed;
    job.error = "the stored result of this job was lost";
    job.result_on_disk = false;
    const auto key = s.done_by_key.find(job.cache_key);
    if (key != s.done_by_key.end() && key->second == id) s.done_by_key.erase(key);  // a cache miss now
    s.persist_final_locked(job);
  }
  return JobFailed{s.status_locked(job)};
}

std::shared_ptr<const std::string> FileJobStore::cached_result(const std::string& cache_key) {
  Impl& s = *impl_;
  fs::path file;
  {
    std::lock_guard lock(s.mutex);
    const auto job = s.cached_locked(cache_key);
    if (!job) return nullptr;
    if (!job->result_on_disk) return job->result;
    file = s.result_path(job->id);
  }
  auto text = read_whole_file(file);
  return text ? std::make_shared<const std::string>(std::move(*text)) : nullptr;
}

CancelOutcome FileJobStore::cancel_or_remove(const std::string& id) {
  Impl& s = *impl_;
  std::lock_guard lock(s.mutex);
  const auto it = s.jobs.find(id);
  if (it == s.jobs.end()) return {};
  const std::shared_ptr<Job> job = it->second;
  if (is_final(job->state)) {
    CancelOutcome out{CancelOutcome::Kind::Removed, s.status_locked(*job)};
    s.erase_locked(it);
    return out;
  }
  if (job->state == JobState::Queued) s.queue.erase(std::find(s.queue.begin(), s.queue.end(), job));
  // Running: its claim is lost from now on; the worker stops at its next renewal.
  job->state = JobState::Cancelled;
  job->finished = SystemClock::now();
  job->scene_json.clear();
  s.persist_final_locked(*job);
  return {CancelOutcome::Kind::Cancelled, s.status_locked(*job)};
}

StoreCounts FileJobStore::counts() {
  Impl& s = *impl_;
  std::lock_guard lock(s.mutex);
  StoreCounts c;
  for (const auto& [id, job] : s.jobs) {
    switch (job->state) {
      case JobState::Queued: ++c.queued; break;
      case JobState::Running: ++c.running; break;
      case JobState::Done: ++c.done; break;
      case JobState::Failed: ++c.failed; break;
      case JobState::Cancelled: ++c.cancelled; break;
    }
  }
  return c;
}

void FileJobStore::sweep_expired() {
  Impl& s = *impl_;
  if (s.options.result_ttl.count() <= 0) return;
  std::lock_guard lock(s.mutex);
  const auto now = SystemClock::now();
  for (auto it = s.jobs.begin(); it != s.jobs.end();) {
    const auto exp = s.expiry(*it->second);
    auto next = std::next(it);
    if (exp && *exp <= now) s.erase_locked(it);
    it = next;
  }
}

}  // namespace lambert
