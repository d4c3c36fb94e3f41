#pragma once
// The progress lines of a long run on stderr, at most one every 2 s (and one at the end):
// gammadot t against t_end, the step, its size, the rate and the time left, estimated
// from this invocation's pace.
#include <chrono>

namespace capsim {

class ProgressReport {
public:
  ProgressReport(bool quiet, double t_end) : quiet_(quiet), t_end_(t_end) {}
  // Where this invocation's stepping begins.
  void start(double time, long step);
  // After a step; rejected < 0 for a fixed step (no count shown). `force`: the last line.
  void report(double time, long step, double dt, long rejected, bool force);

private:
  using Clock = std::chrono::steady_clock;
  bool quiet_;
  double t_end_;
  Clock::time_point begin_{}, last_{};
  double first_time_ = 0;
  long first_step_ = 0;
};

} // namespace capsim
