#include "stress/stress_config.hpp"

#include "common/stage_config.hpp"

namespace dem2d::analysis {

StressConfig load_stress_config(const std::string& path) {
  StageConfig f(path);
  StressConfig c;
  StageConfig k = f.table("kernel");
  k.number("w_over_d", c.w_over_d, 0.0, 100.0, "kernel width w in mean diameters", StageConfig::Ends::open_low);
  k.number("cutoff_over_w", c.cutoff_over_w, 0.0, 100.0, "kernel cut-off radius in w", StageConfig::Ends::open_low);
  k.reject_unknown();
  StageConfig g = f.table("grid");
  g.number("spacing_mm", c.spacing_mm, 0.0, 1000.0, "grid spacing, mm", StageConfig::Ends::open_low);
  g.reject_unknown();
  StageConfig b = f.table("body");
  b.text("role", c.body_role, "the role of the body whose force the stress is checked against");
  b.number("box_margin_mm", c.box_margin_mm, 0.0, 1000.0, "the box around the body: its outline + the cut-off + this, mm");
  b.number("min_load_n", c.min_load_n, 0.0, 1e9, "the force check's snapshots: recorded |F_y| at least this, N per m depth");
  b.number("tolerance", c.tolerance, 0.0, 1.0, "the force check's relative tolerance", StageConfig::Ends::open_low);
  b.reject_unknown();
  f.integer("every", c.every, 1, 1000000000, "every k-th snapshot (and the last)");
  f.integer("maps", c.maps, 0, 1000, "snapshots whose stress maps stress.h5 keeps");
  f.reject_unknown();
  return c;
}

nlohmann::ordered_json to_json(const StressConfig& c) {
  return {{"kernel", {{"w_over_d", c.w_over_d}, {"cutoff_over_w", c.cutoff_over_w}}},
          {"grid", {{"spacing_mm", c.spacing_mm}}},
          {"body", {{"role", c.body_role}, {"box_margin_mm", c.box_margin_mm}, {"min_load_n", c.min_load_n}, {"tolerance", c.tolerance}}},
          {"every", c.every},
          {"maps", c.maps}};
}

}  // namespace dem2d::analysis
