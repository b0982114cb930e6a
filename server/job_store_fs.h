// The job store of one machine (`lambert serve` without --store): jobs in memory, and with a data
// directory durable from the moment they are accepted:
//   <data_dir>/jobs/<id>.scene.json   the scene, written before submit() returns; removed when the
//                                     job reaches a final state
//   <data_dir>/jobs/<id>.result.json  the result of a done job (a hard link to another job's result
//                                     file when it was answered from the cache)
//   <data_dir>/jobs/<id>.job.json     the final state (done, failed with its reason, cancelled) and
//                                     the cache key, written last: the commit record of a job
// Every file is written to a temporary name, flushed and renamed, so a crash leaves either the old
// state or the new one. On start the directory is read back: finished jobs are served again (until
// they expire) and jobs that were accepted but not finished are queued again. One server per data
// directory (a lock file).
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>

#include "server/job_store.h"

namespace lambert {

struct FileJobStoreOptions {
  std::optional<std::filesystem::path> data_dir;  // none: in memory only
  std::chrono::duration<double> result_ttl = std::chrono::hours(24 * 7);  // <= 0: keep forever
};

class FileJobStore final : public JobStore {
 public:
  // Creates and reloads the data directory; throws std::runtime_error when it cannot be used.
  explicit FileJobStore(FileJobStoreOptions options);
  ~FileJobStore() override;

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
  std::chrono::milliseconds renew_interval() const override { return std::chrono::milliseconds(50); }
  std::chrono::milliseconds poll_interval() const override { return std::chrono::milliseconds(1000); }
  std::string describe() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lambert
