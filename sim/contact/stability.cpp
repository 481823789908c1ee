#include "contact/stability.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

namespace dem2d {

namespace {

using cd = std::complex<double>;
using Mat3 = Eigen::Matrix<cd, 3, 3>;
using Mat6 = Eigen::Matrix<cd, 6, 6>;

struct Wave {
  double qx, qy;
  std::string name;  // "Gamma", "M", "K" or "" between them
};

// M^-1 K(q) and M^-1 C(q) of the hexagonal crystal, dofs (u_x, u_y, phi).
struct Dynamics {
  Mat3 stiffness, damping;
  Wave q;
};

// One contact of grain i with its neighbour j at i + l (|l| = d): with n the
// unit vector from j to i, t = z x n and a = d/2, the springs see
//   normal  (u_i - u_j).n,   tangential (u_i - u_j).t - a (phi_i + phi_j),
//   rolling phi_i - phi_j    (contact_law.hpp; their forces follow as -dU/du).
// In a Bloch wave u_j = u_i exp(i q.l), so each contact adds
// B_i^T k (B_i + B_j exp(i q.l)) to K(q).
Dynamics dynamics(const ContactLaw& law, EffectSet effects, double density, double d, const Wave& q) {
  const double a = 0.5 * d, m = density * M_PI * d * d / 4.0, inertia = m * d * d / 8.0;
  const Rows r = contact_rows(law, effects, Inertia{0.5 * m, 0.5 * inertia});  // the pair's effective mass, inertia
  Dynamics out{Mat3::Zero(), Mat3::Zero(), q};
  for (int k = 0; k < 6; ++k) {
    const double angle = M_PI / 3.0 * k, lx = d * std::cos(angle), ly = d * std::sin(angle);
    const double nx = -lx / d, ny = -ly / d, tx = -ny, ty = nx;
    Eigen::Matrix3d bi, bj;
    bi << nx, ny, 0.0, tx, ty, -a, 0.0, 0.0, 1.0;
    bj << -nx, -ny, 0.0, -tx, -ty, -a, 0.0, 0.0, -1.0;
    const cd phase = std::exp(cd(0.0, q.qx * lx + q.qy * ly));
    const Mat3 coupling = bi.cast<cd>() + bj.cast<cd>() * phase;
    out.stiffness += bi.transpose().cast<cd>() * Eigen::Vector3d(r.kn, r.kt, r.kr).asDiagonal().toDenseMatrix().cast<cd>() * coupling;
    out.damping += bi.transpose().cast<cd>() * Eigen::Vector3d(r.cn, r.ct, r.cr).asDiagonal().toDenseMatrix().cast<cd>() * coupling;
  }
  const Eigen::Vector3d inv_mass(1.0 / m, 1.0 / m, 1.0 / inertia);
  out.stiffness = inv_mass.cast<cd>().asDiagonal() * out.stiffness;
  out.damping = inv_mass.cast<cd>().asDiagonal() * out.damping;
  return out;
}

// The one-step map of (x_{n+1}, x_n) and its largest |z| with its mode.
struct Growth {
  double radius;
  bool rotation;  // the mode is mostly spin (a |phi| > |u|)
};

Growth growth(const Dynamics& dyn, double dt, double a) {
  const Mat3 id = Mat3::Identity();
  Mat6 step;
  step << 2.0 * id - dt * dt * dyn.stiffness - dt * dyn.damping, dt * dyn.damping - id, id, Mat3::Zero();
  const Eigen::ComplexEigenSolver<Mat6> solver(step);
  Eigen::Index k = 0;
  const double radius = solver.eigenvalues().cwiseAbs().maxCoeff(&k);
  const auto v = solver.eigenvectors().col(k);
  return {radius, a * std::abs(v(2)) > std::hypot(std::abs(v(0)), std::abs(v(1)))};
}

StabilityLimit limit_over(const ContactLaw& law, EffectSet effects, double density, double d,
                          const std::vector<Wave>& waves) {
  std::vector<Dynamics> dyn;
  for (const Wave& q : waves) dyn.push_back(dynamics(law, effects, density, d, q));
  const double m = density * M_PI * d * d / 4.0, dt_c = std::sqrt(m / law.kn);
  // Rigid motions (q = 0 translations, free spins) have double roots z = 1,
  // which an eigensolver returns as 1 +- O(sqrt(eps)): a tolerance far above
  // that and far below any real growth per step.
  constexpr double kTolerance = 1e-7;
  auto worst = [&](double dt) {
    std::size_t at = 0;
    Growth g{0.0, false};
    for (std::size_t k = 0; k < dyn.size(); ++k) {
      const Growth here = growth(dyn[k], dt, 0.5 * d);
      if (here.radius > g.radius) g = here, at = k;
    }
    return std::pair{g, at};
  };
  // the normal springs alone give 2/sqrt(6) dt_c undamped; a term that softens them allows more
  double lo = 0.0, hi = 2.0 * dt_c;
  while (worst(hi).first.radius <= 1.0 + kTolerance && hi < 1e6 * dt_c) lo = hi, hi *= 2.0;
  for (int k = 0; k < 60 && hi - lo > 1e-12 * dt_c; ++k) {
    const double mid = 0.5 * (lo + hi);
    (worst(mid).first.radius <= 1.0 + kTolerance ? lo : hi) = mid;
  }
  const auto [g, at] = worst(hi);  // the mode that grows just above the limit
  const std::string& where = dyn[at].q.name;
  StabilityLimit out;
  out.dt = lo;
  out.dt_over_critical = lo / dt_c;
  out.mode = std::string(g.rotation ? "grains spinning against their tangential/rolling springs"
                                    : "grains moving against their normal/tangential springs") +
             (where.empty() ? "" : " (wave vector " + where + ")");
  return out;
}

}  // namespace

StabilityLimit stability_limit(const ContactLaw& law, EffectSet effects, double density, double d) {
  // Gamma = 0, M = b1/2, K = (2 b1 + b2)/3 with the reciprocal vectors of the
  // lattice of spacing d (b1 = 2pi/d (1, -1/sqrt3), b2 = 2pi/d (0, 2/sqrt3)).
  const double s = 2.0 * M_PI / d, r3 = std::sqrt(3.0);
  const double mx = 0.5 * s, my = -0.5 * s / r3, kx = 2.0 * s / 3.0, ky = 0.0;
  std::vector<Wave> path;
  constexpr int kPerLeg = 10;
  for (int k = 0; k < kPerLeg; ++k) {
    const double u = static_cast<double>(k) / kPerLeg;
    path.push_back({u * mx, u * my, k == 0 ? "Gamma" : ""});
    path.push_back({mx + u * (kx - mx), my + u * (ky - my), k == 0 ? "M" : ""});
    path.push_back({kx * (1.0 - u), ky * (1.0 - u), k == 0 ? "K" : ""});
  }
  return limit_over(law, effects, density, d, path);
}

StabilityLimit stability_limit_on_grid(const ContactLaw& law, EffectSet effects, double density, double d, int n) {
  const double s = 2.0 * M_PI / d, r3 = std::sqrt(3.0);
  std::vector<Wave> grid;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
      grid.push_back({u * s, s * (-u / r3 + 2.0 * v / r3), ""});
    }
  return limit_over(law, effects, density, d, grid);
}

}  // namespace dem2d
