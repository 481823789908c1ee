// The run file's schema as the writer uses it: the units and descriptions it
// writes on each dataset, and the whole schema as JSON (`dem2d inspect
// --schema`), with the energy ledger's terms (one row each) and the effects.
#pragma once

#include <string>

namespace dem2d {

namespace h5 {
class File;
}

// Writes `units` and `description` on every dataset of the schema that f holds.
void describe_run_file(const h5::File& f);

// The schema as JSON: format, dimensions, attributes, datasets, effects, the most vertices of a
// body's core, and /parameters' layout (its format, the values' shapes, the motion kinds' values).
std::string run_file_schema_json();

}  // namespace dem2d
