// What every job store shares: state names and job ids (see job_store.h).
#include "server/job_store.h"

#include <sys/random.h>

#include <algorithm>
#include <cerrno>
#include <random>

namespace lambert {

const char* to_string(JobState state) {
  switch (state) {
    case JobState::Queued: return "queued";
    case JobState::Running: return "running";
    case JobState::Done: return "done";
    case JobState::Failed: return "failed";
    case JobState::Cancelled: return "cancelled";
  }
  return "unknown";
}

std::optional<JobState> job_state_from_string(const std::string& text) {
  for (JobState state : {JobState::Queued, JobState::Running, JobState::Done, JobState::Failed,
                         JobState::Cancelled})
    if (text == to_string(state)) return state;
  return std::nullopt;
}

std::string JobStore::new_id() {
  unsigned char bytes[16];
  std::size_t got = 0;
  while (got < sizeof bytes) {
    const ssize_t n = ::getrandom(bytes + got, sizeof bytes - got, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    got += static_cast<std::size_t>(n);
  }
  if (got < sizeof bytes) {  // no getrandom: the library's non-deterministic source
    std::random_device rd;
    for (auto& b : bytes) b = static_cast<unsigned char>(rd());
  }
  static constexpr char kHex[] = "0123456789abcdef";
  std::string id(32, '0');
  for (std::size_t k = 0; k < 16; ++k) {
    id[2 * k] = kHex[bytes[k] >> 4];
    id[2 * k + 1] = kHex[bytes[k] & 15];
  }
  return id;
}

bool JobStore::is_valid_id(const std::string& id) {
  return id.size() == 32 && std::all_of(id.begin(), id.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

}  // namespace lambert
