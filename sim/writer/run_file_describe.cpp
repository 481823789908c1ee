#include "writer/run_file_describe.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <utility>

#include "core/effects.hpp"
#include "core/motion.hpp"
#include "engine/energy_ledger.hpp"
#include "runfile/h5.hpp"
#include "runfile/run_file_schema.hpp"
#include "runfile/run_format.hpp"
#include "runfile/run_parameters.hpp"
#include "shape/shape.hpp"
#include "shape/shape_kinds.hpp"

namespace dem2d {

namespace {

constexpr DatasetSchema kEnergy{"series/energy/", "f8", "T", "J/m", "energy ledger term (docs/energy.md)", "output.energy_balance"};

// The ledger's terms, one row each (from the ledger's own list).
template <class Fn>
void for_each_energy_row(Fn&& fn) {
  for (const auto& [term, value] : EnergyBalance{}.terms()) {
    const std::string path = std::string(kEnergy.path) + std::string(term);
    fn(path, kEnergy);
  }
}

// A dataset's one-line description; the body shapes' names the kinds the registry has (a new kind is named
// without an edit here).
std::string description_of(const DatasetSchema& d) {
  if (d.path != "bodies/shape") return std::string(d.description);
  std::string kinds;
  for (const ShapeKind& k : shape_kinds()) kinds += (kinds.empty() ? "" : ", ") + std::string(k.name);
  return std::string(d.description) + ": " + kinds;
}

}  // namespace

void describe_run_file(const h5::File& f) {
  const auto describe = [&](const std::string& path, const DatasetSchema& d) {
    if (!h5::exists(f, path)) return;
    h5::write_attr(f, path, "units", std::string(d.units));
    h5::write_attr(f, path, "description", description_of(d));
  };
  for (const DatasetSchema& d : run_file_datasets()) describe(std::string(d.path), d);
  for_each_energy_row(describe);
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
                    {"description", description_of(d)}, {"when", d.when}, {"optional", d.optional}});
  };
  for (const DatasetSchema& d : run_file_datasets()) row(std::string(d.path), d);
  for_each_energy_row(row);
  Json& balance = out["energy_balance"] = Json::object();  // the ledger's terms: their signs in its total
  for (const auto& [term, value] : EnergyBalance{}.terms()) balance[std::string(term)] = EnergyBalance::sign_of(term);
  Json& effects = out["effects"] = Json::array();
  for (const EffectName& e : kEffectNames) effects.push_back(e.key);
  out["max_vertices"] = Shape::kMaxVertices;
  // /parameters: its layout's name, the values that are not one number, the motion kinds' values
  Json& params = out["parameters"] = {{"format", kParametersFormat}};
  Json& shapes = params["shapes"] = Json::object();
  for (const ParameterShape& p : parameter_shapes()) shapes[std::string(p.key)] = p.text();
  Json& kinds = params["motion_kinds"] = Json::object();
  for (const MotionKindSpec& k : kMotionKinds) {
    Json& keys = kinds[std::string(k.name)] = Json::array();
    for (const auto& [key, used] : {std::pair{"velocity", k.velocity}, {"duration", k.duration},
                                    {"amplitude", k.amplitude}, {"period", k.period}, {"cycles", k.cycles}})
      if (used) keys.push_back(key);
  }
  params["max_motion_pieces"] = kMaxMotionPieces;
  return out.dump(2) + "\n";
}

}  // namespace dem2d
