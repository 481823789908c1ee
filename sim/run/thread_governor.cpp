#include "run/thread_governor.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>

#include "run/thread_choice.hpp"

namespace dem2d {

namespace {

std::string pace_text(double per_step) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g steps/s", 1.0 / per_step);
  return text;
}

}  // namespace

ThreadGovernor::ThreadGovernor(int threads) : max_(std::max(1, threads)), kept_(max_), current_(max_) {}

std::int64_t ThreadGovernor::step_cap() const {
  constexpr auto none = std::numeric_limits<std::int64_t>::max();
  if (max_ <= 1 || window_.steps <= 0.0) return none;  // nothing timed yet (the run loop's first call is short)
  double seconds;                                      // how long the call may last at the kept pace
  if (current_ == kept_)
    seconds = period_ - since_probe_;  // until the next probe is due
  else if (probe_.steps <= 0.0)
    seconds = kFirstCall;  // a probe's first call
  else
    return none;
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(std::min(seconds / window_.per_step(), 1e18)));
}

std::string ThreadGovernor::record(std::int64_t steps, double seconds) {
  if (max_ <= 1 || steps <= 0 || !(seconds > 0.0)) return "";
  const auto n = static_cast<double>(steps);
  if (current_ == kept_) {
    window_.steps += n, window_.seconds += seconds;
    if (window_.seconds > kWindowSeconds) {  // an exponentially weighted pace over about the last kWindowSeconds
      const double keep = kWindowSeconds / window_.seconds;
      window_.steps *= keep, window_.seconds *= keep;
    }
    since_probe_ += seconds;
    if (since_probe_ >= period_) {
      current_ = kept_ == max_ ? 1 : max_;
      probe_ = {};
    }
    return "";
  }
  probe_.steps += n, probe_.seconds += seconds;
  const bool losing = probe_.per_step() > (1.0 + kMargin) * window_.per_step();
  if (probe_.seconds < kProbeSeconds && !losing) return "";
  since_probe_ = 0.0;
  const int probed = current_;
  current_ = kept_;
  if (losing || !(probe_.per_step() < (1.0 - kMargin) * window_.per_step())) {
    period_ = std::min(2.0 * period_, kLongestPeriod);
    return "";
  }
  const std::string line = threads_text(kept_) + " ran " + pace_text(window_.per_step()) + ", " +
                           threads_text(probed) + " " + pace_text(probe_.per_step()) + ": on " +
                           threads_text(probed) + " from here" +
                           (probed < max_ ? " (other work takes the cores; the results do not depend on it)"
                                          : " (the cores are free again)");
  kept_ = current_ = probed;
  window_ = probe_;
  period_ = kFirstPeriod;
  return line;
}

}  // namespace dem2d
