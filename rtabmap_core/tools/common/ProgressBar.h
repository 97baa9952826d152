#pragma once
// Progress of a long run on stderr, e.g.
//   processing images [#########-----------]  45% 450/1000  12.3/s  ETA 0:44
// Live mode redraws one line in place at most every 200 ms; it is meant for a terminal. When
// stderr is not a terminal or the tool prints --json, only a final summary line is written, so
// logs and CI output stay clean.
#include <chrono>
#include <cstddef>
#include <ostream>
#include <string>

namespace rtabmap::tools {

class CommandLine;

class ProgressBar {
 public:
  // total = 0 means unknown: the line then shows the count and the rate, without ETA.
  ProgressBar(std::string label, std::size_t total, bool live, std::ostream& err);
  // Live when stderr is a terminal and the tool was not asked for --json; writes to std::cerr.
  ProgressBar(std::string label, std::size_t total, const CommandLine& cli);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // Sets the number of items done (redraws if live and the throttle allows).
  void update(std::size_t done);
  void increment(std::size_t count = 1) { update(done_ + count); }
  // Writes the final line (always, even when not live). Called by the destructor if needed.
  void finish();

  std::size_t done() const { return done_; }

 private:
  double elapsedSeconds() const;

  std::string label_;
  std::size_t total_;
  bool live_;
  std::ostream& err_;
  std::size_t done_ = 0;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point lastDraw_;
};

// One progress line, without "\r" or newline: label, bar and percent (if total > 0),
// done/total, rate per second and ETA (when they can be estimated).
std::string formatProgress(const std::string& label, std::size_t done, std::size_t total,
                           double elapsedSeconds);
// "1:05", "1:02:03": durations for humans.
std::string formatDuration(double seconds);
// True if stderr is an interactive terminal.
bool stderrIsTerminal();

}  // namespace rtabmap::tools
