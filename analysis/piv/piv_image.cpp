#include "piv/piv_image.hpp"

#include <algorithm>
#include <cmath>

namespace dem2d::analysis {

namespace {

// Keys' cubic convolution kernel weights for the offset t in [0, 1): pixels -1, 0, 1, 2
void keys(double t, double w[4]) {
  const double a = -0.5, t2 = t * t, t3 = t2 * t;
  w[0] = a * (t3 - 2 * t2 + t);
  w[1] = (a + 2) * t3 - (a + 3) * t2 + 1;
  w[2] = -(a + 2) * t3 + (2 * a + 3) * t2 - a * t;
  w[3] = a * (t2 - t3);
}

}  // namespace

double Image::sample(double x, double y) const {
  const double fx = std::floor(x), fy = std::floor(y);
  double wx[4], wy[4];
  keys(x - fx, wx);
  keys(y - fy, wy);
  const long ix = static_cast<long>(fx), iy = static_cast<long>(fy);
  const long W = static_cast<long>(width) - 1, H = static_cast<long>(height) - 1;
  double sum = 0.0;
  for (int b = 0; b < 4; ++b) {
    const std::size_t row = static_cast<std::size_t>(std::clamp(iy - 1 + b, 0L, H)) * width;
    double line = 0.0;
    for (int a = 0; a < 4; ++a) line += wx[a] * px[row + static_cast<std::size_t>(std::clamp(ix - 1 + a, 0L, W))];
    sum += wy[b] * line;
  }
  return sum;
}

}  // namespace dem2d::analysis
