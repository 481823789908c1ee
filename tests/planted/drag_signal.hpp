// Synthetic drag profiles with planted truth, for the spectrum stage's
// detectors (rupture spacing and sizes, top layer): a relaxing load, a
// sawtooth of loading/rupture events on it whose spacing, sizes and amplitude
// against height are chosen, and noise (white, and a stationary correlated
// background). SI units: heights in m, drag in N/m.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "frame/drag_profile.hpp"

namespace dem2d::planted {

// How the events' typical size varies with height H.
enum class Amplitude {
  load,      // size = fraction x load(H) all the way to the surface (no top layer)
  abrupt,    // as `load` below top, none above
  fade,      // as `load` below top - fade_length, then falling linearly to zero at top
  constant,  // size = fraction x load at the start of the loading/rupture part, everywhere (no top layer)
  none,      // no events at all
};

// The events' sizes around the typical size.
// power_law_body: half the events a body below the typical size (uniform in
// [0.2, 1] of it), half a power law above it (x_min = the typical size).
enum class Sizes { fixed, exponential, lognormal, power_law, power_law_body };

struct DragScenario {
  // sampling: rows every row_s seconds, the intruder at speed m/s from start to end (m)
  double d = 0.003, speed = 0.0012, row_s = 0.02, start = 0.0, end = 0.160;
  double bed_height = 0.141;  // m: the surface; load and events stop there
  // load (the trend, N/m): peak exp(-H / relax) + slope x (bed - H) below the bed, carried above it
  double peak_load = 200.0, relax = 0.035, slope = 300.0, carried = 0.5;
  // events: spacing (d of travel) with a relative jitter (uniform +-jitter x spacing), from event_from (m)
  double spacing_d = 0.5, jitter = 0.0, event_from = 0.014;
  Amplitude amplitude = Amplitude::load;
  double fraction = 0.15;    // typical size / load
  double top = 0.096;        // m: where abrupt and fade events end
  double fade_length = 0.03; // m
  Sizes sizes = Sizes::fixed;
  double size_shape = 2.5;   // power law: exponent alpha (x_min = the typical size); lognormal: sigma of ln
  // small slips between the events: spacing (d) and size as a fraction of the load (0: none)
  double slip_spacing_d = 0.0, slip_fraction = 0.0;
  // noise: white, of rms white + white_relative x load (N/m: the study's runs'
  // noise follows the load, ~2.7 % of it, the bed's ringing growing with its
  // load), and a stationary AR(1) background (N/m rms, correlation length in d)
  double white = 0.25, white_relative = 0.025, correlated = 0.0, correlation_d = 0.3;
  // an AR(1) part that follows the load (rms x load, the same correlation
  // length): the study's drag noise is both correlated and load-proportional
  double correlated_relative = 0.0;
  // the white part's tails: Gaussian (0) or Student-t with this many degrees of
  // freedom, scaled to the Gaussian's median absolute value (the same typical
  // amplitude, heavier tails)
  double tails_nu = 0.0;
  std::uint64_t seed = 1;
};

// The profile, and the planted events' peak heights (m) and sizes (N/m).
struct PlantedDrag {
  analysis::DragProfile profile;
  std::vector<double> event_height, event_size;
};

PlantedDrag make_drag(const DragScenario& s);

// The scenario's load at height h (N/m).
double load_at(const DragScenario& s, double h);

}  // namespace dem2d::planted
