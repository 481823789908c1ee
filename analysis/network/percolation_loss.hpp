// The percolation loss as a test: the height rule of network.hpp
// (loss_height: the top of the highest bin that still percolates in at least
// loss_level of its snapshots) gives the height, the step test of
// common/flag_step.hpp on the percolating flags against the intruder's height
// says whether a loss is there at all (p < loss_false_alarm), and where none
// is found, the power to find one planted at the paper's depth below the bed's
// surface in flags as mixed as the run's own. SI units (m).
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "common/flag_step.hpp"
#include "frame/height_bins.hpp"

namespace dem2d::analysis {

struct LossTestSettings {
  HeightBins bins;
  double level = 0.5;          // the height rule's percolating fraction
  double false_alarm = 0.01;   // a loss: step p-value below this
  int permutations = 200;      // of the step test
  double depth = 0.0;          // the planted loss's depth below the surface (m): the paper's claim
  double tolerance = 0.0;      // a planted loss is found within this (m)
  int replicas = 20;           // planted series for the power
  double min_power = 0.8;      // a none is evidence of absence from this power on
};

struct LossTest {
  std::optional<double> rule_height;  // the height rule alone (m)
  std::optional<double> height;       // the loss: the rule's height where the step is significant (m)
  double p_value = std::numeric_limits<double>::quiet_NaN();
  StepPower power;                    // measured found or not
  std::string outcome;                // "found", "none: ...", "undetermined: ..."
};

// `heights`: the intruder's height at each snapshot (m); `flags`: percolating
// or not; `surface`: the bed's surface (m).
LossTest percolation_loss(const std::vector<double>& heights, const std::vector<std::uint8_t>& flags, double surface,
                          const LossTestSettings& s);

}  // namespace dem2d::analysis
