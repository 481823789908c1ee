// Stage `spectrum`: its computations on synthetic drag profiles with known
// answers, its configuration, and the whole stage on the quick pull-off run.
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <filesystem>
#include <numeric>
#include <random>

#include "runfile/h5.hpp"
#include "spectrum/spectrum.hpp"
#include "spectrum/spectrum_stage.hpp"
#include "quick_study.hpp"
#include "temp_dir.hpp"

namespace dem2d::analysis {
namespace {

constexpr double kD = 0.003;            // m, mean diameter
constexpr double kStep = kD / 125.0;    // m per row, as the study's series (0.02 s at 1.2 mm/s)
constexpr double kV = 0.0012;           // m/s

const SpectrumScales kScales{kD, 0.150, kV};
// The defaults without the resampling (the top layer's permutations and bootstrap, the size
// distribution's synthetic sets): for the tests of the spectrum, the ringing and the events,
// which read none of it (the top layer's and the sizes' own tests keep the defaults)
const SpectrumConfig kNoResampling = [] {
  SpectrumConfig c;
  c.top_bootstrap = 0, c.size_bootstrap = 0, c.power_replicas = 0;
  return c;
}();

// The defaults without a miss's power (20 plantings, each a permutation test): for the tests that
// judge no miss (AMissCarriesItsPower judges it)
const SpectrumConfig kNoPower = [] {
  SpectrumConfig c;
  c.power_replicas = 0;
  return c;
}();

// A pull-off at speed v from 1 mm to `top`, one row every `interval` seconds, plus Gaussian noise. A row
// holds the mean of drag(t, H) over `subsamples` instants of the interval ending at it, as the run's
// /series/body_force_mean (an interval mean: a line above the Nyquist frequency is attenuated and folded).
DragProfile pulled(const std::function<double(double, double)>& drag, double v, double interval, double noise,
                   unsigned seed, double top, int subsamples) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, noise);
  DragProfile p;
  for (std::size_t k = 0;; ++k) {
    const double t = static_cast<double>(k) * interval, h = 0.001 + v * t;
    if (h > top) break;
    double mean = 0.0;
    for (int j = 0; j < subsamples; ++j) {
      const double tj = t - interval * j / subsamples;
      mean += drag(tj, 0.001 + v * tj) / subsamples;
    }
    p.time.push_back(t);
    p.height.push_back(h);
    p.drag.push_back(mean + gauss(rng));
  }
  return p;
}

// The study's pull-off from 1 mm to `top`: drag(H) from `shape` sampled every d/125 (0.02 s), plus noise.
DragProfile synthetic(const std::function<double(double)>& shape, double noise, unsigned seed = 1,
                      double top = 0.150) {
  return pulled([&shape](double, double h) { return shape(h); }, kV, kStep / kV, noise, seed, top, 1);
}

double trend(double h) { return 40.0 * std::exp(-h / 0.05) + 5.0 * (0.150 - h) / 0.150; }

// Loading ramps of amplitude `a` ended by a drop within one sample, period `period` (m), up to `stop` (m).
std::function<double(double)> sawtooth(double period, double a, double stop = 1.0) {
  return [=](double h) { return trend(h) + (h < stop ? a * std::fmod(h, period) / period : 0.0); };
}

// Slips every `period` of travel (m), each spacing drawn uniformly within +-jitter x period (the drag of
// a granular pull-out is not a perfect sawtooth: jitter smears the harmonics), each ending a loading ramp
// of 10 N/m on the trend and exciting the bed's ringing: a burst at ring_hz with a random phase and an
// amplitude uniform in [0.5, 1.5] x ring_amplitude (N/m), decaying with the contacts' damping ratio
// (e = 0.9: zeta = 0.0335, decay time 1 / (2 pi zeta f) = 0.14 s at 35 Hz). drag(t, H) at speed v.
struct Slips {
  struct Burst {
    double time, amplitude, phase;
  };
  std::vector<double> heights;  // m, of the slips
  std::vector<Burst> bursts;
  double ring_hz, decay;

  Slips(double period, double jitter, double v, double ring_hz_, double ring_amplitude, unsigned seed)
      : ring_hz(ring_hz_), decay(1.0 / (2.0 * 3.14159265358979 * 0.0335 * ring_hz_)) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (double h = 0.001 + period * u(rng); h < 0.3; h += period * (1.0 + jitter * (2.0 * u(rng) - 1.0))) {
      heights.push_back(h);
      bursts.push_back({(h - 0.001) / v, ring_amplitude * (0.5 + u(rng)), 2.0 * 3.14159265358979 * u(rng)});
    }
  }
  double operator()(double t, double h) const {
    const std::size_t i = static_cast<std::size_t>(std::upper_bound(heights.begin(), heights.end(), h) - heights.begin());
    const double last = i > 0 ? heights[i - 1] : 0.001;
    double drag = trend(h) + 10.0 * (h - last) / (heights[i] - last);
    for (std::size_t j = i; j-- > 0 && t - bursts[j].time < 10.0 * decay;) {
      const double dt = t - bursts[j].time;
      drag += bursts[j].amplitude * std::exp(-dt / decay) * std::sin(2.0 * 3.14159265358979 * ring_hz * dt + bursts[j].phase);
    }
    return drag;
  }
};

TEST(SpectrumBlocks, RunningMedianKeepsAMonotoneSignalAndRemovesSpikes) {
  std::vector<double> x(50);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sqrt(static_cast<double>(i));
  EXPECT_EQ(running_median(x, 7), x);
  x[20] += 100.0;
  EXPECT_NEAR(running_median(x, 3)[20], std::sqrt(20.0), 0.3);
}

TEST(SpectrumBlocks, WelchPsdIntegratesToTheVarianceAndNoiseLevelIsSigma) {
  std::mt19937 rng(3);
  std::normal_distribution<double> gauss(0.0, 2.0);
  std::vector<double> x(20000);
  for (double& v : x) v = gauss(rng);
  const Psd p = welch_psd(x, 125.0, 1000, 0.5, "hann");
  const double dk = p.frequency[1] - p.frequency[0];
  EXPECT_NEAR(std::accumulate(p.power.begin(), p.power.end(), 0.0) * dk, 4.0, 0.1);
  EXPECT_EQ(p.segments, 39u);
  EXPECT_NEAR(p.dof, 36.0 * 39 * 39 / (19.0 * 39 - 1), 0.5);  // Welch's Hann, 50 % overlap
  EXPECT_NEAR(noise_level(x, 0, x.size()), 2.0, 0.05);
}

TEST(SpectrumBlocks, ZigzagAlternatesWithHysteresis) {
  const std::vector<double> x{0, 1, 5, 4.5, 5.2, 1, 1.5, 0.5, 4, 3};
  const auto piv = zigzag(x, 2.0);
  ASSERT_EQ(piv.size(), 3u);  // the last rise to 4 is no peak: 4 -> 3 is not a fall of 2
  EXPECT_TRUE(!piv[0].peak && piv[0].index == 0);
  EXPECT_TRUE(piv[1].peak && piv[1].index == 4);
  EXPECT_TRUE(!piv[2].peak && piv[2].index == 7);
}

TEST(Spectrum, SawtoothOnADecayingTrendGivesItsPeriodAndEvents) {
  const double period = 0.5 * kD;
  const SpectrumResult r = analyse(synthetic(sawtooth(period, 10.0), 0.2), kScales, kNoPower, "synthetic");
  const DominantPeak& k = r.second_part.peak;
  EXPECT_TRUE(k.significant);
  EXPECT_NEAR(k.period, 0.5, 0.01) << "within 2 %";
  const double drops = std::floor(0.150 / period) - std::floor(0.001 / period);
  EXPECT_NEAR(static_cast<double>(r.events.size()), drops, 0.02 * drops);
  ASSERT_FALSE(r.spacing_d.empty());
  for (const double s : r.spacing_d) EXPECT_NEAR(s, 0.5, 0.05);
  for (const Event& e : r.events) {
    EXPECT_LT(e.load_start, e.peak);
    EXPECT_LT(e.peak, e.drop_end);
    EXPECT_NEAR(r.profile.drag[e.peak] - r.profile.drag[e.drop_end], 10.0, 1.5);
  }
  EXPECT_NEAR(r.noise, 0.2, 0.03);
}

TEST(Spectrum, PureNoiseHasNoSignificantPeriod) {
  // false_alarm = 0.01 per spectrum: 20 noise records should give at most one false detection
  int significant = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const SpectrumResult r = analyse(synthetic(trend, 1.0, seed), kScales, kNoResampling, "noise");
    significant += r.second_part.peak.significant;
    EXPECT_LE(r.events.size(), 1u) << "seed " << seed;  // false drops are rare at 7 sigma
    EXPECT_LT(r.second_part.peak.peak_to_background, 2.0 * r.second_part.peak.threshold);
  }
  EXPECT_LE(significant, 1);
}

TEST(Spectrum, TopLayerStartsWhereTheFluctuationsStop) {
  const double period = 0.5 * kD, stop = 0.105;
  const SpectrumResult r = analyse(synthetic(sawtooth(period, 10.0, stop), 0.2), kScales, {}, "synthetic");
  ASSERT_TRUE(r.top_found);
  EXPECT_EQ(r.top.outcome, "found");
  // within a variance block (1 d): the change point's resolution
  EXPECT_NEAR(r.top_height, stop, kD);
  EXPECT_LE(r.top.low, r.top_height);
  EXPECT_GE(r.top.high, r.top_height);
  // the envelope's definition finds it too, within a period
  ASSERT_TRUE(r.envelope_top_found);
  EXPECT_NEAR(r.envelope_top_height, stop, period + 1e-9);
  // there the drag follows the (nearly linear) trend
  EXPECT_GT(r.top_fit.r2, 0.9);
  EXPECT_GT(r.top_fit.slope, 0.0);  // grows with depth
}

// Events that shrink with the load all the way to the surface: no top layer
// (the envelope's definition found one where they sink below 2 sigma).
TEST(Spectrum, NoTopLayerWhenTheEventsFollowTheLoadToTheSurface) {
  const double period = 0.5 * kD;
  const auto shape = [=](double h) { return trend(h) * (1.0 + 0.3 * std::fmod(h, period) / period); };
  const SpectrumResult r = analyse(synthetic(shape, 0.2), kScales, kNoPower, "synthetic");
  EXPECT_FALSE(r.top_found) << r.top.outcome << " at " << r.top.best.height << " p " << r.top.p_value;
  EXPECT_TRUE(std::isnan(r.top_height));
  EXPECT_NE(r.top.outcome, "found");
  // the load and noise alone: nothing either
  const SpectrumResult q = analyse(synthetic(trend, 0.2), kScales, kNoPower, "synthetic");
  EXPECT_FALSE(q.top_found) << q.top.outcome;
}

// A miss carries its power: the events that follow the load to the surface
// give no layer; a layer planted at the paper's depth into that very series
// would be found (the events dwarf the noise), so the miss is "none", a
// confident absence. Drowned in noise ten times larger, the same events give
// a miss too, but one the detector could not have told from a layer:
// "undetermined", with a power below 0.8.
TEST(Spectrum, AMissCarriesItsPower) {
  const double period = 0.5 * kD;
  const auto shape = [=](double h) { return trend(h) * (1.0 + 0.3 * std::fmod(h, period) / period); };
  SpectrumConfig c;
  c.power_replicas = 10;
  const SpectrumResult clear = analyse(synthetic(shape, 0.05), kScales, c, "synthetic");
  ASSERT_FALSE(clear.top_found);
  EXPECT_EQ(clear.top.outcome, "none");
  EXPECT_GE(clear.top_power.power, 0.8);
  ASSERT_EQ(clear.top_power.height.size(), 1u);
  EXPECT_NEAR(clear.top_power.height[0], 0.7 * kScales.bed_height, 1e-12);  // 0.3 of the bed deep
  const SpectrumResult drowned = analyse(synthetic(shape, 3.0), kScales, c, "synthetic");
  ASSERT_FALSE(drowned.top_found);
  EXPECT_EQ(drowned.top.outcome, "undetermined");
  EXPECT_LT(drowned.top_power.power, 0.8);
  // without plantings no power: a miss is undetermined
  c.power_replicas = 0;
  EXPECT_EQ(analyse(synthetic(shape, 0.2), kScales, c, "synthetic").top.outcome, "undetermined");
}

// Heavy-tailed noise: a lone spike falls by more than the threshold within
// the window and comes straight back; it is no rupture. A real drop keeps
// its level down and stays one.
TEST(SpectrumBlocks, ALoneSpikeIsNoRupture) {
  std::vector<double> f(200, 0.0);
  for (std::size_t k = 0; k < 200; ++k) f[k] = 0.01 * static_cast<double>(k % 100);  // ramps of 1, dropping at 100
  f[50] -= 5.0;                                                                    // a spike mid-ramp
  const auto with = detect_events(f, 0.5, 5, 2), without = detect_events(f, 0.5, 5, 0);
  ASSERT_EQ(with.size(), 1u);
  EXPECT_EQ(with[0].peak, 99u);
  EXPECT_EQ(without.size(), 2u);  // the spike counted as a rupture
}

// Sizes drawn from a power law (alpha 2.5) and from an exponential: the
// maximum-likelihood fits recover the exponent and tell the two apart.
TEST(SpectrumSizes, PowerLawAndExponentialAreToldApart) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> pl, ex;
  for (int i = 0; i < 400; ++i) pl.push_back(std::pow(1.0 - u(rng), -1.0 / 1.5)), ex.push_back(1.0 - std::log(1.0 - u(rng)));
  const SizeFitSettings s{10, 100, 0.1, 1};
  const SizeDistribution a = fit_sizes(pl, s), b = fit_sizes(ex, s);
  ASSERT_TRUE(a.fitted);
  EXPECT_NEAR(a.power_law.alpha, 2.5, 0.25);
  EXPECT_GT(a.power_law_p, 0.1);                 // plausible
  EXPECT_NE(a.best, "exponential");
  EXPECT_NE(b.best, "power_law");
  EXPECT_NEAR(1.0 / b.exponential.lambda, 1.0, 0.2);  // the mean excess over x_min
  EXPECT_TRUE(a.power_law_plausible);
  EXPECT_GT(a.decades, 1.0);
  // too few sizes: no fit
  EXPECT_FALSE(fit_sizes({1.0, 2.0, 3.0}, s).fitted);
}

// The study's catalogue size: 90 exponential sizes. The power law's goodness
// of fit alone can pass them (a steep power law over the tail's last factor
// of a few), but a power law is plausible only over a decade; and an
// undecided fit says which family leads and how many sizes would decide.
TEST(SpectrumSizes, ExponentialSizesAreNoPlausiblePowerLawAndUndecidedSaysWhatWouldDecide) {
  const SizeFitSettings s{10, 200, 0.05, 1};
  int plausible = 0, undecided_with_need = 0;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<double> ex;
    for (int i = 0; i < 90; ++i) ex.push_back(1.0 - std::log(1.0 - u(rng)));
    const SizeDistribution d = fit_sizes(ex, s);
    ASSERT_TRUE(d.fitted);
    plausible += d.power_law_plausible;
    if (d.best == "undecided") {
      EXPECT_FALSE(d.leading.empty());
      undecided_with_need += std::isfinite(d.tail_needed) && d.tail_needed > static_cast<double>(d.tail);
    }
  }
  EXPECT_LE(plausible, 1);
  EXPECT_GE(undecided_with_need, 1);
}

TEST(Spectrum, BottomZoneFindsPeakCollapseAndReload) {
  // a high peak at 3 mm, a collapse to 5 N/m at 6 mm, a reload to 30 N/m at 10 mm, a relaxation to 5 N/m
  // at 16 mm, then small ramps
  auto shape = [](double h) {
    const double mm = 1e3 * h;
    if (mm < 3) return 10 + 30 * mm;
    if (mm < 6) return 100 - 95 * (mm - 3) / 3;
    if (mm < 10) return 5 + 25 * (mm - 6) / 4;
    return 5 + 25 * std::max(0.0, 1 - (mm - 10) / 6) + 2 * std::fmod(mm, 1.5) / 1.5;
  };
  const SpectrumResult r = analyse(synthetic(shape, 0.05), kScales, kNoPower, "synthetic");
  ASSERT_NE(r.bottom_collapse, SpectrumResult::npos);
  ASSERT_NE(r.bottom_reload, SpectrumResult::npos);
  EXPECT_NEAR(r.profile.height[r.bottom_peak], 0.003, 0.0002);
  EXPECT_NEAR(r.profile.height[r.bottom_collapse], 0.006, 0.0002);
  EXPECT_NEAR(r.profile.height[r.bottom_reload], 0.010, 0.0002);
}

// A pull-off at speed v, rows every `interval` s (means over 8 instants each), from 1 mm to 110 mm of a
// 150 mm bed: slips every d/2 (+-20 %) and a 35 Hz ringing of 25 N/m after each, noise 0.2 N/m. The
// ringing is strong enough that the old search (wavelengths 0.1-2 d, whatever their time frequency)
// takes it for the dominant period at 12 mm/s, as it did on the fast preset's bed at 12 mm/s.
constexpr double kRingHz = 35.0;
SpectrumResult ringing_run(double v, double interval, const SpectrumConfig& c = kNoResampling) {
  const Slips slips(0.5 * kD, 0.2, v, kRingHz, 25.0, 7);
  return analyse(pulled(slips, v, interval, 0.2, 1, 0.110, 8), kScales, c, "synthetic");
}

// Tolerances. Ringing: +-1 Hz, one bin of the 1 s time segments (the line is 2 zeta f = 2.3 Hz wide and
// its highest bin can be a neighbour of the centre's in a chi-square spectrum). Geometric period: +-0.03 d,
// one bin of the 8 d travel segments at 2 cycles per d (0.125 cycle per d); the +-20 % jitter of the
// spacings broadens the line to several bins, and over 8 seeds its maximum fell within 0.48-0.51 d.
constexpr double kRingTolHz = 1.0, kPeriodTolD = 0.03;

TEST(SpectrumRinging, AtTheStudysRowsTheRingingIsFoldedAndTheSearchIsUnchanged) {
  // 1.2 mm/s, rows every 0.02 s (Nyquist 25 Hz): the 35 Hz ringing is attenuated (interval mean: x 0.37)
  // and folded to 50 - 35 = 15 Hz, where the search over [10, 25] Hz finds it. Any line found there cuts
  // at >= 5 Hz, i.e. at wavelengths <= 1.2 mm/s / (5 Hz d) = 0.08 d: the search stays [0.1, 2] d.
  const SpectrumResult r = ringing_run(kV, kStep / kV);
  EXPECT_NEAR(r.ringing.nyquist, 25.0, 1e-9);
  EXPECT_TRUE(r.ringing.peak.significant);
  EXPECT_NEAR(r.ringing.peak.frequency, 2.0 * r.ringing.nyquist - kRingHz, kRingTolHz);
  EXPECT_EQ(r.min_period_d, SpectrumConfig{}.min_period_d);
  EXPECT_TRUE(r.second_part.peak.significant);
  EXPECT_NEAR(r.second_part.peak.period, 0.5, kPeriodTolD);
}

TEST(SpectrumRinging, FoundAt35HzAndKeptOutOfTheGeometricSearchAtEverySpeed) {
  for (const double v : {0.0012, 0.012}) {  // rows every 2 ms: Nyquist 250 Hz
    SCOPED_TRACE("V = " + std::to_string(1e3 * v) + " mm/s");
    const SpectrumResult r = ringing_run(v, 0.002);
    ASSERT_TRUE(r.ringing.searched);
    EXPECT_TRUE(r.ringing.peak.significant);
    EXPECT_NEAR(r.ringing.peak.frequency, kRingHz, kRingTolHz);
    EXPECT_NEAR(r.geometric_cutoff, 0.5 * r.ringing.peak.frequency, 1e-12);
    // the search starts where V / wavelength = the cutoff (at 1.2 mm/s that is 0.023 d: 0.1 d stays)
    EXPECT_NEAR(r.min_period_d, std::max(0.1, v / (r.geometric_cutoff * kD)), 1e-12);
    EXPECT_TRUE(r.second_part.peak.significant);
    EXPECT_NEAR(r.second_part.peak.period, 0.5, kPeriodTolD);
  }
}

TEST(SpectrumRinging, TheOldSearchTakesTheRingingForTheDominantPeriodAt12mmPerS) {
  // What the stage did before: the dominant peak over the configured 0.1-2 d alone. At 12 mm/s the
  // ringing's wavelength V / f = 0.114 d lies in that range and stands highest.
  const double v = 0.012;
  const SpectrumResult r = ringing_run(v, 0.002);
  const SpectrumConfig c;
  const DominantPeak old = dominant_peak(r.second_part.psd, 1.0 / c.max_period_d, 1.0 / c.min_period_d, c.false_alarm);
  EXPECT_TRUE(old.significant);
  EXPECT_NEAR(old.period, v / (kRingHz * kD), v / (kRingHz * kD) * kRingTolHz / kRingHz) << "the ringing";
  EXPECT_NEAR(r.second_part.peak.period, 0.5, kPeriodTolD) << "the slips, once the ringing is kept out";
}

TEST(SpectrumRinging, At30mmPerSDOverTwoIsBeyondTheCutoffAndNoPeriodIsClaimed) {
  // d/2 at 30 mm/s is 20 Hz, above f_ring / 2 = 17.5 Hz: the search starts at ~0.57 d and can find
  // neither d/2 nor the ringing (0.29 d); the stage then reports no significant period rather than the
  // ringing's. (A wider cutoff would not help here: this ringing's flank at 20 Hz, ~1 % of its peak power
  // density, is above the slips' line.)
  const double v = 0.030;
  const SpectrumResult r = ringing_run(v, kD / 125.0 / v);  // rows every d/125 of travel (0.8 ms)
  EXPECT_NEAR(r.ringing.peak.frequency, kRingHz, kRingTolHz);
  EXPECT_NEAR(r.min_period_d, v / (0.5 * r.ringing.peak.frequency * kD), 1e-12);
  EXPECT_GT(r.min_period_d, 0.5);
  EXPECT_GE(r.second_part.peak.period, r.min_period_d);
  EXPECT_FALSE(r.second_part.peak.significant);
}

TEST(SpectrumRinging, TheMetricsAndTheSensitivityTableReportTheRingingAndTheSearchRange) {
  const double v = 0.012;
  const SpectrumResult r = ringing_run(v, 0.002);
  const SpectrumConfig& c = kNoResampling;
  const auto m = spectrum_metrics(r, kScales, c, 0.049);
  EXPECT_NEAR(m["ringing_frequency_hz"].get<double>(), kRingHz, kRingTolHz);
  EXPECT_TRUE(m["ringing_significant"].get<bool>());
  EXPECT_NEAR(m["ringing_period_d_at_run_speed"].get<double>(), v / (r.ringing.peak.frequency * kD), 1e-9);
  EXPECT_EQ(m["dominant_period_search_range_d"][0].get<double>(), r.min_period_d);
  EXPECT_NEAR(m["dominant_period_search_max_frequency_hz_at_run_v"].get<double>(), r.geometric_cutoff, 1e-9);
  EXPECT_GT(m["ringing"]["line_rms_N_per_m"].get<double>(), 0.0);
  const auto t = sensitivity_table(pulled(Slips(0.5 * kD, 0.2, v, kRingHz, 25.0, 7), v, 0.002, 0.2, 1, 0.110, 8),
                                   kScales, c, "synthetic");
  ASSERT_EQ(t["ringing_cutoff_fraction"].size(), c.ringing_cutoff_fractions.size());
  for (const auto& row : t["ringing_cutoff_fraction"])
    EXPECT_NEAR(row["dominant_period_search_min_d"].get<double>(),
                v / (row["value"].get<double>() * r.ringing.peak.frequency * kD), 1e-9);
}

void expect_error(const DragProfile& p, const std::string& what) {
  try {
    analyse(p, kScales, {}, "in.h5");
    ADD_FAILURE() << "no error, expected: " << what;
  } catch (const SpectrumError& e) {
    EXPECT_NE(std::string(e.what()).find("in.h5: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(Spectrum, BadProfilesAreClearErrors) {
  expect_error({}, "the drag profile is empty");
  DragProfile p = synthetic(sawtooth(0.0015, 10.0), 0.2);
  auto first_rows = [&p](std::size_t n) {
    DragProfile s = p;
    for (auto* c : {&s.time, &s.height, &s.drag}) c->resize(n);
    return s;
  };
  expect_error(first_rows(5), "too short: 5 rows");
  expect_error(first_rows(p.time.size() / 10), "too short");  // 16 mm: the loading/rupture part holds 0.5 mm
  DragProfile nan = p;
  nan.drag[100] = std::nan("");
  expect_error(nan, "row 100 is not finite");
  DragProfile back = p;
  std::swap(back.height[200], back.height[201]);
  expect_error(back, "does not increase at row 201");
  DragProfile jump = p;
  for (std::size_t k = 300; k < jump.height.size(); ++k) jump.height[k] += 0.5 * kStep;
  expect_error(jump, "not uniform in height");
}

TEST(Spectrum, AShorterLastRowIsDropped) {
  DragProfile p = synthetic(sawtooth(0.0015, 10.0), 0.2);
  p.height.back() = p.height[p.height.size() - 2] + 0.4 * kStep;
  p.time.back() = p.time[p.time.size() - 2] + 0.4 * kStep / kV;
  const SpectrumResult r = analyse(p, kScales, kNoPower, "synthetic");
  EXPECT_EQ(r.rows_dropped, 1u);
  EXPECT_EQ(r.profile.height.size(), p.height.size() - 1);
}

TEST(SpectrumConfigFile, TheShippedConfigHoldsTheDefaults) {
  const SpectrumConfig c = load_spectrum_config(DEM2D_DATA_DIR "/spectrum.toml"), d;
  EXPECT_EQ(c.trend_window_d, d.trend_window_d);
  EXPECT_EQ(c.segment_d, d.segment_d);
  EXPECT_EQ(c.drop_threshold, d.drop_threshold);
  EXPECT_EQ(c.floor_factor, d.floor_factor);
  EXPECT_EQ(c.upper_top, d.upper_top);
  EXPECT_EQ(c.window, d.window);
  EXPECT_EQ(c.drop_thresholds, d.drop_thresholds);
  EXPECT_EQ(c.ringing_min_frequency_hz, d.ringing_min_frequency_hz);
  EXPECT_EQ(c.ringing_segment_s, d.ringing_segment_s);
  EXPECT_EQ(c.ringing_cutoff_fraction, d.ringing_cutoff_fraction);
  EXPECT_EQ(c.ringing_cutoff_fractions, d.ringing_cutoff_fractions);
  EXPECT_EQ(c.min_relative_drop, d.min_relative_drop);
  EXPECT_EQ(c.size_min_tail, d.size_min_tail);
  EXPECT_EQ(c.size_bootstrap, d.size_bootstrap);
  EXPECT_EQ(c.size_significance, d.size_significance);
  EXPECT_EQ(c.block_d, d.block_d);
  EXPECT_EQ(c.search_from_fraction, d.search_from_fraction);
  EXPECT_EQ(c.search_margin_d, d.search_margin_d);
  EXPECT_EQ(c.top_bootstrap, d.top_bootstrap);
  EXPECT_EQ(c.top_false_alarm, d.top_false_alarm);
  EXPECT_EQ(c.top_confidence, d.top_confidence);
  EXPECT_EQ(c.min_relative_drops, d.min_relative_drops);
  EXPECT_EQ(c.blocks_d, d.blocks_d);
  EXPECT_EQ(c.search_from_fractions, d.search_from_fractions);
}

TEST(SpectrumConfigFile, UnknownKeysAndBadValuesNameFileKeyAndValue) {
  const test::TempDir dir;
  auto error = [&](const std::string& text) {
    const std::string path = dir.file("c.toml", text);
    try {
      load_spectrum_config(path);
    } catch (const SpectrumError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("[events]\ndrop_treshold = 4\n").find("c.toml:2:1: unknown key 'drop_treshold' in [events] (allowed: drop_threshold, drop_window_d, confirm_samples, confirm_fraction); did you "
                                                          "mean 'drop_threshold'?"),
            std::string::npos);
  EXPECT_NE(error("[psd]\noverlap = 1.5\n").find("c.toml:2:11: psd.overlap = 1.5: must be in [0, 1)"),
            std::string::npos);
  const auto expect_parts = [&](const std::string& text, std::initializer_list<const char*> parts) {
    const std::string msg = error(text);
    for (const char* part : parts) EXPECT_NE(msg.find(part), std::string::npos) << msg;
  };
  expect_parts("[psd]\nwindow = \"kaiser\"\n", {"c.toml:2:10: psd.window = ", "kaiser"});
  EXPECT_NE(error("[colour]\nx = 1\n").find("unknown key 'colour' at the top level"), std::string::npos);
  EXPECT_NE(error("[bands]\nmiddle_top = 0.8\n").find("bottom_top < middle_top < upper_top"), std::string::npos);
  EXPECT_NE(error("[sensitivity]\nfloor_factors = [1, -2]\n").find("sensitivity.floor_factors[1] = -2"),
            std::string::npos);
  EXPECT_NE(error("[ringing]\ncutoff_fraction = 1.5\n")
                .find("c.toml:2:19: ringing.cutoff_fraction = 1.5: must be in (0, 1) (fraction of the ringing frequency)"),
            std::string::npos);
  EXPECT_NE(error("[ringing]\nmin_frequency_hz = 0\n").find("ringing.min_frequency_hz = 0: must be in (0, 1e+09] (Hz)"),
            std::string::npos);
  expect_parts("[ringing]\nsegment_s = \"1 s\"\n", {"c.toml:2:13: ringing.segment_s = ", "wrong type, expected a number"});
  EXPECT_EQ(load_spectrum_config(dir.file("ok.toml", "[events]\ndrop_threshold = 4\n")).drop_threshold, 4.0);
}

TEST(SpectrumStage, QuickRunGivesTheOutputsAndTheEventsContract) {
  const std::string run = test::quick_study_run("pulloff");
  ASSERT_TRUE(std::filesystem::exists(run)) << test::quick_study_missing(run);
  const test::TempDir dir;
  const SpectrumInputs in{run, DEM2D_DATA_DIR "/spectrum.toml", DEM2D_DATA_DIR "/study.toml", ""};
  const SpectrumStage st = compute_spectrum_stage(in, load_spectrum_config(in.config), load_study(in.study));
  const std::string out = dir.sub("out").string();
  write_spectrum_outputs(out, st);
  ASSERT_TRUE(std::filesystem::exists(out + "/metrics.json"));
  ASSERT_FALSE(std::filesystem::exists(out + "/spectrum.h5.tmp"));
  const auto& m = st.metrics.at("spectrum");
  for (const char* key : {"bottom_peak_height_mm", "amplitude_slope_upper", "amplitude_fit_r2_upper",
                          "rupture_spacing_d", "rupture_frequency_hz_at_1p2mm_s", "top_layer_height_mm",
                          "top_layer_depth_fit_r2", "ringing_frequency_hz", "ringing_significant",
                          "ringing_period_d_at_run_speed", "dominant_period_search_range_d", "ringing", "sensitivity"})
    EXPECT_TRUE(m.contains(key)) << key;
  EXPECT_EQ(m["sensitivity"]["drop_threshold"].size(), 5u);

  const h5::File f = h5::File::open_read(out + "/spectrum.h5");
  const hsize_t rows = h5::shape(f, "profile/height")[0];
  for (const char* name : {"time", "drag", "trend", "fluctuation", "envelope"})
    EXPECT_EQ(h5::shape(f, std::string("profile/") + name)[0], rows) << name;
  const std::size_t events = st.result.events.size();
  EXPECT_GT(events, 0u);
  for (const char* name :
       {"load_start_time", "peak_time", "peak_height", "peak_drag", "drop_end_time", "drop", "duration"})
    EXPECT_EQ(h5::shape(f, std::string("events/") + name), std::vector<hsize_t>{events}) << name;
  const auto start = h5::read<double>(f, "events/load_start_time"), peak = h5::read<double>(f, "events/peak_time"),
             end = h5::read<double>(f, "events/drop_end_time"), drop = h5::read<double>(f, "events/drop");
  for (std::size_t e = 0; e < events; ++e) {
    EXPECT_LT(start[e], peak[e]);
    EXPECT_LT(peak[e], end[e]);
    EXPECT_GT(drop[e], 0.0);
    if (e > 0) {
      EXPECT_LE(end[e - 1], start[e]);
    }
  }
  for (const char* name : {"psd/wavelength_d", "psd/frequency_hz_at_paper_v", "psd/power",
                           "psd/bands/upper/power", "ringing/frequency_hz", "ringing/power", "top_layer/depth",
                           "top_layer/drag", "top_layer/fit_drag"})
    EXPECT_TRUE(h5::exists(f, name)) << name;
}

}  // namespace
}  // namespace dem2d::analysis
