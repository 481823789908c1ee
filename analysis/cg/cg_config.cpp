#include "cg/cg_config.hpp"

#include <functional>
#include <optional>
#include <sstream>

#include "common/stage_config.hpp"

namespace dem2d::analysis {

namespace {

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
  check(c.average_snapshots >= 1, "grid.average_snapshots", c.average_snapshots, "must be >= 1 (snapshots averaged per field)");
  check(c.immobile_below > 0.0 && c.immobile_below < c.dragged_above, "zones.immobile_below", c.immobile_below,
        "must be > 0 and below zones.dragged_above");
  check(c.reference_speed_mm_s >= 0.0, "zones.reference_speed_mm_s", c.reference_speed_mm_s,
        "must be >= 0 (mm/s; 0: the intruder's speed)");
  check(c.level > 0.0, "cone.level", c.level, "must be > 0 (v*)");
  check(c.fit_start_w >= 0.0, "cone.fit_start_w", c.fit_start_w, "must be >= 0 (in w)");
  check(c.fit_min_span_d > 0.0, "cone.fit_min_span_d", c.fit_min_span_d, "must be > 0 (in d)");
  check(c.seed_depth_d > 0.0, "cone.seed_depth_d", c.seed_depth_d, "must be > 0 (in d)");
  check(c.frame_snapshots >= 1 && c.frame_snapshots <= 100, "cone.frame_snapshots", c.frame_snapshots,
        "must be an integer in [1, 100] (snapshots averaged in the intruder's frame)");
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
  CgConfig c;
  std::optional<StageConfig> file;
  try {
    file.emplace(path);
    using E = StageConfig::Ends;
    constexpr double kBig = 1e3, kMm = 1e5;  // bounds of lengths in d, w or L, and in mm
    StageConfig kernel = file->table("kernel");
    kernel.number("w_over_d", c.w_over_d, 0.0, 100.0, "kernel width w in mean diameters", E::open_low);
    kernel.number("cutoff_over_w", c.cutoff_over_w, 0.0, 100.0, "cut-off radius in w", E::open_low);
    kernel.reject_unknown();
    StageConfig grid = file->table("grid");
    grid.number("spacing_mm", c.spacing_mm, 0.0, kMm, "node spacing in mm", E::open_low);
    grid.number("height_mm", c.height_mm, 0.0, kMm, "mm; 0: automatic");
    grid.number("mask_fraction", c.mask_fraction, 0.0, 1.0, "fraction of the bulk solid fraction", E::open_high);
    grid.integer("average_snapshots", c.average_snapshots, 1, 1000000, "snapshots averaged per field");
    grid.reject_unknown();
    StageConfig velocity = file->table("velocity");
    velocity.choice("use", c.velocity, {"piv", "instantaneous"}, "the velocity the zones use");
    velocity.reject_unknown();
    StageConfig zones = file->table("zones");
    zones.number("immobile_below", c.immobile_below, 0.0, kBig, "v*", E::open_low);
    zones.number("dragged_above", c.dragged_above, 0.0, kBig, "v*", E::open_low);
    zones.number("reference_speed_mm_s", c.reference_speed_mm_s, 0.0, kMm, "mm/s; 0: the intruder's speed");
    zones.reject_unknown();
    StageConfig cone = file->table("cone");
    cone.number("level", c.level, 0.0, kBig, "v*", E::open_low);
    cone.number("fit_start_w", c.fit_start_w, 0.0, kBig, "in w");
    cone.number("fit_min_span_d", c.fit_min_span_d, 0.0, kBig, "in d", E::open_low);
    cone.number("seed_depth_d", c.seed_depth_d, 0.0, kBig, "in d", E::open_low);
    cone.integer("min_snapshots", c.min_snapshots, 2, 1000000, "snapshots with an edge angle");
    cone.number("max_interval_deg", c.max_interval_deg, 0.0, 90.0, "deg, the 95 % interval's half-width", E::open_low);
    cone.integer("frame_snapshots", c.frame_snapshots, 1, 100, "snapshots averaged in the intruder's frame");
    cone.reject_unknown();
    StageConfig wall = file->table("wall");
    wall.number("band_d", c.wall_band_d, 0.0, kBig, "in d", E::open_low);
    wall.number("min_mobile_d", c.wall_min_mobile_d, 0.0, kBig, "in d");
    wall.number("kernel_w", c.wall_kernel_w, 0.0, kBig, "in w", E::open_low);
    wall.number("pool_d", c.wall_pool_d, 0.0, kBig, "in d of intruder travel");
    wall.number("loss_false_alarm", c.wall_loss_false_alarm, 0.0, 1.0, "probability", E::open);
    wall.integer("permutations", c.wall_permutations, 0, 1000000, "permutations of the mobile flags");
    wall.number("power_cone_angle_deg", c.wall_power_cone_angle_deg, 0.0, 90.0, "deg from the horizontal", E::open);
    wall.integer("power_replicas", c.wall_power_replicas, 0, 1000000, "planted flag series (0: no power)");
    wall.number("power_tolerance_d", c.wall_power_tolerance_d, 0.0, kBig, "in d", E::open_low);
    wall.number("min_power", c.wall_min_power, 0.0, 1.0, "probability", E::open);
    wall.reject_unknown();
    StageConfig noise = file->table("noise");
    noise.number("rest_margin_w", c.rest_margin_w, 0.0, kBig, "in w");
    noise.number("cone_false_alarm", c.cone_false_alarm, 0.0, 1.0, "probability", E::open);
    noise.number("wall_false_alarm", c.wall_false_alarm, 0.0, 1.0, "probability", E::open);
    noise.integer("snapshots", c.noise_snapshots, 1, 1000000, "snapshots of the noise pre-pass");
    noise.reject_unknown();
    StageConfig dilatancy = file->table("dilatancy");
    dilatancy.number("region_width_L", c.region_width_L, 0.0, kBig, "in L", E::open_low);
    dilatancy.number("region_offset_w", c.region_offset_w, 0.0, kBig, "in w");
    dilatancy.number("region_height_d", c.region_height_d, 0.0, kBig, "in d", E::open_low);
    dilatancy.number("after_travel_d", c.after_travel_d, 0.0, kBig, "in d", E::open_low);
    dilatancy.reject_unknown();
    StageConfig output = file->table("output");
    output.numbers("bands_mm", c.bands_mm, 0.0, kMm, "band edges in mm");
    output.number("field_every_mm", c.field_every_mm, 0.0, kMm, "mm; 0: none");
    output.integer("field_max_snapshots", c.field_max_snapshots, 1, 1000000, "fields written at most");
    output.integer("field_follow_snapshots", c.field_follow_snapshots, 1, 1000000, "snapshots after each pre-rupture one");
    output.number("tip_window_width_mm", c.tip_window_width_mm, 0.0, kMm, "mm", E::open_low);
    output.number("tip_window_height_mm", c.tip_window_height_mm, 0.0, kMm, "mm", E::open_low);
    output.reject_unknown();
    StageConfig sensitivity = file->table("sensitivity");
    sensitivity.numbers("levels", c.levels, 0.0, kBig, "v*", E::open_low);
    sensitivity.numbers("fit_starts_w", c.fit_starts_w, 0.0, kBig, "in w");
    sensitivity.numbers("max_edge_angles_deg", c.max_edge_angles_deg, 0.0, 180.0,
                        "degrees from the horizontal; 180: every edge", E::open_low);
    sensitivity.numbers("wall_bands_d", c.wall_bands_d, 0.0, kBig, "in d", E::open_low);
    sensitivity.numbers("cone_false_alarms", c.cone_false_alarms, 0.0, 1.0, "probability", E::open);
    sensitivity.numbers("wall_false_alarms", c.wall_false_alarms, 0.0, 1.0, "probability", E::open);
    sensitivity.numbers("after_travels_d", c.after_travels_d, 0.0, kBig, "in d", E::open_low);
    sensitivity.numbers("region_heights_d", c.region_heights_d, 0.0, kBig, "in d", E::open_low);
    sensitivity.reject_unknown();
    file->reject_unknown();
  } catch (const StageError& e) {
    throw CgError(e.what());
  }
  // conditions across keys, at the first key's line
  check_ranges(c, [&](const std::string& key) {
    const auto dot = key.find('.');
    return file->table(key.substr(0, dot)).where(key.substr(dot + 1));
  });
  return c;
}

}  // namespace dem2d::analysis
