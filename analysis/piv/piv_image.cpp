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

namespace {

// out(i) = sum_q k[q + r] in(clamp(i + q)) along a row of n values
void convolve_row(const float* in, float* out, std::size_t n, const std::vector<double>& k, long r) {
  const long N = static_cast<long>(n);
  for (long i = 0; i < N; ++i) {
    double s = 0.0;
    if (i >= r && i + r < N) {  // inside: no clamp
      const float* p = in + (i - r);
      for (std::size_t q = 0; q < k.size(); ++q) s += k[q] * p[q];
    } else {
      for (long q = -r; q <= r; ++q) s += k[static_cast<std::size_t>(q + r)] * in[std::clamp(i + q, 0L, N - 1)];
    }
    out[i] = static_cast<float>(s);
  }
}

}  // namespace

Image gaussian_blur(const Image& im, double sigma) {
  const long r = static_cast<long>(std::ceil(3.0 * sigma));
  std::vector<double> k(2 * static_cast<std::size_t>(r) + 1);
  double sum = 0.0;
  for (long i = -r; i <= r; ++i) sum += k[static_cast<std::size_t>(i + r)] = std::exp(-0.5 * static_cast<double>(i * i) / (sigma * sigma));
  for (double& v : k) v /= sum;
  Image tmp(im.width, im.height), out(im.width, im.height);
  for (std::size_t j = 0; j < im.height; ++j) convolve_row(&im.px[j * im.width], &tmp.px[j * im.width], im.width, k, r);
  // down the columns a row at a time (the rows are contiguous)
  const long H = static_cast<long>(im.height);
  std::vector<double> acc(im.width);
  for (long j = 0; j < H; ++j) {
    std::fill(acc.begin(), acc.end(), 0.0);
    for (long q = -r; q <= r; ++q) {
      const float* row = &tmp.px[static_cast<std::size_t>(std::clamp(j + q, 0L, H - 1)) * im.width];
      const double w = k[static_cast<std::size_t>(q + r)];
      for (std::size_t i = 0; i < im.width; ++i) acc[i] += w * row[i];
    }
    float* o = &out.px[static_cast<std::size_t>(j) * im.width];
    for (std::size_t i = 0; i < im.width; ++i) o[i] = static_cast<float>(acc[i]);
  }
  return out;
}

Image highpass(const Image& im, double sigma) {
  if (!(sigma > 0.0)) return im;
  Image out = gaussian_blur(im, sigma);
  for (std::size_t q = 0; q < out.px.size(); ++q) out.px[q] = im.px[q] - out.px[q];
  return out;
}

}  // namespace dem2d::analysis
