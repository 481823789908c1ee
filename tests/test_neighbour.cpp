// Neighbour search: finds every touching pair (against brute force) for size
// ratios up to 10; contact history survives rebuilds; when the lists are
// rebuilt never changes the result; runs are bitwise reproducible, also
// across thread counts.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "engine/diagnostics.hpp"
#include "scene_builder.hpp"

namespace dem2d::test {
namespace {

// All touching pairs by brute force, O(N^2).
std::set<std::pair<int, int>> touching_brute_force(const System& sys) {
  std::set<std::pair<int, int>> out;
  const Particles& p = sys.state.p;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j)
      if (p.active[i] && p.active[j] &&
          std::hypot(p.x[i] - p.x[j], p.y[i] - p.y[j]) < p.radius[i] + p.radius[j])
        out.insert({static_cast<int>(i), static_cast<int>(j)});
  return out;
}

std::set<std::pair<int, int>> touching_in_lists(const System& sys) {
  std::set<std::pair<int, int>> out;
  const PairList& L = sys.state.lists.pairs;
  for (std::size_t i = 0; i + 1 < L.start.size(); ++i)
    for (auto s = static_cast<std::size_t>(L.start[i]); s < static_cast<std::size_t>(L.start[i + 1]); ++s)
      if (L.overlap[s] > 0.0) out.insert({static_cast<int>(i), L.partner[s]});
  return out;
}

TEST(Neighbour, FindsEveryContactWithSizeRatioTen) {
  // d in [0.5, 5] mm: d_max/d_min = 10, poured into a box and settling
  Scene s = boxed_bed(kFull, 300, 0.04, 1.92e6, 7, 0.5e-3, 5e-3);
  System sys(s);
  for (int k = 0; k < 8; ++k) {
    run_for(sys, 0.06);
    const auto brute = touching_brute_force(sys);
    EXPECT_EQ(touching_in_lists(sys), brute) << "t = " << sys.time();
    if (k == 7) {
      EXPECT_GT(brute.size(), 200u);  // not a vacuous comparison: a dense packing by then (~240 contacts)
    }
  }
  EXPECT_GT(sys.state.lists.rebuild_count, 10);
}

// Every grain within skin of a body is a wall candidate, found through the
// cell grid; checked against all grain-body pairs, with many bodies of every
// orientation (short segments and points, as pegs in the bed) among the walls.
TEST(Neighbour, FindsEveryWallCandidateAmongManyBodies) {
  Scene s = boxed_bed(kFull, 300, 0.04, 1.92e6, 3);
  for (int k = 0; k < 40; ++k) {
    const double x = 0.002 + 0.036 * ((k * 37) % 40) / 40.0, y = 0.002 + 0.004 * (k % 10);
    const double len = k % 4 == 0 ? 0.0 : 0.003;  // every fourth a point obstacle
    const double angle = 0.7 * k;
    s.bodies.push_back(BodySpec::segment("peg" + std::to_string(k), x, y, x + len * std::cos(angle), y + len * std::sin(angle), 1e-3));
  }
  System sys(s);
  for (int k = 0; k < 4; ++k) {
    run_for(sys, 0.05);
    std::set<std::pair<int, int>> brute, listed;
    const Particles& p = sys.state.p;
    for (std::size_t i = 0; i < p.size(); ++i)
      for (std::size_t b = 0; b < sys.state.bodies.size(); ++b)
        if (p.active[i] && closest_point(sys.state.bodies.shape[b], p.x[i], p.y[i]).dist <
                               p.radius[i] + sys.state.bodies.radius[b] + sys.state.lists.skin())
          brute.insert({static_cast<int>(i), static_cast<int>(b)});
    const WallList& W = sys.state.lists.walls;
    for (std::size_t sl = 0; sl < W.slots(); ++sl) listed.insert({W.owner[sl], W.body[sl]});
    // the lists were built at the last rebuild: every pair within the skin then is listed,
    // so every pair touching now is; compare the touching ones both ways
    std::set<std::pair<int, int>> touching;
    for (const auto& [i, b] : brute)
      if (closest_point(sys.state.bodies.shape[static_cast<std::size_t>(b)], p.x[static_cast<std::size_t>(i)],
                        p.y[static_cast<std::size_t>(i)])
              .dist < p.radius[static_cast<std::size_t>(i)] + sys.state.bodies.radius[static_cast<std::size_t>(b)])
        touching.insert({i, b});
    for (const auto& ib : touching) EXPECT_TRUE(listed.count(ib)) << "grain " << ib.first << " body " << ib.second;
    if (k == 3) {
      EXPECT_GT(touching.size(), 30u);  // not vacuous: by then the pegs and walls carry the bed
    }
    sys.rebuild();
    listed.clear();
    for (std::size_t sl = 0; sl < W.slots(); ++sl) listed.insert({W.owner[sl], W.body[sl]});
    EXPECT_EQ(listed, brute) << "right after a rebuild the lists hold exactly the pairs within the skin";
  }
}

std::vector<double> state_of(const System& sys) {
  std::vector<double> v;
  for (const auto* a : {&sys.state.p.x, &sys.state.p.y, &sys.state.p.vx, &sys.state.p.vy, &sys.state.p.omega, &sys.state.p.theta})
    v.insert(v.end(), a->begin(), a->end());
  return v;
}

bool bitwise_equal(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// Forcing a rebuild every few steps (history carried over each time) gives
// the same trajectory, bit for bit, as rebuilding only when the skin requires.
TEST(Neighbour, HistorySurvivesRebuildsBitwise) {
  Scene s = boxed_bed(kFull, 120, 0.02);
  System a(s), b(s);
  run_for(a, 0.2);  // in contact, with loaded tangential springs
  run_for(b, 0.2);
  std::size_t loaded = 0;
  for (const double ft : a.state.lists.pairs.ft) loaded += ft != 0.0;
  ASSERT_GT(loaded, 30u);
  const std::int64_t before = b.state.lists.rebuild_count;
  for (int k = 0; k < 400; ++k) {
    a.advance(5);
    b.advance(5);
    b.rebuild();
  }
  EXPECT_GE(b.state.lists.rebuild_count - before, 400);
  EXPECT_TRUE(bitwise_equal(state_of(a), state_of(b)));
}

TEST(Determinism, RerunIsBitwiseIdentical) {
  Scene s = boxed_bed(kFull, 200, 0.03);
  System a(s), b(s);
  run_for(a, 0.1);
  run_for(b, 0.1);
  EXPECT_TRUE(bitwise_equal(state_of(a), state_of(b)));
}

TEST(Determinism, OneTwoAndThreeThreadsAreBitwiseIdentical) {
  // the threads split the grains by their work (System::split_work), which
  // changes at every rebuild; the results must not depend on it
  Scene s = boxed_bed(kFull, 200, 0.03);
  System a(s);
  run_for(a, 0.1);
  for (const int threads : {2, 3}) {
    s.threads = threads;
    System b(s);
    ASSERT_EQ(b.config.threads, threads);
    run_for(b, 0.1);
    EXPECT_GT(b.state.lists.rebuild_count, 5);
    // the ranges cover the grains in order, and no cache line of a per-grain
    // array is shared by two threads' ranges
    ASSERT_EQ(b.work.part.size(), static_cast<std::size_t>(threads) + 1);
    EXPECT_EQ(b.work.part.front(), 0u);
    EXPECT_EQ(b.work.part.back(), b.size());
    for (std::size_t t = 1; t < b.work.part.size(); ++t) {
      EXPECT_LE(b.work.part[t - 1], b.work.part[t]);
      EXPECT_TRUE(b.work.part[t] % System::kGrainsPerLine == 0 || b.work.part[t] == b.size()) << b.work.part[t];
    }
    // shared_end[t] is one past the highest grain of thread t that a lower
    // thread's pair row reads (part[t] if none)
    std::vector<std::size_t> expected(b.work.part.begin(), b.work.part.end() - 1);
    for (std::size_t sl = 0; sl < b.state.lists.pairs.slots(); ++sl) {
      const auto i = static_cast<std::size_t>(b.state.lists.pairs.owner[sl]), j = static_cast<std::size_t>(b.state.lists.pairs.partner[sl]);
      for (std::size_t t = 1; t < expected.size(); ++t)
        if (i < b.work.part[t] && j >= b.work.part[t] && j < b.work.part[t + 1]) expected[t] = std::max(expected[t], j + 1);
    }
    EXPECT_EQ(b.work.shared_end, expected);
    EXPECT_GT(b.work.shared_end[1], b.work.part[1]);  // a packed bed: the threads share grains
    EXPECT_TRUE(bitwise_equal(state_of(a), state_of(b))) << threads << " threads";
    EXPECT_EQ(kinetic_energy(a), kinetic_energy(b));
  }
}

// A run whose thread count changes between calls of advance (the run loop's
// ThreadGovernor, run/thread_governor.hpp) has the bits of a run on one thread.
TEST(Determinism, ChangingTheThreadCountMidRunKeepsTheBits) {
  Scene s = boxed_bed(kFull, 200, 0.03);
  System a(s);
  s.threads = 3;
  System b(s);
  ASSERT_EQ(b.config.threads, 3);
  const std::int64_t steps = static_cast<std::int64_t>(std::llround(0.1 / s.dt));
  const int schedule[] = {3, 1, 2, 3, 1, 3, 2, 1};
  for (std::size_t k = 0; k < std::size(schedule); ++k) {
    b.set_threads(schedule[k]);
    EXPECT_EQ(b.work.part.size(), static_cast<std::size_t>(schedule[k]) + 1);
    EXPECT_EQ(b.work.drift.size(), static_cast<std::size_t>(schedule[k]));
    const std::int64_t n = steps / 8 + (k == 0 ? steps % 8 : 0);
    a.advance(n);
    b.advance(n);
  }
  EXPECT_GT(b.state.lists.rebuild_count, 5);
  EXPECT_TRUE(bitwise_equal(state_of(a), state_of(b)));
  EXPECT_THROW(b.set_threads(4), std::invalid_argument);  // more than it was set up for
  EXPECT_THROW(b.set_threads(0), std::invalid_argument);
}

// Timing the passes of a step (dem2d bench --passes) changes no bit; the calling thread's passes add up to
// the wall time of the steps (but entering and leaving the parallel region), the pair loop takes time on
// every thread, the energy ledger none when it is off, and turning it off drops the totals.
TEST(Determinism, TimingThePassesChangesNoBitAndAccountsForTheStep) {
  Scene s = boxed_bed(kFull, 200, 0.03);
  s.threads = 2;
  System a(s), b(s);
  b.time_passes(true);
  ASSERT_EQ(b.work.pass_totals.size(), 2u);
  const std::int64_t steps = static_cast<std::int64_t>(std::llround(0.05 / s.dt));
  a.advance(steps);
  const auto t0 = std::chrono::steady_clock::now();
  b.advance(steps);
  const double wall = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_TRUE(bitwise_equal(state_of(a), state_of(b)));
  for (std::size_t k = 0; k < b.work.pass_totals.size(); ++k) {
    const PassTotals& t = b.work.pass_totals[k];
    double sum = 0.0;
    for (const double ns : t.ns) {
      EXPECT_GE(ns, 0.0);
      sum += ns;
    }
    EXPECT_LE(sum, wall);
    if (k == 0) {  // the calling thread (the others may start late on a busy machine)
      EXPECT_GT(sum, 0.5 * wall);
    }
    EXPECT_GT(t.ns[static_cast<std::size_t>(Pass::pairs)], 0.0);
    EXPECT_EQ(t.ns[static_cast<std::size_t>(Pass::ledger)], 0.0);
  }
  b.time_passes(false);
  EXPECT_TRUE(b.work.pass_totals.empty());
}

// Where OpenMP makes parallel regions inactive (OMP_MAX_ACTIVE_LEVELS=0, or a System made inside a parallel
// region) a team has one thread: the System splits the work for it instead of waiting at its barriers for
// a second thread that never comes (it hung there), and the results are the same
TEST(Determinism, InactiveParallelRegionsRunOnTheTeamThereIs) {
  Scene s = boxed_bed(kFull, 200, 0.03);
  System a(s);
  run_for(a, 0.05);
  const int levels = omp_get_max_active_levels();
  omp_set_max_active_levels(0);
  s.threads = 2;
  System b(s);
  omp_set_max_active_levels(levels);
  EXPECT_EQ(b.config.threads, 1);
  omp_set_max_active_levels(0);
  run_for(b, 0.05);
  omp_set_max_active_levels(levels);
  EXPECT_TRUE(bitwise_equal(state_of(a), state_of(b)));
}

}  // namespace
}  // namespace dem2d::test
