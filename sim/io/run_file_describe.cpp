#include "io/run_file_describe.hpp"

#include <nlohmann/json.hpp>

#include <string>

#include "core/effects.hpp"
#include "engine/energy_ledger.hpp"
#include "io/h5.hpp"
#include "io/run_file_schema.hpp"
#include "io/run_format.hpp"
#include "shape/shape_kinds.hpp"

namespace dem2d {

namespace {

constexpr DatasetSchema kEnergy{"series/energy/", "f8", "T", "J/m", "energy ledger term (docs/energy.md)", "output.energy_balance"};

// The ledger's terms, one row each (from the ledger's own list).
template <class Fn>
void for_each_energy_row(Fn&& fn) {
  for (const auto& [term, value] : EnergyBalance{}.terms()) {
    const std::string path = std::string(kEnergy.path) + term;
    fn(path, kEnergy);
  }
}

}  // namespace

void describe_run_file(const h5::File& f) {
  const auto describe = [&](const std::string& path, std::string_view units, const std::string& description) {
    if (!h5::exists(f, path)) return;
    h5::write_attr(f, path, "units", std::string(units));
    h5::write_attr(f, path, "description", description);
  };
  std::string kinds;  // from the registry: a new kind is named without an edit here
  for (const ShapeKind& k : shape_kinds()) kinds += (kinds.empty() ? "" : ", ") + std::string(k.name);
  for (const DatasetSchema& d : run_file_datasets())
    describe(std::string(d.path), d.units,
             d.path == "bodies/shape" ? "the scene's shape kind: " + kinds : std::string(d.description));
  for_each_energy_row([&](const std::string& path, const DatasetSchema& d) {
    describe(path, d.units, std::string(d.description));
  });
}

std::string run_file_schema_json() {
  using Json = nlohmann::ordered_json;
  Json out{{"format", kRunFileFormat}};
  Json& dims = out["dimensions"] = Json::object();
  for (const DimensionSchema& d : run_file_dimensions()) dims[std::string(d.symbol)] = d.meaning;
  Json& attrs = out["attributes"] = Json::array();
  for (const AttributeSchema& a : run_file_attributes())
    attrs.push_back({{"name", a.name}, {"type", a.type}, {"description", a.description}});
  Json& sets = out["datasets"] = Json::array();
  const auto row = [&](const std::string& path, const DatasetSchema& d) {
    sets.push_back({{"path", path}, {"type", d.type}, {"shape", d.shape}, {"units", d.units},
                    {"description", d.description}, {"when", d.when}});
  };
  for (const DatasetSchema& d : run_file_datasets()) row(std::string(d.path), d);
  for_each_energy_row(row);
  Json& effects = out["effects"] = Json::array();
  for (const EffectName& e : kEffectNames) effects.push_back(e.key);
  return out.dump(2) + "\n";
}

}  // namespace dem2d
