#include "paper_targets.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "frame/pulloff_frame.hpp"  // StageError
#include "common/normal.hpp"
#include "common/stage_config.hpp"
#include "common/stage_output.hpp"   // format_number

namespace dem2d::check {

using analysis::format_number;
using analysis::StageError;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Target read_target(analysis::StageConfig& c) {
  Target t;
  c.text("result", t.result, "the paper's result number (docs/paper.md), e.g. \"R1\"");
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
  c.text("power", t.power_metric, "dotted path of the detector's power where it found nothing");
  c.number("min_power", t.min_power, 0.0, 1.0, "power that makes a none evidence of absence");
  c.text("undecided", t.undecided_metric, "dotted path of the text saying why the detector gave no value");
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

namespace {

// The node at a dotted path ("a.b.c"), nullptr if there is none.
const nlohmann::json* at_path(const nlohmann::json& metrics, const std::string& dotted) {
  const nlohmann::json* node = &metrics;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = dotted.find('.', start);
    const std::string key = dotted.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (!node->is_object() || !node->contains(key)) return nullptr;
    node = &(*node)[key];
    if (dot == std::string::npos) return node;
    start = dot + 1;
  }
}

// The text at a dotted path ("" if there is none).
std::string lookup_text(const nlohmann::json& metrics, const std::string& dotted) {
  const nlohmann::json* node = at_path(metrics, dotted);
  return node && node->is_string() ? node->get<std::string>() : "";
}

}  // namespace

std::optional<double> lookup(const nlohmann::json& metrics, const std::string& dotted) {
  const nlohmann::json* node = at_path(metrics, dotted);
  if (!node || !node->is_number()) return std::nullopt;
  const double v = node->get<double>();
  return std::isfinite(v) ? std::optional<double>(v) : std::nullopt;
}

std::vector<double> member_values(const nlohmann::json& stats, const std::string& metric) {
  std::vector<double> out;
  const auto m = stats.find("metrics");
  if (m == stats.end() || !m->is_object() || !m->contains(metric)) return out;
  const nlohmann::json& v = (*m)[metric]["values"];
  if (!v.is_array()) return out;
  for (const auto& x : v)
    out.push_back(x.is_number() && std::isfinite(x.get<double>()) ? x.get<double>() : std::nan(""));
  return out;
}

namespace {

std::vector<double> finite(const std::vector<double>& v) {
  std::vector<double> out;
  for (const double x : v)
    if (std::isfinite(x)) out.push_back(x);
  return out;
}

// The ensemble's three-valued verdict: the interval [lo, hi] against the
// region where the claim holds, (lo_ok, hi_ok) (infinite ends for a bound).
void judge(Verdict& v, const std::vector<double>& values, double lo_ok, double hi_ok, bool open_ends) {
  const std::vector<double> x = finite(values);
  v.members = static_cast<int>(x.size());
  v.members_total = static_cast<int>(values.size());
  if (x.empty()) return;  // the caller judges an ensemble of nones by their power
  double mean = 0.0;
  for (const double a : x) mean += a;
  mean /= static_cast<double>(x.size());
  v.ours = mean;
  v.interval = t_interval(x);
  if (!v.interval) {
    v.outcome = "undetermined";
    return;
  }
  const auto [lo, hi] = *v.interval;
  const bool inside = open_ends ? lo > lo_ok && hi < hi_ok : lo >= lo_ok && hi <= hi_ok;
  const bool outside = open_ends ? hi <= lo_ok || lo >= hi_ok : hi < lo_ok || lo > hi_ok;
  v.outcome = inside ? "holds" : outside ? "fails" : "undetermined";
  // a member without a value (a detector that found nothing) is a result too:
  // the others alone cannot make the claim hold
  if (inside && x.size() < values.size()) v.outcome = "undetermined";
  v.pass = v.outcome == "holds";
  if (v.outcome == "undetermined") {
    // the half-width that would decide: the mean's distance to the nearer edge of the region
    const double edge = std::min(std::abs(mean - lo_ok), std::abs(mean - hi_ok));
    const double half = 0.5 * (hi - lo);
    if (edge > 0.0)
      v.members_needed = static_cast<long>(std::ceil(static_cast<double>(x.size()) * (half / edge) * (half / edge)));
  }
}

}  // namespace

std::optional<std::pair<double, double>> t_interval(const std::vector<double>& values) {
  const std::vector<double> x = finite(values);
  if (x.size() < 2) return std::nullopt;
  const double n = static_cast<double>(x.size());
  double mean = 0.0, ss = 0.0;
  for (const double a : x) mean += a;
  mean /= n;
  for (const double a : x) ss += (a - mean) * (a - mean);
  const double half = analysis::student_t975(static_cast<int>(x.size()) - 1) * std::sqrt(ss / (n - 1.0) / n);
  return std::pair<double, double>{mean - half, mean + half};
}

Verdict evaluate(const Target& t, const nlohmann::json& metrics, const nlohmann::json* ensemble) {
  Verdict v;
  v.ours = lookup(metrics, t.metric);
  std::optional<double> other;
  switch (t.kind) {
    case Target::Kind::Within:
      v.paper = format_number(t.value);
      v.tolerance = "± " + format_number(t.tolerance);
      v.expected = v.paper + " " + v.tolerance;
      if (ensemble) judge(v, member_values(*ensemble, t.metric), t.value - t.tolerance, t.value + t.tolerance, false);
      else v.pass = v.ours && std::abs(*v.ours - t.value) <= t.tolerance;
      break;
    case Target::Kind::Below:
      v.expected = v.paper = "< " + format_number(t.value);
      v.tolerance = "a bound";
      if (ensemble) judge(v, member_values(*ensemble, t.metric), -kInf, t.value, true);
      else v.pass = v.ours && *v.ours < t.value;
      break;
    case Target::Kind::Above:
      v.expected = v.paper = "> " + format_number(t.value);
      v.tolerance = "a bound";
      if (ensemble) judge(v, member_values(*ensemble, t.metric), t.value, kInf, true);
      else v.pass = v.ours && *v.ours > t.value;
      break;
    case Target::Kind::AboveMetric:
      other = lookup(metrics, t.other_metric);
      v.expected = v.paper = "> " + t.other_metric + (other ? " (= " + format_number(*other) + ")" : " (missing)");
      v.tolerance = "a shape";
      if (ensemble) {  // the members' differences, ours - the other
        const std::vector<double> a = member_values(*ensemble, t.metric), b = member_values(*ensemble, t.other_metric);
        std::vector<double> diff;
        for (std::size_t k = 0; k < a.size() && k < b.size(); ++k) diff.push_back(a[k] - b[k]);
        judge(v, diff, 0.0, kInf, true);
        v.ours = lookup(metrics, t.metric);  // report our mean, the verdict is on the differences
      } else {
        v.pass = v.ours && other && *v.ours > *other;
      }
      break;
  }
  // nothing found: evidence of absence only where the detector could have found it
  std::string power_note;
  if (!t.power_metric.empty() && (ensemble ? v.members == 0 : !v.ours)) {
    std::vector<double> power = ensemble ? member_values(*ensemble, t.power_metric) : std::vector<double>{};
    if (!ensemble) power.push_back(lookup(metrics, t.power_metric).value_or(std::nan("")));
    bool confident = !power.empty();
    double lowest = 1.0;
    for (const double p : power) {
      confident = confident && p >= t.min_power;  // NaN (no power measured) is not confident
      lowest = std::isfinite(p) ? std::min(lowest, p) : std::nan("");
    }
    power_note = std::string(ensemble ? "every member found none" : "none found") + ", power " +
                 (std::isfinite(lowest) ? (ensemble ? "at least " : "") + format_number(lowest) : "not measured") +
                 (confident ? " >= " : " < ") + format_number(t.min_power) + " (" + t.power_metric + ")";
    v.outcome = confident ? (ensemble ? "fails" : "fail") : "undetermined";
  }
  // no value because the detector could not decide: undetermined, with its reason
  if (!t.undecided_metric.empty() && (ensemble ? v.members == 0 : !v.ours)) {
    const std::string why = ensemble ? std::string() : lookup_text(metrics, t.undecided_metric);
    power_note = std::string(ensemble ? "no member could decide" : "the detector could not decide") +
                 (why.empty() ? "" : " (" + why + ")") + " [" + t.undecided_metric + "]";
    v.outcome = "undetermined";
  }
  if (!ensemble && v.outcome.empty()) v.outcome = v.pass ? "pass" : "fail";
  else if (v.outcome.empty()) v.outcome = "fails";  // no member gave it
  if (ensemble && v.interval)
    v.tolerance += std::string(t.kind == Target::Kind::AboveMetric ? "; the differences' " : "; the members' ") +
                   "95 % t-interval [" + format_number(v.interval->first) + ", " + format_number(v.interval->second) +
                   "], " + std::to_string(v.members) + " members" +
                   (v.members < v.members_total ? " of " + std::to_string(v.members_total) + " (the others gave none)" : "");
  const std::string head = t.result + " " + t.metric + " (" + t.what + "): ";
  if (!v.ours)
    v.message = head + "missing, null or not a number in the metrics" +
                (power_note.empty() ? "" : ": " + power_note + ": " + v.outcome);
  else
    v.message = head + format_number(*v.ours) + ", paper " + v.expected + ": " +
                v.outcome +
                (v.members_needed ? " (about " + std::to_string(*v.members_needed) + " members would decide)" : "") +
                " [" + t.source + "; tolerance: " + t.why + "]";
  return v;
}

}  // namespace dem2d::check
