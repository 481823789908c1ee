// Planted truth for the spectrum stage: rupture spacing (R3's rule and every
// event), the size distribution's fits, the top layer (R4) and, for
// comparison, the top layer's old envelope definition.
#include <cmath>
#include <cstdio>

#include "planted/drag_signal.hpp"
#include "planted/planted.hpp"
#include "spectrum/spectrum.hpp"

namespace dem2d::planted {

namespace {

struct Runner {
  analysis::SpectrumConfig config;
  analysis::SpectrumResult analyse(const DragScenario& s) const {
    const analysis::SpectrumScales scales{s.d, s.bed_height, 0.0012};
    return analysis::analyse(make_drag(s).profile, scales, config, "planted");
  }
};

double median_of(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void spacing_cases(const Settings& set, const Runner& run, std::vector<Row>& rows) {
  for (const double noise : set.drag_noise) {
    for (const double spacing : set.spacings_d)
      for (const double jitter : {0.0, 0.3}) {
        Row r{"rupture spacing (R3)", "ruptures every " + fmt("%g", spacing) + " d" + (jitter > 0 ? ", jittered +-30 %" : ""),
              "median spacing of the counted ruptures", "d", spacing, noise, "x load"};
        r.tolerance = 0.1 * spacing;
        summarise(r, set.replicas, [&](unsigned seed) {
          DragScenario s;
          s.spacing_d = spacing, s.jitter = jitter, s.white_relative = noise, s.fraction = 0.3, s.seed = seed;
          const auto a = run.analyse(s);
          const double m = median_of(a.rupture_spacing_d);
          return Outcome{std::isfinite(m), m};
        });
        rows.push_back(r);
      }
    // large ruptures every 0.5 d and slips between them at 15 % of the load:
    // the spacing by size separates them; R3's rule (10 % of the load) does not
    for (const bool by_size : {true, false}) {
      Row r{"rupture spacing (R3)", std::string("ruptures every 0.5 d (30 % of the load), slips every 0.12 d (15 %): ") +
                                        (by_size ? "events above 0.2 of the load" : "R3's rule, 0.1 of the load"),
            "median spacing", "d", 0.5, noise, "x load"};
      r.tolerance = 0.05;
      r.judged = by_size;
      if (!by_size) r.note = "slips above a tenth of the load count as ruptures; the spacing-by-size table separates them";
      summarise(r, set.replicas, [&](unsigned seed) {
        DragScenario s;
        s.spacing_d = 0.5, s.jitter = 0.2, s.white_relative = noise, s.fraction = 0.3, s.seed = seed;
        s.slip_spacing_d = 0.12, s.slip_fraction = 0.15;
        const analysis::SpectrumResult a = run.analyse(s);
        if (!by_size) {
          const double m = median_of(a.rupture_spacing_d);
          return Outcome{std::isfinite(m), m};
        }
        const auto m = analysis::spectrum_metrics(a, {s.d, s.bed_height, 0.0012}, run.config, 1.0);
        for (const auto& row : m["spacing_by_threshold"]["relative_drop"])
          if (row["threshold"].get<double>() == 0.2 && row["median_spacing_d"].is_number())
            return Outcome{true, row["median_spacing_d"].get<double>()};
        return Outcome{};
      });
      rows.push_back(r);
    }
    Row none{"rupture spacing (R3)", "no events: the load and noise only", "median spacing of the counted ruptures", "d",
             std::numeric_limits<double>::quiet_NaN(), noise, "x load"};
    summarise(none, set.replicas, [&](unsigned seed) {
      DragScenario s;
      s.amplitude = Amplitude::none, s.white_relative = noise, s.seed = seed;
      const auto a = run.analyse(s);
      return Outcome{!a.rupture_spacing_d.empty(), median_of(a.rupture_spacing_d)};
    });
    rows.push_back(none);
  }
}

void size_cases(const Settings& set, const Runner& run, std::vector<Row>& rows) {
  struct Family {
    Sizes sizes;
    const char* name;
    const char* family;
    double shape;
  };
  for (const double noise : set.drag_noise)
    for (const Family f : {Family{Sizes::power_law, "power law, alpha = 2.5", "power_law", 2.5},
                           Family{Sizes::exponential, "exponential", "exponential", 0.0},
                           Family{Sizes::lognormal, "lognormal, sigma = 0.6", "lognormal", 0.6}}) {
      auto scenario = [&](unsigned seed) {
        DragScenario s;
        s.amplitude = Amplitude::constant, s.sizes = f.sizes, s.size_shape = f.shape, s.spacing_d = 0.2;
        s.fraction = 0.2, s.white_relative = noise, s.seed = seed;
        return s;
      };
      if (f.sizes == Sizes::power_law) {
        Row r{"rupture sizes", std::string("sizes ") + f.name, "power-law exponent alpha", "-", 2.5, noise, "x load"};
        r.tolerance = 0.4;
        summarise(r, set.replicas, [&](unsigned seed) {
          const auto a = run.analyse(scenario(seed));
          return Outcome{a.sizes.fitted, a.sizes.power_law.alpha};
        });
        rows.push_back(r);
      }
      Row wrong{"rupture sizes", std::string("sizes ") + f.name, "another family favoured (likelihood ratios)", "-",
                std::numeric_limits<double>::quiet_NaN(), noise, "x load"};
      wrong.note = "the fit must favour the planted family or say 'undecided'";
      summarise(wrong, set.replicas, [&](unsigned seed) {
        const auto a = run.analyse(scenario(seed));
        const bool is_wrong = a.sizes.best != f.family && a.sizes.best != "undecided";
        return Outcome{is_wrong, 1.0};
      });
      rows.push_back(wrong);
    }
}

void top_layer_cases(const Settings& set, const Runner& run, std::vector<Row>& rows) {
  const double bed = DragScenario{}.bed_height;
  auto depth = [&](const analysis::SpectrumResult& a) {
    return Outcome{a.top_found, 1e3 * (bed - a.top_height)};
  };
  auto envelope_depth = [&](const analysis::SpectrumResult& a) {
    return Outcome{a.envelope_top_found, 1e3 * (bed - a.envelope_top_height)};
  };
  struct Kind {
    Amplitude amplitude;
    const char* name;
    double correlated;  // background, N/m rms
  };
  for (const double noise : set.drag_noise) {
    for (const double depth_mm : set.top_depths_mm)
      for (const Kind k : {Kind{Amplitude::abrupt, "events stop abruptly", 0.0}, Kind{Amplitude::fade, "events fade linearly to zero over 30 mm", 0.0},
                           Kind{Amplitude::abrupt, "events stop abruptly, a correlated background (1 N/m, 0.3 d) everywhere", 1.0}})
        for (const bool envelope : {false, true}) {
          Row r{"top layer (R4)", std::string(k.name) + " at " + fmt("%g", depth_mm) + " mm depth" +
                                      (envelope ? ": the envelope's definition" : ""),
                "depth below the surface", "mm", depth_mm, noise, "x load"};
          r.tolerance = 5.0;
          r.judged = !envelope;
          // what the change point has to stand out from: the events' rms just
          // below an abrupt end against the noise and background there
          DragScenario planted;
          planted.white_relative = noise, planted.correlated = k.correlated, planted.top = bed - 1e-3 * depth_mm;
          const double load = load_at(planted, planted.top), events = 0.3 * load / std::sqrt(12.0);
          const double background = std::hypot(k.correlated, planted.white + noise * load);
          if (envelope) {
            r.note = "the definition before the change point: envelope >= 2 sigma";
          } else if (k.amplitude == Amplitude::abrupt && events < 1.5 * background) {
            // a vanishing no larger than the background need not be found; where it is, it must be right
            r.min_found = 0.0;
            r.note = "the events just below (rms " + fmt("%.2g", events) + " N/m) hardly exceed the background (" +
                     fmt("%.2g", background) + " N/m): finding it is not required, its depth where found is judged";
          }
          summarise(r, set.replicas, [&](unsigned seed) {
            DragScenario s;
            s.amplitude = k.amplitude, s.top = bed - 1e-3 * depth_mm, s.white_relative = noise, s.correlated = k.correlated;
            s.fraction = 0.3, s.spacing_d = 0.4, s.jitter = 0.3, s.seed = seed;
            const auto a = run.analyse(s);
            return envelope ? envelope_depth(a) : depth(a);
          });
          rows.push_back(r);
        }
    const Kind none_kinds[] = {{Amplitude::load, "events to the surface, sizes following the load", 0.0},
                               {Amplitude::constant, "events of one size to the surface", 0.0},
                               {Amplitude::none, "no events: the load and noise only", 0.0},
                               {Amplitude::none, "no events, a correlated background (1 N/m, 0.3 d)", 1.0}};
    for (const Kind& k : none_kinds)
      for (const bool envelope : {false, true}) {
        Row r{"top layer (R4)", std::string(k.name) + (envelope ? ": the envelope's definition" : ""),
              "depth below the surface", "mm", std::numeric_limits<double>::quiet_NaN(), noise, "x load"};
        r.judged = !envelope;
        if (envelope) r.note = "the definition before the change point: envelope >= 2 sigma";
        summarise(r, set.replicas, [&](unsigned seed) {
          DragScenario s;
          s.amplitude = k.amplitude, s.white_relative = noise, s.correlated = k.correlated;
          s.fraction = 0.3, s.spacing_d = 0.4, s.jitter = 0.3, s.seed = seed;
          const auto a = run.analyse(s);
          return envelope ? envelope_depth(a) : depth(a);
        });
        rows.push_back(r);
      }
  }
}

}  // namespace

std::vector<Row> drag_cases(const Settings& set, const std::string& data_dir) {
  const Runner run{analysis::load_spectrum_config(data_dir + "/spectrum.toml")};
  std::vector<Row> rows;
  spacing_cases(set, run, rows);
  size_cases(set, run, rows);
  top_layer_cases(set, run, rows);
  return rows;
}

}  // namespace dem2d::planted
