#include "bed/bed_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

#include "common/units.hpp"

namespace dem2d::analysis {

namespace {


double ratio(double sum, std::int64_t count) { return count > 0 ? sum / static_cast<double>(count) : kNaN; }

}  // namespace

Coverage sample_coverage(const Snapshot& s, const Region& region, double spacing) {
  const Rect& box = region.box;
  // The disks that can reach the box, binned by centre into square cells at
  // least one diameter wide: a disk covering a point is centred in the
  // point's cell or one of its 8 neighbours.
  std::vector<std::size_t> disks;
  double cell = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double r = 0.5 * s.diameter[i];
    const Vec2 p = s.position[i];
    if (s.active[i] && p.x >= box.xmin - r && p.x <= box.xmax + r && p.y >= box.ymin - r && p.y <= box.ymax + r) {
      disks.push_back(i);
      cell = std::max(cell, s.diameter[i]);
    }
  }
  if (cell == 0.0) cell = box.width() + box.height();  // no disk: any size will do
  const double gx0 = box.xmin - cell, gy0 = box.ymin - cell;
  const int gnx = static_cast<int>(box.width() / cell) + 3, gny = static_cast<int>(box.height() / cell) + 3;
  const auto cell_of = [&](double x, double y) {
    const int ix = std::clamp(static_cast<int>((x - gx0) / cell), 0, gnx - 1);
    const int iy = std::clamp(static_cast<int>((y - gy0) / cell), 0, gny - 1);
    return std::pair{ix, iy};
  };
  std::vector<std::size_t> start(static_cast<std::size_t>(gnx * gny) + 1, 0), members(disks.size());
  for (std::size_t g : disks) {
    const auto [ix, iy] = cell_of(s.position[g].x, s.position[g].y);
    ++start[static_cast<std::size_t>(iy * gnx + ix) + 1];
  }
  for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::size_t g : disks) {
    const auto [ix, iy] = cell_of(s.position[g].x, s.position[g].y);
    members[fill[static_cast<std::size_t>(iy * gnx + ix)]++] = g;
  }
  const auto covered = [&](double x, double y) {
    const auto [ix, iy] = cell_of(x, y);
    for (int cy = std::max(iy - 1, 0); cy <= std::min(iy + 1, gny - 1); ++cy)
      for (int cx = std::max(ix - 1, 0); cx <= std::min(ix + 1, gnx - 1); ++cx) {
        const auto c = static_cast<std::size_t>(cy * gnx + cx);
        for (std::size_t m = start[c]; m < start[c + 1]; ++m) {
          const std::size_t g = members[m];
          const double dx = x - s.position[g].x, dy = y - s.position[g].y, r = 0.5 * s.diameter[g];
          if (dx * dx + dy * dy < r * r) return true;
        }
      }
    return false;
  };

  Coverage out;
  out.spacing = spacing;
  const auto points_along = [&](double length) {
    return std::max<std::int64_t>(1, static_cast<std::int64_t>(std::floor(length / spacing * (1 + 1e-12))));
  };
  const std::int64_t nx = points_along(box.width()), ny = points_along(box.height());
  const double x0 = box.xmin + 0.5 * (box.width() - static_cast<double>(nx - 1) * spacing);
  const double y0 = box.ymin + 0.5 * (box.height() - static_cast<double>(ny - 1) * spacing);
  const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
  for (std::int64_t b = 0; b < ny; ++b) {
    // each row shifted by a fraction of the spacing in [-1/2, 1/2) (golden-ratio
    // sequence): no aliasing with lattice-like packings
    const double row_x0 = x0 + (std::fmod(static_cast<double>(b) * golden, 1.0) - 0.5) * spacing;
    for (std::int64_t a = 0; a < nx; ++a) {
      const double x = row_x0 + static_cast<double>(a) * spacing, y = y0 + static_cast<double>(b) * spacing;
      if (region.hole && region.hole->contains(x, y)) {
        ++out.excluded;
        continue;
      }
      ++out.points;
      if (covered(x, y)) ++out.covered;
    }
  }
  out.fraction = ratio(static_cast<double>(out.covered), out.points);
  return out;
}

Coordination coordination(const Snapshot& s, const Region& bulk) {
  std::vector<std::int64_t> n(s.size(), 0);
  Coordination z;
  const Contacts& c = s.contacts;
  for (std::size_t r = 0; r < c.size(); ++r) {
    // touching and carrying a force (with cohesion fn may be <= 0 in contact;
    // contacts across a gap, overlap < 0, are not counted)
    if (!(c.overlap[r] > 0.0) || c.fn[r] == 0.0) continue;
    ++z.contacts;
    const auto i = static_cast<std::size_t>(c.i[r]);
    if (s.active[i]) ++n[i];
    if (c.j[r] >= 0 && s.active[static_cast<std::size_t>(c.j[r])]) ++n[static_cast<std::size_t>(c.j[r])];
  }
  double all = 0.0, in_bulk = 0.0, held = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!s.active[i]) continue;
    const auto k = static_cast<double>(n[i]);
    ++z.grains;
    all += k;
    if (n[i] < 2) ++z.rattlers;
    else held += k;
    if (bulk.contains(s.position[i].x, s.position[i].y)) ++z.bulk_grains, in_bulk += k;
  }
  z.mean = ratio(all, z.grains);
  z.bulk = ratio(in_bulk, z.bulk_grains);
  z.without_rattlers = ratio(held, z.grains - z.rattlers);
  return z;
}

MaxOverlap max_overlap(const Snapshot& s) {
  MaxOverlap out;
  const Contacts& c = s.contacts;
  for (std::size_t r = 0; r < c.size(); ++r) {
    const double di = s.diameter[static_cast<std::size_t>(c.i[r])];
    const double d = c.j[r] >= 0 ? std::min(di, s.diameter[static_cast<std::size_t>(c.j[r])]) : di;
    if (c.overlap[r] / d > out.over_d) out = {c.overlap[r] / d, c.overlap[r], c.i[r], c.j[r]};
  }
  return out;
}

double active_grain_area(const Snapshot& s) {
  double area = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.active[i]) area += 0.25 * std::numbers::pi * s.diameter[i] * s.diameter[i];
  return area;
}

double kinetic_energy(const Snapshot& s) {
  double e = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!s.active[i]) continue;
    const double m = s.mass[i], d = s.diameter[i], inertia = m * d * d / 8.0;
    const Vec2 v = s.velocity[i];
    e += 0.5 * m * (v.x * v.x + v.y * v.y) + 0.5 * inertia * s.omega[i] * s.omega[i];
  }
  return e;
}

nlohmann::ordered_json fill_metrics(const Snapshot& s, const BedConfig& cfg) {
  using json = nlohmann::ordered_json;
  const Cell cell = find_cell(s);
  const double d = mean_active_diameter(s);
  const Surface surface = bed_surface(s, cell, cfg.column_width_d * d);
  const Region bulk = bulk_region(cell, surface.height, cfg.margin_d * d);
  const Coverage cover = sample_coverage(s, bulk, d / cfg.sampling_per_d);
  if (cover.points == 0) throw BedError("the bulk region lies entirely within the intruder's exclusion zone");
  const Coordination z = coordination(s, bulk);
  const MaxOverlap o = max_overlap(s);

  json contact = nullptr;
  if (o.i >= 0) {
    contact = {{"i", o.i}, {"j", o.j}};
    contact["partner"] = o.j >= 0 ? "grain" : s.bodies[static_cast<std::size_t>(-1 - o.j)].name;
  }
  json f;
  f["solid_fraction"] = cover.fraction;
  f["bed_height_mm"] = surface.height * kMm;
  f["bed_height_from_area_mm"] = active_grain_area(s) / (cover.fraction * (cell.right - cell.left)) * kMm;
  f["bed_surface_min_mm"] = surface.min * kMm;
  f["bed_surface_max_mm"] = surface.max * kMm;
  f["surface_columns"] = surface.columns;
  f["surface_column_width_mm"] = surface.column_width * kMm;
  f["surface_empty_columns"] = surface.empty_columns;
  f["grains_above_surface"] = surface.grains_above;
  f["coordination_number"] = z.mean;
  f["coordination_number_bulk"] = z.bulk;
  f["coordination_number_without_rattlers"] = z.without_rattlers;
  f["rattlers"] = z.rattlers;
  f["bulk_grains"] = z.bulk_grains;
  f["contacts_with_force"] = z.contacts;
  f["max_overlap_over_d"] = o.over_d;
  f["max_overlap_mm"] = o.overlap * kMm;
  f["max_overlap_contact"] = contact;
  f["kinetic_energy_J_per_m"] = kinetic_energy(s);
  f["particles"] = s.size();
  f["lost_particles"] = s.size() - s.active_count();
  f["mean_diameter_mm"] = d * kMm;
  f["cell_mm"] = {{"left", cell.left * kMm}, {"right", cell.right * kMm}, {"floor", cell.floor * kMm}};
  f["bulk_region_mm"] = {bulk.box.xmin * kMm, bulk.box.xmax * kMm, bulk.box.ymin * kMm, bulk.box.ymax * kMm};
  f["bulk_region_excluded_intruder"] = bulk.hole.has_value();
  f["intruder_exclusion_radius_mm"] = bulk.hole ? json(bulk.hole->radius * kMm) : json(nullptr);
  f["sampling_spacing_mm"] = cover.spacing * kMm;
  f["sampling_points"] = cover.points;
  f["sampling_points_excluded"] = cover.excluded;
  f["snapshot"] = {{"index", s.index}, {"time_s", s.time}, {"step", s.step}};
  f["config"] = {{"margin_d", cfg.margin_d},
                 {"sampling_per_d", cfg.sampling_per_d},
                 {"column_width_d", cfg.column_width_d}};
  return f;
}

nlohmann::ordered_json measure_run_file(const std::string& run_path, const BedConfig& cfg,
                                        const std::string& config_path) {
  const RunReader reader(run_path);
  const Snapshot s = reader.last_snapshot();
  nlohmann::ordered_json fill;
  fill["run_file"] = run_path;
  fill["config_file"] = config_path;
  try {
    fill.update(fill_metrics(s, cfg));
  } catch (const StageError& e) {
    throw BedError(run_path + ": " + e.what());
  }
  return {{"fill", fill}};
}

}  // namespace dem2d::analysis
