// The Prometheus text exposition (see metrics.h).
#include "server/metrics.h"

#include <algorithm>
#include <charconv>

namespace lambert {
namespace {

// A sample value: integers as integers, others in the shortest form that reads back exactly.
std::string value_text(double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, end);
}

std::string label_value(const std::string& v) {
  std::string out;
  for (char c : v) {
    if (c == '\\') out += "\\\\";
    else if (c == '"') out += "\\\"";
    else if (c == '\n') out += "\\n";
    else out += c;
  }
  return out;
}

void family(std::string& out, const std::string& name, const std::string& type, const std::string& help) {
  out += "# HELP " + name + " " + help + "\n# TYPE " + name + " " + type + "\n";
}

void sample(std::string& out, const std::string& name, const std::string& labels, double v) {
  out += name + (labels.empty() ? "" : "{" + labels + "}") + " " + value_text(v) + "\n";
}

}  // namespace

const std::vector<double>& Histogram::bounds() {
  static const std::vector<double> b = {0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30, 60, 120, 300, 600, 1800};
  return b;
}

void Histogram::observe(double seconds) {
  const auto& b = bounds();
  const auto k = static_cast<std::size_t>(std::lower_bound(b.begin(), b.end(), seconds) - b.begin());
  ++counts[k];
  sum += seconds;
  ++count;
}

std::string prometheus_text(const MetricsSnapshot& m) {
  std::string out;
  family(out, "lambert_jobs", "gauge", "Jobs in the store by state (with a shared store: every instance's).");
  const std::pair<const char*, std::size_t> states[] = {{"queued", m.jobs.queued}, {"running", m.jobs.running},
                                                         {"done", m.jobs.done}, {"failed", m.jobs.failed},
                                                         {"cancelled", m.jobs.cancelled}};
  for (const auto& [state, n] : states) sample(out, "lambert_jobs", "state=\"" + std::string(state) + "\"", double(n));
  family(out, "lambert_queue_depth", "gauge", "Jobs waiting for a worker.");
  sample(out, "lambert_queue_depth", "", double(m.jobs.queued));

  family(out, "lambert_solve_seconds", "histogram", "Wall time of this instance's solves, by outcome.");
  for (const char* outcome : {"done", "failed"}) {
    const auto it = m.solve_seconds.find(outcome);
    const Histogram h = it == m.solve_seconds.end() ? Histogram{} : it->second;
    const std::string o = "outcome=\"" + std::string(outcome) + "\"";
    std::uint64_t cumulative = 0;
    for (std::size_t k = 0; k < Histogram::bounds().size(); ++k) {
      cumulative += h.counts[k];
      sample(out, "lambert_solve_seconds_bucket", o + ",le=\"" + value_text(Histogram::bounds()[k]) + "\"",
             double(cumulative));
    }
    sample(out, "lambert_solve_seconds_bucket", o + ",le=\"+Inf\"", double(h.count));
    sample(out, "lambert_solve_seconds_sum", o, h.sum);
    sample(out, "lambert_solve_seconds_count", o, double(h.count));
  }

  family(out, "lambert_running_solves", "gauge", "Solves running on this instance.");
  sample(out, "lambert_running_solves", "", double(m.running_here));
  family(out, "lambert_workers", "gauge", "Solver workers of this instance (--threads).");
  sample(out, "lambert_workers", "", double(m.workers));
  family(out, "lambert_draining", "gauge", "1 while this instance drains after SIGTERM.");
  sample(out, "lambert_draining", "", m.draining ? 1 : 0);
  family(out, "lambert_jobs_submitted_total", "counter", "Jobs accepted by this instance.");
  sample(out, "lambert_jobs_submitted_total", "", double(m.submitted));
  family(out, "lambert_cache_hits_total", "counter", "Scenes this instance answered from a stored result.");
  sample(out, "lambert_cache_hits_total", "", double(m.cache_hits));
  family(out, "lambert_http_responses_total", "counter", "HTTP responses of this instance by status code.");
  for (const auto& [code, n] : m.http_responses)
    sample(out, "lambert_http_responses_total", "code=\"" + std::to_string(code) + "\"", double(n));
  family(out, "lambert_build_info", "gauge", "The running version.");
  sample(out, "lambert_build_info", "version=\"" + label_value(m.version) + "\"", 1);
  return out;
}

}  // namespace lambert
