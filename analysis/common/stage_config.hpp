// Reading a stage's settings file (data/<stage>.toml, data/study.toml) through
// the one validating TOML reader (sim/toml/toml_reader.hpp): each key read with
// its type and range as it is asked for, then every key the stage did not ask
// for is an error listing the allowed ones. Sub-tables ([grid], [cone], ...)
// read the same way. Every error is a StageError "FILE:LINE:COL: key = value:
// what is wrong (meaning)" or "FILE: no such file".
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/stage_error.hpp"
#include "toml/toml_reader.hpp"

namespace dem2d::analysis {

// A stage's settings file: its errors are StageErrors.
struct StageFile : TomlFile {
  using TomlFile::TomlFile;

 protected:
  void raise(const std::string& message) const override { throw StageError(message); }
};

class StageConfig {
 public:
  // Ends of a range: closed unless said open.
  enum class Ends { closed, open_low, open_high, open };

  explicit StageConfig(const std::string& path);
  const std::string& path() const { return file_->path; }

  // Each reader leaves `out` unchanged when the key is absent; values must be
  // finite and within [min, max] (ends as given).
  void number(std::string_view key, double& out, double min, double max, std::string_view meaning,
              Ends ends = Ends::closed);
  void number(std::string_view key, std::optional<double>& out, double min, double max, std::string_view meaning,
              Ends ends = Ends::closed);
  void integer(std::string_view key, std::int64_t& out, std::int64_t min, std::int64_t max, std::string_view meaning);
  void integer(std::string_view key, int& out, int min, int max, std::string_view meaning);
  void numbers(std::string_view key, std::vector<double>& out, double min, double max, std::string_view meaning,
               Ends ends = Ends::closed);
  void text(std::string_view key, std::string& out, std::string_view meaning);
  void choice(std::string_view key, std::string& out, const std::vector<std::string>& allowed,
              std::string_view meaning);
  // Whether the key is present (and, from then on, known).
  bool has(std::string_view key) { return take(key) != nullptr; }
  // The sub-table [key] (empty if absent; from then on known): read it, then
  // call its reject_unknown().
  StageConfig table(std::string_view key);
  // The tables of the array [[key]] (none if absent; from then on known), named key[k].
  std::vector<StageConfig> entries(std::string_view key);
  // After the reads: a key that was not asked for is an error listing the allowed keys.
  void reject_unknown() const;
  // "FILE:LINE:COL" of key (the file alone if absent), for checks across keys.
  std::string where(std::string_view key) const;

 private:
  StageConfig(std::shared_ptr<const StageFile> file, std::shared_ptr<const toml::table> root, const toml::table* table,
              std::string name)
      : file_(std::move(file)), root_(std::move(root)), table_(table), name_(std::move(name)) {}
  const toml::node* take(std::string_view key);
  TableReader reader() const;  // reads any key of the table (the unknown ones are rejected at the end)

  std::shared_ptr<const StageFile> file_;
  std::shared_ptr<const toml::table> root_;  // keeps the parsed file alive for sub-tables
  const toml::table* table_ = nullptr;       // this table (nullptr: absent)
  std::string name_;                         // its dotted name, "" at the top
  std::vector<std::string> known_;
};

}  // namespace dem2d::analysis
