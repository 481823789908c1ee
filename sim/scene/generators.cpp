#include "scene/generators.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace dem2d {

bool point_in_polygon(const std::vector<std::array<double, 2>>& poly, double x, double y) {
  bool inside = false;  // even-odd rule: count edge crossings of a ray towards +x
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const auto& a = poly[i];
    const auto& b = poly[j];
    if ((a[1] > y) != (b[1] > y) && x < (b[0] - a[0]) * (y - a[1]) / (b[1] - a[1]) + a[0])
      inside = !inside;
  }
  return inside;
}

double distance_to_segment(double px, double py, double ax, double ay, double bx, double by) {
  const double ex = bx - ax, ey = by - ay, rx = px - ax, ry = py - ay;
  const double len2 = ex * ex + ey * ey;
  const double t = len2 > 0.0 ? std::clamp((rx * ex + ry * ey) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(rx - t * ex, ry - t * ey);
}

namespace {

double effective_spacing(const LatticeSpec& s) {
  return s.spacing > 0.0 ? s.spacing : 1.05 * s.d_max;
}

// The sites the scan of for_each_site visits: rows x columns of the region's
// bounding box. Bounded, so that a region of 1e300 m (where adding one
// spacing no longer moves x) is an error, not a scan that never ends.
constexpr double kMaxScannedSites = 1e9;
double lattice_sites_in_box(const LatticeSpec& s) {
  double xmin = s.region[0][0], xmax = xmin, ymin = s.region[0][1], ymax = ymin;
  for (const auto& v : s.region) {
    xmin = std::min(xmin, v[0]), xmax = std::max(xmax, v[0]);
    ymin = std::min(ymin, v[1]), ymax = std::max(ymax, v[1]);
  }
  const double spacing = effective_spacing(s);
  return ((xmax - xmin) / spacing + 2.0) * ((ymax - ymin) / (spacing * std::sqrt(3.0) / 2.0) + 2.0);
}

void validate(const LatticeSpec& s) {
  std::ostringstream msg;
  const double spacing = effective_spacing(s);
  if (s.count < 1)
    msg << "count = " << s.count << ": must be >= 1";
  else if (!(s.d_min > 0.0) || !std::isfinite(s.d_min))
    msg << "diameter min = " << s.d_min << ": must be > 0 (m)";
  else if (!(s.d_max >= s.d_min) || !std::isfinite(s.d_max))
    msg << "diameter max = " << s.d_max << ": must be >= min = " << s.d_min << " (m)";
  else if (s.region.size() < 3)
    msg << "region has " << s.region.size() << " vertices: a polygon needs >= 3";
  else if (!std::all_of(s.region.begin(), s.region.end(),
                        [](const auto& v) { return std::isfinite(v[0]) && std::isfinite(v[1]); }))
    msg << "region has a non-finite vertex";
  else if (!(spacing >= s.d_max) || !std::isfinite(spacing))
    msg << "spacing = " << spacing << ": must be >= the largest diameter " << s.d_max << " (m)";
  else if (!std::isfinite(s.vx) || !std::isfinite(s.vy))
    msg << "velocity must be finite";
  else if (const double sites = lattice_sites_in_box(s); !(sites <= kMaxScannedSites))
    msg << "the region's bounding box spans " << sites << " lattice sites of spacing " << spacing
        << " m, more than the " << kMaxScannedSites << " a generator scans (a region far larger than its grains?)";
  else
    return;
  throw std::invalid_argument(msg.str());
}

// Calls visit(x, y) for each usable site in order until it returns false.
template <class Visit>
void for_each_site(const LatticeSpec& s, Visit&& visit) {
  const double r = 0.5 * s.d_max, spacing = effective_spacing(s);
  const double row_step = spacing * std::sqrt(3.0) / 2.0;
  double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
  for (const auto& v : s.region) {
    xmin = std::min(xmin, v[0]);
    xmax = std::max(xmax, v[0]);
    ymin = std::min(ymin, v[1]);
    ymax = std::max(ymax, v[1]);
  }
  const double x0 = xmin + r, y0 = ymin + r;
  const auto inside = [&](double x, double y) {
    if (!point_in_polygon(s.region, x, y)) return false;
    for (std::size_t i = 0, j = s.region.size() - 1; i < s.region.size(); j = i++)
      if (distance_to_segment(x, y, s.region[j][0], s.region[j][1], s.region[i][0],
                              s.region[i][1]) < r - kTouchTolerance)
        return false;
    return true;
  };
  for (std::int64_t row = 0;; ++row) {
    const double y = y0 + static_cast<double>(row) * row_step;
    if (y > ymax - r + kTouchTolerance) return;
    const double shift = (row % 2 == 1) ? 0.5 * spacing : 0.0;
    for (std::int64_t col = 0;; ++col) {
      const double x = x0 + shift + static_cast<double>(col) * spacing;
      if (x > xmax - r + kTouchTolerance) break;
      if (inside(x, y) && !visit(x, y)) return;
    }
  }
}

}  // namespace

std::int64_t count_lattice_sites(const LatticeSpec& spec) {
  validate(spec);
  std::int64_t n = 0;
  for_each_site(spec, [&](double, double) {
    ++n;
    return true;
  });
  return n;
}

std::vector<ParticleInit> triangular_lattice(const LatticeSpec& spec) {
  validate(spec);
  std::vector<ParticleInit> out;
  out.reserve(static_cast<std::size_t>(std::min<std::int64_t>(spec.count, 1 << 24)));
  for_each_site(spec, [&](double x, double y) {
    out.push_back({x, y, 0.0, spec.vx, spec.vy, 0.0});
    return static_cast<std::int64_t>(out.size()) < spec.count;
  });
  if (static_cast<std::int64_t>(out.size()) < spec.count) {
    std::ostringstream msg;
    msg << "the region holds only " << out.size() << " lattice sites for disks of diameter "
        << spec.d_max << " m at spacing " << effective_spacing(spec)
        << " m, fewer than count = " << spec.count
        << " (enlarge the region, or reduce count or the diameters)";
    throw std::invalid_argument(msg.str());
  }
  std::mt19937_64 rng(spec.seed);
  for (auto& p : out) p.d = spec.d_min + uniform01(rng) * (spec.d_max - spec.d_min);
  return out;
}

}  // namespace dem2d
