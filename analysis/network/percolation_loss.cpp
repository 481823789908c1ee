#include "network/percolation_loss.hpp"

#include <algorithm>
#include <cmath>

#include "common/stage_output.hpp"  // format_number
#include "network/network.hpp"

namespace dem2d::analysis {

namespace {

double rule_height(const FlagProfile& f, const LossTestSettings& s) {
  const std::vector<std::uint8_t> flags(f.flags.begin(), f.flags.end());
  const std::optional<double> h = loss_height(percolation_profile(s.bins, f.heights, flags), s.level);
  return h ? *h : std::nan("");
}

}  // namespace

LossTest percolation_loss(const std::vector<double>& heights, const std::vector<std::uint8_t>& flags, double surface,
                          const LossTestSettings& s) {
  FlagProfile f;
  f.heights = heights;
  f.surfaces.assign(heights.size(), surface);
  f.flags.assign(flags.begin(), flags.end());
  LossTest out;
  const double rule = rule_height(f, s);
  if (std::isfinite(rule)) out.rule_height = rule;
  out.p_value = step_p_value(f, s.permutations);
  const bool significant = out.rule_height && out.p_value < s.false_alarm;
  if (significant) out.height = out.rule_height;
  out.power = step_power(f, s.depth, s.tolerance, s.false_alarm, s.permutations, s.replicas,
                         [&](const FlagProfile& p) { return rule_height(p, s); });
  if (significant) {
    out.outcome = "found";
    return out;
  }
  const bool confident = std::isfinite(out.power.power) && out.power.power >= s.min_power;
  const bool never = std::find(flags.begin(), flags.end(), std::uint8_t{1}) == flags.end();
  const std::string why =
      !out.rule_height ? "the strong network still percolates in the highest height bin"
      : never ? "the strong network percolates in no snapshot (lost at or below the lowest height seen)"
              : "no significant loss (percolating below, not above, is not better than the same flags shuffled over "
                "the heights: p = " + format_number(out.p_value) + ")";
  out.outcome = std::string(confident ? "none: " : "undetermined: ") + why + "; power " +
                format_number(out.power.power) + " to find one at the paper's depth";
  return out;
}

}  // namespace dem2d::analysis
