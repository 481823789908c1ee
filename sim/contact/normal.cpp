#include "contact/normal.hpp"

#include <cmath>

#include <stdexcept>
#include <string>

#include "core/number_text.hpp"

namespace dem2d {

double restitution_of_damping_ratio(double nu) {
  if (!(nu >= 0.0)) throw std::invalid_argument("damping ratio " + shortest(nu) + " is not >= 0");
  if (nu == 0.0) return 1.0;
  // arccos(nu)/sqrt(1 - nu^2) continues analytically to arccosh(nu)/sqrt(nu^2 - 1)
  // above 1; both tend to 1 at nu = 1, where a series avoids 0/0.
  const double s = nu * nu - 1.0;
  double g;
  if (std::abs(s) < 1e-6)
    g = 1.0 - s / 6.0;  // g(nu) = 1 - (nu^2 - 1)/6 + O((nu^2 - 1)^2)
  else if (s < 0.0)
    g = std::acos(nu) / std::sqrt(-s);
  else
    g = std::acosh(nu) / std::sqrt(s);
  return std::exp(-2.0 * nu * g);
}

double damping_ratio(double restitution) {
  const double e = restitution;
  if (!(e > 0.0 && e <= 1.0))
    throw std::invalid_argument("restitution " + shortest(e) + " is not in (0, 1]");
  if (e == 1.0) return 0.0;
  // e(nu) falls monotonically from 1 to 0: bisect on [0, hi] with e(hi) < e
  double lo = 0.0, hi = 1.0;
  while (restitution_of_damping_ratio(hi) > e) hi *= 2.0;
  for (int k = 0; k < 200 && hi - lo > 1e-16 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    (restitution_of_damping_ratio(mid) > e ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace dem2d
