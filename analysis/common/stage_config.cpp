#include "common/stage_config.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>

#include "common/stage_output.hpp"

namespace dem2d::analysis {

namespace {

std::string show(const toml::node& n) {
  std::ostringstream s;
  n.visit([&s](const auto& v) { s << v; });
  return s.str();
}

std::string where(const std::string& path, const toml::source_region& r) {
  return path + ":" + std::to_string(r.begin.line) + ":" + std::to_string(r.begin.column);
}

}  // namespace

StageConfig::StageConfig(std::string path) : path_(std::move(path)) {
  if (!std::filesystem::exists(path_)) throw StageError(path_ + ": no such file");
  try {
    root_ = toml::parse_file(path_);
  } catch (const toml::parse_error& e) {
    throw StageError(where(path_, e.source()) + ": cannot read the config: " + std::string(e.description()));
  }
}

void StageConfig::fail(const toml::node& n, std::string_view key, const std::string& what) const {
  throw StageError(where(path_, n.source()) + ": " + std::string(key) + " = " + show(n) + ": " + what);
}

const toml::node* StageConfig::take(std::string_view key) {
  known_.emplace_back(key);
  return root_.get(key);
}

void StageConfig::number(std::string_view key, double& out, double min, double max, std::string_view meaning) {
  std::optional<double> v;
  number(key, v, min, max, meaning);
  if (v) out = *v;
}

void StageConfig::number(std::string_view key, std::optional<double>& out, double min, double max,
                         std::string_view meaning) {
  const toml::node* n = take(key);
  if (!n) return;
  const std::optional<double> v = n->value<double>();
  if (!n->is_number() || !v || !std::isfinite(*v)) fail(*n, key, "wrong type, expected a number (" + std::string(meaning) + ")");
  if (*v < min || *v > max)
    fail(*n, key, "must be in [" + format_number(min) + ", " + format_number(max) + "] (" + std::string(meaning) + ")");
  out = *v;
}

void StageConfig::integer(std::string_view key, std::int64_t& out, std::int64_t min, std::int64_t max,
                          std::string_view meaning) {
  const toml::node* n = take(key);
  if (!n) return;
  if (!n->is_integer()) fail(*n, key, "wrong type, expected an integer (" + std::string(meaning) + ")");
  const std::int64_t v = n->as_integer()->get();
  if (v < min || v > max)
    fail(*n, key, "must be in [" + std::to_string(min) + ", " + std::to_string(max) + "] (" + std::string(meaning) + ")");
  out = v;
}

void StageConfig::numbers(std::string_view key, std::vector<double>& out, double min, double max,
                          std::string_view meaning) {
  const toml::node* n = take(key);
  if (!n) return;
  const toml::array* a = n->as_array();
  if (!a || a->empty()) fail(*n, key, "wrong type, expected a non-empty array of numbers (" + std::string(meaning) + ")");
  std::vector<double> v;
  for (const toml::node& e : *a) {
    const std::optional<double> x = e.value<double>();
    if (!e.is_number() || !x || !std::isfinite(*x) || *x < min || *x > max)
      fail(*n, key, "every element must be a number in [" + format_number(min) + ", " + format_number(max) + "] (" + std::string(meaning) + ")");
    v.push_back(*x);
  }
  out = std::move(v);
}

void StageConfig::text(std::string_view key, std::string& out, std::string_view meaning) {
  const toml::node* n = take(key);
  if (!n) return;
  const auto* s = n->as_string();
  if (!s || s->get().empty()) fail(*n, key, "wrong type, expected a non-empty string (" + std::string(meaning) + ")");
  out = s->get();
}

void StageConfig::choice(std::string_view key, std::string& out, const std::vector<std::string>& allowed,
                         std::string_view meaning) {
  const toml::node* n = take(key);
  if (!n) return;
  std::string list;
  for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + ("\"" + a + "\"");
  const auto* s = n->as_string();
  if (!s) fail(*n, key, "wrong type, expected one of " + list + " (" + std::string(meaning) + ")");
  for (const std::string& a : allowed)
    if (s->get() == a) {
      out = a;
      return;
    }
  fail(*n, key, "must be one of " + list + " (" + std::string(meaning) + ")");
}

void StageConfig::reject_unknown() const {
  std::string list;
  for (const std::string& k : known_) list += (list.empty() ? "" : ", ") + k;
  for (const auto& [key, node] : root_) {
    bool ok = false;
    for (const std::string& k : known_) ok = ok || key.str() == k;
    if (!ok)
      throw StageError(where(path_, key.source()) + ": unknown key '" + std::string(key.str()) + "' = " + show(node) +
                       " (allowed: " + list + ")");
  }
}

}  // namespace dem2d::analysis
