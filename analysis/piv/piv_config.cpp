#include "piv/piv_config.hpp"

#include <filesystem>

#include "common/stage_config.hpp"
#include "common/stage_output.hpp"

namespace dem2d::analysis {

PivConfig load_piv_config(const std::string& path) {
  StageConfig f(path);
  PivConfig c;
  CameraSettings& cam = c.camera;
  StageConfig k = f.table("camera");
  std::int64_t width = static_cast<std::int64_t>(cam.width), height = static_cast<std::int64_t>(cam.height);
  k.integer("width_px", width, 16, 100000, "image width, px");
  k.integer("height_px", height, 16, 100000, "image height, px");
  cam.width = static_cast<std::size_t>(width), cam.height = static_cast<std::size_t>(height);
  k.number("px_per_diameter", cam.px_per_diameter, 1.0, 1000.0, "the mean grain diameter's length, px");
  k.number("background", cam.background, 0.0, 1.0, "intensity between the beads (0..1)");
  k.number("bead", cam.bead, 0.0, 1.0, "a bead's body (0..1)");
  k.number("rim", cam.rim, 0.0, 1.0, "a bead's edge (0..1)");
  k.number("highlight", cam.highlight, 0.0, 1.0, "a bead's specular spot (0..1)");
  k.number("highlight_offset", cam.highlight_offset, 0.0, 1.0, "the spot's offset from the centre, x radius");
  k.number("noise", cam.noise, 0.0, 1.0, "sensor noise, rms of the full scale");
  k.number("blur_px", cam.blur_px, 0.0, 100.0, "Gaussian blur sigma, px");
  k.number("light_falloff", cam.light_falloff, 0.0, 1.0, "intensity falling by this fraction from left to right");
  k.reject_unknown();
  StageConfig p = f.table("piv");
  std::vector<double> windows(c.piv.windows.begin(), c.piv.windows.end());
  p.numbers("windows_px", windows, 8.0, 1024.0, "window size of each pass, px (even, not growing)");
  c.piv.windows.clear();
  for (std::size_t q = 0; q < windows.size(); ++q) {
    const double w = windows[q];
    if (w != static_cast<double>(static_cast<int>(w)) || static_cast<int>(w) % 2 != 0 || (q > 0 && w > windows[q - 1]))
      throw StageError(p.where("windows_px") + ": " + format_number(w) + ": each pass's window an even number of px, "
                       "no larger than the pass before");
    c.piv.windows.push_back(static_cast<int>(w));
  }
  if (c.piv.windows.empty()) throw StageError(p.where("windows_px") + ": at least one pass");
  p.number("highpass_px", c.piv.highpass_px, 0.0, 100.0, "both images less their Gaussian blur of this sigma, px (0: not)");
  p.number("overlap", c.piv.overlap, 0.0, 0.875, "the windows' overlap, fraction of their size");
  p.number("median_threshold", c.piv.median_threshold, 0.0, 100.0, "normalised median test: an outlier above it",
           StageConfig::Ends::open_low);
  p.number("median_epsilon_px", c.piv.median_epsilon, 0.0, 10.0, "the median test's noise level, px");
  p.number("max_excluded", c.piv.max_excluded, 0.0, 1.0, "a window with a larger share of masked pixels gives no vector");
  p.number("converged_px", c.piv.converged_px, 0.0, 10.0, "the last pass repeated until the field changes less, px rms");
  p.integer("max_repeats", c.piv.max_repeats, 0, 100, "at most this many repeats of the last pass");
  p.reject_unknown();
  StageConfig r = f.table("roi");
  r.number("wall_margin_d", c.wall_margin_d, 0.0, 100.0, "the walls' and floor's faces and this many d inside left out");
  r.number("surface_margin_d", c.surface_margin_d, 0.0, 100.0, "above the free surface less this many d left out");
  r.number("mask_margin_d", c.mask_margin_d, 0.0, 100.0, "the intruder's outline widened by this many d, masked");
  r.reject_unknown();
  StageConfig s = f.table("snapshots");
  s.integer("every", c.every, 1, 1000000000, "every k-th snapshot (and the last)");
  s.number("frame_interval_s", c.frame_interval_s, 0.0, 1e6,
           "the frames' interval, s (0: the run's displacement_window; else it, or a whole number of snapshot intervals)");
  s.integer("maps", c.maps, 0, 1000, "snapshots whose maps piv.h5 keeps");
  s.integer("png_frames", c.png_frames, 0, 1000, "of those, this many written as PNG frame pairs");
  s.reject_unknown();
  StageConfig m = f.table("compare");
  m.text("cg_config", c.cg_config, "the cg stage's settings file, relative to this file's folder");
  m.reject_unknown();
  StageConfig v = f.table("vortex");
  v.number("tip_radius_d", c.tip_radius_d, 0.0, 100.0, "a tip's disc radius, d", StageConfig::Ends::open_low);
  v.number("min_swirl_share", c.min_swirl_share, 0.0, 1.0, "lambda_ci counted where at least this share of the gradient's norm");
  v.number("rest_quantile", c.rest_quantile, 0.5, 1.0, "the threshold's quantile of lambda_ci at rest",
           StageConfig::Ends::open_high);
  v.integer("min_nodes", c.min_nodes, 1, 1000000, "nodes of a tip's disc above the threshold that make a vortex");
  v.reject_unknown();
  f.reject_unknown();
  return c;
}

nlohmann::ordered_json to_json(const PivConfig& c) {
  const CameraSettings& k = c.camera;
  return {{"camera", {{"width_px", k.width}, {"height_px", k.height}, {"px_per_diameter", k.px_per_diameter},
                      {"background", k.background}, {"bead", k.bead}, {"rim", k.rim}, {"highlight", k.highlight},
                      {"highlight_offset", k.highlight_offset}, {"noise", k.noise}, {"blur_px", k.blur_px},
                      {"light_falloff", k.light_falloff}}},
          {"piv", {{"windows_px", c.piv.windows}, {"highpass_px", c.piv.highpass_px}, {"overlap", c.piv.overlap}, {"median_threshold", c.piv.median_threshold},
                   {"median_epsilon_px", c.piv.median_epsilon}, {"max_excluded", c.piv.max_excluded},
                   {"converged_px", c.piv.converged_px}, {"max_repeats", c.piv.max_repeats}}},
          {"roi", {{"wall_margin_d", c.wall_margin_d}, {"surface_margin_d", c.surface_margin_d}, {"mask_margin_d", c.mask_margin_d}}},
          {"snapshots", {{"every", c.every}, {"frame_interval_s", c.frame_interval_s}, {"maps", c.maps}, {"png_frames", c.png_frames}}},
          {"compare", {{"cg_config", c.cg_config}}},
          {"vortex", {{"tip_radius_d", c.tip_radius_d}, {"min_swirl_share", c.min_swirl_share}, {"rest_quantile", c.rest_quantile}, {"min_nodes", c.min_nodes}}}};
}

std::string cg_config_path(const std::string& path, const PivConfig& c) {
  const std::filesystem::path p(c.cg_config);
  const std::string found =
      p.is_absolute() ? p.string() : (std::filesystem::path(path).parent_path() / p).lexically_normal().string();
  std::error_code ec;
  if (!std::filesystem::exists(found, ec))  // (a settings file elsewhere names the cg stage's, relative to itself)
    throw StageError((path.empty() ? std::string("the default settings") : path) + ": compare.cg_config = \"" +
                     c.cg_config + "\": " + found + ": no such file (the cg stage's settings, relative to this "
                     "file's folder)");
  return found;
}

}  // namespace dem2d::analysis
