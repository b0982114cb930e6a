// `lambert solve-worker` (see worker_command.h). Lines it writes on descriptor 3, one per event:
//   progress F        the solve's progress, 0 < F <= 1, only ever growing
//   failed MESSAGE    the scene cannot be solved (invalid, over a limit, ...): MESSAGE is for the client
//   memory            an allocation failed: the address-space limit, or the machine's memory
//   internal MESSAGE  an unexpected exception: MESSAGE is for the server's log only
// The result goes to standard output, and exit status 0 says it is complete.
#include "server/worker_command.h"

#include <sys/prctl.h>
#include <sys/resource.h>
#include <signal.h>
#include <unistd.h>

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <iterator>
#include <mutex>
#include <new>
#include <optional>
#include <sstream>

#include "server/cli_common.h"
#include "server/result_codec.h"
#include "server/scene_codec.h"
#include "solver/radiosity.h"
#include "solver/report.h"

namespace lambert {
namespace {

void report(const std::string& word, const std::string& message = "") {
  std::string line = word;
  if (!message.empty()) {
    line += ' ';
    for (char c : message) line += (c == '\n' || c == '\r') ? ' ' : c;
  }
  line += '\n';
  const char* p = line.data();
  std::size_t left = line.size();
  while (left > 0) {
    const ssize_t n = ::write(kWorkerStatusFd, p, left);
    if (n <= 0) return;  // the server is gone; PR_SET_PDEATHSIG ends this process
    p += n;
    left -= static_cast<std::size_t>(n);
  }
}

template <typename T>
std::optional<T> number(const std::string& text) {
  T value{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

// Progress lines at most every 50 ms or 1 %, whichever comes later, from any solver thread.
class ProgressReporter {
 public:
  void operator()(double f) {
    if (!std::isfinite(f)) return;
    std::lock_guard lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    if (f <= last_ + 0.01 && f < 1 && now - last_time_ < std::chrono::milliseconds(50)) return;
    if (f <= last_) return;
    last_ = f;
    last_time_ = now;
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4f", std::min(f, 1.0));
    report("progress", buf);
  }

 private:
  std::mutex mutex_;
  double last_ = 0;
  std::chrono::steady_clock::time_point last_time_{};
};

}  // namespace

int run_solve_worker(const std::vector<std::string>& args) {
  FileAccess files;
  files.policy = FileAccess::Policy::Deny;
  SolveControl control;
  SceneLimits limits;
  std::size_t max_patches = 0;
  std::optional<pid_t> parent;
  std::uint64_t memory_limit = 0;
  for (std::size_t k = 0; k + 1 < args.size(); k += 2) {
    const std::string &a = args[k], &v = args[k + 1];
    if (a == "--parent-pid" && number<pid_t>(v)) {
      parent = *number<pid_t>(v);
    } else if (a == "--mesh-root") {
      files.policy = FileAccess::Policy::UnderRoot;
      files.root = v;
    } else if (a == "--scene-dir") {
      files.policy = FileAccess::Policy::Anywhere;
      files.base_dir = v;
    } else if (a == "--max-patches" && number<std::size_t>(v)) {
      max_patches = *number<std::size_t>(v);
    } else if (a == "--max-probe-points" && number<std::size_t>(v)) {
      limits.max_probe_points = *number<std::size_t>(v);
    } else if (a == "--max-spectral-values" && number<std::size_t>(v)) {
      limits.max_spectral_values = *number<std::size_t>(v);
    } else if (a == "--max-result-bytes" && number<std::size_t>(v)) {
      limits.max_result_bytes = *number<std::size_t>(v);
    } else if (a == "--memory-limit" && number<std::uint64_t>(v)) {
      memory_limit = *number<std::uint64_t>(v);
    } else {
      std::cerr << "lambert solve-worker: bad argument " << a << " (this command is run by lambert serve)\n";
      return 2;
    }
  }
  if (args.size() % 2 != 0 || !parent) {
    std::cerr << "lambert solve-worker: needs --parent-pid (this command is run by lambert serve)\n";
    return 2;
  }
  // Ends with the server (or, strictly, with the server's thread that started it), and not a
  // moment later if the server is already gone.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != *parent) return 1;
  if (memory_limit > 0) {
#if defined(LAMBERT_ADDRESS_SANITIZER)
    // AddressSanitizer reserves terabytes of shadow address space: a limit would stop every solve.
    std::cerr << "lambert solve-worker: --memory-limit is not applied in a sanitizer build\n";
#else
    const rlimit limit{memory_limit, memory_limit};
    if (::setrlimit(RLIMIT_AS, &limit) != 0) {
      report("internal", "cannot set the address-space limit");
      return 1;
    }
#endif
  }

  std::ios::sync_with_stdio(false);  // the result can be large: no stdio lock per character
  try {
    const std::string text((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
    DecodeResult decoded = decode_scene(text, files, limits);
    if (!decoded.ok()) {
      // Checked when the job was accepted: the scene, or a mesh file it names, changed since.
      const DecodeError& e = decoded.errors.front();
      report("failed", "the scene no longer decodes: " + (e.pointer.empty() ? "" : e.pointer + ": ") + e.message);
      return 1;
    }
    const Scene& scene = *decoded.scene;
    apply_patch_budget(scene, limits, max_patches, control);
    ProgressReporter progress;
    control.progress = [&progress](double f) { progress(f); };
    const Solution solution = solve(scene, control);
    const Report summary = make_report(scene, solution);
    write_result(std::cout, scene, solution, summary);
    std::cout.flush();
    if (!std::cout) {
      report("internal", "cannot write the result");
      return 1;
    }
  } catch (const SolveError& e) {
    report("failed", e.what());  // written for the scene's author
    return 1;
  } catch (const std::bad_alloc&) {
    report("memory");
    return 1;
  } catch (const std::exception& e) {
    report("internal", e.what());
    return 1;
  }
  return 0;
}

}  // namespace lambert
