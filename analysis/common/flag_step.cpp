#include "common/flag_step.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace dem2d::analysis {

namespace {

// How much the step fit beats calling every snapshot the majority class.
int step_gain(const std::vector<double>& h, const std::vector<bool>& f) {
  const auto yes = static_cast<int>(std::count(f.begin(), f.end(), true));
  return std::min(yes, static_cast<int>(f.size()) - yes) - step_down(h, f).misclassified;
}

std::vector<std::size_t> height_order(const std::vector<double>& heights) {
  std::vector<std::size_t> order(heights.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return heights[a] < heights[b]; });
  return order;
}

}  // namespace

StepFit step_down(const std::vector<double>& heights, const std::vector<bool>& flags) {
  const std::vector<std::size_t> order = height_order(heights);
  const std::size_t n = order.size();
  StepFit fit;
  fit.count = static_cast<int>(n);
  // errors(s): the s lowest are called yes, the rest no
  int errors = static_cast<int>(std::count(flags.begin(), flags.end(), true));  // s = 0: all called no
  int best = errors;
  std::vector<std::size_t> best_s = {0};
  for (std::size_t s = 1; s <= n; ++s) {
    errors += flags[order[s - 1]] ? -1 : +1;
    if (s < n && heights[order[s]] == heights[order[s - 1]]) continue;  // no split between equal heights
    if (errors < best) best = errors, best_s.assign(1, s);
    else if (errors == best) best_s.push_back(s);
  }
  fit.misclassified = best;
  std::vector<double> splits;
  for (const std::size_t s : best_s)
    if (s > 0 && s < n) splits.push_back(0.5 * (heights[order[s - 1]] + heights[order[s]]));
  if (!splits.empty()) fit.height = 0.5 * (splits.front() + splits.back());
  return fit;
}

double surface_near(const FlagProfile& f, double height) {
  if (f.heights.empty()) return std::nan("");
  std::size_t best = 0;
  for (std::size_t q = 1; q < f.heights.size(); ++q)
    if (std::abs(f.heights[q] - height) < std::abs(f.heights[best] - height)) best = q;
  return f.surfaces[best];
}

double step_p_value(const FlagProfile& f, int permutations) {
  if (permutations <= 0 || f.flags.empty()) return std::nan("");
  const int gain = step_gain(f.heights, f.flags);
  std::mt19937_64 rng(1);
  std::vector<bool> shuffled = f.flags;
  int as_large = 0;
  for (int p = 0; p < permutations; ++p) {
    for (std::size_t i = shuffled.size(); i-- > 1;) {
      const std::size_t j = static_cast<std::size_t>(rng() % (i + 1));
      const bool t = shuffled[i];
      shuffled[i] = shuffled[j], shuffled[j] = t;
    }
    as_large += step_gain(f.heights, shuffled) >= gain;
  }
  return (as_large + 1.0) / (permutations + 1.0);
}

double flip_rate(const FlagProfile& f, const std::function<bool(std::size_t)>& in) {
  std::size_t n = 0, yes = 0;
  for (std::size_t i = 0; i < f.flags.size(); ++i)
    if (in(i)) ++n, yes += f.flags[i];
  if (n == 0) return 0.0;
  return static_cast<double>(std::min(yes, n - yes)) / static_cast<double>(n);
}

StepPower step_power(const FlagProfile& f, double depth, double tolerance, double false_alarm, int permutations,
                     int replicas, const StepLocator& locate) {
  StepPower out;
  out.depth = depth;
  if (f.flags.empty() || replicas <= 0) return out;
  const auto below = [&](std::size_t i) { return f.heights[i] < f.surfaces[i] - depth; };
  out.flip_below = flip_rate(f, below);
  out.flip_above = flip_rate(f, [&](std::size_t i) { return !below(i); });
  out.replicas = replicas;
  int found = 0;
  for (int r = 0; r < replicas; ++r) {
    std::mt19937_64 rng(static_cast<std::uint64_t>(r) + 1);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    FlagProfile p = f;
    for (std::size_t i = 0; i < p.flags.size(); ++i) {
      const bool yes = below(i);
      p.flags[i] = u(rng) < (yes ? out.flip_below : out.flip_above) ? !yes : yes;
    }
    const double h = locate(p);
    if (!std::isfinite(h) || !(step_p_value(p, permutations) < false_alarm)) continue;
    found += std::abs(surface_near(p, h) - h - depth) <= tolerance;
  }
  out.power = static_cast<double>(found) / static_cast<double>(replicas);
  return out;
}

}  // namespace dem2d::analysis
