// The paper's results with a number (data/paper_targets.toml) and their
// comparison with our metrics (results/<preset>/metrics.json): the tolerance
// tests of `make check`.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace dem2d::check {

struct Target {
  enum class Kind { Within, Below, Above, AboveMetric };
  std::string result;       // "R1" ... "R11"
  std::string metric;       // dotted path into metrics.json
  std::string what, source, why;
  Kind kind = Kind::Within;
  double value = 0.0;       // paper value (Within) or bound (Below, Above)
  double tolerance = 0.0;   // Within: absolute, in the metric's unit
  std::string other_metric; // AboveMetric
  // a detector that can answer "none": the metric holding its power to find
  // what the target claims (0-1) where it found nothing. A none with at least
  // min_power is evidence of absence (the target fails); with less, or
  // without a power, it is undetermined
  std::string power_metric;
  double min_power = 0.8;
  // a detector that gives no value when it cannot decide (too few or too
  // scattered measurements): the metric (a text) saying why. A missing value
  // is then undetermined, not a failure
  std::string undecided_metric;
};

// Reads and validates the targets file: every key typed, exactly one
// comparison per target, unknown keys rejected. Throws analysis::StageError
// naming the file, line, key and value.
std::vector<Target> load_targets(const std::string& path);

// The metrics file; throws analysis::StageError naming it and saying what to run.
nlohmann::json load_metrics(const std::string& path);

// The value at a dotted path, if it is there and a finite number.
std::optional<double> lookup(const nlohmann::json& metrics, const std::string& dotted);

struct Verdict {
  bool pass = false;
  // one run: "pass", "fail" or "undetermined" (the detector found nothing and
  // its power to find the claim is below the target's min_power); an
  // ensemble: "holds" (the members' 95 % interval
  // lies wholly on the paper's side), "fails" (wholly on the other side) or
  // "undetermined" (it straddles the edge: more members would decide)
  std::string outcome;
  std::optional<double> ours;   // absent: the metric is missing, null or not a number
  std::string expected;         // "0.82 ± 0.02", "< 0.2", "> spectrum.x (= 3.1)"
  std::string paper, tolerance; // expected in two parts: ("0.82", "± 0.02"), ("< 0.2", "a bound"), ("> spectrum.x (= 3.1)", "a shape")
  std::string message;          // one line for the failure report
  // an ensemble: the members that gave the metric, the t-interval of their mean
  // (of the differences for a shape), and for an undetermined verdict the
  // members that would shrink it to decide if the spread stays the same
  int members = 0, members_total = 0;  // members that gave the metric, of all members
  std::optional<std::pair<double, double>> interval;
  std::optional<long> members_needed;
};
// `metrics`: one run's, or an ensemble's member means (pipeline/ensemble/aggregate.py).
// With `ensemble` (that ensemble's stats.json, whose "values" are each
// member's) the verdict is three-valued, on the 95 % Student-t interval of
// the members' mean (n >= 2; one member gives no interval: undetermined):
// a paper value +- tolerance holds when the interval lies inside
// [paper - tol, paper + tol] and fails when it lies wholly outside it; a bound
// holds when the interval lies wholly beyond it; a shape (ours > another
// metric) is judged on the interval of the members' differences. A member
// without a value keeps the others from making it hold. A wider
// interval (fewer members, more noise) can only make a verdict undetermined,
// never make it hold (docs/ensemble.md).
Verdict evaluate(const Target& t, const nlohmann::json& metrics, const nlohmann::json* ensemble = nullptr);

// The members' finite values of a metric in an ensemble's stats.json, in
// member order (NaN where a member gave none).
std::vector<double> member_values(const nlohmann::json& stats, const std::string& metric);

// The two-sided 95 % Student-t interval of the mean of values (n >= 2).
std::optional<std::pair<double, double>> t_interval(const std::vector<double>& values);

}  // namespace dem2d::check
