// The local and remote runners of `lambert batch` (see batch_runner.h). cpp-httplib's client is used
// here and its server in http_server.cpp only.
#include "server/batch_runner.h"

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

namespace lambert {
namespace {

using Clock = std::chrono::steady_clock;
using json = nlohmann::json;
using namespace std::chrono_literals;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Runs `work(k)` for every item on `threads` threads, each taking the next item when it is free.
void for_each_item(std::size_t count, std::size_t threads, const std::function<void(std::size_t)>& work) {
  std::atomic<std::size_t> next{0};
  std::vector<std::thread> pool;
  for (std::size_t t = 0; t < std::max<std::size_t>(1, std::min(threads, count)); ++t)
    pool.emplace_back([&] {
      for (std::size_t k; (k = next.fetch_add(1)) < count;) work(k);
    });
  for (auto& t : pool) t.join();
}

std::string local_failure(const SolveProcessOutcome& o, std::uint64_t memory_bytes) {
  using Kind = SolveProcessOutcome::Kind;
  switch (o.kind) {
    case Kind::Failed: return o.reason;
    case Kind::OutOfMemory:
      return "the solve ran out of memory (its limit is " + std::to_string(memory_bytes >> 20) +
             " MiB: the machine's memory divided by --jobs)";
    case Kind::Internal: return "internal error: " + o.reason;
    case Kind::Crashed: return o.reason.empty() ? std::string("the solve process crashed") : o.reason;
    case Kind::Done: case Kind::Killed: break;
  }
  return "the solve was stopped";
}

// ---- remote -----------------------------------------------------------------------------------------

// The message of a service's error answer, or the status when it has none.
std::string service_error(const httplib::Result& res) {
  if (!res) return "no answer from the service: " + httplib::to_string(res.error());
  const json body = json::parse(res->body, nullptr, false);
  if (body.is_object() && body.contains("error") && body["error"].is_object()) {
    const json& e = body["error"];
    const std::string pointer = e.value("pointer", "");
    return (pointer.empty() ? "" : pointer + ": ") + e.value("message", "HTTP " + std::to_string(res->status));
  }
  return "HTTP " + std::to_string(res->status);
}

class RemoteItem {
 public:
  RemoteItem(const RemoteBatch& remote, const BatchItem& item)
      : remote_(remote), item_(item), id_file_(remote.ids_dir / (item.name + ".job")), client_(remote.url) {
    client_.set_connection_timeout(10, 0);
    client_.set_read_timeout(120, 0);
    client_.set_write_timeout(120, 0);
  }

  BatchOutcome run() {
    const auto t0 = Clock::now();
    BatchOutcome out;
    std::string id = earlier_id();
    if (id.empty() && !submit(id, out)) return finish(out, t0);
    // Poll until final: every 0.2 s at first, then up to every 2 s.
    for (auto wait = 200ms;; wait = std::min<std::chrono::milliseconds>(wait * 3 / 2, 2000ms)) {
      auto res = client_.Get("/v1/jobs/" + id);
      if (res && res->status == 404) {  // expired or deleted meanwhile: submit it again
        std::filesystem::remove(id_file_);
        if (!submit(id, out)) return finish(out, t0);
        continue;
      }
      const json status = res && res->status == 200 ? json::parse(res->body, nullptr, false) : json();
      const std::string state = status.is_object() ? status.value("state", "") : "";
      if (state == "done") {
        out.cached = out.cached || status.value("cached", false);
        auto result = client_.Get("/v1/jobs/" + id + "/result");
        if (result && result->status == 200) {
          out.done = true;
          out.result = std::move(result->body);
        } else {
          out.error = "cannot fetch the result: " + service_error(result);
        }
        return finish(out, t0);
      }
      if (state == "failed" || state == "cancelled") {
        out.error = state == "failed" ? status.value("error", std::string("failed")) : "the job was cancelled";
        return finish(out, t0);
      }
      std::this_thread::sleep_for(wait);  // queued, running, or the service briefly unreachable
    }
  }

 private:
  std::string earlier_id() const {
    std::ifstream in(id_file_);
    std::string url, id;
    in >> url >> id;
    return url == remote_.url ? id : "";
  }

  // POSTs the scene, waiting out a full queue; false (with the reason in `out`) when refused.
  bool submit(std::string& id, BatchOutcome& out) {
    for (;;) {
      auto res = client_.Post("/v1/jobs", item_.scene_json, "application/json");
      if (res && res->status == 202) {
        const json status = json::parse(res->body, nullptr, false);
        id = status.is_object() ? status.value("id", "") : "";
        out.cached = status.is_object() && status.value("cached", false);
        std::ofstream(id_file_) << remote_.url << " " << id << "\n";
        return !id.empty();
      }
      if (res && res->status == 503) {
        const int retry = std::atoi(res->get_header_value("Retry-After").c_str());
        std::this_thread::sleep_for(std::chrono::seconds(std::clamp(retry, 1, 60)));
        continue;
      }
      out.error = service_error(res);
      return false;
    }
  }

  BatchOutcome& finish(BatchOutcome& out, Clock::time_point t0) {
    out.seconds = since(t0);
    std::error_code ec;
    std::filesystem::remove(id_file_, ec);
    return out;
  }

  const RemoteBatch& remote_;
  const BatchItem& item_;
  std::filesystem::path id_file_;
  httplib::Client client_;
};

}  // namespace

void run_batch_locally(const std::vector<BatchItem>& items, std::size_t jobs, const SolveLimits& limits,
                       const std::filesystem::path& executable, const BatchEvents& events) {
  for_each_item(items.size(), jobs, [&](std::size_t k) {
    events.started(k);
    const auto t0 = Clock::now();
    BatchOutcome out;
    SolveLimits own = limits;
    own.scene_dir = items[k].scene_dir;
    try {
      SolveProcess process(executable, items[k].scene_json, own);
      while (process.wait(200ms, [&](const std::string& line) {
        std::cerr << "lambert batch: " << items[k].name << ": " << line << "\n";
      })) {
      }
      SolveProcessOutcome o = process.outcome();
      out.done = o.kind == SolveProcessOutcome::Kind::Done;
      if (out.done) out.result = std::move(o.result);
      else out.error = local_failure(o, limits.memory_bytes);
    } catch (const std::exception& e) {
      out.error = e.what();
    }
    out.seconds = since(t0);
    events.finished(k, out);
  });
}

void run_batch_remotely(const std::vector<BatchItem>& items, const RemoteBatch& remote, const BatchEvents& events) {
  for_each_item(items.size(), remote.jobs, [&](std::size_t k) {
    events.started(k);
    RemoteItem item(remote, items[k]);
    events.finished(k, item.run());
  });
}

}  // namespace lambert
