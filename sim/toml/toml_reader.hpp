// The one validating TOML reader: the engine's scenes (scene/scene_toml.cpp)
// and every analysis stage's settings (data/*.toml, analysis/*/..._config.cpp)
// read their keys through it. A table's unknown keys are errors listing the
// allowed ones; each key is read with its type and range (core/key_spec.hpp);
// every message names the file, line and column, the dotted key
// (`contact.wall.kn`, `body[2].thickness`), the value given and what is allowed.
#pragma once

#include <toml++/toml.h>

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/key_spec.hpp"
#include "core/number_text.hpp"  // shortest

namespace dem2d {

// "; did you mean 'kn'?" for the allowed name nearest a misspelt one (at most
// a third of its letters apart), "" if none is that near.
std::string did_you_mean(std::string_view key, const std::vector<std::string_view>& allowed);
// A name as a message shows it: whole up to 64 characters, else its start and its length.
std::string show_key(std::string_view key);

class TomlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A value as the user wrote it (near enough), shortened if long.
std::string show(const toml::node& n);
// Integers are accepted where a float is expected.
std::optional<double> number_of(const toml::node& n);
std::string join(const std::vector<std::string_view>& keys);  // "a, b, c"

// The file being read: where a node is, and the error it raises (TomlError;
// a reader with its own error type overrides raise(), e.g. the scene's SceneError).
class TomlFile {
 public:
  explicit TomlFile(std::string file_path) : path(std::move(file_path)) {}
  virtual ~TomlFile() = default;
  std::string path;

  // "file:line:column"; the file is the node's own (an overlay's key names the overlay).
  std::string at(const toml::source_region* where) const;
  [[noreturn]] void fail(const toml::source_region* where, const std::string& msg) const { error(at(where) + ": " + msg); }
  [[noreturn]] void fail(const toml::node& n, const std::string& msg) const { fail(&n.source(), msg); }
  // The file's text parsed: "FILE: no such file", "FILE:LINE:COL: TOML syntax error: ...".
  toml::table parse_file() const;
  // The file's text: "FILE: cannot read the <what>: <reason>" if it cannot be read, is neither a
  // regular file nor a pipe (a directory, a device such as /dev/zero), is larger than kMaxBytes, or is
  // a pipe that nothing writes to for kPipeWaitSeconds.
  std::string read(const char* what = "file") const;
  static constexpr std::uintmax_t kMaxBytes = std::uintmax_t{256} << 20;  // bytes: no scene or settings file is near
  // A pipe is read while its writer sends: a wait for its next bytes longer than this (s) is an error.
  static constexpr int kPipeWaitSeconds = 10;
  toml::table parse(std::string_view text) const;

  // Throws the reader's error: raise(message), TomlError if raise returns.
  [[noreturn]] void error(const std::string& message) const {
    raise(message);
    throw TomlError(message);
  }

 protected:
  // Throws a reader's own error type (the scene's SceneError, a stage's StageError).
  virtual void raise(const std::string&) const {}

 private:
  std::string read_pipe(const std::string& cannot) const;
};

// One table of the file: rejects unknown keys on construction, then reads
// typed keys with range checks. Key paths in messages are dotted from the root.
// A reader of an absent table sees every key as missing.
class TableReader {
 public:
  TableReader(const TomlFile& f, const toml::node* node, std::string name, std::vector<std::string_view> allowed);

  const toml::node* node(std::string_view key) const { return table_ ? table_->get(key) : nullptr; }
  bool has(std::string_view key) const { return node(key) != nullptr; }
  std::string path(std::string_view key) const {
    return name_.empty() ? std::string(key) : name_ + "." + std::string(key);
  }
  const toml::source_region* where() const { return table_ ? &table_->source() : nullptr; }

  // "<key> = <value>: <msg>" at the key's value.
  [[noreturn]] void fail(std::string_view key, const std::string& msg) const { fail_after(key, ": " + msg); }
  [[noreturn]] void fail_after(std::string_view key, const std::string& msg) const;
  [[noreturn]] void missing(std::string_view key, const std::string& what) const;
  // A key that only makes sense when `reason` does not hold.
  void forbid(std::string_view key, const std::string& reason) const;

  std::optional<double> number(std::string_view key, const Num& spec) const;
  double number_or(std::string_view key, const Num& spec, double fallback) const {
    return number(key, spec).value_or(fallback);
  }
  double required(std::string_view key, const Num& spec, const std::string& why = "") const;
  // A non-empty array of numbers, each checked against spec.
  std::optional<std::vector<double>> numbers(std::string_view key, const Num& spec) const;
  std::optional<bool> boolean(std::string_view key) const;
  std::optional<std::string> string(std::string_view key) const;
  // One of `allowed`.
  std::optional<std::string> choice(std::string_view key, const std::vector<std::string_view>& allowed,
                                    const char* what) const;
  // An array of non-empty strings.
  std::vector<std::string> strings(std::string_view key, const char* what) const;
  static constexpr std::int64_t kNoMax = std::numeric_limits<std::int64_t>::max();
  std::int64_t integer(std::string_view key, std::int64_t min, const char* what, std::int64_t max = kNoMax) const;
  std::int64_t integer_or(std::string_view key, std::int64_t min, const char* what, std::int64_t fallback,
                          std::int64_t max = kNoMax) const;
  std::int64_t integer_at(const toml::node& n, std::string_view key, std::int64_t min, const char* what,
                          std::int64_t max = kNoMax) const;
  std::optional<std::array<double, 2>> vec2(std::string_view key, const Num& spec) const;
  std::array<double, 2> required_vec2(std::string_view key, const Num& spec, const std::string& why = "") const;
  // The number at n (p: its dotted path), checked against spec.
  double number_at(const toml::node& n, const std::string& p, const Num& spec) const;
  // [x, y] at n, both checked against spec.
  std::array<double, 2> vec2_at(const toml::node& n, const std::string& p, const Num& spec) const;
  TableReader table(std::string_view key, std::vector<std::string_view> allowed) const {
    return TableReader(*f_, node(key), path(key), std::move(allowed));
  }
  // [[key]] entries (an absent key is an empty list).
  std::vector<TableReader> entries(std::string_view key, std::vector<std::string_view> allowed) const;

 private:
  [[noreturn]] void wrong_type(const toml::node& n, const std::string& p, const std::string& expected) const;

  const TomlFile* f_;
  const toml::table* table_ = nullptr;
  std::string name_;
};

}  // namespace dem2d
