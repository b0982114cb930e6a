// `lambert bench`: speed against error on built-in reference scenes with exact answers.
#pragma once

#include <string>
#include <vector>

namespace lambert {

int run_bench(const std::vector<std::string>& args);

}  // namespace lambert
