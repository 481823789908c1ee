// The run loop's thread governor (sim/run/thread_governor.hpp) on paces given
// in code: it keeps all threads where they are faster, falls back to one
// where other work makes them slow, comes back when the cores are free, and
// says so; where nothing competes its probes cost under 1 % of the time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "run/thread_governor.hpp"

namespace dem2d::test {
namespace {

struct Trace {
  double wall = 0.0, on_one = 0.0;  // wall seconds in all, and on one thread
  std::vector<std::string> changes;
};

// Calls of 1000 steps (fewer where the governor caps them), each taking seconds_per_step(threads, wall) per
// step, until `until` s of wall time.
void drive(ThreadGovernor& g, Trace& t, double until, const std::function<double(int, double)>& seconds_per_step) {
  while (t.wall < until) {
    const int threads = g.threads();
    const std::int64_t steps = std::min<std::int64_t>(1000, g.step_cap());
    const double secs = static_cast<double>(steps) * seconds_per_step(threads, t.wall);
    t.wall += secs;
    if (threads == 1) t.on_one += secs;
    if (const std::string change = g.record(steps, secs); !change.empty()) t.changes.push_back(change);
  }
}

TEST(ThreadGovernor, KeepsAllThreadsWhereTheyAreFasterAndItsProbesCostLittle) {
  ThreadGovernor g(2);
  Trace t;
  drive(g, t, 3600.0, [](int threads, double) { return threads == 2 ? 60e-6 : 100e-6; });  // 1.67x on 2
  EXPECT_TRUE(t.changes.empty()) << t.changes.front();
  EXPECT_EQ(g.threads(), 2);
  EXPECT_LT(t.on_one / t.wall, 0.01);  // probes: kProbeSeconds every kLongestPeriod once they keep losing
  EXPECT_GT(t.on_one, 0.0);            // (it does probe)
}

TEST(ThreadGovernor, FallsBackToOneThreadBesideOtherWorkAndReturnsWhenTheCoresAreFree) {
  ThreadGovernor g(2);
  Trace t;
  // two threads 20x slower than one from 10 s to 300 s of wall time (a busy process took a core)
  const auto pace = [](int threads, double wall) {
    const bool busy = wall >= 10.0 && wall < 300.0;
    return threads == 1 ? 100e-6 : busy ? 2000e-6 : 60e-6;
  };
  drive(g, t, 10.0 + ThreadGovernor::kLongestPeriod, pace);
  ASSERT_EQ(t.changes.size(), 1u);
  EXPECT_NE(t.changes[0].find("on 1 thread from here"), std::string::npos) << t.changes[0];
  EXPECT_NE(t.changes[0].find("other work takes the cores"), std::string::npos) << t.changes[0];
  EXPECT_EQ(g.threads(), 1);
  // the collapse costs little: the run spends all but a few % of the busy time on one thread (a probe of
  // two threads starts with a call of kFirstCall at one thread's pace: 20x that at two threads' pace)
  drive(g, t, 300.0, pace);
  EXPECT_EQ(t.changes.size(), 1u);
  EXPECT_GT(t.on_one, 0.97 * (300.0 - 10.0));
  // the cores free again: back on two threads within the longest probe period
  drive(g, t, 300.0 + ThreadGovernor::kLongestPeriod + 2.0, pace);
  ASSERT_EQ(t.changes.size(), 2u);
  EXPECT_NE(t.changes[1].find("on 2 threads from here (the cores are free again)"), std::string::npos) << t.changes[1];
  EXPECT_EQ(g.threads(), 2);
}

TEST(ThreadGovernor, OneThreadIsLeftAlone) {
  ThreadGovernor g(1);
  for (int k = 0; k < 1000; ++k) {
    EXPECT_EQ(g.threads(), 1);
    EXPECT_EQ(g.record(1000, 0.1), "");
  }
}

}  // namespace
}  // namespace dem2d::test
