#include "cg/wall_loss.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace dem2d::analysis {

namespace {

// How much the step fit beats calling every snapshot the majority class.
double step_gain(const std::vector<double>& h, const std::vector<bool>& f) {
  const auto mobile = static_cast<int>(std::count(f.begin(), f.end(), true));
  return std::min(mobile, static_cast<int>(f.size()) - mobile) - step_down(h, f).misclassified;
}

double fraction(std::size_t part, std::size_t whole) {
  return whole ? static_cast<double>(part) / static_cast<double>(whole) : kNaN;
}

}  // namespace

double surface_near(const WallLoss& w, double height) {
  if (w.heights.empty()) return kNaN;
  std::size_t best = 0;
  for (std::size_t q = 1; q < w.heights.size(); ++q)
    if (std::abs(w.heights[q] - height) < std::abs(w.heights[best] - height)) best = q;
  return w.surfaces[best];
}

double loss_p_value(const WallLoss& w, int permutations) {
  const double gain = step_gain(w.heights, w.flags);
  if (permutations <= 0 || w.flags.empty()) return kNaN;
  std::mt19937_64 rng(1);
  std::vector<bool> f = w.flags;
  int as_large = 0;
  for (int p = 0; p < permutations; ++p) {
    for (std::size_t i = f.size(); i-- > 1;) {
      const std::size_t j = static_cast<std::size_t>(rng() % (i + 1));
      const bool t = f[i];
      f[i] = f[j], f[j] = t;
    }
    as_large += step_gain(w.heights, f) >= gain;
  }
  return (as_large + 1.0) / (permutations + 1.0);
}

LossPower loss_power(const WallLoss& w, double depth, double tolerance, double false_alarm, int permutations,
                     int replicas) {
  LossPower out;
  out.depth = depth;
  if (w.flags.empty() || replicas <= 0) return out;
  std::size_t below = 0, above = 0, immobile_below = 0, mobile_above = 0;
  for (std::size_t i = 0; i < w.heights.size(); ++i) {
    if (w.heights[i] < w.surfaces[i] - depth) ++below, immobile_below += !w.flags[i];
    else ++above, mobile_above += w.flags[i];
  }
  out.missed = fraction(immobile_below, below);
  out.false_mobile = fraction(mobile_above, above);
  out.replicas = replicas;
  int found = 0;
  for (int r = 0; r < replicas; ++r) {
    std::mt19937_64 rng(static_cast<std::uint64_t>(r) + 1);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    WallLoss p = w;
    for (std::size_t i = 0; i < p.flags.size(); ++i) {
      const bool mobile = p.heights[i] < p.surfaces[i] - depth;
      const double flip = mobile ? (std::isfinite(out.missed) ? out.missed : 0.0)
                                 : (std::isfinite(out.false_mobile) ? out.false_mobile : 0.0);
      p.flags[i] = u(rng) < flip ? !mobile : mobile;
    }
    p.fit = step_down(p.heights, p.flags);
    if (!std::isfinite(p.fit.height) || !(loss_p_value(p, permutations) < false_alarm)) continue;
    found += std::abs(surface_near(p, p.fit.height) - p.fit.height - depth) <= tolerance;
  }
  out.power = static_cast<double>(found) / static_cast<double>(replicas);
  return out;
}

}  // namespace dem2d::analysis
