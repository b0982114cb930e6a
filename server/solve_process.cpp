// The server's side of a solve in its own process (see solve_process.h; the worker's side is
// server/worker_command.cpp, and the line protocol on descriptor 3 is written there).
#include "server/solve_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "server/worker_command.h"

extern char** environ;

namespace lambert {
namespace {

constexpr std::size_t kMaxStderrLine = 4096;
constexpr std::size_t kMaxStatusBytes = 64 << 10;  // a status line (a failure's reason is short)

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

std::runtime_error system_error(const std::string& what, int err) {
  return std::runtime_error(what + ": " + std::strerror(err));
}

// The scene as a file the worker reads like any standard input (no pipe to feed while it runs).
int scene_memfd(const std::string& scene_json) {
  const int fd = ::memfd_create("lambert-scene", MFD_CLOEXEC);
  if (fd < 0) throw system_error("cannot create the scene's memory file", errno);
  std::size_t done = 0;
  while (done < scene_json.size()) {
    const ssize_t n = ::write(fd, scene_json.data() + done, scene_json.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = errno;
      ::close(fd);
      throw system_error("cannot write the scene's memory file", err);
    }
    done += static_cast<std::size_t>(n);
  }
  ::lseek(fd, 0, SEEK_SET);
  return fd;
}

}  // namespace

std::string describe_signal(int signal) {
  switch (signal) {
    case SIGSEGV: return "segmentation fault (SIGSEGV)";
    case SIGABRT: return "abort (SIGABRT)";
    case SIGBUS: return "bus error (SIGBUS)";
    case SIGFPE: return "arithmetic exception (SIGFPE)";
    case SIGILL: return "illegal instruction (SIGILL)";
    case SIGKILL: return "SIGKILL";
    case SIGTERM: return "SIGTERM";
    default: return "signal " + std::to_string(signal);
  }
}

SolveProcess::SolveProcess(const std::filesystem::path& executable, const std::string& scene_json,
                           const SolveLimits& limits) {
  int scene = scene_memfd(scene_json);
  int out[2], status[2], err[2];
  if (::pipe2(out, O_CLOEXEC) != 0) throw system_error("pipe", errno);
  if (::pipe2(status, O_CLOEXEC) != 0) throw system_error("pipe", errno);
  if (::pipe2(err, O_CLOEXEC) != 0) throw system_error("pipe", errno);

  std::vector<std::string> args = {executable.string(), "solve-worker", "--parent-pid",
                                   std::to_string(::getpid())};
  if (limits.mesh_root) args.insert(args.end(), {"--mesh-root", limits.mesh_root->string()});
  else if (limits.scene_dir) args.insert(args.end(), {"--scene-dir", limits.scene_dir->string()});
  if (limits.max_patches) args.insert(args.end(), {"--max-patches", std::to_string(limits.max_patches)});
  if (limits.memory_bytes) args.insert(args.end(), {"--memory-limit", std::to_string(limits.memory_bytes)});
  args.insert(args.end(), {"--max-probe-points", std::to_string(limits.scene.max_probe_points),
                           "--max-spectral-values", std::to_string(limits.scene.max_spectral_values),
                           "--max-result-bytes", std::to_string(limits.scene.max_result_bytes)});
  max_result_bytes_ = limits.scene.max_result_bytes;
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // glibc reserves 64 MiB of address space per malloc arena, up to 8 per core: two keep a small
  // solve far below any sensible --job-memory-limit.
  std::vector<std::string> env_text;
  for (char** e = environ; *e; ++e)
    if (std::strncmp(*e, "MALLOC_ARENA_MAX=", 17) != 0) env_text.emplace_back(*e);
  env_text.emplace_back("MALLOC_ARENA_MAX=2");
  std::vector<char*> envp;
  for (auto& e : env_text) envp.push_back(e.data());
  envp.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, scene, 0);
  posix_spawn_file_actions_adddup2(&actions, out[1], 1);
  posix_spawn_file_actions_adddup2(&actions, err[1], 2);
  posix_spawn_file_actions_adddup2(&actions, status[1], kWorkerStatusFd);
  // Nothing else of the server's (its listening socket, client connections, the data directory's
  // lock) reaches the worker, whose descriptors are not all close-on-exec.
  posix_spawn_file_actions_addclosefrom_np(&actions, kWorkerStatusFd + 1);
  const int rc = ::posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  ::close(scene);
  ::close(out[1]);
  ::close(status[1]);
  ::close(err[1]);
  out_fd_ = out[0];
  status_fd_ = status[0];
  err_fd_ = err[0];
  if (rc != 0) {
    pid_ = -1;
    reaped_ = true;
    close_fd(out_fd_);
    close_fd(status_fd_);
    close_fd(err_fd_);
    throw system_error("cannot start " + executable.string(), rc);
  }
  for (int fd : {out_fd_, status_fd_, err_fd_}) ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
}

SolveProcess::~SolveProcess() {
  if (!reaped_) {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, &wait_status_, 0);
  }
  close_fd(out_fd_);
  close_fd(status_fd_);
  close_fd(err_fd_);
}

void SolveProcess::kill() {
  if (reaped_ || killed_) return;
  killed_ = true;
  ::kill(pid_, SIGKILL);
}

void SolveProcess::read_status(const std::string& line) {
  const auto space = line.find(' ');
  const std::string word = line.substr(0, space), rest = space == std::string::npos ? "" : line.substr(space + 1);
  if (word == "progress") {
    char* end = nullptr;
    const double p = std::strtod(rest.c_str(), &end);
    if (end != rest.c_str() && p > progress_ && p <= 1) progress_ = p;
  } else if (word == "failed") {
    failed_ = rest;
  } else if (word == "memory") {
    out_of_memory_ = true;
  } else if (word == "internal") {
    internal_ = rest;
  }
}

bool SolveProcess::wait(std::chrono::milliseconds timeout,
                        const std::function<void(const std::string&)>& on_stderr) {
  if (reaped_) return false;
  if (out_fd_ < 0 && status_fd_ < 0 && err_fd_ < 0) {
    // Every stream has ended: the worker is exiting (or was killed). Reap it.
    if (::waitpid(pid_, &wait_status_, 0) == pid_ || errno != EINTR) reaped_ = true;
    return !reaped_;
  }
  pollfd fds[3];
  int* owners[3];
  nfds_t n = 0;
  for (int* fd : {&out_fd_, &status_fd_, &err_fd_})
    if (*fd >= 0) {
      fds[n] = {*fd, POLLIN, 0};
      owners[n++] = fd;
    }
  const int ready = ::poll(fds, n, static_cast<int>(timeout.count()));
  if (ready <= 0) return true;
  char buf[65536];
  for (nfds_t k = 0; k < n; ++k) {
    if (!(fds[k].revents & (POLLIN | POLLHUP | POLLERR))) continue;
    int& fd = *owners[k];
    for (;;) {
      const ssize_t got = ::read(fd, buf, sizeof buf);
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) break;  // EAGAIN: read all there was
      if (got == 0) {
        if (&fd == &err_fd_ && !err_buf_.empty()) on_stderr(err_buf_);
        close_fd(fd);
        break;
      }
      if (&fd == &out_fd_) {
        // The worker checked its result's bound before solving; this holds whatever it writes.
        if (max_result_bytes_ > 0 && result_.size() + static_cast<std::size_t>(got) > max_result_bytes_) {
          result_too_large_ = true;
          result_.clear();
          result_.shrink_to_fit();
          close_fd(fd);
          if (!reaped_ && !killed_) ::kill(pid_, SIGKILL);
          break;
        }
        result_.append(buf, static_cast<std::size_t>(got));
        continue;
      }
      std::string& pending = &fd == &status_fd_ ? status_buf_ : err_buf_;
      pending.append(buf, static_cast<std::size_t>(got));
      if (&fd == &status_fd_ && pending.size() > kMaxStatusBytes && pending.find('\n') == std::string::npos)
        pending.resize(kMaxStatusBytes / 2);  // a runaway line: keep its start, which says what it is
      for (std::size_t nl; (nl = pending.find('\n')) != std::string::npos;) {
        const std::string line = pending.substr(0, nl);
        pending.erase(0, nl + 1);
        if (&fd == &status_fd_) read_status(line);
        else on_stderr(line);
      }
      if (&fd == &err_fd_ && pending.size() > kMaxStderrLine) {
        on_stderr(pending);
        pending.clear();
      }
    }
  }
  return true;
}

SolveProcessOutcome SolveProcess::outcome() const {
  SolveProcessOutcome o;
  using Kind = SolveProcessOutcome::Kind;
  if (killed_) {
    o.kind = Kind::Killed;
    return o;
  }
  if (result_too_large_) {
    o.kind = Kind::Failed;
    o.reason = "the result is larger than this server's limit (" + limit_text(kMaxResultBytesName, max_result_bytes_) +
               " bytes)";
    return o;
  }
  const bool clean_exit = WIFEXITED(wait_status_) && WEXITSTATUS(wait_status_) == 0;
  if (clean_exit && !failed_ && !out_of_memory_ && !internal_) {
    o.kind = Kind::Done;
    o.result = result_;
  } else if (failed_) {
    o.kind = Kind::Failed;
    o.reason = *failed_;
  } else if (out_of_memory_) {
    o.kind = Kind::OutOfMemory;
  } else if (internal_) {
    o.kind = Kind::Internal;
    o.reason = *internal_;
  } else if (WIFSIGNALED(wait_status_)) {
    o.kind = Kind::Crashed;
    o.signal = WTERMSIG(wait_status_);
    o.reason = "the solve process was killed by " + describe_signal(o.signal);
  } else {
    o.kind = Kind::Crashed;
    o.reason = "the solve process exited with status " +
               std::to_string(WIFEXITED(wait_status_) ? WEXITSTATUS(wait_status_) : -1) +
               " without a result";
  }
  return o;
}

}  // namespace lambert
