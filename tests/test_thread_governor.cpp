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

// Like the run loop (sim/run/run.cpp): `steps` steps in calls of ~0.1 s at the last full call's pace (64 steps
// first), each capped by the governor; returns the wall seconds.
double run_loop(ThreadGovernor& g, std::int64_t steps, const std::function<double(int)>& seconds_per_step) {
  double wall = 0.0;
  std::int64_t chunk = 64;
  while (steps > 0) {
    const std::int64_t n = std::min({chunk, steps, g.step_cap()});
    const double secs = static_cast<double>(n) * seconds_per_step(g.threads());
    g.record(n, secs);
    wall += secs, steps -= n;
    if (n == chunk) chunk = std::max<std::int64_t>(1, static_cast<std::int64_t>(static_cast<double>(n) / secs * 0.1));
  }
  return wall;
}

TEST(ThreadGovernor, AShortRunOnTwoThreadsBesideABusyProcessCostsLittleMoreThanOnOne) {
  // The box example (200 grains) beside a process holding a core: one thread 4.0e5 steps/s, two 4.2e4
  // (docs/performance.md). 0.4 s of one thread's work asked on two threads: within 1.2x of one thread's time
  // (the governor's start, its switch and its probes of two threads included).
  ThreadGovernor g(2);
  const double one = 2.5e-6, two = 2.4e-5;
  const std::int64_t steps = 160000;
  const double wall = run_loop(g, steps, [&](int threads) { return threads == 1 ? one : two; });
  EXPECT_LT(wall, 1.2 * static_cast<double>(steps) * one);  // 1.88x before the probes could end early
  EXPECT_EQ(g.threads(), 1);
  // and where two threads are faster (the cores free), a short run keeps them: its probes of one thread end
  // after their first short call
  ThreadGovernor idle(2);
  const double wall_idle = run_loop(idle, steps, [](int threads) { return threads == 1 ? 2.5e-6 : 1.5e-6; });
  EXPECT_EQ(idle.threads(), 2);
  EXPECT_LT(wall_idle, 1.03 * static_cast<double>(steps) * 1.5e-6);
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
