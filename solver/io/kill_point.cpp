#include "io/kill_point.hpp"

#include <csignal>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace capsim {
namespace {

struct KillPlan {
  bool armed = false;
  KillPoint point{};
  long countdown = 0;
};

const char* const kNames[] = {"series_written", "series_renamed", "checkpoint_written",
                              "checkpoint_closed"};

KillPlan parse_plan(const char* value) {
  KillPlan plan;
  if (!value || !*value)
    return plan;
  const std::string text = value;
  const std::size_t colon = text.find(':');
  const std::string name = text.substr(0, colon);
  for (int i = 0; i < 4; ++i)
    if (name == kNames[i])
      plan.point = static_cast<KillPoint>(i), plan.armed = true;
  char* end = nullptr;
  if (colon != std::string::npos)
    plan.countdown = std::strtol(text.c_str() + colon + 1, &end, 10);
  if (!plan.armed || plan.countdown < 1 || !end || *end)
    throw std::runtime_error("CAPSIM_TEST_KILL_AT: expected <point>:<k> with k >= 1 and "
                             "point one of series_written, series_renamed, "
                             "checkpoint_written, checkpoint_closed; got '" +
                             text + "'");
  return plan;
}

} // namespace

void kill_point(KillPoint point) {
  static KillPlan plan = parse_plan(std::getenv("CAPSIM_TEST_KILL_AT"));
  if (!plan.armed || point != plan.point)
    return;
  if (--plan.countdown == 0)
    std::raise(SIGKILL);
}

} // namespace capsim
