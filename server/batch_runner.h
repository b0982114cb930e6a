// The two ways `lambert batch` (server/batch_command.cpp) solves its scenes:
//   locally   up to N `lambert solve-worker` processes at once (server/solve_process.h: a crash or
//             an exhausted memory limit fails that scene only);
//   remotely  up to N jobs at once on a `lambert serve` (POST /v1/jobs, polling, GET .../result),
//             waiting out 503 queue_full as its Retry-After says.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "server/solve_process.h"

namespace lambert {

struct BatchItem {
  std::string name;                                // the output's file name: NAME.result.json
  std::string source;                              // for messages: "scenes/a.json", "study.jsonl:3"
  std::string scene_json;
  std::optional<std::filesystem::path> scene_dir;  // where relative "file" surfaces are (local runs)
};

struct BatchOutcome {
  bool done = false;
  std::string result;   // done: the result document
  std::string error;    // otherwise: why
  double seconds = 0;   // wall time, submission or start to the result
  bool cached = false;  // remote: answered from the service's store without a solve
};

// Called from the runners' threads; the caller serialises what it shares.
struct BatchEvents {
  std::function<void(std::size_t item)> started;
  std::function<void(std::size_t item, const BatchOutcome&)> finished;
};

void run_batch_locally(const std::vector<BatchItem>& items, std::size_t jobs, const SolveLimits& limits,
                       const std::filesystem::path& executable, const BatchEvents& events);

struct RemoteBatch {
  std::string url;  // http://host:port
  std::size_t jobs = 4;
  // A job submitted by an earlier, interrupted run of the same batch is asked for again instead of
  // submitted twice: its id is kept in ids_dir/NAME.job while it runs.
  std::filesystem::path ids_dir;
};
void run_batch_remotely(const std::vector<BatchItem>& items, const RemoteBatch& remote, const BatchEvents& events);

}  // namespace lambert
