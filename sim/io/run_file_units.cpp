#include "io/run_file_units.hpp"

#include <string>

#include "engine/energy_ledger.hpp"
#include "io/h5.hpp"
#include "shape/shape_kinds.hpp"

namespace dem2d {

namespace {

constexpr DatasetMeaning kMeanings[] = {
    {"particles/id", "-", "particle index 0..N-1, its identity for the whole run"},
    {"particles/diameter", "m", "grain diameter"},
    {"particles/mass", "kg/m", "grain mass per unit depth, rho pi d^2 / 4"},
    {"particles/inertia", "kg m", "moment of inertia per unit depth, m d^2 / 8"},
    {"bodies/name", "-", "body name from the scene"},
    {"bodies/role", "-", "body role from the scene: intruder, floor, left_wall, right_wall, hopper, or empty"},
    {"bodies/vertex_count", "-", "vertices of the body's core (2: a segment; >= 3: a polygon, counter-clockwise)"},
    {"bodies/thickness", "m", "rounding diameter: the body is every point within thickness/2 of its core"},
    {"bodies/velocity", "m/s", "prescribed velocity (vx, vy) at the end of the run"},
    {"series/time", "s", "time of the series row"},
    {"series/step", "-", "step of the series row"},
    {"series/body_force", "N/m", "force (fx, fy) the grains exert on each body at that step"},
    {"series/body_force_mean", "N/m", "mean force (fx, fy) on each body over the steps since the previous row"},
    {"series/body_torque", "N", "torque of the grains on each body about its pivot (the scene's, else its core's vertex mean), counter-clockwise"},
    {"series/body_torque_mean", "N", "mean torque on each body over the steps since the previous row"},
    {"series/body_vertices", "m", "core vertices (x, y) of each body, padded by repeating the last"},
    {"series/kinetic_energy", "J/m", "translational + rotational kinetic energy of the active grains"},
    {"series/max_overlap", "m", "largest overlap of all contacts"},
    {"series/contacts", "-", "number of touching contacts, grain-grain and grain-body"},
    {"snapshots/time", "s", "time of the snapshot"},
    {"snapshots/step", "-", "step of the snapshot"},
    {"snapshots/position", "m", "grain centre (x, y)"},
    {"snapshots/velocity", "m/s", "grain velocity (vx, vy)"},
    {"snapshots/displacement", "m", "grain displacement over displacement_window before the snapshot; NaN: not recorded"},
    {"snapshots/omega", "rad/s", "grain angular velocity, counter-clockwise"},
    {"snapshots/theta", "rad", "grain orientation (integrated omega)"},
    {"snapshots/active", "-", "1, or 0 once the grain has left the domain"},
    {"snapshots/body_vertices", "m", "core vertices (x, y) of each body, padded by repeating the last"},
    {"snapshots/contact_start", "-", "contacts of snapshot k: rows contact_start[k] .. contact_start[k+1]-1 of /contacts"},
    {"contacts/i", "-", "grain"},
    {"contacts/j", "-", "partner: grain j > i if j >= 0, else body -1-j"},
    {"contacts/fn", "N/m", "normal force, > 0 repulsive"},
    {"contacts/ft", "N/m", "tangential force on grain i along t = z x n"},
    {"contacts/overlap", "m", "overlap, > 0 touching (< 0: attracting across a gap, with cohesion)"},
    {"contacts/nx", "-", "x of the unit normal from the partner to grain i"},
    {"contacts/ny", "-", "y of the unit normal from the partner to grain i"},
    {"contacts/mr", "N", "rolling moment on grain i (the partner receives -mr)"},
    {"contacts/sliding", "-", "1 if the tangential force is on the Coulomb cone |ft| >= mu F_load"},
    {"contacts/mu_star", "-", "friction mobilisation |ft| / (mu F_load); NaN without friction or load"},
    {"contacts/line", "m", "the contact's line for drawing: grain i's centre to the partner grain's centre, or to the contact point on a body"},
    {"lost/id", "-", "particle that left the domain"},
    {"lost/step", "-", "step at which it was removed"},
    {"events/jam_time", "s", "times a jam of the hopper outlet was detected and tapped"},
    {"lost/x", "m", "its last x"},
    {"lost/y", "m", "its last y"},
    {"xdmf/sequence", "-", "0, 1, 2, ...: connectivity of the contact lines in run.xdmf"},
    {"xdmf/body_outline", "-", "each body's vertices in body_vertices, closed for polygons: its polyline in run.xdmf"},
};
constexpr DatasetMeaning kEnergy{"series/energy/", "J/m", "energy ledger term (docs/energy.md)"};

}  // namespace

void describe_run_file(const h5::File& f) {
  const auto describe = [&](const std::string& path, const DatasetMeaning& m) {
    if (!h5::exists(f, path)) return;
    h5::write_attr(f, path, "units", std::string(m.units));
    h5::write_attr(f, path, "description", std::string(m.description));
  };
  for (const DatasetMeaning& m : kMeanings) describe(std::string(m.path), m);
  std::string kinds;  // from the registry: a new kind is named without an edit here
  for (const ShapeKind& k : shape_kinds()) kinds += (kinds.empty() ? "" : ", ") + std::string(k.name);
  const std::string shape = "the scene's shape kind: " + kinds;
  describe("bodies/shape", {"bodies/shape", "-", shape});
  for (const auto& [term, value] : EnergyBalance{}.terms())
    describe(std::string(kEnergy.path) + term, kEnergy);
}

}  // namespace dem2d
