// Grey images for PIV: intensities 0..1 in floats, row-major, row 0 at the
// top (a camera's frame); pixel (i, j) has its centre at x = i, y = j (px).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dem2d::analysis {

struct Image {
  std::size_t width = 0, height = 0;  // px
  std::vector<float> px;              // [height][width]
  Image() = default;
  Image(std::size_t w, std::size_t h, float value = 0.0f) : width(w), height(h), px(w * h, value) {}
  float at(std::size_t i, std::size_t j) const { return px[j * width + i]; }
  float& at(std::size_t i, std::size_t j) { return px[j * width + i]; }
  // The intensity at (x, y) by bicubic (Keys, a = -1/2) interpolation, the edge pixels repeated beyond it.
  double sample(double x, double y) const;
};

// A rectangle of pixels: columns [c0, c1), rows [r0, r1), cut to the image it is used on (by default
// the whole image).
struct PixelBox {
  std::size_t c0 = 0, c1 = SIZE_MAX, r0 = 0, r1 = SIZE_MAX;
};

// The image convolved with a Gaussian of sigma px (separable, the edge pixels repeated beyond it); with
// a box, only the pixels in it (the rest 0), each bitwise what the whole image's blur has there.
Image gaussian_blur(const Image& im, double sigma, PixelBox box = {});
// The image less its Gaussian blur of sigma px: the beads' slow shading removed, their edges and
// highlights kept (PIVlab's high-pass pre-processing). sigma <= 0: the image unchanged. With a box, only
// the pixels in it (the rest 0).
Image highpass(const Image& im, double sigma, PixelBox box = {});

// Pixels excluded from PIV (the intruder and what is not granular): 1 excluded.
struct Mask {
  std::size_t width = 0, height = 0;
  std::vector<std::uint8_t> px;  // [height][width]
  bool at(std::size_t i, std::size_t j) const { return !px.empty() && px[j * width + i] != 0; }
};

}  // namespace dem2d::analysis
