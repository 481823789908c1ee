#include "piv/piv_correlate.hpp"

#include <fftw3.h>

#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>

#include "common/fftw_lock.hpp"

namespace dem2d::analysis {

WindowCorrelation::WindowCorrelation(int n) : n_(n), excluded_(static_cast<std::size_t>(n) * n, 0) {
  if (n < 4 || n % 2 != 0) throw std::invalid_argument("PIV window of " + std::to_string(n) + " px: must be even, >= 4");
  const std::size_t real = static_cast<std::size_t>(n) * n, complex = static_cast<std::size_t>(n) * (n / 2 + 1);
  a_ = fftw_alloc_real(real), b_ = fftw_alloc_real(real), r_ = fftw_alloc_real(real);
  fa_ = fftw_alloc_complex(complex), fb_ = fftw_alloc_complex(complex);
  {
    const std::lock_guard<std::mutex> lock(fftw_planner_lock());
    auto* fa = static_cast<fftw_complex*>(fa_);
    auto* fb = static_cast<fftw_complex*>(fb_);
    plan_a_ = fftw_plan_dft_r2c_2d(n, n, a_, fa, FFTW_ESTIMATE);  // ESTIMATE: the same plan, the same bits, every run
    plan_b_ = fftw_plan_dft_r2c_2d(n, n, b_, fb, FFTW_ESTIMATE);
    plan_r_ = fftw_plan_dft_c2r_2d(n, n, fb, r_, FFTW_ESTIMATE);
  }
  if (!a_ || !b_ || !r_ || !fa_ || !fb_ || !plan_a_ || !plan_b_ || !plan_r_)
    throw std::runtime_error("FFTW: cannot plan a " + std::to_string(n) + " x " + std::to_string(n) + " correlation");
}

WindowCorrelation::~WindowCorrelation() {
  {
    const std::lock_guard<std::mutex> lock(fftw_planner_lock());
    for (void* p : {plan_a_, plan_b_, plan_r_})
      if (p) fftw_destroy_plan(static_cast<fftw_plan>(p));
  }
  fftw_free(a_), fftw_free(b_), fftw_free(r_), fftw_free(fa_), fftw_free(fb_);
}

namespace {

// sub-pixel offset of a peak from its value c0 and its neighbours' cm, cp
double subpixel(double cm, double c0, double cp) {
  if (cm > 0.0 && c0 > 0.0 && cp > 0.0) {
    const double lm = std::log(cm), l0 = std::log(c0), lp = std::log(cp), den = 2.0 * lm - 4.0 * l0 + 2.0 * lp;
    if (den < 0.0) return (lm - lp) / den;
  }
  const double den = cm - 2.0 * c0 + cp;
  return den < 0.0 ? 0.5 * (cm - cp) / den : 0.0;
}

}  // namespace

WindowCorrelation::Peak WindowCorrelation::correlate() {
  const std::size_t N = static_cast<std::size_t>(n_) * n_;
  // remove each window's mean over its unexcluded pixels; excluded pixels contribute nothing
  for (double* w : {a_, b_}) {
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t p = 0; p < N; ++p)
      if (!excluded_[p]) sum += w[p], ++count;
    const double mean = count > 0 ? sum / static_cast<double>(count) : 0.0;
    for (std::size_t p = 0; p < N; ++p) w[p] = excluded_[p] ? 0.0 : w[p] - mean;
  }
  fftw_execute(static_cast<fftw_plan>(plan_a_));
  fftw_execute(static_cast<fftw_plan>(plan_b_));
  auto* fa = static_cast<fftw_complex*>(fa_);
  auto* fb = static_cast<fftw_complex*>(fb_);
  const std::size_t C = static_cast<std::size_t>(n_) * (n_ / 2 + 1);
  for (std::size_t k = 0; k < C; ++k) {  // conj(A) B
    const double re = fa[k][0] * fb[k][0] + fa[k][1] * fb[k][1], im = fa[k][0] * fb[k][1] - fa[k][1] * fb[k][0];
    fb[k][0] = re, fb[k][1] = im;
  }
  fftw_execute(static_cast<fftw_plan>(plan_r_));
  const auto at = [&](int i, int j) { return r_[static_cast<std::size_t>((j + n_) % n_) * n_ + (i + n_) % n_]; };
  std::size_t bk = 0;
  double best = -1.0;
  for (std::size_t k = 0; k < N; ++k)
    if (r_[k] > best) best = r_[k], bk = k;
  Peak p;
  if (!(best > 0.0) || !std::isfinite(best)) return p;
  const int bi = static_cast<int>(bk % static_cast<std::size_t>(n_)), bj = static_cast<int>(bk / static_cast<std::size_t>(n_));
  p.found = true;
  const int si = bi >= n_ / 2 ? bi - n_ : bi, sj = bj >= n_ / 2 ? bj - n_ : bj;
  p.dx = si + subpixel(at(bi - 1, bj), best, at(bi + 1, bj));
  p.dy = sj + subpixel(at(bi, bj - 1), best, at(bi, bj + 1));
  return p;
}

}  // namespace dem2d::analysis
