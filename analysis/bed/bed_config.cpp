#include "bed/bed_config.hpp"

#include <toml++/toml.h>

#include <filesystem>
#include <sstream>

namespace dem2d::analysis {

namespace {

[[noreturn]] void fail(const std::string& path, const toml::source_region& where, const std::string& what) {
  throw BedError(path + ":" + std::to_string(where.begin.line) + ":" + std::to_string(where.begin.column) + ": " +
                 what);
}

std::string show(const toml::node& n) {
  std::ostringstream s;
  n.visit([&s](const auto& v) { s << v; });
  return s.str();
}

void read_number(const std::string& path, const std::string& key, const toml::node& n, double min, bool inclusive,
                 const char* what, double& out) {
  const std::optional<double> v = n.value<double>();
  if (!n.is_number() || !v) fail(path, n.source(), key + " = " + show(n) + ": wrong type, expected a number");
  if (*v < min || (!inclusive && *v == min))
    fail(path, n.source(), key + " = " + show(n) + ": must be " + (inclusive ? ">= " : "> ") +
                               std::to_string(static_cast<int>(min)) + " (" + what + ")");
  out = *v;
}

}  // namespace

BedConfig load_bed_config(const std::string& path) {
  if (!std::filesystem::exists(path)) throw BedError(path + ": no such file");
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    fail(path, e.source(), "cannot read the config: " + std::string(e.description()));
  }
  BedConfig c;
  for (const auto& [key, node] : root) {
    const std::string k(key.str());
    if (k == "margin_d") {
      read_number(path, k, node, 0.0, true, "mean diameters", c.margin_d);
    } else if (k == "sampling_per_d") {
      read_number(path, k, node, 1.0, true, "sample points per mean diameter", c.sampling_per_d);
    } else if (k == "column_width_d") {
      read_number(path, k, node, 0.0, false, "mean diameters", c.column_width_d);
    } else {
      fail(path, key.source(),
           "unknown key '" + k + "' (allowed: margin_d, sampling_per_d, column_width_d)");
    }
  }
  return c;
}

}  // namespace dem2d::analysis
