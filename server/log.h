// Structured log lines of `lambert serve`: one JSON object per line on standard error, for a log
// collector (journald, Loki, CloudWatch, kubectl logs) to parse without patterns:
//   {"time":"2026-12-04T19:39:10.123Z","event":"request","method":"POST","path":"/v1/jobs",...}
//   {"time":"...","event":"job","id":"4f0c...","state":"done","instance":"host/1234","solve_s":1.25}
// Each line is written with one write(2), so lines from concurrent threads never interleave.
#pragma once

#include <nlohmann/json.hpp>

namespace lambert {

// Writes `fields` with "time" (UTC, milliseconds) first, as one line on stderr.
void log_json(const nlohmann::json& fields);

}  // namespace lambert
