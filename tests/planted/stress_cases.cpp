// Planted truth for the stress stage: the stress of a strained lattice with
// friction (exact), with each contact's force scattered (the planted mean
// recovered within the kernel's averaging), and unloaded (nothing); the
// kinetic stress of grains moving at +u and -u; the force on a body among
// random contacts from the fields' balance; a stack at rest whose weight the
// stress carries to the floor. The stage's own code: its fields
// (stress_field.hpp) and balance (stress_balance.hpp), with the kernel and
// grid of data/stress.toml.
#include <cmath>
#include <numbers>
#include <random>

#include "planted/planted.hpp"
#include "planted/stress_scenes.hpp"
#include "stress/stress_balance.hpp"
#include "stress/stress_config.hpp"

namespace dem2d::planted {

namespace {

constexpr double kD = 0.003;  // grain diameter (m)
constexpr double kG = 9.81;   // m/s^2

}  // namespace

std::vector<Row> stress_cases(const Settings& set, const std::string& data_dir) {
  using namespace analysis;
  const StressConfig cfg = load_stress_config(data_dir + "/stress.toml");
  const Kernel kernel = make_kernel(cfg.w_over_d * kD, cfg.cutoff_over_w);
  const double dx = cfg.spacing_mm * 1e-3;
  // the fields at a lattice's middle: mean over the nodes within 5 mm of it
  auto at_middle = [&](const StrainedLattice& L) {
    const Grid g = make_grid(L.centre.x - 0.005, L.centre.x + 0.005, L.centre.y - 0.005, L.centre.y + 0.005, dx);
    const StressFields f = coarse_grain_stress(g, kernel, L.s);
    std::array<double, 4> mean{};
    for (std::size_t c = 0; c < 4; ++c) {
      for (std::size_t n = 0; n < g.size(); ++n) mean[c] += f.contact[c][n];
      mean[c] /= static_cast<double>(g.size());
    }
    return mean;
  };
  std::vector<Row> rows;
  // a lattice strained at random (spacing 0.5 % short of d at most) with random forces along its three
  // directions (fn 1-3 N/m, ft within +-0.3 fn), each contact's force scattered: the pressure relative to
  // the exact one, and the error of the asymmetric part (friction's) relative to the pressure
  for (const double scatter : set.stress_force_scatter) {
    const std::string unit = "of each contact's force (rms)";
    Row p{"stress (contact)", "a strained lattice with friction: pressure", "pressure / exact", "-", 1.0, scatter, unit};
    const auto lattice = [&](unsigned seed) {
      std::mt19937 rng(seed);
      std::uniform_real_distribution<double> u(0.0, 1.0);
      const std::array<double, 3> fn{1.0 + 2.0 * u(rng), 1.0 + 2.0 * u(rng), 1.0 + 2.0 * u(rng)};
      const std::array<double, 3> ft{0.3 * fn[0] * (2 * u(rng) - 1), 0.3 * fn[1] * (2 * u(rng) - 1), 0.3 * fn[2] * (2 * u(rng) - 1)};
      return strained_lattice(kD, 1.0 - 0.005 * u(rng), 1.0 - 0.005 * u(rng), fn, ft, 40, scatter, seed);
    };
    // scattered forces: the kernel averages N_eff = 1 / int G^2 dA x contacts per area = 4 pi w^2 x 3 / A
    // contacts (~100 at w = 1.5 d), an rms error of scatter / sqrt(N_eff) per replica; the mean of the
    // replicas is judged within three of its standard errors
    const double n_eff = 4.0 * std::numbers::pi * kernel.w * kernel.w * 3.0 / (std::sqrt(3.0) / 2.0 * kD * kD);
    const double band = scatter > 0.0 ? 3.0 * scatter / std::sqrt(n_eff * set.replicas) : 1e-3;
    p.tolerance = band;
    p.note = "exact: sigma = (1/A) sum_k F_k (x) l_k over a grain's three contact directions; the field averaged over "
             "the nodes within 5 mm of the lattice's middle; scattered forces: the kernel averages N_eff = " +
             fmt("%.0f", n_eff) + " contacts, an rms error of scatter / sqrt(N_eff) per replica (tolerance: three "
             "standard errors of the replicas' mean)";
    summarise(p, set.replicas, [&](unsigned seed) {
      const StrainedLattice L = lattice(seed);
      const std::array<double, 4> m = at_middle(L);
      return Outcome{true, 0.5 * (m[0] + m[3]) / (0.5 * (L.sigma[0] + L.sigma[3]))};
    });
    rows.push_back(p);
    Row d{"stress (contact)", "the same: the friction's asymmetry (sigma_xy - sigma_yx) / 2, its error", "error / exact pressure",
          "-", 0.0, scatter, unit};
    d.tolerance = scatter > 0.0 ? band : 1e-4;
    summarise(d, set.replicas, [&](unsigned seed) {
      const StrainedLattice L = lattice(seed);
      const std::array<double, 4> m = at_middle(L);
      return Outcome{true, (0.5 * (m[1] - m[2]) - 0.5 * (L.sigma[1] - L.sigma[2])) / (0.5 * (L.sigma[0] + L.sigma[3]))};
    });
    rows.push_back(d);
  }
  // nothing loaded: no stress (a lattice whose contacts carry no force)
  {
    Row r{"stress (contact)", "a lattice whose contacts carry no force", "pressure", "Pa", 0.0, 0.0, "-"};
    r.tolerance = 1e-12;
    summarise(r, set.replicas, [&](unsigned seed) {
      const std::array<double, 4> m = at_middle(strained_lattice(kD, 1.0, 1.0, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, 40, 0.0, seed));
      return Outcome{true, 0.5 * (m[0] + m[3])};
    });
    rows.push_back(r);
  }
  // kinetic: grains at +u and -u along x
  {
    Row r{"stress (kinetic)", "grains moving at +u and -u along x: sigma_k,xx / (rho u^2)", "ratio", "-", 1.0, 0.0, "-"};
    r.tolerance = 2e-3;
    summarise(r, set.replicas, [&](unsigned seed) {
      const double u = 0.005 * seed;
      const Snapshot s = counter_moving_lattice(kD, u);
      const Grid g = make_grid(0.05, 0.06, 0.04, 0.05, dx);
      const StressFields f = coarse_grain_stress(g, kernel, s);
      const double rho = s.mass[0] / (kD * kD * std::sqrt(3.0) / 2);
      return Outcome{true, f.kinetic[kXX][g.size() / 2] / (rho * u * u)};
    });
    rows.push_back(r);
  }
  // the force on a body among random contacts, from the fields' exact balance
  {
    Row r{"stress balance", "a body among random contacts: its force from the fields", "|F_fields - F| / |F|", "-", 0.0, 0.0,
          "-"};
    r.tolerance = 5e-3;
    r.note = "F_fields = - oint sigma_c . n - int net over the box around the body; the trapezoid rule's error is "
             "second order in the grid spacing";
    summarise(r, set.replicas, [&](unsigned seed) {
      Vec2 truth;
      const Snapshot s = random_contacts(seed, kD, &truth);
      const Grid g = make_grid(-0.04, 0.04, -0.04, 0.04, dx);
      const StressFields f = coarse_grain_stress(g, kernel, s);
      const BodyBalance b = body_balance(g, kernel, f, s, 0, cfg.box_margin_mm * 1e-3, {0.0, -kG});
      return Outcome{true, std::hypot(b.exact.x - truth.x, b.exact.y - truth.y) / std::hypot(truth.x, truth.y)};
    });
    rows.push_back(r);
  }
  // a stack at rest: the stress carries its weight to the floor
  {
    Row r{"stress balance", "a stack of 6-15 grains at rest on a floor: its load from the stress over its weight",
          "F_stress / weight", "-", 1.0, 0.0, "-"};
    r.tolerance = 2e-3;
    summarise(r, set.replicas, [&](unsigned seed) {
      double weight = 0.0;
      const Snapshot s = stack_on_floor(5 + static_cast<int>(seed), kD, kG, &weight);
      const Grid g = make_grid(-0.04, 0.04, -0.04, 0.06, dx);
      const StressFields f = coarse_grain_stress(g, kernel, s);
      const BodyBalance b = body_balance(g, kernel, f, s, 0, cfg.box_margin_mm * 1e-3, {0.0, -kG});
      return Outcome{true, -b.quasi_static.y / weight};
    });
    rows.push_back(r);
  }
  return rows;
}

}  // namespace dem2d::planted
