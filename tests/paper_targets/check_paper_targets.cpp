// check_paper_targets: the tolerance tests of `make check`. One GoogleTest
// test per [[target]] of the targets file, named after its SPEC result and
// metric; a missing metric fails. Each test records its metric, our value,
// the paper's and the verdict as properties, so --gtest_output=json:FILE
// gives the report its table.
//   check_paper_targets METRICS.json TARGETS.toml [--gtest_* options]
// Exit codes: 0 all pass; 1 a target fails; 2 unreadable input.
#include <gtest/gtest.h>

#include <cstdio>
#include <exception>

#include "common/stage_output.hpp"
#include "paper_targets.hpp"

namespace {

using dem2d::check::Target;

class TargetTest : public testing::Test {
 public:
  TargetTest(Target t, const nlohmann::json* metrics) : t_(std::move(t)), metrics_(metrics) {}
  void TestBody() override {
    const dem2d::check::Verdict v = dem2d::check::evaluate(t_, *metrics_);
    RecordProperty("result", t_.result);
    RecordProperty("metric", t_.metric);
    RecordProperty("what", t_.what);
    RecordProperty("ours", v.ours ? dem2d::analysis::format_number(*v.ours) : "missing");
    RecordProperty("paper", v.paper);
    RecordProperty("tolerance", v.tolerance);
    RecordProperty("source", t_.source);
    RecordProperty("why", t_.why);
    RecordProperty("verdict", v.pass ? "pass" : "fail");
    EXPECT_TRUE(v.pass) << v.message;
  }

 private:
  Target t_;
  const nlohmann::json* metrics_;
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
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s METRICS.json TARGETS.toml [--gtest_* options]\n", argv[0]);
    return 2;
  }
  static nlohmann::json metrics;
  std::vector<Target> targets;
  try {
    metrics = dem2d::check::load_metrics(argv[1]);
    targets = dem2d::check::load_targets(argv[2]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "check_paper_targets: %s\n", e.what());
    return 2;
  }
  int index = 0;
  for (const Target& t : targets) {
    ++index;
    testing::RegisterTest(t.result.c_str(), test_name(t.metric, index).c_str(), nullptr, nullptr, __FILE__, __LINE__,
                          [t]() -> testing::Test* { return new TargetTest(t, &metrics); });
  }
  return RUN_ALL_TESTS() == 0 ? 0 : 1;
}
