// One solve in its own process, so that a solve that segfaults, aborts, or is killed for memory
// fails its job and never the server. The server starts `lambert solve-worker`
// (server/worker_command.h) with posix_spawn: the scene on its standard input (a memfd), the result
// document on its standard output, progress and the reason of a failure as lines on descriptor 3,
// and its standard error captured line by line for the server's log. The worker limits its own
// address space (RLIMIT_AS) before it reads the scene, and dies with the thread that started it
// (PR_SET_PDEATHSIG), so a killed server leaves no solve running.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "server/scene_limits.h"

namespace lambert {

struct SolveLimits {
  std::optional<std::filesystem::path> mesh_root;  // none: the scene may not name files
  std::size_t max_patches = 0;                     // 0: the solver's own limit only
  std::uint64_t memory_bytes = 0;                  // address space of the worker; 0: none
  // The scene came from a file in this directory (`lambert batch`): its "file" surfaces resolve
  // against it, anywhere, as on the command line. Ignored with a mesh root.
  std::optional<std::filesystem::path> scene_dir;
  // Probe points, spectral values and the result's size (server/scene_limits.h). The worker checks
  // them before it solves; the server also stops reading a result past max_result_bytes.
  SceneLimits scene;
};

// Why a worker process ended, as the server tells its client.
struct SolveProcessOutcome {
  enum class Kind {
    Done,      // exit 0 with a result
    Failed,    // the worker reported why (an invalid scene, the patch limit, ...): `reason`
    OutOfMemory,  // the worker reported an allocation failure
    Internal,  // the worker reported an unexpected exception: `reason` is for the log only
    Crashed,   // killed by a signal or exited without a report: `reason` says which
    Killed,    // stopped by kill() (cancelled, time limit, shutdown)
  } kind = Kind::Crashed;
  std::string result;   // Done: the result document
  std::string reason;
  int signal = 0;       // Crashed by a signal: its number
};

class SolveProcess {
 public:
  // Starts `executable solve-worker ...`; throws std::runtime_error when it cannot.
  SolveProcess(const std::filesystem::path& executable, const std::string& scene_json,
               const SolveLimits& limits);
  ~SolveProcess();  // kills and reaps a worker still running
  SolveProcess(const SolveProcess&) = delete;
  SolveProcess& operator=(const SolveProcess&) = delete;

  // Reads what the worker wrote, for at most `timeout`; false once it has ended and been reaped.
  // Each line the worker writes on standard error goes to `on_stderr`.
  bool wait(std::chrono::milliseconds timeout, const std::function<void(const std::string&)>& on_stderr);
  double progress() const { return progress_; }
  pid_t pid() const { return pid_; }
  void kill();  // SIGKILL; the outcome is then Killed
  SolveProcessOutcome outcome() const;  // once wait() returned false

 private:
  void read_status(const std::string& line);
  pid_t pid_ = -1;
  int out_fd_ = -1, status_fd_ = -1, err_fd_ = -1;
  std::string result_, status_buf_, err_buf_;
  double progress_ = 0;
  std::optional<std::string> failed_, internal_;
  bool out_of_memory_ = false, killed_ = false, reaped_ = false;
  std::size_t max_result_bytes_ = 0;  // 0: none
  bool result_too_large_ = false;
  int wait_status_ = 0;
};

// "segmentation fault (SIGSEGV)" and the like.
std::string describe_signal(int signal);

}  // namespace lambert
