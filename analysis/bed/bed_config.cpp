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

void read_name(const std::string& path, const std::string& key, const toml::node& n, std::string& out) {
  if (!n.is_string() || n.as_string()->get().empty())
    fail(path, n.source(), key + " = " + show(n) + ": must be a non-empty string (a body name)");
  out = n.as_string()->get();
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
    } else if (k == "bodies" && node.is_table()) {
      for (const auto& [bkey, bnode] : *node.as_table()) {
        const std::string b(bkey.str());
        std::string* field = b == "left" ? &c.left : b == "right" ? &c.right : b == "floor" ? &c.floor
                           : b == "intruder" ? &c.intruder : nullptr;
        if (!field) fail(path, bkey.source(), "unknown key 'bodies." + b + "' (allowed: left, right, floor, intruder)");
        read_name(path, "bodies." + b, bnode, *field);
      }
    } else if (k == "bodies") {
      fail(path, node.source(), "bodies = " + show(node) + ": wrong type, expected a table");
    } else {
      fail(path, key.source(),
           "unknown key '" + k + "' (allowed: margin_d, sampling_per_d, column_width_d, [bodies])");
    }
  }
  return c;
}

}  // namespace dem2d::analysis
