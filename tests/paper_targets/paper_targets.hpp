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
  std::optional<double> ours;   // absent: the metric is missing, null or not a number
  std::string expected;         // "0.82 ± 0.02", "< 0.2", "> spectrum.x (= 3.1)"
  std::string paper, tolerance; // expected in two parts: ("0.82", "± 0.02"), ("< 0.2", "a bound"), ("> spectrum.x (= 3.1)", "a shape")
  std::string message;          // one line for the failure report
};
// `metrics`: one run's, or an ensemble's member means (pipeline/ensemble/aggregate.py).
// With `ensemble` (that ensemble's stats.json) a paper value with a tolerance
// passes when it lies within the 95 % interval of the members' mean widened
// by the tolerance on both sides, [lo - tol, hi + tol]; bounds and shapes are
// judged on the mean (docs/ensemble.md).
Verdict evaluate(const Target& t, const nlohmann::json& metrics, const nlohmann::json* ensemble = nullptr);

// The 95 % interval [lo, hi] of the members' mean of a metric in an
// ensemble's stats.json, if the members gave it.
std::optional<std::pair<double, double>> ensemble_interval(const nlohmann::json& stats, const std::string& metric);

}  // namespace dem2d::check
