// The built `lambert` binary as a hostile client's tests meet it: a command run as a child process
// with a time limit (a hang is a failure, not a stuck test), its exit status or signal, what it wrote
// (bounded: a runaway report must not exhaust the test) and its peak memory from wait4's rusage;
// and `lambert serve` started as a child on a free port, whose resident memory /proc reports.
#pragma once

#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace lambert::testing {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

inline const fs::path kLambertBinary = LAMBERT_BINARY;

// A fresh directory under the system's temporary directory, removed afterwards.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag)
      : path_(fs::temp_directory_path() /
              (tag + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++))) {
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  static int& counter() {
    static int n = 0;
    return n;
  }
  fs::path path_;
};

// The first `max_bytes` of a file (and its full size).
inline std::string read_head(const fs::path& path, std::size_t max_bytes, std::size_t* size = nullptr) {
  std::error_code ec;
  const auto bytes = fs::file_size(path, ec);
  if (size) *size = ec ? 0 : static_cast<std::size_t>(bytes);
  std::ifstream in(path, std::ios::binary);
  std::string out(max_bytes, '\0');
  in.read(out.data(), static_cast<std::streamsize>(max_bytes));
  out.resize(static_cast<std::size_t>(in.gcount()));
  return out;
}

inline void write_file(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

struct ChildOutcome {
  int status = -1;         // exit status, or -1 when it was killed
  int signal = 0;          // the signal that ended it
  bool timed_out = false;  // killed by the time limit
  std::string out, err;    // the first 1 MiB of each
  std::size_t out_bytes = 0, err_bytes = 0;  // what it wrote in all
  long max_rss_kb = 0;     // peak resident set (getrusage ru_maxrss)
  double seconds = 0;
};

// Runs `lambert args...` with stdin from /dev/null, for at most `limit`.
inline ChildOutcome run_lambert(const std::vector<std::string>& args, std::chrono::seconds limit = 60s) {
  ScratchDir dir("lambert_child");
  const fs::path out = dir / "stdout", err = dir / "stderr";
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int i = ::open("/dev/null", O_RDONLY);
    const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    ::dup2(i, 0);
    ::dup2(o, 1);
    ::dup2(e, 2);
    std::vector<char*> argv{const_cast<char*>(kLambertBinary.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(kLambertBinary.c_str(), argv.data());
    ::_exit(127);
  }
  ChildOutcome r;
  int status = 0;
  rusage usage{};
  for (;;) {
    const pid_t done = ::wait4(pid, &status, WNOHANG, &usage);
    if (done == pid) break;
    if (std::chrono::steady_clock::now() - t0 > limit && !r.timed_out) {
      r.timed_out = true;
      ::kill(pid, SIGKILL);
    }
    std::this_thread::sleep_for(5ms);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  r.max_rss_kb = usage.ru_maxrss;
  r.out = read_head(out, 1 << 20, &r.out_bytes);
  r.err = read_head(err, 1 << 20, &r.err_bytes);
  return r;
}

// A field of /proc/PID/status in kB ("VmRSS", "VmHWM"), or -1.
inline long proc_status_kb(pid_t pid, const std::string& field) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind(field + ":", 0) == 0) return std::stol(line.substr(field.size() + 1));
  return -1;
}

// `lambert serve --port 0 extra...` as a child process; the port from its first line of output.
class ServeProcess {
 public:
  explicit ServeProcess(const std::vector<std::string>& extra) : dir_("lambert_serve") {
    const fs::path out = dir_ / "stdout", err = dir_ / "stderr";
    pid_ = ::fork();
    if (pid_ == 0) {
      const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
      const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
      ::dup2(o, 1);
      ::dup2(e, 2);
      std::vector<std::string> args{kLambertBinary.string(), "serve", "--port", "0"};
      args.insert(args.end(), extra.begin(), extra.end());
      std::vector<char*> argv;
      for (std::string& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(kLambertBinary.c_str(), argv.data());
      ::_exit(127);
    }
    const std::regex listening(R"(listening on http://[^:]+:(\d+))");
    for (int k = 0; k < 3000 && port_ <= 0; ++k) {
      std::smatch m;
      const std::string text = read_head(out, 4096);
      if (std::regex_search(text, m, listening)) port_ = std::stoi(m[1]);
      else std::this_thread::sleep_for(5ms);
    }
    EXPECT_GT(port_, 0) << "lambert serve did not start: " << read_head(err, 4096);
  }
  ~ServeProcess() { stop(); }
  ServeProcess(const ServeProcess&) = delete;
  ServeProcess& operator=(const ServeProcess&) = delete;

  int port() const { return port_; }
  pid_t pid() const { return pid_; }
  long rss_kb() const { return proc_status_kb(pid_, "VmRSS"); }
  long peak_rss_kb() const { return proc_status_kb(pid_, "VmHWM"); }
  bool alive() const { return ::kill(pid_, 0) == 0 && proc_status_kb(pid_, "VmRSS") >= 0; }
  std::string log() const { return read_head(dir_ / "stderr", 1 << 20); }

  // SIGTERM, then the exit status (or -1 after SIGKILL when it does not stop within 30 s).
  int stop() {
    if (pid_ <= 0) return status_;
    ::kill(pid_, SIGTERM);
    int status = 0;
    for (int k = 0; k < 3000; ++k) {
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return status_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      }
      std::this_thread::sleep_for(10ms);
    }
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    return status_ = -1;
  }

 private:
  ScratchDir dir_;
  pid_t pid_ = -1;
  int port_ = -1;
  int status_ = -1;
};

}  // namespace lambert::testing
