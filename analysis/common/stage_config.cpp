#include "common/stage_config.hpp"

#include "common/stage_output.hpp"  // format_number

namespace dem2d::analysis {

namespace {

Num range(std::string_view meaning, double min, double max, StageConfig::Ends ends, std::string& storage) {
  storage = std::string(meaning);
  using E = StageConfig::Ends;
  return {storage.c_str(), "", Rule::interval, min, max, ends == E::open_low || ends == E::open,
          ends == E::open_high || ends == E::open};
}

}  // namespace

StageConfig::StageConfig(const std::string& path) {
  auto file = std::make_shared<const StageFile>(path);
  auto root = std::make_shared<const toml::table>(file->parse_file());
  table_ = root.get();
  file_ = std::move(file);
  root_ = std::move(root);
}

const toml::node* StageConfig::take(std::string_view key) {
  known_.emplace_back(key);
  return table_ ? table_->get(key) : nullptr;
}

TableReader StageConfig::reader() const {
  std::vector<std::string_view> all;
  if (table_)
    for (auto&& [key, value] : *table_) all.push_back(key.str());
  static const toml::table empty;
  return TableReader(*file_, table_ ? table_ : &empty, name_, all);
}

void StageConfig::number(std::string_view key, double& out, double min, double max, std::string_view meaning,
                         Ends ends) {
  std::optional<double> v;
  number(key, v, min, max, meaning, ends);
  if (v) out = *v;
}

void StageConfig::number(std::string_view key, std::optional<double>& out, double min, double max,
                         std::string_view meaning, Ends ends) {
  if (!take(key)) return;
  std::string text;
  out = *reader().number(key, range(meaning, min, max, ends, text));
}

void StageConfig::integer(std::string_view key, std::int64_t& out, std::int64_t min, std::int64_t max,
                          std::string_view meaning) {
  if (!take(key)) return;
  const std::string what(meaning);
  out = reader().integer(key, min, what.c_str(), max);
}

void StageConfig::integer(std::string_view key, int& out, int min, int max, std::string_view meaning) {
  std::int64_t v = out;
  integer(key, v, min, max, meaning);
  out = static_cast<int>(v);
}

void StageConfig::numbers(std::string_view key, std::vector<double>& out, double min, double max,
                          std::string_view meaning, Ends ends) {
  if (!take(key)) return;
  std::string text;
  std::vector<double> v = *reader().numbers(key, range(meaning, min, max, ends, text));
  // Each value is one row of a table or one band edge: a repeat means nothing
  // (and two rows of one name cannot both be written).
  constexpr std::size_t kMaxValues = 100;
  if (v.size() > kMaxValues)
    reader().fail(key, "has " + std::to_string(v.size()) + " values, at most " + std::to_string(kMaxValues));
  for (std::size_t i = 0; i < v.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (v[i] == v[j]) reader().fail(key, "lists " + format_number(v[i]) + " twice: each value once");
  out = std::move(v);
}

void StageConfig::text(std::string_view key, std::string& out, std::string_view meaning) {
  if (!take(key)) return;
  const TableReader r = reader();
  if (!r.node(key)->is_string()) r.fail(key, "wrong type, expected a string (" + std::string(meaning) + ")");
  out = *r.string(key);
}

void StageConfig::choice(std::string_view key, std::string& out, const std::vector<std::string>& allowed,
                         std::string_view meaning) {
  if (!take(key)) return;
  const std::vector<std::string_view> names(allowed.begin(), allowed.end());
  const std::string what(meaning);
  out = *reader().choice(key, names, what.c_str());
}

StageConfig StageConfig::table(std::string_view key) {
  const toml::node* n = take(key);
  if (n && !n->is_table()) reader().fail(key, "wrong type, expected a table [" + std::string(key) + "]");
  return StageConfig(file_, root_, n ? n->as_table() : nullptr, name_.empty() ? std::string(key) : name_ + "." + std::string(key));
}

std::vector<StageConfig> StageConfig::entries(std::string_view key) {
  std::vector<StageConfig> out;
  const toml::node* n = take(key);
  if (!n) return out;
  const toml::array* a = n->as_array();
  if (!a || !a->is_array_of_tables())
    reader().fail(key, "wrong type, expected an array of tables [[" + std::string(key) + "]]");
  for (std::size_t k = 0; k < a->size(); ++k)
    out.push_back(StageConfig(file_, root_, a->get(k)->as_table(),
                              (name_.empty() ? "" : name_ + ".") + std::string(key) + "[" + std::to_string(k) + "]"));
  return out;
}

void StageConfig::reject_unknown() const {
  if (!table_) return;
  const std::vector<std::string_view> allowed(known_.begin(), known_.end());
  TableReader(*file_, table_, name_, allowed);  // throws on the first key not in `allowed`
}

std::string StageConfig::where(std::string_view key) const {
  const toml::node* n = table_ ? table_->get(key) : nullptr;
  return file_->at(n ? &n->source() : nullptr);
}

}  // namespace dem2d::analysis
