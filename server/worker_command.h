// `lambert solve-worker`: one solve for `lambert serve`, in a process of its own (see
// server/solve_process.h). Not meant to be run by hand: it reads a scene on standard input, writes
// the result document on standard output and reports on descriptor 3.
#pragma once

#include <string>
#include <vector>

namespace lambert {

// The descriptor on which the worker reports its progress and the reason of a failure, line by line
// (server/solve_process.cpp reads it).
inline constexpr int kWorkerStatusFd = 3;

// `args` are the arguments after "solve-worker". Returns the process exit status: 0 with a result,
// 1 after a failure it reported, 2 on bad usage.
int run_solve_worker(const std::vector<std::string>& args);

}  // namespace lambert
