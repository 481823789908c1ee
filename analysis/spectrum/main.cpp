// spectrum: drag spectrum, loading/rupture events, bottom zone and top layer
// of a pull-off run (analysis/spectrum/README.md).
//   spectrum PULLOFF_RUN.h5 --out DIR [--config data/spectrum.toml] [--study data/study.toml]
//            [--fill-metrics results/<preset>/fill/metrics.json]
// Writes DIR/metrics.json ({"spectrum": {...}}) and DIR/spectrum.h5.
// Exit codes: 0 done; 1 an output could not be written; 2 bad input.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "core/share_dir.hpp"
#include "spectrum/spectrum_stage.hpp"

namespace {
constexpr int kExitFailed = 1, kExitBadInput = 2;
}

int main(int argc, char** argv) {
  using namespace dem2d::analysis;
  CLI::App app{"spectrum: trend and fluctuations of the drag on the intruder, their spectrum (Welch, FFTW), "
               "loading/rupture events, bottom zone and top layer of a pull-off run"};
  SpectrumInputs in{"", dem2d::data_file("spectrum.toml"), dem2d::data_file("study.toml"), ""};
  std::string out_dir;
  app.add_option("run", in.run, "Pull-off run file (HDF5) written by dem2d")->required();
  app.add_option("--out", out_dir, "Output directory (metrics.json, spectrum.h5)")->required();
  app.add_option("--config", in.config, "Settings (TOML)")->capture_default_str();
  app.add_option("--study", in.study, "The study's constants (TOML)")->capture_default_str();
  app.add_option("--fill-metrics", in.fill_metrics,
                 "The fill stage's metrics.json: bed height = fill.bed_height_mm (default: where the intruder "
                 "left the bed, by the run's stop criterion)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : kExitBadInput;
  }
  SpectrumStage stage;
  try {
    stage = compute_spectrum_stage(in, load_spectrum_config(in.config), load_study(in.study));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "spectrum: %s\n", e.what());
    return kExitBadInput;
  }
  try {
    write_spectrum_outputs(out_dir, stage);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "spectrum: %s\n", e.what());
    return kExitFailed;
  }
  const auto& m = stage.metrics["spectrum"];
  auto num = [&m](const char* key) { return m[key].is_number() ? m[key].get<double>() : -1.0; };
  char ringing[64] = "not searched";
  if (m["ringing_frequency_hz"].is_number())
    std::snprintf(ringing, sizeof ringing, "%.3g Hz (%s)", num("ringing_frequency_hz"),
                  m["ringing_significant"].get<bool>() ? "significant" : "not significant");
  std::fprintf(stderr,
               "spectrum: %s: %zu events, rupture spacing %.3g d (%.3g Hz at 1.2 mm/s), dominant period %.3g d%s "
               "(searched from %.3g d), ringing %s, top layer from %.1f mm -> %s\n",
               in.run.c_str(), m["event_count"].get<std::size_t>(), num("rupture_spacing_d"),
               num("rupture_frequency_hz_at_1p2mm_s"), num("dominant_period_d"),
               m["dominant_period_significant"].get<bool>() ? " (significant)" : " (not significant)",
               m["dominant_period_search_range_d"][0].get<double>(), ringing, num("top_layer_height_mm"),
               out_dir.c_str());
  return 0;
}
