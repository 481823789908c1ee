// Stage `network`: hand-built contact networks with known answers, the
// run-level summaries, the settings file, and the stage on the quick run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

#include <sys/stat.h>

#include "common/stage_config.hpp"
#include "network/network_stage.hpp"
#include "network/percolation_loss.hpp"
#include "runfile/h5.hpp"
#include "quick_study.hpp"
#include "temp_dir.hpp"

namespace dem2d::analysis {
namespace {

// A 30 mm wide cell (inner faces x = 0, 0.03; floor y = 0) with an intruder
// whose segment runs from x = 0.011 to 0.019 at y = 0.010 (cap radius 1 mm):
// bodies left 0, right 1, floor 2, intruder 3 (partner j = -1 - body).
constexpr std::int32_t kLeft = -1, kRight = -2, kFloor = -3, kIntruder = -4;

Snapshot cell(const std::vector<Vec2>& grains) {
  Snapshot s;
  s.position = grains;
  s.velocity.assign(grains.size(), {});
  s.omega.assign(grains.size(), 0.0);
  s.active.assign(grains.size(), 1);
  s.diameter.assign(grains.size(), 0.003);
  s.mass.assign(grains.size(), 1e-5);
  s.bodies = {Body::segment("left", -0.001, -0.001, -0.001, 0.1, 0.002, "left_wall"),
              Body::segment("right", 0.031, -0.001, 0.031, 0.1, 0.002, "right_wall"),
              Body::segment("floor", -0.001, -0.001, 0.031, -0.001, 0.002, "floor"),
              Body::segment("intruder", 0.011, 0.010, 0.019, 0.010, 0.002, "intruder")};
  return s;
}

void touch(Snapshot& s, std::int32_t i, std::int32_t j, double fn) { s.contacts.add(i, j, fn, 1e-6, 1.0, 0.0); }

struct Built {
  Snapshot s;
  PulloffGeometry geo;
  std::vector<Partner> partners;
  ContactGraph g;
};
Built build(Snapshot s) {
  Built b{std::move(s), {}, {}, {}};
  b.geo = pulloff_geometry(b.s);
  b.partners = classify_contacts(b.s, b.geo);
  b.g = build_contact_graph(b.s, b.partners);
  return b;
}

// Grains 0, 1 lead from the intruder's left end to the left wall, grains 2, 3
// from its right end to the right wall (fn = 10); grains 4, 5 touch each other
// weakly (fn = 1), so the mean is below 10 and the chains are strong.
Snapshot two_chains() {
  Snapshot s = cell({{0.008, 0.011}, {0.002, 0.012}, {0.022, 0.011}, {0.028, 0.012}, {0.015, 0.030}, {0.018, 0.030}});
  touch(s, 0, kIntruder, 10), touch(s, 0, 1, 10), touch(s, 1, kLeft, 10);
  touch(s, 2, kIntruder, 10), touch(s, 2, 3, 10), touch(s, 3, kRight, 10);
  touch(s, 4, 5, 1);
  return s;
}

// An earlier stage's metrics given as input (--spectrum-metrics here; --fill-metrics and --cg-metrics read
// the same way): what is not a regular file is refused naming it, and a pipe's writer is waited for, not
// for ever (a pipe nobody wrote to blocked the stage for ever; /dev/zero was read until memory ran out).
TEST(NetworkInputs, EarlierMetricsAreARegularFileOrAPipeWithAWriter) {
  const auto message = [](const std::string& path) {
    try {
      return std::to_string(read_top_layer_height_mm(path));
    } catch (const StageError& e) {
      return std::string(e.what());
    }
  };
  EXPECT_EQ(message("/dev/zero"), "/dev/zero: cannot read the spectrum metrics: not a regular file");
  const test::TempDir dir;
  EXPECT_EQ(message(dir.path().string()), dir.path().string() + ": cannot read the spectrum metrics: not a regular file");
  EXPECT_EQ(message(dir.path().string() + "/none.json"), dir.path().string() + "/none.json: no such file (spectrum metrics)");
  EXPECT_EQ(message(dir.file("cut.json", "{\"spectrum\": {")).rfind(dir.path().string() + "/cut.json: not JSON (", 0), 0u);
  EXPECT_EQ(message(dir.file("m.json", "{\"spectrum\": {\"top_layer_height_mm\": 87.5}}")), "87.500000");
  const std::string pipe = (dir.path() / "late.json").string();
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  std::thread writer([&] {  // a writer that comes late
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    std::ofstream(pipe) << "{\"spectrum\": {\"top_layer_height_mm\": 12.25}}";
  });
  EXPECT_EQ(message(pipe), "12.250000");
  writer.join();
}

// With cohesion, tensile contacts (fn < 0, touching or across a gap) are
// neither edges nor part of the mean: the graph and the threshold are those
// of the compressive network.
TEST(NetworkGraph, TensileContactsAreNotEdges) {
  Snapshot s = two_chains();
  s.contacts.add(4, 5, -0.4, 1e-7, 1.0, 0.0);    // pulled, touching
  s.contacts.add(1, 5, -0.2, -3e-5, 1.0, 0.0);   // attracting across a gap
  const Built b = build(std::move(s));
  EXPECT_EQ(b.g.edges(), 7u);
  EXPECT_DOUBLE_EQ(b.g.mean_fn, 61.0 / 7.0);
}

TEST(NetworkGraph, VerticesAndEdgesFollowTheContacts) {
  Snapshot s = two_chains();
  touch(s, 5, kFloor, 0.0);  // no load: no edge
  const Built b = build(std::move(s));
  EXPECT_EQ(boost::num_vertices(b.g.graph), 6u + 4u);
  EXPECT_EQ(b.g.edges(), 7u);
  EXPECT_DOUBLE_EQ(b.g.mean_fn, 61.0 / 7.0);
  EXPECT_EQ(b.partners[6], Partner::grain);
  EXPECT_EQ(b.partners[7], Partner::floor);
  EXPECT_NEAR(b.geo.height(), 0.010, 1e-15);
  EXPECT_NEAR(b.geo.length(), 0.010, 1e-15);
  EXPECT_NEAR(b.geo.end_to_wall(), 0.010, 1e-15);
}

TEST(NetworkPercolation, ChainsToBothWallsPercolate) {
  const Built b = build(two_chains());
  const Percolation p = percolation(b.g, b.g.mean_fn, FloorRule::vertex_removed, b.g.intruder());
  EXPECT_TRUE(p.left);
  EXPECT_TRUE(p.right);
  EXPECT_TRUE(p.both());
}

TEST(NetworkPercolation, RemovingAGrainCutsItsChain) {
  Snapshot s = two_chains();
  s.active[1] = 0;  // grain 1 left the domain: its contacts are no edges
  const Built b = build(std::move(s));
  const Percolation p = percolation(b.g, b.g.mean_fn, FloorRule::vertex_removed, b.g.intruder());
  EXPECT_FALSE(p.left);
  EXPECT_TRUE(p.right);
  EXPECT_FALSE(p.both());
  EXPECT_TRUE(p.either());
}

TEST(NetworkPercolation, AWeakLinkBreaksTheStrongNetworkOnly) {
  Snapshot s = two_chains();
  s.contacts.fn[1] = 2.0;  // grain 0 - grain 1 below the mean
  const Built b = build(std::move(s));
  EXPECT_FALSE(percolation(b.g, b.g.mean_fn, FloorRule::vertex_removed, b.g.intruder()).left);
  EXPECT_TRUE(percolation(b.g, 0.0, FloorRule::vertex_removed, b.g.intruder()).left);  // whole network
}

TEST(NetworkPercolation, EmptyNetworkPercolatesNowhere) {
  const Built b = build(cell({{0.005, 0.005}, {0.025, 0.005}}));
  EXPECT_EQ(b.g.edges(), 0u);
  EXPECT_EQ(b.g.mean_fn, 0.0);
  const Percolation p = percolation(b.g, 0.0, FloorRule::vertex_removed, b.g.intruder());
  EXPECT_FALSE(p.either());
  const KeystoneAnalysis k = analyse_keystones(b.g, b.s, b.geo, 0.0, FloorRule::vertex_removed, 0.0015);
  EXPECT_EQ(k.flow_left, 0.0);
  EXPECT_TRUE(k.candidates.empty());
  EXPECT_TRUE(k.keystones(0.5).empty());
  EXPECT_TRUE(std::isnan(region_fabric(b.s, b.partners, 0.0, 0.0, 1.0, 1).anisotropy));
}

TEST(NetworkPercolation, APathThroughTheFloorDoesNotCount) {
  // intruder - grain 0 - floor - grain 1 - left wall: linked only through the floor.
  Snapshot s = cell({{0.009, 0.0015}, {0.0015, 0.0015}, {0.015, 0.030}, {0.018, 0.030}});
  touch(s, 0, kIntruder, 10), touch(s, 0, kFloor, 10), touch(s, 1, kFloor, 10), touch(s, 1, kLeft, 10);
  touch(s, 2, 3, 1);
  const Built b = build(s);
  EXPECT_FALSE(percolation(b.g, b.g.mean_fn, FloorRule::vertex_removed, b.g.intruder()).left);
  EXPECT_FALSE(percolation(b.g, 0.0, FloorRule::bottom_layer_removed, b.g.intruder()).left);
  EXPECT_EQ(analyse_keystones(b.g, b.s, b.geo, 0.0, FloorRule::vertex_removed, 0.0015).flow_left, 0.0);

  // With a direct contact between the two bottom grains, the path runs through
  // grains: it counts when only the floor vertex is removed, not when the
  // grains touching the floor are removed as well.
  touch(s, 0, 1, 10);
  const Built c = build(s);
  EXPECT_TRUE(percolation(c.g, c.g.mean_fn, FloorRule::vertex_removed, c.g.intruder()).left);
  EXPECT_FALSE(percolation(c.g, c.g.mean_fn, FloorRule::bottom_layer_removed, c.g.intruder()).left);
}

TEST(NetworkPercolation, TheOtherWallIsNoShortcut) {
  // intruder - grain 0 - right wall - grain 1 - left wall: walls end paths.
  Snapshot s = cell({{0.021, 0.010}, {0.002, 0.040}, {0.015, 0.030}, {0.018, 0.030}});
  touch(s, 0, kIntruder, 10), touch(s, 0, kRight, 10), touch(s, 1, kRight, 10), touch(s, 1, kLeft, 10);
  touch(s, 2, 3, 1);
  const Built b = build(s);
  const Percolation p = percolation(b.g, b.g.mean_fn, FloorRule::vertex_removed, b.g.intruder());
  EXPECT_TRUE(p.right);
  EXPECT_FALSE(p.left);
}

// The grain with the highest index links like any other: a chain intruder -
// 2 - 3 - 4 - left wall percolates through grain 4, the last of the list,
// and so does the chain the other way round (4 on the intruder, 2 on the
// wall). Grains 0 and 1 hold a weak contact (below the mean force).
TEST(NetworkPercolation, TheLastGrainLinksLikeAnyOther) {
  for (const bool reversed : {false, true}) {
    SCOPED_TRACE(reversed ? "grain 4 on the intruder" : "grain 4 on the wall");
    Snapshot s = cell({{0.030, 0.030}, {0.033, 0.030}, {0.012, 0.012}, {0.008, 0.014}, {0.004, 0.016}});
    touch(s, 0, 1, 1);
    touch(s, reversed ? 4 : 2, kIntruder, 10), touch(s, 2, 3, 10), touch(s, 3, 4, 10);
    touch(s, reversed ? 2 : 4, kLeft, 10);
    const Built b = build(s);
    const Percolation p = percolation(b.g, b.g.mean_fn, FloorRule::vertex_removed, b.g.intruder());
    EXPECT_TRUE(p.left);
    EXPECT_FALSE(p.right);
  }
}

TEST(NetworkKeystones, ASingleEndGrainCarryingAllTheLoadIsAKeystone) {
  // Grain 0 at the left end is the only way from the intruder to the left wall;
  // grain 4 on the middle of the intruder's top leads nowhere.
  Snapshot s = two_chains();
  s.position.push_back({0.015, 0.0125});
  s.diameter.push_back(0.003), s.active.push_back(1), s.mass.push_back(1e-5);
  touch(s, 6, kIntruder, 10);
  const Built b = build(std::move(s));
  const KeystoneAnalysis k = analyse_keystones(b.g, b.s, b.geo, b.g.mean_fn, FloorRule::vertex_removed, 0.0015);
  EXPECT_DOUBLE_EQ(k.flow_left, 10.0);
  EXPECT_DOUBLE_EQ(k.flow_right, 10.0);
  ASSERT_EQ(k.candidates.size(), 2u);  // grains 0 and 2; grain 6 is not at an end
  EXPECT_EQ(k.candidates[0].grain, 0);
  EXPECT_EQ(k.candidates[0].end, -1);
  EXPECT_DOUBLE_EQ(k.candidates[0].share_left, 1.0);
  EXPECT_DOUBLE_EQ(k.candidates[0].share_right, 0.0);
  EXPECT_EQ(k.keystones(0.5), (std::vector<std::int32_t>{0, 2}));
  // Removing it disconnects the intruder from the left wall.
  Snapshot without = b.s;
  without.active[0] = 0;
  const Built c = build(std::move(without));
  EXPECT_FALSE(percolation(c.g, b.g.mean_fn, FloorRule::vertex_removed, c.g.intruder()).left);
}

TEST(NetworkKeystones, MaxFlowIsTheMinimumCutAndSharesSplitParallelPaths) {
  // Two end grains a (0) and b (1) on the left end: intruder-a 5, intruder-b 3,
  // a-left 2, b-left 10, a-b 1. Min cut {a-left, a-b, intruder-b} = 6.
  Snapshot s = cell({{0.0085, 0.011}, {0.0085, 0.008}});
  touch(s, 0, kIntruder, 5), touch(s, 1, kIntruder, 3), touch(s, 0, kLeft, 2), touch(s, 1, kLeft, 10);
  touch(s, 0, 1, 1);
  const Built b = build(std::move(s));
  const KeystoneAnalysis k = analyse_keystones(b.g, b.s, b.geo, 0.0, FloorRule::vertex_removed, 0.0015);
  EXPECT_DOUBLE_EQ(k.flow_left, 6.0);
  EXPECT_DOUBLE_EQ(k.flow_right, 0.0);
  ASSERT_EQ(k.candidates.size(), 2u);
  // Without a: 3 through b; without b: 2 through a.
  EXPECT_DOUBLE_EQ(k.candidates[0].share_left, 0.5);
  EXPECT_DOUBLE_EQ(k.candidates[1].share_left, 4.0 / 6.0);
  EXPECT_EQ(k.keystones(0.5), (std::vector<std::int32_t>{0, 1}));
  EXPECT_EQ(k.keystones(0.6), (std::vector<std::int32_t>{1}));
  EXPECT_TRUE(k.keystones(0.7).empty());
}

TEST(NetworkFabric, KnownDirections) {
  const Fabric h = fabric({{1, 0}, {-1, 0}, {1, 0}}, 1);
  EXPECT_NEAR(h.anisotropy, 2.0, 1e-12);
  EXPECT_NEAR(h.angle_deg, 0.0, 1e-9);
  const double r = std::sqrt(0.5);
  const Fabric iso = fabric({{1, 0}, {r, r}, {0, 1}, {-r, r}}, 1);
  EXPECT_NEAR(iso.anisotropy, 0.0, 1e-12);
  const Fabric v = fabric({{0, 1}, {0, 1}, {1, 0}, {0, -1}}, 1);  // 3 vertical, 1 horizontal
  EXPECT_NEAR(v.anisotropy, 1.0, 1e-12);
  EXPECT_NEAR(v.angle_deg, 90.0, 1e-9);
  EXPECT_NEAR(v.noise, std::sqrt(std::acos(-1.0) / 4.0), 1e-12);
  EXPECT_NEAR(v.debiased, 0.0, 1e-12);  // a^2 = 1 = 4/n: not resolved with 4 contacts
  EXPECT_NEAR(h.debiased, std::sqrt(4.0 - 4.0 / 3.0), 1e-12);
  EXPECT_TRUE(std::isnan(fabric({{1, 0}}, 2).anisotropy));
}

TEST(NetworkFabric, RegionSelectsStrongGrainContactsAboveTheIntruder) {
  Snapshot s = cell({{0.010, 0.020}, {0.013, 0.020}, {0.010, 0.005}, {0.013, 0.005}, {0.020, 0.020}});
  s.contacts.add(0, 1, 10, 1e-6, -1, 0);  // above, strong, horizontal
  s.contacts.add(2, 3, 10, 1e-6, -1, 0);  // below the intruder
  s.contacts.add(0, 4, 1, 1e-6, 0, 1);    // weak
  s.contacts.add(4, kRight, 10, 1e-6, -1, 0);  // a wall contact
  const Built b = build(std::move(s));
  const Fabric f = region_fabric(b.s, b.partners, 5.0, 0.010, 0.055, 1);
  EXPECT_EQ(f.contacts, 1);
  EXPECT_NEAR(f.anisotropy, 2.0, 1e-12);
}

TEST(NetworkProfile, LossHeightIsWherePercolationStaysBelowTheLevel) {
  const HeightBins bins{0.003};
  // bins [0,3) [3,6) [6,9) [9,12) mm: fractions 1, 1, 0.5, 0 and 0 again in [12, 15).
  const std::vector<double> h = {0.001, 0.002, 0.004, 0.005, 0.007, 0.008, 0.010, 0.011, 0.013};
  const std::vector<std::uint8_t> f = {1, 1, 1, 1, 1, 0, 0, 0, 0};
  const PercolationProfile p = percolation_profile(bins, h, f);
  ASSERT_EQ(p.fraction.size(), 5u);
  EXPECT_DOUBLE_EQ(p.fraction[2], 0.5);
  EXPECT_NEAR(*loss_height(p, 0.5), 0.009, 1e-15);
  EXPECT_NEAR(*loss_height(p, 0.75), 0.006, 1e-15);
  // a late percolating bin moves it up; percolating in the highest bin: never lost
  std::vector<std::uint8_t> g = f;
  g[7] = 1;
  EXPECT_NEAR(*loss_height(percolation_profile(bins, h, g), 0.5), 0.012, 1e-15);
  g[8] = 1;
  EXPECT_FALSE(loss_height(percolation_profile(bins, h, g), 0.5).has_value());
  // never percolating: lost from the lowest bin
  EXPECT_NEAR(*loss_height(percolation_profile(bins, h, std::vector<std::uint8_t>(h.size(), 0)), 0.5), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(flagged_fraction(h, f, 0.0, 0.009), 5.0 / 6.0);
}

// The loss is reported only where the step in the flags is significant, and
// a none says whether it could have seen the paper's loss (150 mm bed, the
// loss planted 45 mm below its surface, found within 9 mm).
TEST(NetworkProfile, LossIsATestAndANoneCarriesItsPower) {
  LossTestSettings s;
  s.bins = HeightBins{0.003}, s.depth = 0.045, s.tolerance = 0.009;
  const double surface = 0.150;
  std::vector<double> h;
  for (int k = 0; k < 130; ++k) h.push_back(0.020 + 0.001 * k);  // 20 ... 149 mm, one snapshot a mm
  const auto flags = [&](double loss, double flip, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<std::uint8_t> f;
    for (const double x : h) f.push_back((x < loss) != (u(rng) < flip));
    return f;
  };
  // lost at 105 mm with 5 % of the flags flipped: found, at the rule's height
  const LossTest found = percolation_loss(h, flags(0.105, 0.05, 1), surface, s);
  EXPECT_EQ(found.outcome, "found");
  ASSERT_TRUE(found.height);
  EXPECT_NEAR(*found.height, 0.105, 0.006);
  EXPECT_EQ(found.height, found.rule_height);
  EXPECT_LT(found.p_value, 0.01);
  // percolating at every height: none, and the power says a loss at 105 mm would have been seen
  const LossTest never = percolation_loss(h, flags(1.0, 0.0, 1), surface, s);
  EXPECT_FALSE(never.height);
  EXPECT_EQ(never.outcome.rfind("none: the strong network still percolates in the highest height bin", 0), 0u)
      << never.outcome;
  EXPECT_EQ(never.power.power, 1.0);
  // coin flips: no loss, and the power is too low to call it absent
  const LossTest coin = percolation_loss(h, flags(1.0, 0.5, 2), surface, s);
  EXPECT_FALSE(coin.height);
  EXPECT_GT(coin.p_value, 0.01);
  EXPECT_LT(coin.power.power, 0.8);
  EXPECT_EQ(coin.outcome.rfind("undetermined: ", 0), 0u) << coin.outcome;
  // percolating everywhere but in 4 snapshots only: nothing could be significant
  const LossTest few = percolation_loss({0.10, 0.11, 0.12, 0.13}, {1, 1, 1, 1}, surface, s);
  EXPECT_EQ(few.power.power, 0.0);
  EXPECT_EQ(few.outcome.rfind("undetermined", 0), 0u);
}

// an event from its peak to the end of its drop (s)
RuptureEvent drop(double peak, double end) { return {.peak_time = peak, .drop_end_time = end}; }

TEST(NetworkEvents, WindowsAndDisplacements) {
  const std::vector<double> t = {0.0, 0.25, 0.5, 0.75, 1.0};
  const EventWindow w = event_window(t, drop(0.3, 0.55), 0.3);
  EXPECT_EQ(w.before, 1);
  EXPECT_EQ(w.after, 3);
  EXPECT_TRUE(w.resolved);
  EXPECT_EQ(event_window(t, drop(0.25, 0.5), 0.3).before, 1);  // at the peak counts
  EXPECT_EQ(event_window(t, drop(0.25, 0.5), 0.3).after, 2);
  EXPECT_FALSE(event_window(t, drop(0.3, 0.55), 0.1).resolved);  // snapshots too far
  EXPECT_FALSE(event_window(t, drop(0.9, 1.1), 0.3).resolved);   // no snapshot after
  EXPECT_FALSE(event_window(t, drop(-0.1, 0.1), 0.3).resolved);  // none before

  const std::vector<Vec2> a = {{0, 0}, {0.01, 0.01}}, b = {{0.001, 0}, {0.01, 0.006}};
  const Displacement d = largest_displacement({0, 1}, a, b, {0.002, 0.003});
  EXPECT_EQ(d.grain, 1);
  EXPECT_NEAR(d.over_d, 4.0 / 3.0, 1e-12);
  EXPECT_NEAR(d.dy, -0.004, 1e-15);
  EXPECT_EQ(largest_displacement({}, a, b, {0.002, 0.003}).grain, -1);
}

void write_events(const std::string& path, const std::vector<double>& peak, const std::vector<double>& end,
                  bool with_height = true) {
  const h5::File f = h5::File::create(path);
  h5::write(f, "events/peak_time", peak);
  h5::write(f, "events/drop_end_time", end);
  if (with_height) h5::write(f, "events/peak_height", std::vector<double>(peak.size(), 0.01));
  h5::write(f, "events/load_start_time", std::vector<double>(peak.size(), 0.0));
}

TEST(NetworkEvents, ReadsTheSpectrumContractAndNamesTheFile) {
  const test::TempDir dir;
  const std::string ok = (dir.path() / "ok.h5").string(), bad = (dir.path() / "bad.h5").string();
  write_events(ok, {1.0, 2.0}, {1.2, 2.5});
  const auto e = read_events(ok);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_DOUBLE_EQ(e[1].drop_end_time, 2.5);
  write_events(bad, {1.0}, {1.2}, false);
  try {
    read_events(bad);
    FAIL();
  } catch (const StageError& x) {
    EXPECT_NE(std::string(x.what()).find(bad + ": dataset /events/peak_height is missing"), std::string::npos) << x.what();
  }
  write_events(bad, {1.0}, {0.5});
  EXPECT_THROW(read_events(bad), StageError);
  EXPECT_THROW(read_events((dir.path() / "none.h5").string()), StageError);
}

// The events file's one schema (common/events.hpp): what the spectrum stage
// writes is what cg and network read, every field; an event out of order is refused.
TEST(NetworkEvents, SchemaWrittenIsSchemaRead) {
  const test::TempDir dir;
  const std::vector<RuptureEvent> rows = {{0.10, 0.020, 0.30, 0.021, 5.0, 0.35, 0.0212, 2.0},
                                          {0.40, 0.022, 0.60, 0.024, 7.5, 0.62, 0.0241, 3.5}};
  const std::string path = (dir.path() / "spectrum.h5").string();
  const auto write_schema = [](const std::string& to, const std::vector<RuptureEvent>& events) {
    H5Output h;
    add_events(h, events);
    h.write(to);
  };
  write_schema(path, rows);
  const std::vector<RuptureEvent> back = read_events(path);
  ASSERT_EQ(back.size(), rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k)
    for (const EventColumn& c : event_columns()) EXPECT_EQ(back[k].*c.field, rows[k].*c.field) << c.name;
  EXPECT_EQ(h5::read_attr_string(h5::File::open_read(path), "events/peak_drag", "units"), "N/m");
  std::vector<RuptureEvent> bad = rows;
  bad[1].drop_end_time = 0.5;  // before its peak
  const std::string out_of_order = (dir.path() / "bad.h5").string();
  write_schema(out_of_order, bad);
  try {
    read_events(out_of_order);
    FAIL() << "no error";
  } catch (const StageError& x) {
    EXPECT_NE(std::string(x.what()).find(out_of_order + ": event 1: load_start_time"), std::string::npos) << x.what();
  }
}

TEST(NetworkConfig, DataFileHoldsTheDefaultsAndBadKeysAreNamed) {
  const NetworkConfig d = load_network_config(DEM2D_DATA_DIR "/network.toml");
  EXPECT_EQ(to_json(d), to_json(NetworkConfig{}));
  const test::TempDir dir;
  const std::string p = dir.file("c.toml", "strong_threshold = 1.2\nfloor_rule = \"bottom_layer_removed\"\nwalls = \"either\"\n");
  const NetworkConfig c = load_network_config(p);
  EXPECT_EQ(c.strong_threshold, 1.2);
  EXPECT_EQ(c.floor_rule, "bottom_layer_removed");
  const auto error = [&](const std::string& text) {
    try {
      load_network_config(dir.file("e.toml", text));
    } catch (const StageError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("\n\nstrong_treshold = 1.0\n").find("; did you mean 'strong_threshold'?"), std::string::npos);
  EXPECT_NE(error("\n\nstrong_treshold = 1.0\n").find("e.toml:3:1: unknown key 'strong_treshold' at the top level"), std::string::npos);
  EXPECT_NE(error("loss_level = 2.0\n").find("e.toml:1:14: loss_level = 2: must be in [0, 1]"), std::string::npos);
  EXPECT_NE(error("bin_width_d = nan\n").find("bin_width_d = nan: must be finite and in [0.001, 100]"), std::string::npos)
      << error("bin_width_d = nan\n");
  EXPECT_NE(error("walls = \"left\"\n").find("must be one of \"both\", \"either\""), std::string::npos);
  EXPECT_NE(error("figure_every = 2.5\n").find("expected an integer"), std::string::npos);
  EXPECT_NE(error("walls = \n").find("e.toml:1:"), std::string::npos);
  EXPECT_NE(error("# only a comment\n").find("no error"), std::string::npos);
  EXPECT_THROW(load_network_config((dir.path() / "missing.toml").string()), StageError);
}

// The stage on the quick run (200 grains, 40 mm cell, 20 mm/s), with two
// events placed on its snapshots.
TEST(NetworkStage, QuickRun) {
  const std::string run = test::quick_study_run("pulloff");
  ASSERT_TRUE(std::filesystem::exists(run)) << test::quick_study_missing(run);
  const test::TempDir dir;
  const std::string events = (dir.path() / "events.h5").string();
  write_events(events, {0.5, 1.0}, {0.56, 1.05});
  const std::string spectrum = dir.file("spectrum.json", R"({"spectrum": {"top_layer_height_mm": 30.0}})");
  const NetworkResult r = run_network({run, "test", events, spectrum}, NetworkConfig{}, load_study(DEM2D_DATA_DIR "/study.toml"));
  const auto& m = r.metrics["network"];
  EXPECT_EQ(m["top_layer_height_mm"].get<double>(), 30.0);
  for (const char* key : {"percolation_loss_height_mm", "percolating_fraction_below_top_layer", "keystone_explained_fraction"})
    ASSERT_TRUE(m[key].is_number()) << key << " = " << m[key].dump();
  const double f = m["percolating_fraction_below_top_layer"].get<double>();
  EXPECT_GE(f, 0.0);
  EXPECT_LE(f, 1.0);
  EXPECT_GT(m["percolation_loss_height_mm"].get<double>(), 1.0);
  EXPECT_LT(m["percolation_loss_height_mm"].get<double>(), m["initial_bed_height_mm"].get<double>() + 3.0);
  EXPECT_EQ(m["events"].get<int>(), 2);
  EXPECT_EQ(m["events_resolved"].get<int>(), 2);
  EXPECT_EQ(m["sensitivity"]["keystones"].size(), 9u);
  // The whole network percolates at least as often as the strong one.
  EXPECT_GE(m["whole_network_percolating_fraction_below_top_layer"].get<double>(), f);

  const std::string out = (dir.path() / "network.h5").string();
  r.h5.write(out);
  const h5::File h = h5::File::open_read(out);
  const auto height = h5::read<double>(h, "snapshots/height");
  EXPECT_EQ(height.size(), m["snapshots"].get<std::size_t>());
  EXPECT_EQ(h5::read<std::int64_t>(h, "keystones/start").size(), height.size() + 1);
  const auto fig = h5::read<std::int64_t>(h, "figure/snapshot");
  EXPECT_EQ(h5::read<std::int64_t>(h, "figure/start").size(), fig.size() + 1);
  EXPECT_EQ(h5::read_attr_string(h, "figure/fn", "units"), "N/m");

  // Without events or spectrum metrics: the check is skipped and the top layer is our loss height.
  const NetworkResult q = run_network({run, "test", "", ""}, NetworkConfig{}, load_study(DEM2D_DATA_DIR "/study.toml"));
  EXPECT_TRUE(q.metrics["network"]["keystone_explained_fraction"].is_null());
  EXPECT_EQ(q.metrics["network"]["top_layer_height_mm"], q.metrics["network"]["percolation_loss_height_mm"]);
}

int run_command(const std::string& args) {
  const int status = std::system((std::string(DEM2D_NETWORK_EXE) + " " + args + " 2>/dev/null").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(NetworkCommand, ExitCodes) {
  const test::TempDir dir;
  const std::string out = (dir.path() / "out").string();
  EXPECT_EQ(run_command((dir.path() / "missing.h5").string() + " --out " + out), 2);
  EXPECT_FALSE(std::filesystem::exists(out + "/metrics.json"));
  const std::string run = test::quick_study_run("pulloff");
  ASSERT_TRUE(std::filesystem::exists(run)) << test::quick_study_missing(run);
  EXPECT_EQ(run_command(run + " --out " + out + " --events " + (dir.path() / "none.h5").string()), 2);
  const std::string blocker = dir.file("file", "x");  // a file where the output directory should be
  EXPECT_EQ(run_command(run + " --out " + blocker), 1);
  EXPECT_EQ(run_command(run + " --out " + out), 0);
  EXPECT_TRUE(std::filesystem::exists(out + "/metrics.json"));
  EXPECT_TRUE(std::filesystem::exists(out + "/network.h5"));
  EXPECT_FALSE(std::filesystem::exists(out + "/network.h5.tmp"));
}

}  // namespace
}  // namespace dem2d::analysis
