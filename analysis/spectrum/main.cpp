// spectrum: drag spectrum, loading/rupture events, bottom zone and top layer
// of a pull-off run (analysis/spectrum/README.md).
//   spectrum PULLOFF_RUN.h5 --out DIR [--config data/spectrum.toml] [--study data/study.toml]
//            [--fill-metrics results/<preset>/fill/metrics.json]
// Writes DIR/metrics.json ({"spectrum": {...}}) and DIR/spectrum.h5 (with the
// events file's /events, common/events.hpp). Exit codes
// (common/stage_main.hpp): 0 done; 1 an output could not be written; 2 bad input.
#include <cstdio>

#include "common/stage_main.hpp"
#include "spectrum/spectrum_stage.hpp"

int main(int argc, char** argv) {
  using namespace dem2d::analysis;
  StageCommand cmd("spectrum",
                   "trend and fluctuations of the drag on the intruder, their spectrum (Welch, FFTW), loading/rupture "
                   "events, bottom zone and top layer of a pull-off run",
                   "Pull-off run file (HDF5) written by dem2d", "Output directory (metrics.json, spectrum.h5)");
  cmd.add_config("spectrum.toml");
  cmd.add_study();
  std::string fill_metrics;
  cmd.add_option("--fill-metrics", fill_metrics,
                 "The fill stage's metrics.json: bed height = fill.bed_height_mm (default: where the intruder "
                 "left the bed, by the run's stop criterion)");
  return cmd.main(
      argc, argv,
      [&] {
        const SpectrumInputs in{cmd.run, cmd.config, cmd.study, fill_metrics};
        return compute_spectrum_stage(in, load_spectrum_config(cmd.config), load_study(cmd.study));
      },
      [&](const SpectrumStage& stage) {
        write_spectrum_outputs(cmd.out, stage);
        const auto& m = stage.metrics["spectrum"];
        auto num = [&m](const char* key) { return m[key].is_number() ? m[key].get<double>() : -1.0; };
        char ringing[64] = "not searched";
        if (m["ringing_frequency_hz"].is_number())
          std::snprintf(ringing, sizeof ringing, "%.3g Hz (%s)", num("ringing_frequency_hz"),
                        m["ringing_significant"].get<bool>() ? "significant" : "not significant");
        char top[96];
        if (m["top_layer_found"].get<bool>())
          std::snprintf(top, sizeof top, "top layer from %.1f mm", num("top_layer_height_mm"));
        else
          std::snprintf(top, sizeof top, "no top layer (%s)", m["top_layer_outcome"].get<std::string>().c_str());
        char line[480];
        std::snprintf(line, sizeof line,
                      "%zu events, %zu ruptures, rupture spacing %.3g d (%.3g Hz at 1.2 mm/s), dominant period %.3g d%s "
                      "(searched from %.3g d), ringing %s, %s",
                      m["event_count"].get<std::size_t>(), m["rupture_count"].get<std::size_t>(), num("rupture_spacing_d"),
                      num("rupture_frequency_hz_at_1p2mm_s"), num("dominant_period_d"),
                      m["dominant_period_significant"].get<bool>() ? " (significant)" : " (not significant)",
                      m["dominant_period_search_range_d"][0].get<double>(), ringing, top);
        return std::string(line);
      });
}
