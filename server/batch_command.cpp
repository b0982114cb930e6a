// `lambert batch INPUT -o OUTDIR [--jobs N] [--server URL] [--shard I/N]`: many scenes, for a
// parametric study (docs/SCALING.md).
//   INPUT   a directory (its *.json scenes, by name) or a JSONL manifest: one JSON object per line,
//           {"scene": "path/relative/to/the/manifest.json"} or {"scene": {...a scene...}}, with an
//           optional "name" (default: the file's stem, or "line-K")
//   OUTDIR  NAME.result.json per scene (written to a temporary name and renamed: complete or absent),
//           NAME.error.txt for a scene that failed, summary.csv
// Resuming: a scene whose result is in OUTDIR is not solved again, so running the same command after
// an interruption finishes the batch. --shard I/N takes every N-th scene from the I-th (0-based) of
// the sorted names: N runs with I = 0 .. N-1 (a Slurm array, a Kubernetes Indexed Job) share the
// scenes without talking to each other. Exit status: 0 all solved, 1 some failed, 2 bad usage or an
// unreadable input (the message names the file and line).
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "server/batch_runner.h"
#include "server/cli_common.h"
#include "server/cli_parser.h"

namespace lambert {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

struct BatchArgs {
  std::string input, output, server, shard;
  std::size_t jobs = 1;
};

struct Shard { std::size_t index = 0, count = 1; };

std::optional<Shard> parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  if (slash == std::string::npos) return std::nullopt;
  try {
    std::size_t used_i = 0, used_n = 0;
    const std::string i = text.substr(0, slash), n = text.substr(slash + 1);
    const unsigned long index = std::stoul(i, &used_i), count = std::stoul(n, &used_n);
    if (used_i != i.size() || used_n != n.size() || i.empty() || n.empty() || i[0] == '-' || n[0] == '-' ||
        count == 0 || index >= count)
      return std::nullopt;
    return Shard{index, count};
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// A name that is a plain file name, so that NAME.result.json stays inside OUTDIR.
bool usable_name(const std::string& name) {
  return !name.empty() && name.size() <= 200 && name != "." && name != ".." && name != "summary" &&
         name.find_first_of("/\\") == std::string::npos && name.find('\0') == std::string::npos;
}

// The scenes of a directory: its *.json files (not results), sorted by name.
std::optional<std::vector<BatchItem>> directory_items(const fs::path& dir) {
  std::vector<BatchItem> items;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string file = entry.path().filename().string();
    if (!entry.is_regular_file() || entry.path().extension() != ".json" || file.ends_with(".result.json")) continue;
    BatchItem item;
    item.name = entry.path().stem().string();
    item.source = entry.path().string();
    if (!read_text_file(item.source, item.scene_json)) {
      std::cerr << "lambert batch: cannot read " << item.source << "\n";
      return std::nullopt;
    }
    item.scene_dir = fs::absolute(dir);
    items.push_back(std::move(item));
  }
  return items;
}

// The scenes of a JSONL manifest; every problem with its file and line.
std::optional<std::vector<BatchItem>> manifest_items(const fs::path& manifest) {
  std::ifstream in(manifest);
  if (!in) {
    std::cerr << "lambert batch: cannot read " << manifest.string() << "\n";
    return std::nullopt;
  }
  std::vector<BatchItem> items;
  bool ok = true;
  std::size_t number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = manifest.string() + ":" + std::to_string(number);
    const auto problem = [&](const std::string& what) {
      std::cerr << where << ": " << what << "\n";
      ok = false;
    };
    const json entry = json::parse(line, nullptr, false);
    if (!entry.is_object() || !entry.contains("scene")) {
      problem("expected a JSON object with \"scene\" (a file name or a scene)");
      continue;
    }
    BatchItem item;
    item.source = where;
    const json& scene = entry["scene"];
    if (scene.is_string()) {
      const fs::path file = manifest.parent_path() / scene.get<std::string>();
      if (!read_text_file(file.string(), item.scene_json)) {
        problem("cannot read the scene " + file.string());
        continue;
      }
      item.name = file.stem().string();
      item.scene_dir = fs::absolute(file.parent_path());
    } else if (scene.is_object()) {
      item.scene_json = scene.dump();
      item.name = "line-" + std::to_string(number);
      item.scene_dir = fs::absolute(manifest.parent_path());
    } else {
      problem("\"scene\" must be a file name or a scene object");
      continue;
    }
    if (entry.contains("name")) item.name = entry["name"].is_string() ? entry["name"].get<std::string>() : "";
    if (!usable_name(item.name)) {
      problem("\"name\" must be a plain file name (no '/'), not \"" + item.name + "\"");
      continue;
    }
    items.push_back(std::move(item));
  }
  return ok ? std::optional(std::move(items)) : std::nullopt;
}

// ---- output --------------------------------------------------------------------------------------

void write_atomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.flush();
    if (!out) throw std::runtime_error("cannot write " + tmp.string());
  }
  fs::rename(tmp, path);
}

// One row of the summary table, from a result document.
struct Row {
  std::string name, state = "done", time = "", patches = "", illuminance = "", balance = "";
};

std::string number(double v, const char* format) {
  char buf[48];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// Key illuminances: every point probe (a grid: its mean), at most three shown; without probes the
// area-weighted mean over the surfaces.
std::string key_illuminances(const json& result) {
  std::string text;
  int shown = 0, total = 0;
  for (const json& p : result.value("probes", json::array())) {
    ++total;
    if (shown == 3) continue;
    const json& e = p.contains("mean_lx") ? p["mean_lx"] : p.value("illuminance_lx", json());
    if (!e.is_number()) continue;
    text += (shown++ ? ", " : "") + p.value("name", "?") + " " + number(e.get<double>(), "%.4g") + " lx";
  }
  if (total > shown) text += " (+" + std::to_string(total - shown) + ")";
  if (total > 0) return text;
  double area = 0, sum = 0;
  for (const json& s : result.value("surfaces", json::array())) {
    const double a = s.value("area", 0.0);
    area += a;
    sum += a * s.value("illuminance_lx", json::object()).value("mean", 0.0);
  }
  return area > 0 ? "surfaces " + number(sum / area, "%.4g") + " lx" : "";
}

Row summarize(const std::string& name, const std::string& result_text, double seconds) {
  Row row;
  row.name = name;
  const json result = json::parse(result_text, nullptr, false);
  if (!result.is_object()) return row;
  const json stats = result.value("stats", json::object());
  const double t = seconds >= 0 ? seconds : stats.value("time_s", json::object()).value("total", 0.0);
  row.time = number(t, "%.2f");
  row.patches = std::to_string(stats.value("patches", 0));
  row.illuminance = key_illuminances(result);
  row.balance = number(stats.value("energy", json::object()).value("relative_imbalance", 0.0), "%.1e");
  return row;
}

void print_table(std::ostream& out, const std::vector<Row>& rows) {
  const std::vector<std::string> head = {"scene", "state", "time_s", "patches", "key illuminances", "energy balance"};
  std::vector<std::size_t> width(head.size());
  const auto cells = [](const Row& r) {
    return std::vector<std::string>{r.name, r.state, r.time, r.patches, r.illuminance, r.balance};
  };
  for (std::size_t c = 0; c < head.size(); ++c) width[c] = head[c].size();
  for (const Row& r : rows)
    for (std::size_t c = 0; c < head.size(); ++c) width[c] = std::max(width[c], cells(r)[c].size());
  const auto line = [&](const std::vector<std::string>& v) {
    for (std::size_t c = 0; c < v.size(); ++c)
      out << v[c] << (c + 1 < v.size() ? std::string(width[c] - v[c].size() + 2, ' ') : "");
    out << "\n";
  };
  line(head);
  for (const Row& r : rows) line(cells(r));
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// ---- progress --------------------------------------------------------------------------------------

// "[#####.....] 12/40 finished (1 failed), 2 running, about 3.0 min left", redrawn in place on a
// terminal (stderr); nothing elsewhere.
class ProgressBar {
 public:
  ProgressBar(std::size_t total) : total_(total), on_terminal_(::isatty(2)), t0_(Clock::now()) {}
  void update(std::size_t solved, std::size_t failed, std::size_t running) {
    if (!on_terminal_) return;
    const std::size_t finished = solved + failed;
    const int filled = total_ ? static_cast<int>(30 * finished / total_) : 30;
    std::string bar = "[" + std::string(filled, '#') + std::string(30 - filled, '.') + "] " +
                      std::to_string(finished) + "/" + std::to_string(total_) + " finished";
    if (failed) bar += " (" + std::to_string(failed) + " failed)";
    bar += ", " + std::to_string(running) + " running";
    const double elapsed = std::chrono::duration<double>(Clock::now() - t0_).count();
    if (finished > 0 && finished < total_)
      bar += ", about " + number(elapsed * double(total_ - finished) / double(finished) / 60, "%.1f") + " min left";
    std::cerr << "\r" << bar << "\033[K" << std::flush;
  }
  void end() {
    if (on_terminal_) std::cerr << "\n";
  }

 private:
  std::size_t total_;
  bool on_terminal_;
  Clock::time_point t0_;
};

int run_batch(const BatchArgs& a) {
  const auto shard = a.shard.empty() ? std::optional(Shard{}) : parse_shard(a.shard);
  if (!shard) return cli::usage_error("batch", "--shard: '" + a.shard + "' is not I/N with 0 <= I < N");
  std::error_code ec;
  const bool is_dir = fs::is_directory(a.input, ec);
  auto all = is_dir ? directory_items(a.input) : manifest_items(a.input);
  if (!all) return 2;
  std::sort(all->begin(), all->end(), [](const auto& x, const auto& y) { return x.name < y.name; });
  for (std::size_t k = 1; k < all->size(); ++k)
    if ((*all)[k].name == (*all)[k - 1].name) {
      std::cerr << "lambert batch: two scenes are named \"" << (*all)[k].name << "\": " << (*all)[k - 1].source
                << " and " << (*all)[k].source << "\n";
      return 2;
    }
  const fs::path out_dir = a.output;
  fs::create_directories(out_dir, ec);
  if (!fs::is_directory(out_dir)) return cli::usage_error("batch", "-o: cannot create the directory " + a.output);

  // This shard's scenes; those solved by an earlier run are summarised from their results.
  std::vector<BatchItem> todo;
  std::map<std::string, Row> rows;
  for (std::size_t k = shard->index; k < all->size(); k += shard->count) {
    BatchItem& item = (*all)[k];
    std::string earlier;
    if (read_text_file((out_dir / (item.name + ".result.json")).string(), earlier)) {
      rows[item.name] = summarize(item.name, earlier, -1);
      rows[item.name].state = "done earlier";
    } else {
      todo.push_back(std::move(item));
    }
  }
  std::cerr << "lambert batch: " << rows.size() + todo.size() << " scenes"
            << (shard->count > 1 ? " in shard " + a.shard : "") << ", " << rows.size()
            << " solved earlier, " << todo.size() << " to solve\n";

  std::mutex mutex;
  std::size_t solved = 0, failed = 0, running = 0;
  ProgressBar bar(todo.size());
  BatchEvents events;
  events.started = [&](std::size_t) {
    std::lock_guard lock(mutex);
    ++running;
    bar.update(solved, failed, running);
  };
  events.finished = [&](std::size_t k, const BatchOutcome& o) {
    const BatchItem& item = todo[k];
    Row row;
    try {
      if (o.done) write_atomically(out_dir / (item.name + ".result.json"), o.result);
      else write_atomically(out_dir / (item.name + ".error.txt"), item.source + ": " + o.error + "\n");
      if (o.done) fs::remove(out_dir / (item.name + ".error.txt"), ec);
      row = o.done ? summarize(item.name, o.result, o.seconds) : Row{item.name, "failed", number(o.seconds, "%.2f")};
      if (o.cached) row.state = "done (cached)";
    } catch (const std::exception& e) {
      row = Row{item.name, "failed"};
      std::cerr << "lambert batch: " << e.what() << "\n";
    }
    std::lock_guard lock(mutex);
    --running;
    (row.state == "failed" ? failed : solved)++;
    if (row.state == "failed") std::cerr << (::isatty(2) ? "\r\033[K" : "") << item.source << ": " << o.error << "\n";
    rows[item.name] = row;
    bar.update(solved, failed, running);
  };
  if (a.server.empty()) {
    SolveLimits limits;
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0) limits.memory_bytes = std::uint64_t(pages) * std::uint64_t(page) / a.jobs;
    run_batch_locally(todo, a.jobs, limits, "/proc/self/exe", events);
  } else {
    run_batch_remotely(todo, RemoteBatch{a.server, a.jobs, out_dir}, events);
  }
  bar.end();

  std::vector<Row> table;
  for (auto& [name, row] : rows) table.push_back(row);
  print_table(std::cout, table);
  std::ostringstream csv;
  csv << "scene,state,time_s,patches,key_illuminances,energy_balance\n";
  for (const Row& r : table)
    csv << csv_field(r.name) << "," << csv_field(r.state) << "," << r.time << "," << r.patches << ","
        << csv_field(r.illuminance) << "," << r.balance << "\n";
  const std::string summary = shard->count > 1 ? "summary-" + std::to_string(shard->index) + ".csv" : "summary.csv";
  try {
    write_atomically(out_dir / summary, csv.str());
  } catch (const std::exception& e) {
    std::cerr << "lambert batch: " << e.what() << "\n";
  }
  std::cerr << "lambert batch: " << solved << " solved, " << failed << " failed, " << rows.size() - solved - failed
            << " solved earlier; results in " << out_dir.string() << "\n";
  return failed ? 1 : 0;
}

}  // namespace

cli::CommandSpec command_batch() {
  return {"batch", "solve many scenes (a directory or a JSONL manifest): locally, on a service, or as one shard",
          [](cli::Options& o) {
            auto args = std::make_shared<BatchArgs>();
            o.input("INPUT", args->input, "a directory of *.json scenes, or a JSONL manifest");
            o.output(args->output, "the directory for NAME.result.json, NAME.error.txt and summary.csv")
                .required();
            o.count("-j,--jobs", args->jobs, 1, 256,
                    "scenes solved at once (locally: worker processes; with --server: jobs in flight)");
            o.text("--server", args->server, "submit to this `lambert serve` instead (http://host:port)", "URL");
            o.text("--shard", args->shard,
                   "solve only shard I of N (0-based): every N-th scene by name from the I-th", "I/N");
            o.footer("Runs again after an interruption solve only what has no result yet. docs/SCALING.md has "
                     "Slurm and Kubernetes examples.");
            return [args] { return run_batch(*args); };
          }};
}

}  // namespace lambert
