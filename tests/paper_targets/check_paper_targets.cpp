// check_paper_targets: the tolerance tests of `make check`. One GoogleTest
// test per [[target]] of the targets file, named after its result (docs/paper.md) and
// metric; a missing metric fails. Each test records its metric, our value,
// the paper's and the verdict as properties, so --gtest_output=json:FILE
// gives the report its table.
//   check_paper_targets METRICS.json TARGETS.toml [--ensemble STATS.json] [--gtest_* options]
// With --ensemble, METRICS.json holds an ensemble's member means and
// STATS.json their intervals (pipeline/ensemble/aggregate.py; the rule:
// paper_targets.hpp, evaluate).
// Exit codes: 0 all pass; 1 a target fails; 2 unreadable input.
#include <gtest/gtest.h>

#include <cstdio>
#include <exception>
#include <string>

#include "common/stage_output.hpp"
#include "paper_targets.hpp"

namespace {

using dem2d::check::Target;

class TargetTest : public testing::Test {
 public:
  TargetTest(Target t, const nlohmann::json* metrics, const nlohmann::json* ensemble)
      : t_(std::move(t)), metrics_(metrics), ensemble_(ensemble) {}
  void TestBody() override {
    const dem2d::check::Verdict v = dem2d::check::evaluate(t_, *metrics_, ensemble_);
    RecordProperty("result", t_.result);
    RecordProperty("metric", t_.metric);
    RecordProperty("what", t_.what);
    RecordProperty("ours", v.ours ? dem2d::analysis::format_number(*v.ours) : "missing");
    RecordProperty("paper", v.paper);
    RecordProperty("tolerance", v.tolerance);
    RecordProperty("source", t_.source);
    RecordProperty("why", t_.why);
    RecordProperty("verdict", v.outcome);
    if (v.interval)
      RecordProperty("interval", dem2d::analysis::format_number(v.interval->first) + ", " +
                                     dem2d::analysis::format_number(v.interval->second));
    if (ensemble_) RecordProperty("members", v.members);
    if (v.members_needed) RecordProperty("members_needed", std::to_string(*v.members_needed));
    EXPECT_TRUE(v.pass) << v.message;
  }

 private:
  Target t_;
  const nlohmann::json* metrics_;
  const nlohmann::json* ensemble_;  // null: one run
};

// "fill.solid_fraction" -> "fill_solid_fraction": GoogleTest names are identifiers.
std::string test_name(std::string s, int index) {
  for (char& c : s)
    if (c == '.') c = '_';
  return std::to_string(index) + "_" + s;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  const bool with_ensemble = argc == 5 && std::string(argv[3]) == "--ensemble";
  if (argc != 3 && !with_ensemble) {
    std::fprintf(stderr, "usage: %s METRICS.json TARGETS.toml [--ensemble STATS.json] [--gtest_* options]\n", argv[0]);
    return 2;
  }
  static nlohmann::json metrics, ensemble;
  std::vector<Target> targets;
  try {
    metrics = dem2d::check::load_metrics(argv[1]);
    targets = dem2d::check::load_targets(argv[2]);
    if (with_ensemble) ensemble = dem2d::check::load_metrics(argv[4]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "check_paper_targets: %s\n", e.what());
    return 2;
  }
  int index = 0;
  for (const Target& t : targets) {
    ++index;
    testing::RegisterTest(t.result.c_str(), test_name(t.metric, index).c_str(), nullptr, nullptr, __FILE__, __LINE__,
                          [t, with_ensemble]() -> testing::Test* {
                            return new TargetTest(t, &metrics, with_ensemble ? &ensemble : nullptr);
                          });
  }
  const int rc = RUN_ALL_TESTS();
  // the three verdicts counted, in the report's words
  int n[3] = {0, 0, 0};
  for (const Target& t : targets) {
    const std::string o = dem2d::check::evaluate(t, metrics, with_ensemble ? &ensemble : nullptr).outcome;
    ++n[o == "holds" || o == "pass" ? 0 : o == "fails" || o == "fail" ? 1 : 2];
  }
  std::printf("[  VERDICTS ] %d %s, %d fail, %d undetermined (of %zu targets)\n", n[0], with_ensemble ? "hold" : "pass",
              n[1], n[2], targets.size());
  return rc == 0 ? 0 : 1;
}
