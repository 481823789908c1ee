#include "paper_targets.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "common/pulloff_frame.hpp"  // StageError
#include "common/stage_config.hpp"
#include "common/stage_output.hpp"   // format_number

namespace dem2d::check {

using analysis::format_number;
using analysis::StageError;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Target read_target(analysis::StageConfig& c) {
  Target t;
  c.text("result", t.result, "SPEC's result number, e.g. \"R1\"");
  c.text("metric", t.metric, "dotted path into metrics.json");
  c.text("what", t.what, "what the number is, with its unit");
  c.text("source", t.source, "where the paper gives it");
  c.text("why", t.why, "why this tolerance or bound");
  const bool within = c.has("paper"), below = c.has("below"), above = c.has("above"),
             above_metric = c.has("above_metric");
  if (within + below + above + above_metric != 1)
    throw StageError(c.path() + ": target " + t.result + " " + t.metric +
                     ": give exactly one comparison: paper + tolerance, below, above or above_metric");
  if (within) {
    std::optional<double> tol;
    c.number("paper", t.value, -kInf, kInf, "the paper's value");
    c.number("tolerance", tol, 0.0, kInf, "absolute tolerance, in the metric's unit");
    if (!tol) throw StageError(c.path() + ": target " + t.result + " " + t.metric + ": paper = ... needs a tolerance");
    t.kind = Target::Kind::Within;
    t.tolerance = *tol;
  } else if (below) {
    c.number("below", t.value, -kInf, kInf, "upper bound");
    t.kind = Target::Kind::Below;
  } else if (above) {
    c.number("above", t.value, -kInf, kInf, "lower bound");
    t.kind = Target::Kind::Above;
  } else {
    c.text("above_metric", t.other_metric, "the metric ours must exceed");
    t.kind = Target::Kind::AboveMetric;
  }
  c.reject_unknown();
  if (t.result.empty() || t.metric.empty() || t.source.empty() || t.why.empty() || t.what.empty())
    throw StageError(c.path() + ": target " + t.result + " " + t.metric +
                     ": every target needs result, metric, what, source and why");
  return t;
}

}  // namespace

std::vector<Target> load_targets(const std::string& path) {
  analysis::StageConfig file(path);
  std::vector<analysis::StageConfig> list = file.entries("target");
  if (list.empty()) throw StageError(path + ": expected one or more [[target]] tables");
  file.reject_unknown();  // only [[target]] tables at the top level
  std::vector<Target> targets;
  for (analysis::StageConfig& c : list) targets.push_back(read_target(c));
  return targets;
}

nlohmann::json load_metrics(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw StageError(path + ": no such file (run `make reproduce` for its preset first)");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw StageError(path + ": not valid JSON (" + e.what() + "); rerun `make reproduce` for its preset");
  }
}

std::optional<double> lookup(const nlohmann::json& metrics, const std::string& dotted) {
  const nlohmann::json* node = &metrics;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = dotted.find('.', start);
    const std::string key = dotted.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (!node->is_object() || !node->contains(key)) return std::nullopt;
    node = &(*node)[key];
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  if (!node->is_number()) return std::nullopt;
  const double v = node->get<double>();
  return std::isfinite(v) ? std::optional<double>(v) : std::nullopt;
}

std::optional<std::pair<double, double>> ensemble_interval(const nlohmann::json& stats, const std::string& metric) {
  const auto m = stats.find("metrics");
  if (m == stats.end() || !m->is_object() || !m->contains(metric)) return std::nullopt;
  const nlohmann::json& ci = (*m)[metric]["ci95"];
  if (!ci.is_array() || ci.size() != 2 || !ci[0].is_number() || !ci[1].is_number()) return std::nullopt;
  return std::pair<double, double>{ci[0].get<double>(), ci[1].get<double>()};
}

Verdict evaluate(const Target& t, const nlohmann::json& metrics, const nlohmann::json* ensemble) {
  Verdict v;
  v.ours = lookup(metrics, t.metric);
  std::optional<double> other;
  std::optional<std::pair<double, double>> ci;
  switch (t.kind) {
    case Target::Kind::Within:
      v.paper = format_number(t.value);
      v.tolerance = "± " + format_number(t.tolerance);
      v.expected = v.paper + " " + v.tolerance;
      if (!ensemble) {
        v.pass = v.ours && std::abs(*v.ours - t.value) <= t.tolerance;
        break;
      }
      ci = ensemble_interval(*ensemble, t.metric);
      if (!ci) v.ours.reset();  // no member gave it
      if (ci) v.tolerance += " around the members' 95 % interval [" + format_number(ci->first) + ", " +
                              format_number(ci->second) + "]";
      v.pass = ci && t.value >= ci->first - t.tolerance && t.value <= ci->second + t.tolerance;
      break;
    case Target::Kind::Below:
      v.expected = v.paper = "< " + format_number(t.value);
      v.tolerance = "a bound";
      v.pass = v.ours && *v.ours < t.value;
      break;
    case Target::Kind::Above:
      v.expected = v.paper = "> " + format_number(t.value);
      v.tolerance = "a bound";
      v.pass = v.ours && *v.ours > t.value;
      break;
    case Target::Kind::AboveMetric:
      other = lookup(metrics, t.other_metric);
      v.expected = v.paper = "> " + t.other_metric + (other ? " (= " + format_number(*other) + ")" : " (missing)");
      v.tolerance = "a shape";
      v.pass = v.ours && other && *v.ours > *other;
      break;
  }
  const std::string head = t.result + " " + t.metric + " (" + t.what + "): ";
  if (!v.ours)
    v.message = head + "missing, null or not a number in the metrics";
  else
    v.message = head + format_number(*v.ours) + ", paper " + v.expected + (v.pass ? ": pass" : ": FAIL") +
                " [" + t.source + "; tolerance: " + t.why + "]";
  return v;
}

}  // namespace dem2d::check
