// A stage's HDF5 output, collected in memory and written at the end under a
// temporary name, then renamed (it exists only when complete). Every dataset
// carries the attributes `units` and `description`, as the run file's do; a
// dataset is 1-D unless it is given a shape. Attributes go on the root or on
// any group or dataset of the file.
#pragma once

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include <hdf5.h>
#include <nlohmann/json.hpp>

namespace dem2d::analysis {

class H5Output {
 public:
  using Column = std::variant<std::vector<double>, std::vector<float>, std::vector<std::int64_t>,
                              std::vector<std::int32_t>, std::vector<std::uint8_t>>;
  using Value = std::variant<std::string, double, std::int64_t>;
  struct Dataset {
    std::string name, units, description;
    Column data;
    std::vector<hsize_t> shape;  // empty: 1-D
  };
  struct Attribute {
    std::string object, name;  // object "/" is the file
    Value value;
  };

  H5Output() = default;
  // A stage's file: notes `stage`, `run_file` and `definitions` (analysis/<stage>/README.md).
  H5Output(const std::string& stage, const std::string& run_file) {
    note("stage", stage);
    note("run_file", run_file);
    note("definitions", "analysis/" + stage + "/README.md");
  }
  void add(std::string name, Column data, std::string units, std::string description,
           std::vector<hsize_t> shape = {}) {
    datasets_.push_back({std::move(name), std::move(units), std::move(description), std::move(data), std::move(shape)});
  }
  // An attribute of the root group.
  void note(std::string name, Value value) { attr("/", std::move(name), std::move(value)); }
  // An attribute of a group or dataset added before write().
  void attr(std::string object, std::string name, Value value) {
    attributes_.push_back({std::move(object), std::move(name), std::move(value)});
  }
  const std::vector<Dataset>& datasets() const { return datasets_; }
  // Writes path + ".tmp" and renames it to path; std::runtime_error naming the file on failure.
  void write(const std::string& path) const;

 private:
  std::vector<Dataset> datasets_;
  std::vector<Attribute> attributes_;
};

// NaN and infinities become JSON null (nlohmann would write null anyway, but
// explicitly so that metrics are never silently a number).
nlohmann::ordered_json number_or_null(double v);
// num / den, or null when den is 0 (a fraction of nothing).
nlohmann::ordered_json fraction_or_null(std::int64_t num, std::int64_t den);

// A number as printf's %g writes it ("0.8", "1e-06"), for names and messages.
std::string format_number(double v);
// A length in metres as millimetres with 4 significant digits ("45.23 mm"), for messages.
std::string format_mm(double metres);
// A metric for a stage's summary line: a number with 4 significant digits
// and its unit ("0.3158", "45.23 mm" for unit " mm"), "n/a" for null, other
// values as JSON.
std::string show_metric(const nlohmann::ordered_json& v, const char* unit = "");

}  // namespace dem2d::analysis
