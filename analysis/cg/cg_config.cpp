#include "cg/cg_config.hpp"

#include <toml++/toml.h>

#include <filesystem>
#include <functional>
#include <sstream>

namespace dem2d::analysis {

namespace {

[[noreturn]] void fail(const std::string& path, const toml::source_region& where, const std::string& what) {
  throw CgError(path + ":" + std::to_string(where.begin.line) + ":" + std::to_string(where.begin.column) + ": " +
                what);
}

std::string show(const toml::node& n) {
  std::ostringstream s;
  n.visit([&s](const auto& v) { s << v; });
  return s.str();
}

// One key: its table, name, and how to read it.
struct Key {
  const char* table;
  const char* name;
  std::function<void(const std::string& path, const std::string& key, const toml::node&, CgConfig&)> read;
};

double number(const std::string& path, const std::string& key, const toml::node& n) {
  const std::optional<double> v = n.value<double>();
  if (!n.is_number() || !v) fail(path, n.source(), key + " = " + show(n) + ": wrong type, expected a number");
  return *v;
}

Key num(const char* table, const char* name, double CgConfig::*field) {
  return {table, name, [field](const std::string& p, const std::string& k, const toml::node& n, CgConfig& c) {
            c.*field = number(p, k, n);
          }};
}

Key integer(const char* table, const char* name, int CgConfig::*field) {
  return {table, name, [field](const std::string& p, const std::string& k, const toml::node& n, CgConfig& c) {
            const std::optional<std::int64_t> v = n.value<std::int64_t>();
            if (!n.is_integer() || !v || *v < 1 || *v > 1000000)
              fail(p, n.source(), k + " = " + show(n) + ": must be an integer >= 1");
            c.*field = static_cast<int>(*v);
          }};
}

Key list(const char* table, const char* name, std::vector<double> CgConfig::*field) {
  return {table, name, [field](const std::string& p, const std::string& k, const toml::node& n, CgConfig& c) {
            const toml::array* a = n.as_array();
            if (!a || a->empty()) fail(p, n.source(), k + " = " + show(n) + ": must be a non-empty list of numbers");
            std::vector<double> v;
            for (const toml::node& e : *a) v.push_back(number(p, k, e));
            c.*field = v;
          }};
}

const std::vector<Key>& keys() {
  static const std::vector<Key> k = {
      num("kernel", "w_over_d", &CgConfig::w_over_d),
      num("kernel", "cutoff_over_w", &CgConfig::cutoff_over_w),
      num("grid", "spacing_mm", &CgConfig::spacing_mm),
      num("grid", "height_mm", &CgConfig::height_mm),
      num("grid", "mask_fraction", &CgConfig::mask_fraction),
      integer("grid", "average_snapshots", &CgConfig::average_snapshots),
      {"velocity", "use",
       [](const std::string& p, const std::string& key, const toml::node& n, CgConfig& c) {
         if (!n.is_string() || (n.as_string()->get() != "piv" && n.as_string()->get() != "instantaneous"))
           fail(p, n.source(), key + " = " + show(n) + ": must be \"piv\" or \"instantaneous\"");
         c.velocity = n.as_string()->get();
       }},
      num("zones", "immobile_below", &CgConfig::immobile_below),
      num("zones", "dragged_above", &CgConfig::dragged_above),
      num("cone", "level", &CgConfig::level),
      num("cone", "fit_start_w", &CgConfig::fit_start_w),
      num("cone", "fit_min_span_d", &CgConfig::fit_min_span_d),
      num("cone", "seed_depth_d", &CgConfig::seed_depth_d),
      num("wall", "band_d", &CgConfig::wall_band_d),
      num("wall", "min_mobile_d", &CgConfig::wall_min_mobile_d),
      num("dilatancy", "region_width_L", &CgConfig::region_width_L),
      num("dilatancy", "region_offset_w", &CgConfig::region_offset_w),
      num("dilatancy", "region_height_d", &CgConfig::region_height_d),
      num("dilatancy", "after_travel_d", &CgConfig::after_travel_d),
      list("output", "bands_mm", &CgConfig::bands_mm),
      num("output", "field_every_mm", &CgConfig::field_every_mm),
      integer("output", "field_max_snapshots", &CgConfig::field_max_snapshots),
      integer("output", "field_follow_snapshots", &CgConfig::field_follow_snapshots),
      num("output", "tip_window_width_mm", &CgConfig::tip_window_width_mm),
      num("output", "tip_window_height_mm", &CgConfig::tip_window_height_mm),
      list("sensitivity", "levels", &CgConfig::levels),
      list("sensitivity", "fit_starts_w", &CgConfig::fit_starts_w),
      list("sensitivity", "max_edge_angles_deg", &CgConfig::max_edge_angles_deg),
      list("sensitivity", "wall_bands_d", &CgConfig::wall_bands_d),
      list("sensitivity", "after_travels_d", &CgConfig::after_travels_d),
      list("sensitivity", "region_heights_d", &CgConfig::region_heights_d),
  };
  return k;
}

std::string allowed(const std::string& table) {
  std::string s;
  for (const Key& k : keys())
    if (table == k.table) s += (s.empty() ? "" : ", ") + std::string(k.name);
  return s;
}

// `where(key)` says where a key is: "FILE" or "FILE:LINE:COL".
void check_ranges(const CgConfig& c, const std::function<std::string(const std::string&)>& where) {
  const auto check = [&](bool ok, const std::string& key, double value, const std::string& rule) {
    if (!ok) {
      std::ostringstream s;
      s << where(key) << ": " << key << " = " << value << ": " << rule;
      throw CgError(s.str());
    }
  };
  check(c.w_over_d > 0.0, "kernel.w_over_d", c.w_over_d, "must be > 0 (kernel width w in mean diameters)");
  check(c.cutoff_over_w > 0.0, "kernel.cutoff_over_w", c.cutoff_over_w, "must be > 0 (cut-off radius in w)");
  check(c.spacing_mm > 0.0, "grid.spacing_mm", c.spacing_mm, "must be > 0 (node spacing in mm)");
  check(c.height_mm >= 0.0, "grid.height_mm", c.height_mm, "must be >= 0 (mm; 0: automatic)");
  check(c.mask_fraction >= 0.0 && c.mask_fraction < 1.0, "grid.mask_fraction", c.mask_fraction,
        "must be in [0, 1) (fraction of the bulk solid fraction)");
  check(c.immobile_below > 0.0 && c.immobile_below < c.dragged_above, "zones.immobile_below", c.immobile_below,
        "must be > 0 and below zones.dragged_above");
  check(c.level > 0.0, "cone.level", c.level, "must be > 0 (v*)");
  check(c.fit_start_w >= 0.0, "cone.fit_start_w", c.fit_start_w, "must be >= 0 (in w)");
  check(c.fit_min_span_d > 0.0, "cone.fit_min_span_d", c.fit_min_span_d, "must be > 0 (in d)");
  check(c.seed_depth_d > 0.0, "cone.seed_depth_d", c.seed_depth_d, "must be > 0 (in d)");
  check(c.wall_band_d > 0.0, "wall.band_d", c.wall_band_d, "must be > 0 (in d)");
  check(c.wall_min_mobile_d >= 0.0, "wall.min_mobile_d", c.wall_min_mobile_d, "must be >= 0 (in d)");
  check(c.region_width_L > 0.0, "dilatancy.region_width_L", c.region_width_L, "must be > 0 (in L)");
  check(c.region_offset_w >= 0.0, "dilatancy.region_offset_w", c.region_offset_w, "must be >= 0 (in w)");
  check(c.region_height_d > 0.0, "dilatancy.region_height_d", c.region_height_d, "must be > 0 (in d)");
  check(c.after_travel_d > 0.0, "dilatancy.after_travel_d", c.after_travel_d, "must be > 0 (in d)");
  check(c.field_every_mm >= 0.0, "output.field_every_mm", c.field_every_mm, "must be >= 0 (mm; 0: none)");
  check(c.field_max_snapshots >= 0, "output.field_max_snapshots", c.field_max_snapshots, "must be >= 0");
  check(c.field_follow_snapshots >= 0, "output.field_follow_snapshots", c.field_follow_snapshots,
        "must be >= 0 (snapshots after each pre-rupture one)");
  check(c.tip_window_width_mm > 0.0, "output.tip_window_width_mm", c.tip_window_width_mm, "must be > 0 (mm)");
  check(c.tip_window_height_mm > 0.0, "output.tip_window_height_mm", c.tip_window_height_mm, "must be > 0 (mm)");
  for (std::size_t k = 1; k < c.bands_mm.size(); ++k)
    check(c.bands_mm[k] > c.bands_mm[k - 1], "output.bands_mm", c.bands_mm[k], "must increase");
  check(c.bands_mm.size() >= 2, "output.bands_mm", static_cast<double>(c.bands_mm.size()), "needs >= 2 edges");
  for (double v : c.levels) check(v > 0.0, "sensitivity.levels", v, "must be > 0 (v*)");
  for (double v : c.fit_starts_w) check(v >= 0.0, "sensitivity.fit_starts_w", v, "must be >= 0");
  for (double v : c.max_edge_angles_deg)
    check(v > 0.0 && v <= 180.0, "sensitivity.max_edge_angles_deg", v,
          "must be in (0, 180] (degrees from the horizontal; 180: every edge)");
  for (double v : c.wall_bands_d) check(v > 0.0, "sensitivity.wall_bands_d", v, "must be > 0");
  for (double v : c.after_travels_d) check(v > 0.0, "sensitivity.after_travels_d", v, "must be > 0");
  for (double v : c.region_heights_d) check(v > 0.0, "sensitivity.region_heights_d", v, "must be > 0");
}

}  // namespace

void validate(const CgConfig& c, const std::string& where) {
  check_ranges(c, [&](const std::string&) { return where; });
}

CgConfig load_cg_config(const std::string& path) {
  if (!std::filesystem::exists(path)) throw CgError(path + ": no such file");
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    fail(path, e.source(), "cannot read the config: " + std::string(e.description()));
  }
  CgConfig c;
  for (const auto& [tkey, tnode] : root) {
    const std::string table(tkey.str());
    if (allowed(table).empty())
      fail(path, tkey.source(),
           "unknown table '" + table + "' (allowed: kernel, grid, velocity, zones, cone, wall, dilatancy, output, "
           "sensitivity)");
    if (!tnode.is_table()) fail(path, tnode.source(), table + " = " + show(tnode) + ": expected a table");
    for (const auto& [key, node] : *tnode.as_table()) {
      const std::string name(key.str());
      const Key* k = nullptr;
      for (const Key& candidate : keys())
        if (table == candidate.table && name == candidate.name) k = &candidate;
      if (!k) fail(path, key.source(), "unknown key '" + table + "." + name + "' (allowed: " + allowed(table) + ")");
      k->read(path, table + "." + name, node, c);
    }
  }
  // range errors point at the key's line when the file gives it
  check_ranges(c, [&](const std::string& key) {
    const toml::node* n = root.at_path(key).node();
    if (!n) return path;
    return path + ":" + std::to_string(n->source().begin.line) + ":" + std::to_string(n->source().begin.column);
  });
  return c;
}

}  // namespace dem2d::analysis
