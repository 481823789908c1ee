// PIV of an image pair (as PIVlab does it, Thielicke & Stamhuis 2014): FFT
// cross-correlation of interrogation windows in several passes, each pass's
// field (validated, outliers replaced) deforming both images for the next,
// symmetrically (A at p - D(p)/2, B at p + D(p)/2, bicubic), so that the
// windows shrink (64 -> 32 px) and the residual displacement is small; a mask
// excludes pixels (the intruder; what is not granular). Displacements in px,
// dy down (image rows); the caller converts to its frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "piv/piv_image.hpp"

namespace dem2d::analysis {

struct PivSettings {
  std::vector<int> windows{64, 32, 32};  // window size of each pass (px, even)
  double overlap = 0.5;                  // windows overlap by this fraction (step = size x (1 - overlap))
  // both images high-passed first (image less its Gaussian blur of this sigma, px; 0: not): beads of
  // 35 px with a smooth shading give broad, cone-topped correlation peaks whose three-point sub-pixel
  // fit returns ~30 % of a small residual (0.72 px read 0.43 px, 0.5 after 10 passes); high-passed at
  // 3 px they read 0.72 to 0.04 px rms in two passes (analysis/piv/README.md)
  double highpass_px = 0.0;
  double median_threshold = 2.0;         // normalised median test (Westerweel & Scarano 2005): outlier above it
  double median_epsilon = 0.1;           // its noise level (px)
  double max_excluded = 0.5;             // a window with a larger share of excluded pixels gives no vector
  // the last pass repeated while its field still changes (rms over the vectors, px) by more than this, at
  // most max_repeats times: each pass removes only part of the residual where the windows' texture is
  // coarse (beads of 35 px in 32 px windows), as the correlation peak is pulled towards zero shift
  double converged_px = 0.01;
  int max_repeats = 8;
};

enum class Vector : std::uint8_t { measured = 0, replaced = 1, none = 2 };

struct VectorField {
  std::size_t nx = 0, ny = 0;
  double x0 = 0.0, y0 = 0.0, step = 0.0;  // window centres x0 + i step, y0 + j step (px)
  std::vector<double> u, v;               // displacement (px) [ny][nx]; NaN where none
  std::vector<Vector> status;             // [ny][nx]
  double x(std::size_t i) const { return x0 + step * static_cast<double>(i); }
  double y(std::size_t j) const { return y0 + step * static_cast<double>(j); }
  std::size_t count(Vector s) const;
};

// The windows of size n at the given overlap over a width x height image (none if n > either).
VectorField window_grid(std::size_t width, std::size_t height, int n, double overlap);

// The normalised median test over each vector's 3 x 3 neighbours with a vector (at least 2): outliers
// (residual sqrt(ru^2 + rv^2) > threshold) replaced by their neighbours' median; returns how many.
std::size_t replace_outliers(VectorField& f, double threshold, double epsilon);

// The field at (x, y) (px), bilinear between window centres, constant beyond them; vectors that are
// none count as their neighbours' mean (filled outwards), 0 if there is no vector at all.
struct Predictor {
  explicit Predictor(const VectorField& f);
  void at(double x, double y, double& u, double& v) const;
  // the same from the bilinear cells of x and of y, each made once for a column or a row of pixels
  struct Cell {
    std::size_t i = 0, i1 = 0;  // the window centres either side
    double t = 0.0;             // the weight of i1
  };
  Cell column(double x) const { return cell(x, field.nx, field.x0, field.step); }
  Cell row(double y) const { return cell(y, field.ny, field.y0, field.step); }
  void at(const Cell& cx, const Cell& cy, double& u, double& v) const;
  VectorField field;

 private:
  static Cell cell(double x, std::size_t n, double x0, double step);
};

// a and b the same size (and the mask, if given); threads: OpenMP threads over window rows (the result
// does not depend on them). std::invalid_argument on sizes that hold no window. *passes (if given): the
// passes made, the repeats included.
VectorField piv(const Image& a, const Image& b, const Mask& mask, const PivSettings& s, int threads, int* passes = nullptr);

}  // namespace dem2d::analysis
