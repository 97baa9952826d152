#include "common/ProgressBar.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "common/CommandLine.h"

namespace rtabmap::tools {
namespace {

constexpr std::chrono::milliseconds kRedrawPeriod(200);
constexpr int kBarWidth = 20;

std::string formatRate(double perSecond) {
  char text[32];
  std::snprintf(text, sizeof(text), perSecond >= 100 ? "%.0f/s" : "%.1f/s", perSecond);
  return text;
}

}  // namespace

std::string formatDuration(double seconds) {
  const long total = std::lround(std::max(0.0, seconds));
  const long hours = total / 3600, minutes = (total / 60) % 60, secs = total % 60;
  char text[32];
  if (hours > 0) {
    std::snprintf(text, sizeof(text), "%ld:%02ld:%02ld", hours, minutes, secs);
  } else {
    std::snprintf(text, sizeof(text), "%ld:%02ld", minutes, secs);
  }
  return text;
}

std::string formatProgress(const std::string& label, std::size_t done, std::size_t total,
                           double elapsedSeconds) {
  std::ostringstream line;
  line << label;
  if (total > 0) {
    const double fraction = std::min(1.0, static_cast<double>(done) / static_cast<double>(total));
    const int filled = static_cast<int>(fraction * kBarWidth);
    line << " [" << std::string(filled, '#') << std::string(kBarWidth - filled, '-') << "] ";
    char percent[8];
    std::snprintf(percent, sizeof(percent), "%3d%%", static_cast<int>(fraction * 100));
    line << percent << ' ' << done << '/' << total;
  } else {
    line << ' ' << done;
  }
  if (elapsedSeconds > 0 && done > 0) {
    const double rate = static_cast<double>(done) / elapsedSeconds;
    line << "  " << formatRate(rate);
    if (total > done) {
      line << "  ETA " << formatDuration(static_cast<double>(total - done) / rate);
    } else {
      line << "  elapsed " << formatDuration(elapsedSeconds);  // done, or total unknown
    }
  }
  return line.str();
}

bool stderrIsTerminal() { return ::isatty(STDERR_FILENO) == 1; }

ProgressBar::ProgressBar(std::string label, std::size_t total, bool live, std::ostream& err)
    : label_(std::move(label)),
      total_(total),
      live_(live),
      err_(err),
      start_(std::chrono::steady_clock::now()),
      lastDraw_(start_ - kRedrawPeriod) {}

ProgressBar::ProgressBar(std::string label, std::size_t total, const CommandLine& cli)
    : ProgressBar(std::move(label), total, stderrIsTerminal() && !cli.json(), std::cerr) {}

ProgressBar::~ProgressBar() {
  try {
    finish();
  } catch (...) {
    // A destructor must not throw; a lost progress line is harmless.
  }
}

void ProgressBar::update(std::size_t done) {
  done_ = done;
  if (!live_ || finished_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - lastDraw_ < kRedrawPeriod) return;
  lastDraw_ = now;
  // "\r" back to the line start, "\033[K" clears what a longer previous line left behind.
  err_ << '\r' << formatProgress(label_, done_, total_, elapsedSeconds()) << "\033[K" << std::flush;
}

void ProgressBar::finish() {
  if (finished_) return;
  finished_ = true;
  if (live_) err_ << '\r';
  err_ << formatProgress(label_, done_, total_, elapsedSeconds());
  if (live_) err_ << "\033[K";
  err_ << '\n' << std::flush;
}

double ProgressBar::elapsedSeconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

}  // namespace rtabmap::tools
