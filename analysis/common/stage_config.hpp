// Reading a stage's settings file (data/network.toml, data/friction.toml):
// flat TOML keys, each read with its type and range; keys the stage did not
// ask for are errors. Every error is a StageError "FILE:LINE:COL: key = value:
// what is wrong (meaning)" or "FILE: no such file".
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "common/pulloff_frame.hpp"

namespace dem2d::analysis {

class StageConfig {
 public:
  explicit StageConfig(std::string path);
  // One table of a file (e.g. an element of an array of tables); errors name `path`.
  StageConfig(std::string path, toml::table table) : path_(std::move(path)), root_(std::move(table)) {}
  const std::string& path() const { return path_; }

  // Each reader leaves `out` unchanged when the key is absent.
  void number(std::string_view key, double& out, double min, double max, std::string_view meaning);
  void number(std::string_view key, std::optional<double>& out, double min, double max, std::string_view meaning);
  void integer(std::string_view key, std::int64_t& out, std::int64_t min, std::int64_t max, std::string_view meaning);
  void numbers(std::string_view key, std::vector<double>& out, double min, double max, std::string_view meaning);
  void text(std::string_view key, std::string& out, std::string_view meaning);
  void choice(std::string_view key, std::string& out, const std::vector<std::string>& allowed,
              std::string_view meaning);
  // Whether the key is present (and, from then on, known).
  bool has(std::string_view key) { return take(key) != nullptr; }
  // After the reads: a key that was not asked for is an error listing the allowed keys.
  void reject_unknown() const;

 private:
  [[noreturn]] void fail(const toml::node& n, std::string_view key, const std::string& what) const;
  const toml::node* take(std::string_view key);

  std::string path_;
  toml::table root_;
  std::vector<std::string> known_;
};

}  // namespace dem2d::analysis
