// The unit and a one-line description of every dataset of a run file, written
// as the dataset's attributes `units` and `description` (docs/run_file.md has
// the same table in full): a reader needs nothing else to know what it holds.
#pragma once

#include <string>
#include <string_view>

namespace dem2d {

namespace h5 {
class File;
}

struct DatasetMeaning {
  std::string_view path, units, description;
};

// Writes `units` and `description` on every dataset of the table that f holds.
void describe_run_file(const h5::File& f);

}  // namespace dem2d
