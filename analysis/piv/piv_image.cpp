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
  if (ix >= 1 && ix + 2 <= W && iy >= 1 && iy + 2 <= H) {  // inside: no pixel repeated (the same sums)
    const float* p = &px[static_cast<std::size_t>(iy - 1) * width + static_cast<std::size_t>(ix - 1)];
    for (int b = 0; b < 4; ++b, p += width) sum += wy[b] * ((((0.0 + wx[0] * p[0]) + wx[1] * p[1]) + wx[2] * p[2]) + wx[3] * p[3]);
    return sum;
  }
  for (int b = 0; b < 4; ++b) {
    const std::size_t row = static_cast<std::size_t>(std::clamp(iy - 1 + b, 0L, H)) * width;
    double line = 0.0;
    for (int a = 0; a < 4; ++a) line += wx[a] * px[row + static_cast<std::size_t>(std::clamp(ix - 1 + a, 0L, W))];
    sum += wy[b] * line;
  }
  return sum;
}

Image gaussian_blur(const Image& im, double sigma, PixelBox box) {
  const long r = static_cast<long>(std::ceil(3.0 * sigma));
  std::vector<double> k(2 * static_cast<std::size_t>(r) + 1);
  double sum = 0.0;
  for (long i = -r; i <= r; ++i) sum += k[static_cast<std::size_t>(i + r)] = std::exp(-0.5 * static_cast<double>(i * i) / (sigma * sigma));
  for (double& v : k) v /= sum;
  box.c1 = std::min(box.c1, im.width), box.r1 = std::min(box.r1, im.height);
  Image out(im.width, im.height);
  if (box.c0 >= box.c1 || box.r0 >= box.r1) return out;
  const std::size_t n = box.c1 - box.c0, R = static_cast<std::size_t>(r);
  const long W = static_cast<long>(im.width), H = static_cast<long>(im.height);
  // along the rows the box's columns need, the edge pixels repeated beyond the image: each pixel's sum
  // over q = -r..r in that order, vectorised across the row's pixels
  const long t0 = std::max(0L, static_cast<long>(box.r0) - r), t1 = std::min(H, static_cast<long>(box.r1) + r);
  Image tmp(n, static_cast<std::size_t>(t1 - t0));
  std::vector<float> padded(n + 2 * R);
  std::vector<double> acc(n);
  for (long j = t0; j < t1; ++j) {
    const float* row = &im.px[static_cast<std::size_t>(j) * im.width];
    for (std::size_t p = 0; p < padded.size(); ++p)
      padded[p] = row[std::clamp(static_cast<long>(box.c0 + p) - r, 0L, W - 1)];
    std::fill(acc.begin(), acc.end(), 0.0);
    for (std::size_t q = 0; q < k.size(); ++q) {
      const double w = k[q];
      const float* in = &padded[q];
      for (std::size_t i = 0; i < n; ++i) acc[i] += w * in[i];
    }
    float* o = &tmp.px[static_cast<std::size_t>(j - t0) * n];
    for (std::size_t i = 0; i < n; ++i) o[i] = static_cast<float>(acc[i]);
  }
  // down the columns a row at a time (the rows are contiguous)
  for (long j = static_cast<long>(box.r0); j < static_cast<long>(box.r1); ++j) {
    std::fill(acc.begin(), acc.end(), 0.0);
    for (long q = -r; q <= r; ++q) {
      const float* row = &tmp.px[static_cast<std::size_t>(std::clamp(j + q, 0L, H - 1) - t0) * n];
      const double w = k[static_cast<std::size_t>(q + r)];
      for (std::size_t i = 0; i < n; ++i) acc[i] += w * row[i];
    }
    float* o = &out.px[static_cast<std::size_t>(j) * im.width + box.c0];
    for (std::size_t i = 0; i < n; ++i) o[i] = static_cast<float>(acc[i]);
  }
  return out;
}

Image highpass(const Image& im, double sigma, PixelBox box) {
  if (!(sigma > 0.0)) return im;
  Image out = gaussian_blur(im, sigma, box);
  box.c1 = std::min(box.c1, im.width), box.r1 = std::min(box.r1, im.height);
  for (std::size_t j = box.r0; j < box.r1; ++j)
    for (std::size_t i = box.c0; i < box.c1; ++i) out.at(i, j) = im.at(i, j) - out.at(i, j);
  return out;
}

}  // namespace dem2d::analysis
