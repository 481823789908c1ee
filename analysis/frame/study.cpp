#include "frame/study.hpp"

#include "common/stage_config.hpp"

namespace dem2d::analysis {

Study load_study(const std::string& path) {
  Study s;
  StageConfig file(path);
  StageConfig e = file.table("experiment");
  using E = StageConfig::Ends;
  for (const char* key : {"intruder_depth", "pull_speed", "mean_diameter"})
    if (!e.has(key)) throw StageError(e.where(key) + ": [experiment] " + key + " is missing (the study's constants need it)");
  e.number("intruder_depth", s.intruder_depth, 0.0, 10.0, "intruder depth W, m (drag N/m x W = N)", E::open_low);
  e.number("pull_speed", s.pull_speed, 0.0, 100.0, "the experiment's pull speed, m/s", E::open_low);
  e.number("mean_diameter", s.mean_diameter, 1e-6, 1.0, "the experiment's mean grain diameter, m");
  e.reject_unknown();
  file.reject_unknown();
  return s;
}

}  // namespace dem2d::analysis
