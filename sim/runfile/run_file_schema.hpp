// The run file's schema, once: every root attribute and every dataset with
// its type, shape, unit and a one-line description. The reader checks a
// file's datasets against it (runfile/run_reader.cpp); the writer puts the unit
// and description on each dataset, and `dem2d inspect --schema` prints the
// whole table as JSON, with the energy ledger's terms and the effects, for
// the checkers and readers that are not this program (writer/run_file_describe.hpp);
// docs/run_file.md explains it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace dem2d {

// A root attribute: its name, type (str, i8, f8) and meaning.
struct AttributeSchema {
  std::string_view name, type, description;
};

// A dataset. `shape`: its dimensions, comma-separated, each a number or one
// of the symbols of kRunFileDimensions (e.g. "S,N,2"; "S+1"); `when`: the
// scene setting it depends on ("" : always written); `optional`: readers take
// a file without it (files written before it existed lack it; a run file
// without series rows has no /series at all, whose other datasets a file
// with /series/time must hold).
struct DatasetSchema {
  std::string_view path, type, shape, units, description, when;
  bool optional = false;
  // Held by every run file (with /series/time, for the series).
  bool required() const { return when.empty() && !optional; }
};

struct DimensionSchema {
  std::string_view symbol, meaning;
};

// A /parameters value that is not one number (the rest are scalars): its key,
// the last part of its path (parameters/bodies/0/velocity: velocity), and the
// count of numbers it holds, 0 for any number of (x, y) (stored [n, 2]).
struct ParameterShape {
  std::string_view key;
  std::size_t count;
  // As the JSON schema spells it: "2", "4", "n,2".
  std::string text() const { return count ? std::to_string(count) : "n,2"; }
};

std::span<const AttributeSchema> run_file_attributes();
std::span<const DatasetSchema> run_file_datasets();
std::span<const DimensionSchema> run_file_dimensions();
std::span<const ParameterShape> parameter_shapes();

// The shape of the /parameters value with this key; nullptr for a scalar.
const ParameterShape* find_parameter_shape(std::string_view key);

// The schema's row of a dataset; nullptr if it has none (the energy ledger's
// terms: writer/run_file_describe.hpp).
const DatasetSchema* find_dataset(std::string_view path);

// Its shape with the file's sizes (symbol -> size); std::logic_error for a
// symbol not among them.
std::vector<std::uint64_t> schema_shape(const DatasetSchema& d, const std::map<char, std::uint64_t>& sizes);

}  // namespace dem2d
