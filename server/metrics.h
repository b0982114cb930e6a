// GET /v1/metrics: the service's numbers in the Prometheus text exposition format (version 0.0.4),
// for a Prometheus server to scrape:
//   lambert_jobs{state="queued"|"running"|"done"|"failed"|"cancelled"}   gauge: jobs in the store
//                                                  (with --store: every instance's)
//   lambert_queue_depth                            gauge: jobs waiting for a worker
//   lambert_solve_seconds{outcome="done"|"failed"} histogram: this instance's solves, start to end
//   lambert_running_solves, lambert_workers        gauges: this instance
//   lambert_jobs_submitted_total, lambert_cache_hits_total   counters: this instance
//   lambert_http_responses_total{code="200"}       counter: this instance's answers by status
//   lambert_draining                               gauge: 1 after SIGTERM, while running solves end
//   lambert_build_info{version="1.3.0"}            gauge: always 1
// The format's rules, as https://prometheus.io/docs/instrumenting/exposition_formats/ states them:
// each family's # HELP and # TYPE lines come once, before its samples, and its samples are
// together; histogram buckets are cumulative with an "le" label, end at le="+Inf", which equals
// _count, and come with _sum; counters end in _total; label values escape \, " and newline; every
// line ends with \n.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "server/job_store.h"

namespace lambert {

// Observations in buckets of seconds (the upper bounds), each counted once (not cumulative here).
struct Histogram {
  static const std::vector<double>& bounds();  // 0.1 s ... 1800 s
  std::vector<std::uint64_t> counts = std::vector<std::uint64_t>(bounds().size() + 1, 0);  // last: +Inf
  double sum = 0;
  std::uint64_t count = 0;
  void observe(double seconds);
};

struct MetricsSnapshot {
  StoreCounts jobs;
  std::size_t running_here = 0, workers = 0;
  bool draining = false;
  std::map<std::string, Histogram> solve_seconds;  // by outcome
  std::uint64_t submitted = 0, cache_hits = 0;
  std::map<int, std::uint64_t> http_responses;     // by status code
  std::string version;
};

std::string prometheus_text(const MetricsSnapshot& m);

// The exposition format's media type.
inline constexpr const char* kPrometheusMediaType = "text/plain; version=0.0.4; charset=utf-8";

}  // namespace lambert
