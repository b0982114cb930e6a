#include "server/cli_progress.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

namespace lambert {
namespace {

constexpr double kMinFractionForEstimate = 0.02;
constexpr double kMinSecondsForEstimate = 1.0;
constexpr double kRedrawInterval_s = 0.1;  // ten lines a second at most

std::string time_left(double seconds) {
  char text[48];
  if (seconds < 90)
    std::snprintf(text, sizeof text, "about %.0f s left", std::ceil(seconds));
  else if (seconds < 5400)
    std::snprintf(text, sizeof text, "about %.0f min left", std::round(seconds / 60));
  else
    std::snprintf(text, sizeof text, "about %.1f h left", seconds / 3600);
  return text;
}

struct TerminalLine {
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  double last_drawn_s = -1;
  int last_percent = -1;
  std::string stage = "solving";
  double fraction = 0;

  void draw(double f) {
    fraction = f;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const int percent = static_cast<int>(std::floor(100 * fraction));
    const bool done = fraction >= 1;
    if (!done && percent == last_percent && elapsed - last_drawn_s < kRedrawInterval_s) return;
    last_percent = percent;
    last_drawn_s = elapsed;
    // \033[K clears what a longer earlier line left to the right.
    std::fprintf(stderr, "\r%s\033[K%s", progress_text(stage, fraction, elapsed).c_str(), done ? "\n" : "");
  }
};

}  // namespace

std::string progress_text(std::string_view stage, double fraction, double elapsed_s) {
  const double f = std::clamp(fraction, 0.0, 1.0);
  char text[96];
  std::snprintf(text, sizeof text, "%.*s: %3d %%", static_cast<int>(stage.size()), stage.data(),
                static_cast<int>(std::floor(100 * f)));
  std::string line = text;
  if (f >= 1) {
    std::snprintf(text, sizeof text, " (%.1f s)", elapsed_s);
    return line + text;
  }
  if (f >= kMinFractionForEstimate && elapsed_s >= kMinSecondsForEstimate)
    line += " (" + time_left(elapsed_s * (1 - f) / f) + ")";
  return line;
}

void show_progress_on_terminal(SolveControl& control) {
  if (!isatty(STDERR_FILENO)) return;
  auto line = std::make_shared<TerminalLine>();
  control.progress = [line](double f) { line->draw(f); };
  control.stage = [line](SolveStage stage) {
    line->stage = stage_name(stage);
    line->last_percent = -1;  // redraw at once with the new name
    line->draw(line->fraction);
  };
}

}  // namespace lambert
