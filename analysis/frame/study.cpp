#include "frame/study.hpp"

#include "common/stage_config.hpp"

namespace dem2d::analysis {

Study load_study(const std::string& path) {
  Study s;
  StageConfig file(path);
  StageConfig e = file.table("experiment");
  using E = StageConfig::Ends;
  e.number("intruder_depth", s.intruder_depth, 0.0, 10.0, "intruder depth W, m (drag N/m x W = N)", E::open_low);
  e.number("cell_width", s.cell_width, 0.0, 10.0, "cell width, m", E::open_low);
  e.number("intruder_length", s.intruder_length, 0.0, 10.0, "intruder length L, m", E::open_low);
  e.number("pull_speed", s.pull_speed, 0.0, 100.0, "the experiment's pull speed, m/s", E::open_low);
  e.number("mean_diameter", s.mean_diameter, 1e-6, 1.0, "the experiment's mean grain diameter, m");
  e.reject_unknown();
  file.reject_unknown();
  return s;
}

}  // namespace dem2d::analysis
