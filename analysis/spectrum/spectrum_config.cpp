#include "spectrum/spectrum_config.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <sstream>

namespace dem2d::analysis {

namespace {

[[noreturn]] void fail(const std::string& path, const toml::source_region& where, const std::string& what) {
  throw SpectrumError(path + ":" + std::to_string(where.begin.line) + ":" + std::to_string(where.begin.column) +
                      ": " + what);
}

std::string show(const toml::node& n) {
  std::ostringstream s;
  n.visit([&s](const auto& v) { s << v; });
  return s.str();
}

// A number in [lo, hi] (open at an end if the flag says so).
struct Range {
  double lo, hi;
  bool lo_open, hi_open;
  const char* unit;
  bool contains(double v) const {
    return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  std::string text() const {
    std::ostringstream s;
    s << "must be in " << (lo_open ? "(" : "[") << lo << ", " << hi << (hi_open ? ")" : "]") << " (" << unit << ")";
    return s.str();
  }
};

constexpr double kInf = HUGE_VAL;
const Range kPositiveD{0.0, kInf, true, true, "d of travel"};
const Range kFraction{0.0, 1.0, true, false, "fraction of the bed height"};
const Range kFactor{0.0, kInf, true, true, "multiple of the noise level"};
const Range kCutoff{0.0, 1.0, true, true, "fraction of the ringing frequency"};

double read_number(const std::string& path, const std::string& key, const toml::node& n, const Range& r) {
  const std::optional<double> v = n.value<double>();
  if (!n.is_number() || !v) fail(path, n.source(), key + " = " + show(n) + ": wrong type, expected a number");
  if (!r.contains(*v)) fail(path, n.source(), key + " = " + show(n) + ": " + r.text());
  return *v;
}

std::vector<double> read_list(const std::string& path, const std::string& key, const toml::node& n, const Range& r) {
  const toml::array* a = n.as_array();
  if (!a || a->empty()) fail(path, n.source(), key + " = " + show(n) + ": expected a non-empty array of numbers");
  std::vector<double> out;
  for (const toml::node& e : *a) out.push_back(read_number(path, key + "[]", e, r));
  return out;
}

}  // namespace

SpectrumConfig load_spectrum_config(const std::string& path) {
  if (!std::filesystem::exists(path)) throw SpectrumError(path + ": no such file");
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    fail(path, e.source(), "cannot read the config: " + std::string(e.description()));
  }
  SpectrumConfig c;
  using Reader = std::function<void(const std::string&, const toml::node&)>;
  auto number = [&](double& out, Range r) -> Reader {
    return [&out, r, &path](const std::string& k, const toml::node& n) { out = read_number(path, k, n, r); };
  };
  auto list = [&](std::vector<double>& out, Range r) -> Reader {
    return [&out, r, &path](const std::string& k, const toml::node& n) { out = read_list(path, k, n, r); };
  };
  const std::map<std::string, std::map<std::string, Reader>> schema{
      {"profile",
       {{"uniform_tolerance", number(c.uniform_tolerance, {0.0, 0.5, true, false, "relative deviation"})},
        {"trend_window_d", number(c.trend_window_d, kPositiveD)}}},
      {"psd",
       {{"segment_d", number(c.segment_d, kPositiveD)},
        {"overlap", number(c.overlap, {0.0, 1.0, false, true, "fraction of a segment"})},
        {"window",
         [&](const std::string& k, const toml::node& n) {
           const auto v = n.value<std::string>();
           if (!v || (*v != "hann" && *v != "hamming" && *v != "blackman" && *v != "rectangular"))
             fail(path, n.source(), k + " = " + show(n) + ": must be \"hann\", \"hamming\", \"blackman\" or \"rectangular\"");
           c.window = *v;
         }},
        {"min_period_d", number(c.min_period_d, kPositiveD)},
        {"max_period_d", number(c.max_period_d, kPositiveD)},
        {"false_alarm", number(c.false_alarm, {0.0, 1.0, true, true, "probability"})}}},
      {"ringing",
       {{"min_frequency_hz", number(c.ringing_min_frequency_hz, {0.0, kInf, true, true, "Hz"})},
        {"segment_s", number(c.ringing_segment_s, {0.0, kInf, true, true, "s"})},
        {"cutoff_fraction", number(c.ringing_cutoff_fraction, kCutoff)}}},
      {"events",
       {{"drop_threshold", number(c.drop_threshold, kFactor)}, {"drop_window_d", number(c.drop_window_d, kPositiveD)}}},
      {"top_layer",
       {{"envelope_window_d", number(c.envelope_window_d, kPositiveD)},
        {"floor_factor", number(c.floor_factor, kFactor)},
        {"fit_margin_d", number(c.fit_margin_d, {0.0, kInf, false, true, "d of travel"})}}},
      {"bands",
       {{"bottom_top", number(c.bottom_top, kFraction)},
        {"middle_top", number(c.middle_top, kFraction)},
        {"upper_top", number(c.upper_top, kFraction)}}},
      {"bottom", {{"collapse_fraction", number(c.collapse_fraction, {0.0, 1.0, true, true, "fraction of the peak"})}}},
      {"sensitivity",
       {{"drop_thresholds", list(c.drop_thresholds, kFactor)},
        {"floor_factors", list(c.floor_factors, kFactor)},
        {"trend_windows_d", list(c.trend_windows_d, kPositiveD)},
        {"ringing_cutoff_fractions", list(c.ringing_cutoff_fractions, kCutoff)}}},
  };
  auto names = [](const auto& m) {
    std::string s;
    for (const auto& [k, v] : m) s += (s.empty() ? "" : ", ") + k;
    return s;
  };
  for (const auto& [section_key, section] : root) {
    const std::string s(section_key.str());
    const auto it = schema.find(s);
    if (it == schema.end())
      fail(path, section_key.source(), "unknown section [" + s + "] (allowed: " + names(schema) + ")");
    if (!section.is_table()) fail(path, section.source(), s + " = " + show(section) + ": expected a table [" + s + "]");
    for (const auto& [key, node] : *section.as_table()) {
      const std::string k(key.str());
      const auto r = it->second.find(k);
      if (r == it->second.end())
        fail(path, key.source(),
             "unknown key '" + s + "." + k + "' = " + show(node) + " (allowed in [" + s + "]: " + names(it->second) + ")");
      r->second(s + "." + k, node);
    }
  }
  check_spectrum_config(c, path);
  return c;
}

void check_spectrum_config(const SpectrumConfig& c, const std::string& source) {
  auto require = [&source](bool ok, const std::string& what) {
    if (!ok) throw SpectrumError(source + ": " + what);
  };
  require(c.bottom_top < c.middle_top && c.middle_top < c.upper_top,
          "bands: need bottom_top < middle_top < upper_top (fractions of the bed height)");
  require(c.min_period_d < c.max_period_d, "psd: need min_period_d < max_period_d");
  require(c.max_period_d < c.segment_d, "psd: need max_period_d < segment_d (a segment must hold the longest period)");
}

}  // namespace dem2d::analysis
