// `lambert serve` (SPEC §3, §4): the HTTP service's command-line entry point.
#pragma once

#include <string>
#include <vector>

namespace lambert {

// `args` are the arguments after "serve". Returns the process exit status.
int run_serve(const std::vector<std::string>& args);

}  // namespace lambert
