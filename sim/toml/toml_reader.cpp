#include "toml/toml_reader.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

namespace dem2d {

std::string show(const toml::node& n) {
  std::string s;
  if (const auto* i = n.as_integer())
    s = std::to_string(i->get());
  else if (const auto* x = n.as_floating_point())
    s = shortest(x->get());
  else if (const auto* b = n.as_boolean())
    s = b->get() ? "true" : "false";
  else if (const auto* str = n.as_string())
    s = '"' + str->get() + '"';
  else if (const auto* a = n.as_array()) {
    s = "[";
    for (std::size_t k = 0; k < a->size() && s.size() < 80; ++k)
      s += (k ? ", " : "") + show(*a->get(k));
    s += "]";
  } else if (const auto* t = n.as_table()) {
    s = "{ ";
    for (auto&& [key, v] : *t) {
      if (s.size() > 80) break;
      s += std::string(key.str()) + " = " + show(v) + ", ";
    }
    s = (s.size() > 2 ? s.substr(0, s.size() - 2) : "{") + " }";
  } else {
    std::ostringstream os;  // dates and times
    n.visit([&](auto&& v) { os << v; });
    s = os.str();
  }
  return s.size() > 80 ? s.substr(0, 77) + "..." : s;
}

std::optional<double> number_of(const toml::node& n) {
  if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
  if (const auto* x = n.as_floating_point()) return x->get();
  return std::nullopt;
}

std::string join(const std::vector<std::string_view>& keys) {
  std::string s;
  for (const auto k : keys) s += (s.empty() ? "" : ", ") + std::string(k);
  return s;
}

// ---------------------------------------------------------------- the file

std::string TomlFile::at(const toml::source_region* where) const {
  if (!where || where->begin.line == 0) return path;
  const std::string& file = where->path && !where->path->empty() ? *where->path : path;
  return file + ":" + std::to_string(where->begin.line) + ":" + std::to_string(where->begin.column);
}

toml::table TomlFile::parse(std::string_view text) const {
  try {
    return toml::parse(text, std::string_view(path));
  } catch (const toml::parse_error& e) {
    fail(&e.source(), "TOML syntax error: " + std::string(e.description()));
  }
}

toml::table TomlFile::parse_file() const {
  if (!std::filesystem::exists(path)) error(path + ": no such file");
  return parse(read());
}

std::string TomlFile::read(const char* what) const {
  const std::string cannot = path + ": cannot read the " + what + ": ";
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);  // follows symbolic links
  if (ec) error(cannot + ec.message());
  if (!std::filesystem::is_regular_file(status) && !std::filesystem::is_fifo(status))  // (a pipe: read up to the bound)
    error(cannot + "not a regular file");
  const auto too_large = [&] {
    error(cannot + "larger than " + std::to_string(kMaxBytes >> 20) + " MiB, more than any scene or settings file");
  };
  if (std::filesystem::file_size(path, ec) > kMaxBytes && !ec) too_large();
  std::string text;
  if (std::filesystem::is_fifo(status)) {
    text = read_pipe(cannot);
    if (text.size() > kMaxBytes) too_large();
    return text;
  }
  std::FILE* file = std::fopen(path.c_str(), "rb");
  int err = file ? 0 : errno;
  if (file) {
    char buf[65536];
    std::size_t got;
    while (text.size() <= kMaxBytes && (got = std::fread(buf, 1, sizeof buf, file)) > 0) text.append(buf, got);
    if (std::ferror(file)) err = errno ? errno : EIO;
    std::fclose(file);
  }
  if (err) error(cannot + std::strerror(err));
  if (text.size() > kMaxBytes) too_large();  // (what was read: a file can grow, or report no size)
  return text;
}

// A pipe (a FIFO, the shell's <(...)): what its writer sends, up to one byte
// past the bound, waiting at most kPipeWaitSeconds for each next piece (a
// FIFO nobody opens for writing is refused, not waited on for ever).
std::string TomlFile::read_pipe(const std::string& cannot) const {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);  // (does not wait for a writer)
  if (fd < 0) error(cannot + std::strerror(errno));
  std::string text;
  char buf[65536];
  std::string failure;
  while (text.size() <= kMaxBytes) {
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, kPipeWaitSeconds * 1000);
    if (ready < 0 && errno == EINTR) continue;
    if (ready < 0) {
      failure = std::strerror(errno);
      break;
    }
    if (ready == 0) {
      failure = text.empty() ? "a pipe that nothing wrote to within " + std::to_string(kPipeWaitSeconds) + " s"
                             : "a pipe whose writer stopped for " + std::to_string(kPipeWaitSeconds) + " s before its end";
      break;
    }
    const ssize_t got = ::read(fd, buf, sizeof buf);
    if (got > 0) {
      text.append(buf, static_cast<std::size_t>(got));
    } else if (got == 0) {
      break;  // the writer closed it: the end
    } else if (errno != EAGAIN && errno != EINTR) {
      failure = std::strerror(errno);
      break;
    }
  }
  ::close(fd);
  if (!failure.empty()) error(cannot + failure);
  return text;
}

// ---------------------------------------------------------------- a table

namespace {

// Edits (insert, delete, replace, swap two neighbours) from a to b: "rnu" is one from "run".
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> before(b.size() + 1), prev(b.size() + 1), row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      row[j] = std::min({prev[j] + 1, row[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) row[j] = std::min(row[j], before[j - 2] + 1);
    }
    std::swap(before, prev);
    std::swap(prev, row);
  }
  return prev[b.size()];
}

}  // namespace

std::string did_you_mean(std::string_view key, const std::vector<std::string_view>& allowed) {
  std::string_view best;
  std::size_t best_distance = key.size() / 3 + 1;
  for (const std::string_view a : allowed) {
    const std::size_t d = edit_distance(key, a);
    if (d < best_distance) best = a, best_distance = d;
  }
  return best.empty() ? "" : "; did you mean '" + std::string(best) + "'?";
}

std::string show_key(std::string_view key) {
  if (key.size() <= 64) return std::string(key);
  return std::string(key.substr(0, 40)) + "... (" + std::to_string(key.size()) + " characters)";
}

TableReader::TableReader(const TomlFile& f, const toml::node* node, std::string name,
                         std::vector<std::string_view> allowed)
    : f_(&f), name_(std::move(name)) {
  if (!node) return;
  table_ = node->as_table();
  if (!table_) f.fail(*node, name_ + " = " + show(*node) + ": wrong type, expected a table");
  for (auto&& [key, value] : *table_) {
    if (std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end()) continue;
    const std::string where = name_.empty()                          ? "at the top level"
                              : name_.find('[') != std::string::npos ? "in " + name_
                                                                     : "in [" + name_ + "]";
    f.fail(&key.source(), "unknown key '" + show_key(key.str()) + "' " + where + " (allowed: " + join(allowed) + ")" +
                              did_you_mean(key.str(), allowed));
  }
}

void TableReader::fail_after(std::string_view key, const std::string& msg) const {
  f_->fail(*node(key), path(key) + " = " + show(*node(key)) + msg);
}

void TableReader::missing(std::string_view key, const std::string& what) const {
  f_->fail(where(), "missing key " + path(key) + " (" + what + ")");
}

void TableReader::forbid(std::string_view key, const std::string& reason) const {
  if (has(key)) fail(key, "given but " + reason + " (a scene names only what it uses: remove it)");
}

void TableReader::wrong_type(const toml::node& n, const std::string& p, const std::string& expected) const {
  f_->fail(n, p + " = " + show(n) + ": wrong type, expected " + expected);
}

std::optional<double> TableReader::number(std::string_view key, const Num& spec) const {
  const toml::node* n = node(key);
  return n ? std::optional(number_at(*n, path(key), spec)) : std::nullopt;
}

double TableReader::required(std::string_view key, const Num& spec, const std::string& why) const {
  if (!has(key)) missing(key, range_text(spec) + why);
  return *number(key, spec);
}

std::optional<std::vector<double>> TableReader::numbers(std::string_view key, const Num& spec) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  const toml::array* a = n->as_array();
  if (!a || a->empty()) fail(key, "must be a non-empty array of numbers (" + range_text(spec) + ")");
  std::vector<double> out;
  for (std::size_t k = 0; k < a->size(); ++k)
    out.push_back(number_at(*a->get(k), path(key) + "[" + std::to_string(k) + "]", spec));
  return out;
}

std::optional<bool> TableReader::boolean(std::string_view key) const {
  const toml::node* n = node(key);
  if (n && !n->is_boolean()) wrong_type(*n, path(key), "a boolean (true or false)");
  return n ? std::optional(n->as_boolean()->get()) : std::nullopt;
}

std::optional<std::string> TableReader::string(std::string_view key) const {
  const toml::node* n = node(key);
  if (n && !n->is_string()) wrong_type(*n, path(key), "a string");
  if (n && n->as_string()->get().empty()) fail(key, "must be a non-empty string");
  return n ? std::optional(n->as_string()->get()) : std::nullopt;
}

std::optional<std::string> TableReader::choice(std::string_view key, const std::vector<std::string_view>& allowed,
                                               const char* what) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  std::string list;
  for (const std::string_view a : allowed) list += (list.empty() ? "\"" : ", \"") + std::string(a) + "\"";
  if (!n->is_string()) wrong_type(*n, path(key), "one of " + list + " (" + what + ")");
  const std::string& v = n->as_string()->get();
  if (std::find(allowed.begin(), allowed.end(), v) == allowed.end())
    fail(key, "must be one of " + list + " (" + what + ")");
  return v;
}

std::vector<std::string> TableReader::strings(std::string_view key, const char* what) const {
  const toml::node* n = node(key);
  if (!n) missing(key, std::string(what) + ", an array of strings");
  const toml::array* a = n->as_array();
  if (!a || a->empty()) fail(key, std::string("must be a non-empty array of strings (") + what + ")");
  std::vector<std::string> out;
  for (std::size_t k = 0; k < a->size(); ++k) {
    const auto* str = a->get(k)->as_string();
    if (!str || str->get().empty()) wrong_type(*a->get(k), path(key) + "[" + std::to_string(k) + "]", "a non-empty string");
    out.push_back(str->get());
  }
  return out;
}

std::int64_t TableReader::integer(std::string_view key, std::int64_t min, const char* what, std::int64_t max) const {
  const toml::node* n = node(key);
  if (!n) missing(key, std::string(what) + ", an integer >= " + std::to_string(min));
  return integer_at(*n, key, min, what, max);
}

std::int64_t TableReader::integer_or(std::string_view key, std::int64_t min, const char* what, std::int64_t fallback,
                                     std::int64_t max) const {
  const toml::node* n = node(key);
  return n ? integer_at(*n, key, min, what, max) : fallback;
}

std::int64_t TableReader::integer_at(const toml::node& n, std::string_view key, std::int64_t min, const char* what,
                                     std::int64_t max) const {
  if (!n.is_integer()) wrong_type(n, path(key), "an integer");
  const std::int64_t v = n.as_integer()->get();
  if (v < min || v > max)
    fail(key, "must be an integer " +
                  (max == kNoMax ? ">= " + std::to_string(min)
                                 : "in [" + std::to_string(min) + ", " + std::to_string(max) + "]") +
                  " (" + what + ")");
  return v;
}

std::optional<std::array<double, 2>> TableReader::vec2(std::string_view key, const Num& spec) const {
  const toml::node* n = node(key);
  return n ? std::optional(vec2_at(*n, path(key), spec)) : std::nullopt;
}

std::array<double, 2> TableReader::required_vec2(std::string_view key, const Num& spec, const std::string& why) const {
  if (!has(key)) missing(key, "[x, y], " + range_text(spec) + why);
  return *vec2(key, spec);
}

double TableReader::number_at(const toml::node& n, const std::string& p, const Num& spec) const {
  const auto v = number_of(n);
  if (!v) wrong_type(n, p, "a number");
  if (!obeys(spec, *v))
    f_->fail(n, p + " = " + show(n) + ": must be " + (std::isfinite(*v) || spec.rule == Rule::finite ? "" : "finite and ") +
                    rule_text(spec) + " (" + describe(spec) + ")");
  return *v;
}

std::array<double, 2> TableReader::vec2_at(const toml::node& n, const std::string& p, const Num& spec) const {
  const toml::array* a = n.as_array();
  if (!a || a->size() != 2) f_->fail(n, p + " = " + show(n) + ": must be an array [x, y] (" + range_text(spec) + ")");
  return {number_at(*a->get(0), p + "[0]", spec), number_at(*a->get(1), p + "[1]", spec)};
}

std::vector<TableReader> TableReader::entries(std::string_view key, std::vector<std::string_view> allowed) const {
  std::vector<TableReader> out;
  const toml::node* n = node(key);
  if (!n) return out;
  if (!n->is_array()) fail(key, "wrong type, expected an array of tables ([[" + std::string(key) + "]])");
  for (std::size_t k = 0; k < n->as_array()->size(); ++k)
    out.emplace_back(*f_, n->as_array()->get(k), path(key) + "[" + std::to_string(k) + "]", allowed);
  return out;
}

}  // namespace dem2d
