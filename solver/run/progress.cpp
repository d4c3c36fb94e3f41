#include "run/progress.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

namespace capsim {

void ProgressReport::start(double time, long step) {
  begin_ = Clock::now();
  first_time_ = time;
  first_step_ = step;
}

void ProgressReport::report(double time, long step, double dt, long rejected,
                            bool force) {
  const auto now = Clock::now();
  if (quiet_ || (!force && now - last_ < std::chrono::seconds(2)))
    return;
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - begin_).count();
  const double rate = (step - first_step_) / std::max(elapsed, 1e-9);
  const double done = time - first_time_, left = t_end_ - time;
  const double eta = done > 0 ? elapsed * left / done : 0;
  const std::string count =
      rejected >= 0 ? " (" + std::to_string(rejected) + " rejected)" : "";
  std::fprintf(stderr,
               "capsim: t = %.3f / %.3f (%5.1f%%)  step %ld  dt %.3g%s  %.1f steps/s  "
               "ETA %.0f s\n",
               time, t_end_, 100.0 * time / t_end_, step, dt, count.c_str(), rate, eta);
}

} // namespace capsim
