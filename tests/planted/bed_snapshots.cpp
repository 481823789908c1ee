#include "planted/bed_snapshots.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numbers>
#include <random>

namespace dem2d::planted {

namespace {

enum BodyIndex : std::int32_t { kLeft = 0, kRight = 1, kFloor = 2, kIntruder = 3 };
std::int32_t partner(BodyIndex b) { return -1 - static_cast<std::int32_t>(b); }

double mean_of(const std::vector<double>& v) {
  double s = 0.0;
  for (const double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

// The intruder's geometry at height y (centre): tips, top face.
struct Bar {
  double xc, yc, half, top, bottom;  // half = tip to centre (m)
};
Bar bar_at(const BedGeometry& g, double yc) {
  return {0.5 * g.width, yc, 0.5 * g.length, yc + 0.5 * g.thickness, yc - 0.5 * g.thickness};
}

// The grain touching the intruder's tip on `side` (-1 left, +1 right): the
// lattice grain nearest the tip among those beside it (at the bar's height).
std::int32_t tip_grain(const Bed& bed, const std::vector<Vec2>& p, const Bar& b, int side) {
  const double tx = b.xc + side * b.half;
  std::int32_t best = -1;
  double best_d = 1e9;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if ((p[i].x - tx) * side < 0.0) continue;  // beside the tip, outwards
    const double dist = std::hypot(p[i].x - tx, p[i].y - b.yc);
    if (dist < best_d) best_d = dist, best = static_cast<std::int32_t>(i);
  }
  (void)bed;
  return best;
}

// Adjacency of the lattice.
std::vector<std::vector<std::int32_t>> adjacency(const Bed& bed) {
  std::vector<std::vector<std::int32_t>> a(bed.position.size());
  for (const auto& [i, j] : bed.neighbours) a[i].push_back(j), a[j].push_back(i);
  return a;
}

// A shortest lattice path from grain `from` to a grain touching the wall on
// `side`, through grains at or above `min_y` (breadth-first; ties: the lower
// index first, so the same bed gives the same path).
std::vector<std::int32_t> arch(const Bed& bed, const std::vector<std::vector<std::int32_t>>& adj, std::int32_t from,
                               int side, double min_y, double short_of = 0.0) {
  const double reach = bed.g.spacing + short_of;  // a grain within a spacing of the wall touches it
  auto at_wall = [&](std::int32_t i) {
    const double x = bed.position[i].x;
    return side < 0 ? x < reach : x > bed.g.width - reach;
  };
  std::vector<std::int32_t> prev(bed.position.size(), -2);
  std::deque<std::int32_t> q{from};
  prev[from] = -1;
  while (!q.empty()) {
    const std::int32_t i = q.front();
    q.pop_front();
    if (at_wall(i)) {
      std::vector<std::int32_t> path;
      for (std::int32_t k = i; k >= 0; k = prev[k]) path.push_back(k);
      std::reverse(path.begin(), path.end());
      return path;
    }
    for (const std::int32_t j : adj[i])
      if (prev[j] == -2 && bed.position[j].y >= min_y) prev[j] = i, q.push_back(j);
  }
  return {};
}

struct ContactMaker {
  const Bed& bed;
  std::mt19937_64 rng;
  double weak = 0.5, strong = 50.0;  // N/m: weak contacts carry up to `weak`, strong ones `strong`
  double spurious = 0.0;
  // the weak network (neighbours; grains at the walls and floor with them)
  // plus the strong pairs given; a fraction `spurious` made strong at random
  Contacts make(const std::vector<Vec2>& p, const Bar& b, const std::vector<std::pair<std::int32_t, std::int32_t>>& strong_pairs) {
    Contacts c;
    std::uniform_real_distribution<double> u(0.0, 1.0);
    auto fn_weak = [&]() { return u(rng) < spurious ? strong * (0.2 + 0.2 * u(rng)) : weak * (0.05 + 0.95 * u(rng)); };
    auto is_strong = [&](std::int32_t i, std::int32_t j) {
      for (const auto& [a, s] : strong_pairs)
        if ((a == i && s == j) || (a == j && s == i)) return true;
      return false;
    };
    for (const auto& [i, j] : bed.neighbours) {
      const Vec2 d{p[i].x - p[j].x, p[i].y - p[j].y};
      const double r = std::hypot(d.x, d.y);
      c.add(i, j, is_strong(i, j) ? strong : fn_weak(), 1e-6, d.x / r, d.y / r);
    }
    const double reach = bed.g.spacing;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const auto gi = static_cast<std::int32_t>(i);
      if (p[i].x < reach) c.add(gi, partner(kLeft), is_strong(gi, partner(kLeft)) ? strong : fn_weak(), 1e-6, 1.0, 0.0);
      if (p[i].x > bed.g.width - reach)
        c.add(gi, partner(kRight), is_strong(gi, partner(kRight)) ? strong : fn_weak(), 1e-6, -1.0, 0.0);
      if (p[i].y < reach) c.add(gi, partner(kFloor), fn_weak(), 1e-6, 0.0, 1.0);
      // on the intruder's top face, or strong (the arches' first grains)
      const bool on_top = std::abs(p[i].x - b.xc) <= b.half && p[i].y > b.top && p[i].y - b.top < 0.5 * reach;
      if (on_top || is_strong(gi, partner(kIntruder))) {
        const double nx = p[i].x - b.xc, ny = p[i].y - b.yc, r = std::hypot(nx, ny);
        c.add(gi, partner(kIntruder), is_strong(gi, partner(kIntruder)) ? strong : fn_weak(), 1e-6, nx / r, ny / r);
      }
    }
    return c;
  }
};

// The strong pairs of the arches from both tips to both walls (the tip grain
// on the intruder, the path, the last grain on the wall); empty when there is
// no path. short_of > 0: the arches stop that far from the walls, touching none.
std::vector<std::pair<std::int32_t, std::int32_t>> arches(const Bed& bed, const std::vector<std::vector<std::int32_t>>& adj,
                                                        const std::vector<Vec2>& p, const Bar& b,
                                                        std::int32_t* tips = nullptr, double short_of = 0.0) {
  std::vector<std::pair<std::int32_t, std::int32_t>> out;
  for (const int side : {-1, 1}) {
    const std::int32_t t = tip_grain(bed, p, b, side);
    if (tips) tips[side < 0 ? 0 : 1] = t;
    const std::vector<std::int32_t> path = arch(bed, adj, t, side, b.bottom, short_of);
    if (path.empty()) continue;
    out.push_back({t, partner(kIntruder)});
    for (std::size_t q = 1; q < path.size(); ++q) out.push_back({path[q - 1], path[q]});
    if (short_of <= 0.0) out.push_back({path.back(), partner(side < 0 ? kLeft : kRight)});
  }
  return out;
}

// Gaussian noise correlated in space: white noise on the grains smoothed by
// exp(-r^2 / 2 l^2) (r < 3 l), each grain's sum renormalised to unit variance
// (two grains r apart correlate as ~exp(-r^2 / 4 l^2)); l = 0: none.
class SmoothedNoise {
 public:
  SmoothedNoise(const std::vector<Vec2>& p, double l) : weights_(l > 0.0 ? p.size() : 0), n_(p.size()) {
    for (std::size_t i = 0; i < weights_.size(); ++i) {
      double norm = 0.0;
      for (std::size_t j = 0; j < p.size(); ++j) {
        const double r2 = (p[i].x - p[j].x) * (p[i].x - p[j].x) + (p[i].y - p[j].y) * (p[i].y - p[j].y);
        if (r2 >= 9.0 * l * l) continue;
        const double wij = std::exp(-0.5 * r2 / (l * l));
        weights_[i].push_back({j, wij}), norm += wij * wij;
      }
      for (auto& [j, wij] : weights_[i]) wij /= std::sqrt(norm);
    }
  }
  std::vector<Vec2> draw(std::mt19937_64& rng) const {
    if (weights_.empty()) return {};
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::vector<Vec2> white(n_), out(n_);
    for (Vec2& x : white) x.x = gauss(rng), x.y = gauss(rng);
    for (std::size_t i = 0; i < n_; ++i)
      for (const auto& [j, wij] : weights_[i]) out[i].x += wij * white[j].x, out[i].y += wij * white[j].y;
    return out;
  }

 private:
  std::vector<std::vector<std::pair<std::size_t, double>>> weights_;
  std::size_t n_;
};

}  // namespace

double intruder_height(const BedGeometry& g, double t) { return g.start + g.speed * t; }

Bed make_bed(const BedGeometry& g) {
  Bed bed;
  bed.g = g;
  std::mt19937_64 rng(g.seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double dy = g.spacing * std::sqrt(3.0) / 2.0;
  std::vector<std::vector<std::int32_t>> rows;
  double area = 0.0;
  for (int row = 0; 0.5 * g.spacing + row * dy <= g.bed_height - 0.5 * g.spacing; ++row) {
    rows.emplace_back();
    const double y = 0.5 * g.spacing + row * dy;
    for (double x = (row % 2 ? g.spacing : 0.5 * g.spacing); x <= g.width - 0.5 * g.spacing + 1e-12; x += g.spacing) {
      const double j = 0.1 * g.spacing;
      rows.back().push_back(static_cast<std::int32_t>(bed.position.size()));
      bed.position.push_back({x + j * (u(rng) - 0.5), y + j * (u(rng) - 0.5)});
      bed.diameter.push_back(g.d_min + (g.d_max - g.d_min) * u(rng));
      const double a = std::numbers::pi * bed.diameter.back() * bed.diameter.back() / 4.0;
      bed.mass.push_back(g.density * a);
      area += a;
    }
  }
  bed.solid_fraction = area / (g.width * g.bed_height);
  for (std::size_t i = 0; i < bed.position.size(); ++i)
    for (std::size_t j = i + 1; j < bed.position.size(); ++j)
      if (std::hypot(bed.position[i].x - bed.position[j].x, bed.position[i].y - bed.position[j].y) < 1.3 * g.spacing)
        bed.neighbours.push_back({static_cast<std::int32_t>(i), static_cast<std::int32_t>(j)});
  return bed;
}

Snapshot bed_snapshot(const Bed& bed, const std::vector<Vec2>& position, double t, std::size_t index) {
  const BedGeometry& g = bed.g;
  Snapshot s;
  s.index = index;
  s.time = t;
  s.step = static_cast<std::int64_t>(index);
  s.position = position;
  s.velocity.assign(position.size(), Vec2{});
  s.omega.assign(position.size(), 0.0);
  s.active.assign(position.size(), 1);
  s.diameter = bed.diameter;
  s.mass = bed.mass;
  const double r = 0.5 * g.thickness, top = 0.5;
  s.bodies = {Body::segment("left", -r, 0.0, -r, top, g.thickness, "left_wall"),
              Body::segment("right", g.width + r, 0.0, g.width + r, top, g.thickness, "right_wall"),
              Body::segment("floor", -0.01, -r, g.width + 0.01, -r, g.thickness, "floor")};
  const Bar b = bar_at(g, intruder_height(g, t));
  s.bodies.push_back(Body::segment("intruder", b.xc - b.half + r, b.yc, b.xc + b.half - r, b.yc, g.thickness, "intruder"));
  return s;
}

double wall_meeting(double beta_deg, double bend, double gap) {
  const double t = std::tan(beta_deg * std::numbers::pi / 180.0);
  if (bend == 0.0) return gap * t;
  const double disc = 1.0 + 4.0 * bend * t;  // a / t (1 + bend a / gap) = gap, solved for a
  if (disc < 0.0) return std::numeric_limits<double>::quiet_NaN();
  return gap * (std::sqrt(disc) - 1.0) / (2.0 * bend);
}

analysis::MemorySource cone_run(const Bed& bed, const ConeScenario& c) {
  const BedGeometry& g = bed.g;
  analysis::MemorySource src;
  src.name = "planted cone";
  src.window = c.window;
  src.velocities = {{}, {}, {}, {0.0, g.speed}};
  std::mt19937_64 rng(c.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double tan_left = std::tan(c.beta_deg * std::numbers::pi / 180.0);
  const double tan_right = std::isnan(c.beta_right_deg) ? tan_left : std::tan(c.beta_right_deg * std::numbers::pi / 180.0);
  const double gap = 0.5 * (g.width - g.length);
  const double d = mean_of(bed.diameter), w = 1.5 * d;
  const SmoothedNoise smooth(bed.position, c.correlation_d * d);
  for (std::size_t k = 0; intruder_height(g, static_cast<double>(k) * c.travel / g.speed) <= c.end; ++k) {
    const double t = static_cast<double>(k) * c.travel / g.speed;
    const Bar b = bar_at(g, intruder_height(g, t));
    std::vector<Vec2> p = bed.position;
    if (k > 0 && c.dilation > 0.0) {
      // the dilatancy region (cg.toml: 2 w above the top face, 10 d high) and 4 w around it
      const double y0 = b.top + 2.0 * w - 4.0 * w, y1 = b.top + 2.0 * w + 10.0 * d + 4.0 * w;
      for (Vec2& q : p)
        if (q.y > y0) q.y += c.dilation * (std::min(q.y, y1) - y0);
    }
    if (c.jitter > 0.0)
      for (Vec2& q : p) q.x += c.jitter * d * gauss(rng), q.y += c.jitter * d * gauss(rng);
    std::vector<Vec2> v(p.size()), disp(p.size());
    const std::vector<Vec2> n = smooth.draw(rng);  // empty: independent per grain
    const bool moving = c.moving && !(c.at_rest > 0.0 && std::uniform_real_distribution<double>(0.0, 1.0)(rng) < c.at_rest);
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double above = p[i].y - b.top, beyond = std::abs(p[i].x - b.xc) - b.half;
      const double reach =
          std::max(1e-12, above / (p[i].x < b.xc ? tan_left : tan_right) * (1.0 + c.bend * above / gap));
      double vstar = 0.0;
      if (moving && above > 0.0)
        vstar = c.graded ? std::clamp(1.0 - 0.75 * beyond / reach, 0.0, 1.0) : beyond <= reach ? 1.0 : 0.0;
      const double nx = n.empty() ? gauss(rng) : n[i].x, ny = n.empty() ? gauss(rng) : n[i].y;
      v[i] = {c.noise * g.speed * nx, vstar * g.speed + c.noise * g.speed * ny};
      if (moving && c.swirl > 0.0) {
        const double R = c.swirl_radius_d * d, omega = c.swirl * g.speed / d;
        for (const double side : {-1.0, 1.0}) {
          const double cx = b.xc + side * (b.half + R), rx = p[i].x - cx, ry = p[i].y - b.yc;
          if (std::hypot(rx, ry) < R) v[i].x += -side * omega * -ry, v[i].y += -side * omega * rx;
        }
      }
      disp[i] = {v[i].x * c.window, v[i].y * c.window};
    }
    Snapshot s = bed_snapshot(bed, p, t, k);
    s.velocity = v;
    src.snaps.push_back(std::move(s));
    src.displacements.push_back(std::move(disp));
  }
  return src;
}

analysis::MemorySource network_run(const Bed& bed, const NetworkScenario& n) {
  const BedGeometry& g = bed.g;
  analysis::MemorySource src;
  src.name = "planted force networks";
  src.velocities = {{}, {}, {}, {0.0, g.speed}};
  const auto adj = adjacency(bed);
  ContactMaker make{bed, std::mt19937_64(n.seed)};
  make.spurious = n.spurious;
  std::mt19937_64 lapses(n.seed + 11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t k = 0; intruder_height(g, static_cast<double>(k) * n.travel / g.speed) <= n.end; ++k) {
    const double t = static_cast<double>(k) * n.travel / g.speed;
    const Bar b = bar_at(g, intruder_height(g, t));
    std::vector<std::pair<std::int32_t, std::int32_t>> strong;
    // below the loss, arches to both walls (but in a fraction `lapse` of the
    // snapshots); above it, the same arches ending 15 mm short of the walls (a
    // network as strong, percolating nowhere)
    const bool lapsed = u(lapses) < n.lapse;
    strong = arches(bed, adj, bed.position, b, nullptr, b.yc < n.loss && !lapsed ? 0.0 : 0.015);
    Snapshot s = bed_snapshot(bed, bed.position, t, k);
    s.contacts = make.make(bed.position, b, strong);
    src.snaps.push_back(std::move(s));
  }
  return src;
}

KeystoneRun keystone_run(const Bed& bed, const KeystoneScenario& ks) {
  const BedGeometry& g = bed.g;
  KeystoneRun out;
  out.source.name = "planted keystones";
  out.source.velocities = {{}, {}, {}, {0.0, g.speed}};
  const auto adj = adjacency(bed);
  ContactMaker make{bed, std::mt19937_64(ks.seed)};
  make.spurious = ks.spurious;
  std::mt19937_64 rng(ks.seed + 7);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double d = mean_of(bed.diameter), gap = 0.1;  // s between a peak and its drop's end
  const int every = ks.ejected > 0.0 ? std::max(1, static_cast<int>(std::lround(1.0 / ks.ejected))) : 0;
  std::size_t index = 0;
  for (int e = 0; e < ks.events; ++e) {
    const double t0 = (5.0 + 1.0 * e) / 1.2;  // 5, 6, ... mm of travel at 1.2 mm/s
    const Bar b = bar_at(g, intruder_height(g, t0));
    std::int32_t tips[2] = {-1, -1};
    const auto strong = arches(bed, adj, bed.position, b, tips);
    std::vector<Vec2> after = bed.position;
    const bool eject = every > 0 && e % every == 0;
    if (eject) {
      Vec2& k = after[static_cast<std::size_t>(tips[0])];
      k.y -= 1.5 * bed.diameter[static_cast<std::size_t>(tips[0])];
      out.planted_ejections++;
    }
    for (Vec2& q : after)
      if (ks.jitter > 0.0) q.x += ks.jitter * d * gauss(rng), q.y += ks.jitter * d * gauss(rng);
    Snapshot before = bed_snapshot(bed, bed.position, t0, index++);
    before.contacts = make.make(bed.position, b, strong);
    Snapshot later = bed_snapshot(bed, after, t0 + gap, index++);
    later.contacts = make.make(after, bar_at(g, intruder_height(g, t0 + gap)), {});
    out.source.snaps.push_back(std::move(before));
    out.source.snaps.push_back(std::move(later));
    analysis::RuptureEvent ev;
    ev.load_start_time = t0 - 0.3, ev.load_start_height = intruder_height(g, t0 - 0.3);
    ev.peak_time = t0, ev.peak_height = intruder_height(g, t0), ev.peak_drag = 10.0;
    ev.drop_end_time = t0 + gap, ev.drop_end_height = intruder_height(g, t0 + gap), ev.drop = 5.0;
    out.events.push_back(ev);
  }
  return out;
}

}  // namespace dem2d::planted
