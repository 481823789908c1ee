#include "planted/stress_scenes.hpp"

#include <cmath>
#include <numbers>
#include <random>
#include <utility>

namespace dem2d::planted {

void add_grain(Snapshot& s, Vec2 x, double d, Vec2 v) {
  s.position.push_back(x);
  s.velocity.push_back(v);
  s.omega.push_back(0.0);
  s.active.push_back(1);
  s.diameter.push_back(d);
  s.mass.push_back(kGlassDensity * std::numbers::pi * d * d / 4.0);
}

StrainedLattice strained_lattice(double d, double stretch_x, double stretch_y, std::array<double, 3> fn,
                                 std::array<double, 3> ft, int n, double scatter, unsigned seed) {
  StrainedLattice L;
  const Vec2 e1{d * stretch_x, 0.0}, e2{0.5 * d * stretch_x, d * std::sqrt(3.0) / 2 * stretch_y};
  const std::array<Vec2, 3> e{e1, e2, Vec2{e2.x - e1.x, e2.y - e1.y}};
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) add_grain(L.s, {i * e1.x + j * e2.x, i * e1.y + j * e2.y}, d);
  L.area = e1.x * e2.y - e1.y * e2.x;
  L.centre = {0.5 * (n - 1) * (e1.x + e2.x), 0.5 * (n - 1) * (e1.y + e2.y)};
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto at = [n](int i, int j) { return j * n + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      for (int dir = 0; dir < 3; ++dir) {
        const int i2 = i + (dir == 0 ? 1 : dir == 1 ? 0 : -1), j2 = j + (dir == 0 ? 0 : 1);
        if (i2 < 0 || i2 >= n || j2 >= n) continue;
        // partner at(i2, j2) > at(i, j): the normal points from the partner to grain i
        const double len = std::hypot(e[dir].x, e[dir].y), k = scatter > 0.0 ? 1.0 + scatter * normal(rng) : 1.0;
        L.s.contacts.add(at(i, j), at(i2, j2), k * fn[dir], d - len, -e[dir].x / len, -e[dir].y / len, k * ft[dir]);
      }
  for (int dir = 0; dir < 3; ++dir) {
    const double len = std::hypot(e[dir].x, e[dir].y), nx = -e[dir].x / len, ny = -e[dir].y / len;
    const double Fx = fn[dir] * nx - ft[dir] * ny, Fy = fn[dir] * ny + ft[dir] * nx;
    const double lx = nx * len, ly = ny * len;  // x_i - x_j
    L.sigma[0] += Fx * lx / L.area, L.sigma[1] += Fx * ly / L.area;
    L.sigma[2] += Fy * lx / L.area, L.sigma[3] += Fy * ly / L.area;
  }
  return L;
}

Snapshot counter_moving_lattice(double d, double u) {
  Snapshot s;
  const double row = d * std::sqrt(3.0) / 2;
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i) add_grain(s, {i * d + (j % 2) * d / 2, j * row}, d, {(i + j) % 2 ? u : -u, 0.0});
  return s;
}

Snapshot random_contacts(unsigned seed, double d, Vec2* body_force) {
  Snapshot s;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 60; ++i) add_grain(s, {0.012 * u(rng), 0.012 * u(rng)}, d * (1.0 + 0.1 * u(rng)));
  s.bodies.push_back(Body::segment("intruder", -0.004, 0.0, 0.004, 0.0, 0.002, "intruder"));
  *body_force = {0.0, 0.0};
  const auto grain = [&] { return static_cast<int>((u(rng) + 1.0) * 29.99); };
  for (int c = 0; c < 150; ++c) {
    int i = grain(), j = grain();
    if (j == i) continue;
    if (j < i) std::swap(i, j);
    const Vec2 x{s.position[i].x - s.position[j].x, s.position[i].y - s.position[j].y};
    const double len = std::hypot(x.x, x.y);
    s.contacts.add(i, j, 1.0 + u(rng), 1e-5, x.x / len, x.y / len, 0.3 * u(rng));
  }
  for (int c = 0; c < 12; ++c) {  // on the body: grain i moved to its surface, the normal from the segment
    const int i = grain();
    const double angle = std::numbers::pi * (u(rng) + 1.0);
    const Vec2 n{std::cos(angle), std::sin(angle)};
    s.position[i] = {0.003 * u(rng) + n.x * 0.0025, n.y * 0.0025};
    const double fn = 1.0 + u(rng), ft = 0.3 * u(rng);
    s.contacts.add(i, -1, fn, 1e-5, n.x, n.y, ft);
    body_force->x -= fn * n.x - ft * n.y, body_force->y -= fn * n.y + ft * n.x;
  }
  return s;
}

Snapshot stack_on_floor(int n, double d, double g, double* weight) {
  Snapshot s;
  s.bodies.push_back(Body::segment("floor", -0.05, 0.0, 0.05, 0.0, 0.0, "floor"));
  for (int i = 0; i < n; ++i) add_grain(s, {0.0, d / 2 + i * d}, d);
  const double mg = s.mass[0] * g;
  for (int i = 0; i + 1 < n; ++i) s.contacts.add(i, i + 1, (n - 1 - i) * mg, 0.0, 0.0, -1.0);
  s.contacts.add(0, -1, n * mg, 0.0, 0.0, 1.0);
  *weight = n * mg;
  return s;
}

}  // namespace dem2d::planted
