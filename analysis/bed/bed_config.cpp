#include "bed/bed_config.hpp"

#include "common/stage_config.hpp"

namespace dem2d::analysis {

BedConfig load_bed_config(const std::string& path) {
  BedConfig c;
  try {
    StageConfig f(path);
    f.number("margin_d", c.margin_d, 0.0, 1e3, "bulk region: mean diameters from walls, surface and intruder");
    f.number("sampling_per_d", c.sampling_per_d, 1.0, 200.0, "solid fraction: sample points per mean diameter");
    f.number("column_width_d", c.column_width_d, 0.01, 1e3, "free surface: column width in mean diameters");
    f.reject_unknown();
  } catch (const StageError& e) {
    throw BedError(e.what());
  }
  return c;
}

}  // namespace dem2d::analysis
