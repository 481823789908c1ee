// The cross-correlation of two n x n interrogation windows by FFT (FFTW,
// real to complex), as PIV does (Raffel et al., "Particle Image
// Velocimetry", ch. 5): R(s) = sum_p a(p) b(p + s) over the windows with
// their means removed (masked pixels contributing nothing), its highest peak
// the displacement of b's pattern against a's, to a fraction of a pixel by a
// three-point Gaussian fit along x and along y (parabolic where a value is
// not positive). One object per thread; plans are made under the shared lock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dem2d::analysis {

class WindowCorrelation {
 public:
  explicit WindowCorrelation(int n);  // n even
  ~WindowCorrelation();
  WindowCorrelation(const WindowCorrelation&) = delete;
  WindowCorrelation& operator=(const WindowCorrelation&) = delete;

  int size() const { return n_; }
  // the windows to fill, row-major [n][n], and their excluded pixels (1 excluded)
  double* a() { return a_; }
  double* b() { return b_; }
  std::uint8_t* excluded() { return excluded_.data(); }

  struct Peak {
    bool found = false;     // false: a blank window (no contrast) or a flat correlation
    double dx = 0.0, dy = 0.0;  // px, b against a (dy down, as image rows)
  };
  Peak correlate();

 private:
  int n_;
  double *a_, *b_, *r_;
  void *fa_, *fb_;  // fftw_complex[n][n/2 + 1]
  void *plan_a_, *plan_b_, *plan_r_;
  std::vector<std::uint8_t> excluded_;
};

}  // namespace dem2d::analysis
