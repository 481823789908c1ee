// The size distribution of the rupture events, fitted by maximum likelihood
// as Clauset, Shalizi & Newman (2009, SIAM Review 51, 661) do: a continuous
// power law above x_min (x_min by the smallest Kolmogorov-Smirnov distance,
// its goodness of fit by a semi-parametric bootstrap), and on the same tail
// (x >= x_min) a lognormal and an exponential, compared pairwise by Vuong's
// normalised log-likelihood ratio. Pure functions; sizes in any one unit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace dem2d::analysis {

struct SizeFitSettings {
  std::size_t min_tail = 10;   // fewest sizes above x_min for a fit
  int bootstrap = 200;         // synthetic sets for the power law's p-value (0: none)
  double significance = 0.1;   // a likelihood ratio decides only below this p (CSN's 0.1)
  std::uint64_t seed = 1;      // of the bootstrap
  // a power law is plausible only over a range of scales: its tail must span
  // at least this many decades (x_max / x_min >= 10^min_decades). On a
  // narrower tail an exponential's or a lognormal's end fits a steep power
  // law as well (the KS test cannot reject it there)
  double min_decades = 1.0;
  double plausible_p = 0.1;    // the goodness of fit's p that makes the power law plausible (CSN)
};

struct FamilyFit {
  std::string family;  // "power_law", "lognormal", "exponential"
  // power law p(x) ~ x^-alpha; lognormal mu, sigma of ln x (truncated at x_min); exponential rate lambda
  double alpha = std::numeric_limits<double>::quiet_NaN();
  double mu = std::numeric_limits<double>::quiet_NaN(), sigma = std::numeric_limits<double>::quiet_NaN();
  double lambda = std::numeric_limits<double>::quiet_NaN();
  double log_likelihood = std::numeric_limits<double>::quiet_NaN();
  double ks = std::numeric_limits<double>::quiet_NaN();  // largest distance between the tail's CDF and the fit's
};

struct Comparison {
  std::string a, b;  // families
  double ratio = std::numeric_limits<double>::quiet_NaN();    // log-likelihood ratio R = sum ln p_a - ln p_b
  double normalised = std::numeric_limits<double>::quiet_NaN();  // R / (sqrt(n) sd): > 0 favours a
  double p = std::numeric_limits<double>::quiet_NaN();        // two-sided p of |R| under "equally good"
  std::string favoured;  // a, b, or "neither" (p >= significance)
};

struct SizeDistribution {
  std::size_t n = 0;         // sizes given
  bool fitted = false;       // at least min_tail sizes
  double x_min = std::numeric_limits<double>::quiet_NaN();
  std::size_t tail = 0;      // sizes >= x_min
  double power_law_p = std::numeric_limits<double>::quiet_NaN();  // goodness of fit: > 0.1 plausible (CSN)
  FamilyFit power_law, lognormal, exponential;
  std::vector<Comparison> comparisons;  // power law - lognormal, power law - exponential, lognormal - exponential
  std::string best;  // the family no other beats and that beats every other; else "undecided"
  double decades = std::numeric_limits<double>::quiet_NaN();  // log10(x_max / x_min) of the tail
  // power law plausible: goodness of fit p >= plausible_p and a tail of at least min_decades
  bool power_law_plausible = false;
  // undecided: the family with the largest likelihood on the tail, and how many
  // sizes in the tail its two comparisons need to decide at `significance` if
  // each size keeps adding to the ratios as these do (n (z_crit / z)^2 for the
  // weaker comparison; infinite when a ratio is zero)
  std::string leading;
  double tail_needed = std::numeric_limits<double>::quiet_NaN();
};

SizeDistribution fit_sizes(const std::vector<double>& sizes, const SizeFitSettings& s);

// The continuous power law's MLE above x_min and its KS distance on the tail (internals, tested).
double power_law_alpha(const std::vector<double>& sorted_tail, double x_min);

}  // namespace dem2d::analysis
