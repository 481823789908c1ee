// The run file's schema, once: every root attribute and every dataset with
// its type, shape, unit and a one-line description. The writer puts the unit
// and description on each dataset (a reader needs nothing else to know what
// it holds); `dem2d inspect --schema` prints the whole table as JSON, with
// the energy ledger's terms and the effects, for the checkers and readers
// that are not this program (tests/check_run_file.py); docs/run_file.md
// explains it.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace dem2d {

namespace h5 {
class File;
}

// A root attribute: its name, type (str, i8, f8) and meaning.
struct AttributeSchema {
  std::string_view name, type, description;
};

// A dataset. `shape`: its dimensions, comma-separated, each a number or one
// of the symbols of kRunFileDimensions (e.g. "S,N,2"; "S+1"); `when`: the
// scene setting it depends on ("" : always written).
struct DatasetSchema {
  std::string_view path, type, shape, units, description, when;
};

struct DimensionSchema {
  std::string_view symbol, meaning;
};

std::span<const AttributeSchema> run_file_attributes();
std::span<const DatasetSchema> run_file_datasets();
std::span<const DimensionSchema> run_file_dimensions();

// Writes `units` and `description` on every dataset of the schema that f holds.
void describe_run_file(const h5::File& f);

// The schema as JSON: format, dimensions, attributes, datasets (the energy
// ledger's terms among them, one row each), effects.
std::string run_file_schema_json();

}  // namespace dem2d
