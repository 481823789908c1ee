#include "planted/piv_images.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace dem2d::planted {

namespace {

// adds a Gaussian spot of e^-2 diameter `d` at (x, y)
void spot(analysis::Image& im, double x, double y, double d, double peak) {
  const double s2 = d * d / 8.0, reach = 1.5 * d;  // I = exp(-r^2 / (2 s^2)), e^-2 at r = d/2
  const long i0 = std::max(0L, static_cast<long>(std::floor(x - reach))), i1 = std::min(static_cast<long>(im.width) - 1, static_cast<long>(std::ceil(x + reach)));
  const long j0 = std::max(0L, static_cast<long>(std::floor(y - reach))), j1 = std::min(static_cast<long>(im.height) - 1, static_cast<long>(std::ceil(y + reach)));
  for (long j = j0; j <= j1; ++j)
    for (long i = i0; i <= i1; ++i) {
      const double dx = static_cast<double>(i) - x, dy = static_cast<double>(j) - y, r2 = dx * dx + dy * dy;
      im.at(static_cast<std::size_t>(i), static_cast<std::size_t>(j)) += static_cast<float>(peak * std::exp(-r2 / (2.0 * s2)));
    }
}

}  // namespace

void particle_pair(std::size_t width, std::size_t height, const ParticleImages& p, const Displacement& d,
                   analysis::Image& a, analysis::Image& b) {
  a = analysis::Image(width, height), b = analysis::Image(width, height);
  std::mt19937 rng(p.seed);
  // particles over the image and a margin around it, so that moved particles enter the frame
  const double margin = 20.0;
  const double w = static_cast<double>(width), h = static_cast<double>(height);
  std::uniform_real_distribution<double> ux(-margin, w + margin), uy(-margin, h + margin), up(0.6, 1.0);
  const auto count = static_cast<std::size_t>(p.density * (w + 2 * margin) * (h + 2 * margin));
  for (std::size_t k = 0; k < count; ++k) {
    const double x = ux(rng), y = uy(rng), peak = up(rng);
    double u, v;
    d(x, y, u, v);
    spot(a, x, y, p.diameter, peak);
    spot(b, x + u, y + v, p.diameter, peak);
  }
  if (p.noise > 0.0) {
    std::normal_distribution<double> n(0.0, p.noise);
    for (float& v : a.px) v += static_cast<float>(n(rng));
    for (float& v : b.px) v += static_cast<float>(n(rng));
  }
}

Beads bead_bed(double w, double h, unsigned seed) {
  Beads b;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.4e-3, 0.4e-3), size(2e-3, 4e-3);
  const double pitch = 4.1e-3, row = pitch * std::sqrt(3.0) / 2.0;
  int r = 0;
  for (double y = 0.0; y <= h; y += row, ++r)
    for (double x = (r % 2) * 0.5 * pitch; x <= w; x += pitch) {
      b.position.push_back({x + jitter(rng), y + jitter(rng)});
      b.diameter.push_back(size(rng));
      b.active.push_back(1);
    }
  return b;
}

}  // namespace dem2d::planted
