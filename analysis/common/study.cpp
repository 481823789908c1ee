#include "common/study.hpp"

#include <toml++/toml.h>

#include <stdexcept>

namespace dem2d::analysis {

namespace {

// Every key of `table` must be in `keys`.
void only(const toml::table& table, std::initializer_list<std::string_view> keys, const std::string& where,
          const std::string& path) {
  for (auto&& [key, value] : table) {
    bool known = false;
    for (const auto k : keys) known = known || key.str() == k;
    if (!known) throw std::runtime_error(path + ": unknown key " + where + "." + std::string(key.str()));
  }
}

double positive(const toml::table& t, std::string_view key, double fallback, const std::string& path) {
  const toml::node* n = t.get(key);
  if (!n) return fallback;
  const auto v = n->value<double>();
  if (!v || !(*v > 0.0))
    throw std::runtime_error(path + ": " + std::string(key) + " must be a number > 0");
  return *v;
}

}  // namespace

Study load_study(const std::string& path) {
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw std::runtime_error(path + ": " + std::string(e.description()));
  }
  only(root, {"experiment"}, "", path);
  Study s;
  if (const auto* e = root["experiment"].as_table()) {
    only(*e, {"intruder_depth", "cell_width", "intruder_length", "pull_speed", "mean_diameter"}, "experiment", path);
    s.intruder_depth = positive(*e, "intruder_depth", s.intruder_depth, path);
    s.cell_width = positive(*e, "cell_width", s.cell_width, path);
    s.intruder_length = positive(*e, "intruder_length", s.intruder_length, path);
    s.pull_speed = positive(*e, "pull_speed", s.pull_speed, path);
    s.mean_diameter = positive(*e, "mean_diameter", s.mean_diameter, path);
  }
  return s;
}

}  // namespace dem2d::analysis
