// The tolerance tests' own logic: the targets file, metric lookup, verdicts.
#include <gtest/gtest.h>

#include <set>

#include "frame/pulloff_frame.hpp"  // StageError
#include "paper_targets.hpp"
#include "temp_dir.hpp"

namespace dem2d::check {
namespace {

const std::string kTargets = std::string(DEM2D_DATA_DIR) + "/paper_targets.toml";

Target within(const std::string& metric, double paper, double tol) {
  Target t;
  t.result = "R0";
  t.metric = metric;
  t.kind = Target::Kind::Within;
  t.value = paper;
  t.tolerance = tol;
  return t;
}

TEST(PaperTargets, TheStudysFileNamesEveryNumberedResultAndSpecsMetrics) {
  const std::vector<Target> targets = load_targets(kTargets);
  std::set<std::string> results, metrics;
  for (const Target& t : targets) {
    results.insert(t.result);
    metrics.insert(t.metric);
  }
  for (const char* r : {"R1", "R2", "R3", "R4", "R5", "R6", "R7", "R8", "R9", "R10", "R11"})
    EXPECT_TRUE(results.count(r)) << r;
  // The metric names docs/paper.md's table gives for R1-R11.
  for (const char* m :
       {"fill.solid_fraction", "fill.bed_height_mm", "spectrum.bottom_peak_height_mm", "spectrum.amplitude_slope_upper",
        "spectrum.amplitude_fit_r2_upper", "spectrum.rupture_spacing_d", "spectrum.rupture_frequency_hz_at_1p2mm_s",
        "spectrum.top_layer_height_mm", "spectrum.top_layer_depth_fit_r2", "network.percolation_loss_height_mm",
        "network.top_layer_anisotropy", "cg.cone_angle_deg", "cg.wall_mobility_length_mm", "friction.slip_fraction",
        "friction.mean_mu_star_lower", "friction.mean_mu_star_upper", "network.keystone_explained_fraction",
        "network.percolating_fraction_below_top_layer", "cg.dilatancy_delta_phi"})
    EXPECT_TRUE(metrics.count(m)) << m;
}

TEST(PaperTargets, LookupFollowsDottedPathsAndRefusesWhatIsNotAFiniteNumber) {
  const auto m = nlohmann::json::parse(R"({"fill": {"solid_fraction": 0.83, "note": "x", "none": null,
                                           "bottom": {"peak": {"drag": 12.5}}}})");
  EXPECT_EQ(lookup(m, "fill.solid_fraction"), 0.83);
  EXPECT_EQ(lookup(m, "fill.bottom.peak.drag"), 12.5);
  EXPECT_FALSE(lookup(m, "fill.note"));
  EXPECT_FALSE(lookup(m, "fill.none"));
  EXPECT_FALSE(lookup(m, "fill.missing"));
  EXPECT_FALSE(lookup(m, "fill"));
  EXPECT_FALSE(lookup(m, "fill.solid_fraction.x"));
}

TEST(PaperTargets, WithinToleranceIsInclusiveAndMissingFails) {
  // binary-exact numbers: 0.75 is exactly 0.5 + 0.25
  const auto m = nlohmann::json::parse(R"({"a": {"x": 0.75, "y": 0.7501, "w": 0.2499, "z": null}})");
  const Verdict edge = evaluate(within("a.x", 0.5, 0.25), m);
  EXPECT_TRUE(edge.pass);
  EXPECT_EQ(edge.paper, "0.5");
  EXPECT_EQ(edge.tolerance, "± 0.25");
  EXPECT_FALSE(evaluate(within("a.y", 0.5, 0.25), m).pass);
  EXPECT_FALSE(evaluate(within("a.w", 0.5, 0.25), m).pass);
  const Verdict missing = evaluate(within("a.z", 0.5, 0.25), m);
  EXPECT_FALSE(missing.pass);
  EXPECT_FALSE(missing.ours);
  EXPECT_NE(missing.message.find("missing"), std::string::npos) << missing.message;
}

// An ensemble's stats.json with the members' values of metric "a.x" (and "a.y").
nlohmann::json members(const std::vector<double>& x, const std::vector<double>& y = {}) {
  nlohmann::json s;
  s["metrics"]["a.x"]["values"] = x;
  s["metrics"]["a.y"]["values"] = y;
  return s;
}
const nlohmann::json kMeans = nlohmann::json::parse(R"({"a": {"x": 1.0, "y": 0.0}})");
Verdict judged(const Target& t, const nlohmann::json& stats) { return evaluate(t, kMeans, &stats); }

// An ensemble: the members' 95 % t-interval against the paper's band.
TEST(PaperTargets, EnsembleHoldsInsideFailsOutsideAndIsUndeterminedAcross) {
  const Target t = within("a.x", 1.0, 0.1);
  // mean 1.0, sd 0.01: interval 1 +- 0.025 inside [0.9, 1.1]
  Verdict v = judged(t, members({0.99, 1.0, 1.01}));
  EXPECT_EQ(v.outcome, "holds");
  EXPECT_TRUE(v.pass);
  ASSERT_TRUE(v.interval);
  EXPECT_NEAR(v.interval->first, 1.0 - 4.303 * 0.01 / std::sqrt(3.0), 1e-9);
  EXPECT_EQ(v.members, 3);
  // mean 1.5, tight: wholly outside
  v = judged(t, members({1.49, 1.5, 1.51}));
  EXPECT_EQ(v.outcome, "fails");
  EXPECT_FALSE(v.pass);
  // mean 1.0 but a wide spread: straddles both edges; the members that would decide are named
  v = judged(t, members({0.5, 1.0, 1.5}));
  EXPECT_EQ(v.outcome, "undetermined");
  EXPECT_FALSE(v.pass);
  ASSERT_TRUE(v.members_needed);
  EXPECT_GT(*v.members_needed, 3);
  EXPECT_NE(v.message.find("members would decide"), std::string::npos) << v.message;
  // one member gives no interval; none gives nothing
  EXPECT_EQ(judged(t, members({1.0})).outcome, "undetermined");
  EXPECT_EQ(judged(t, members({})).outcome, "fails");
  EXPECT_EQ(judged(t, members({std::nan("")})).outcome, "fails");
  // a member that found nothing keeps the others from making it hold
  v = judged(t, members({0.99, 1.0, 1.01, std::nan("")}));
  EXPECT_EQ(v.outcome, "undetermined");
  EXPECT_NE(v.tolerance.find("3 members of 4"), std::string::npos) << v.tolerance;
}

// A verdict never becomes easier to pass as noise grows: the same mean with a
// growing spread goes from holds (or fails) to undetermined, never to holds.
TEST(PaperTargets, MoreNoiseNeverMakesAnEnsembleHold) {
  for (const double mean : {1.05, 1.2}) {  // inside the band, outside it
    const Target t = within("a.x", 1.0, 0.1);
    std::string first;
    for (const double sd : {0.001, 0.01, 0.05, 0.2, 1.0}) {
      const Verdict v = judged(t, members({mean - sd, mean, mean + sd}));
      if (first.empty()) first = v.outcome;
      EXPECT_TRUE(v.outcome == first || v.outcome == "undetermined") << mean << " " << sd << " " << v.outcome;
      if (mean > 1.1) {
        EXPECT_NE(v.outcome, "holds");
      }
    }
    EXPECT_EQ(first, mean < 1.1 ? "holds" : "fails");
  }
}

TEST(PaperTargets, EnsembleBoundsAndShapesAreJudgedOnTheirIntervals) {
  Target below = within("a.x", 0.0, 0.0);
  below.kind = Target::Kind::Below;
  below.value = 2.0;
  EXPECT_EQ(judged(below, members({0.9, 1.0, 1.1})).outcome, "holds");
  EXPECT_EQ(judged(below, members({2.9, 3.0, 3.1})).outcome, "fails");
  EXPECT_EQ(judged(below, members({0.0, 1.0, 3.0})).outcome, "undetermined");
  Target above = below;
  above.kind = Target::Kind::Above;
  EXPECT_EQ(judged(above, members({2.9, 3.0, 3.1})).outcome, "holds");
  // a shape on the members' differences: x - y > 0 member by member
  Target shape = within("a.x", 0.0, 0.0);
  shape.kind = Target::Kind::AboveMetric;
  shape.other_metric = "a.y";
  EXPECT_EQ(judged(shape, members({1.0, 2.0, 3.0}, {0.5, 1.5, 2.5})).outcome, "holds");
  EXPECT_EQ(judged(shape, members({1.0, 2.0, 3.0}, {1.5, 2.5, 3.5})).outcome, "fails");
  EXPECT_EQ(judged(shape, members({1.0, 2.0, 3.0}, {0.5, 2.5, 2.5})).outcome, "undetermined");
}

TEST(PaperTargets, BoundsAreStrictAndAMetricCanBeTheBound) {
  const auto m = nlohmann::json::parse(R"({"s": {"lower": 0.4, "upper": 0.34, "slip": 0.2}})");
  Target t = within("s.slip", 0, 0);
  t.kind = Target::Kind::Below;
  t.value = 0.2;
  EXPECT_FALSE(evaluate(t, m).pass);
  t.value = 0.21;
  EXPECT_TRUE(evaluate(t, m).pass);
  t.kind = Target::Kind::Above;
  EXPECT_FALSE(evaluate(t, m).pass);
  t.value = 0.19;
  EXPECT_TRUE(evaluate(t, m).pass);
  Target shape = within("s.lower", 0, 0);
  shape.kind = Target::Kind::AboveMetric;
  shape.other_metric = "s.upper";
  EXPECT_TRUE(evaluate(shape, m).pass);
  shape.other_metric = "s.absent";
  EXPECT_FALSE(evaluate(shape, m).pass);
  shape.metric = "s.upper";
  shape.other_metric = "s.lower";
  EXPECT_FALSE(evaluate(shape, m).pass);
}

std::string load_error(const std::string& text) {
  test::TempDir dir("paper_targets");
  const std::string path = dir.file("t.toml", text);
  try {
    load_targets(path);
  } catch (const analysis::StageError& e) {
    return e.what();
  }
  return "(no error)";
}

constexpr const char* kHead = "[[target]]\nresult = \"R1\"\nmetric = \"fill.x\"\nwhat = \"w\"\nsource = \"s\"\nwhy = \"y\"\n";

TEST(PaperTargets, BadTargetFilesGetErrorsNamingFileKeyAndValue) {
  EXPECT_EQ(load_error(std::string(kHead) + "paper = 1.0\ntolerance = 0.1\n"), "(no error)");
  const std::string two = load_error(std::string(kHead) + "below = 1.0\nabove = 0.0\n");
  EXPECT_NE(two.find("exactly one comparison"), std::string::npos) << two;
  const std::string no_tol = load_error(std::string(kHead) + "paper = 1.0\n");
  EXPECT_NE(no_tol.find("needs a tolerance"), std::string::npos) << no_tol;
  const std::string negative = load_error(std::string(kHead) + "paper = 1.0\ntolerance = -0.1\n");
  EXPECT_NE(negative.find("t.toml:8:"), std::string::npos) << negative;
  EXPECT_NE(negative.find("tolerance = -0.1"), std::string::npos) << negative;
  const std::string unknown = load_error(std::string(kHead) + "below = 1.0\ntolerence = 0.1\n");
  EXPECT_NE(unknown.find("unknown key 'tolerence'"), std::string::npos) << unknown;
  const std::string type = load_error(std::string(kHead) + "below = \"small\"\n");
  EXPECT_NE(type.find("t.toml:7:9: target[0].below = \"small\": wrong type"), std::string::npos) << type;
  EXPECT_NE(load_error("x = 1\n").find("[[target]]"), std::string::npos);
  EXPECT_NE(load_error("[[target\n").find("t.toml:1"), std::string::npos);
}

TEST(PaperTargets, MissingFilesSayWhatToRun) {
  EXPECT_THROW(load_targets("/no/such/targets.toml"), analysis::StageError);
  try {
    load_metrics("/no/such/metrics.json");
    FAIL();
  } catch (const analysis::StageError& e) {
    EXPECT_NE(std::string(e.what()).find("make reproduce"), std::string::npos) << e.what();
  }
}

// A detector that found nothing: a miss is evidence of absence (the target
// fails) only where its power to find the claim reaches min_power; with
// less, or none measured, the verdict is undetermined, never a pass.
TEST(PaperTargets, ANoneFailsOnlyWithThePowerToFindTheClaim) {
  Target t = within("a.x", 1.0, 0.1);
  t.power_metric = "a.power";
  const auto strong = nlohmann::json::parse(R"({"a": {"x": null, "power": 0.95}})");
  const auto weak = nlohmann::json::parse(R"({"a": {"x": null, "power": 0.5}})");
  const auto unmeasured = nlohmann::json::parse(R"({"a": {"x": null}})");
  EXPECT_EQ(evaluate(t, strong).outcome, "fail");
  EXPECT_EQ(evaluate(t, weak).outcome, "undetermined");
  EXPECT_EQ(evaluate(t, unmeasured).outcome, "undetermined");
  EXPECT_FALSE(evaluate(t, weak).pass);
  EXPECT_NE(evaluate(t, weak).message.find("power 0.5 < 0.8"), std::string::npos) << evaluate(t, weak).message;
  // a value found is judged as before, whatever the power
  const auto found = nlohmann::json::parse(R"({"a": {"x": 1.05, "power": null}})");
  EXPECT_EQ(evaluate(t, found).outcome, "pass");
  // an ensemble in which no member found it: fails only if every member's miss had the power
  nlohmann::json s = members({});
  s["metrics"]["a.x"]["values"] = {nullptr, nullptr, nullptr};
  s["metrics"]["a.power"]["values"] = {0.9, 0.95, 0.85};
  EXPECT_EQ(judged(t, s).outcome, "fails");
  s["metrics"]["a.power"]["values"] = {0.9, 0.6, 0.85};
  EXPECT_EQ(judged(t, s).outcome, "undetermined");
  // without a power rule a missing metric fails, as before
  t.power_metric.clear();
  EXPECT_EQ(evaluate(t, weak).outcome, "fail");
}

// A detector that gives no value when it cannot decide (the cone's angle from
// too few snapshots): a missing value is undetermined, its reason quoted;
// a value is judged as before; without the rule a missing value fails.
TEST(PaperTargets, AnUndecidedDetectorIsUndeterminedNotFailed) {
  Target t = within("a.x", 1.0, 0.1);
  t.undecided_metric = "a.why";
  const auto undecided = nlohmann::json::parse(R"({"a": {"x": null, "why": "undetermined: an angle in 1 snapshot"}})");
  const Verdict v = evaluate(t, undecided);
  EXPECT_EQ(v.outcome, "undetermined");
  EXPECT_FALSE(v.pass);
  EXPECT_NE(v.message.find("an angle in 1 snapshot"), std::string::npos) << v.message;
  EXPECT_EQ(evaluate(t, nlohmann::json::parse(R"({"a": {"x": 1.2, "why": "found"}})")).outcome, "fail");
  nlohmann::json s = members({});
  s["metrics"]["a.x"]["values"] = {nullptr, nullptr};
  EXPECT_EQ(judged(t, s).outcome, "undetermined");
  t.undecided_metric.clear();
  EXPECT_EQ(evaluate(t, undecided).outcome, "fail");
  EXPECT_EQ(judged(t, s).outcome, "fails");
}

}  // namespace
}  // namespace dem2d::check
