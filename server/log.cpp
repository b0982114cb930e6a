// Structured log lines (see log.h).
#include "server/log.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <ctime>

namespace lambert {

void log_json(const nlohmann::json& fields) {
  const auto now = std::chrono::system_clock::now();
  const std::time_t secs = std::chrono::system_clock::to_time_t(now);
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  std::tm tm{};
  gmtime_r(&secs, &tm);
  char stamp[40];
  const std::size_t n = std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%S", &tm);
  std::snprintf(stamp + n, sizeof stamp - n, ".%03dZ", static_cast<int>(ms));
  // "time" first, the rest in the object's (sorted) order.
  std::string line = "{\"time\":\"";
  line.append(stamp);
  line.push_back('"');
  for (auto it = fields.begin(); it != fields.end(); ++it) {
    line.push_back(',');
    line.append(nlohmann::json(it.key()).dump());
    line.push_back(':');
    line.append(it.value().dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  }
  line.append("}\n");
  const char* p = line.data();
  std::size_t left = line.size();
  while (left > 0) {
    const ssize_t w = ::write(2, p, left);
    if (w <= 0) return;  // nowhere to log to: not the service's failure
    p += w;
    left -= static_cast<std::size_t>(w);
  }
}

}  // namespace lambert
