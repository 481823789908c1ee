#include "runfile/run_file_schema.hpp"

#include <stdexcept>
#include <string>

namespace dem2d {

namespace {

constexpr DimensionSchema kDimensions[] = {
    {"N", "grains (the attribute n_particles)"},
    {"B", "bodies (n_bodies)"},
    {"T", "rows of the time series"},
    {"S", "snapshots"},
    {"C", "contact rows of all snapshots together"},
    {"L", "grains that left the domain (lost_particles)"},
    {"J", "jams of the hopper outlet (jams)"},
    {"K", "the most vertices of a body's core (at least 1)"},
    {"Q", "length of run.xdmf's connectivity sequence: twice the most contacts of a snapshot, at least 1"},
};

constexpr AttributeSchema kAttributes[] = {
    {"format", "str", "dem2d-run-2"},
    {"scene_text", "str", "the full text of the scene file"},
    {"scene_path", "str", "the scene file's path (\"\" for scenes built in code)"},
    {"code_version", "str", "dem2d version + git describe --dirty of the source tree at the last build"},
    {"threads", "i8", "OpenMP threads used (results do not depend on it)"},
    {"dt", "f8", "time step (s)"},
    {"steps", "i8", "step number at the end of the run"},
    {"end_time", "f8", "simulated time at the end = steps * dt (s): the last snapshot's"},
    {"stop_reason", "str", "why the run ended, in words"},
    {"stopped_by", "str", "the criterion that ended it: duration, body_free, kinetic_energy, max_taps"},
    {"effects", "str", "the scene's effects, comma-separated (dem2d --list-effects)"},
    {"n_particles", "i8", "N"},
    {"n_bodies", "i8", "B"},
    {"lost_particles", "i8", "L"},
    {"initial_run", "str", "the run file or checkpoint the grains were taken from, \"\" if none"},
    {"initial_source", "str", "which state of it, \"\" if none"},
    {"initial_digest", "str", "a checksum of the grains and contact history taken from it, \"\" if none"},
    {"jams", "i8", "J"},
    {"wall_seconds", "f8", "wall-clock time the run took, summed over resumed invocations (s)"},
    {"displacement_window", "f8", "the window of /snapshots/displacement (s), 0 if not recorded"},
};

constexpr DatasetSchema kDatasets[] = {
    {"particles/id", "i4", "N", "-", "particle index 0..N-1, its identity for the whole run", "", true},
    {"particles/diameter", "f8", "N", "m", "grain diameter", ""},
    {"particles/mass", "f8", "N", "kg/m", "grain mass per unit depth, rho pi d^2 / 4", ""},
    {"particles/inertia", "f8", "N", "kg m", "moment of inertia per unit depth, m d^2 / 8", "", true},
    {"bodies/name", "str", "B", "-", "body name from the scene", ""},
    {"bodies/role", "str", "B", "-", "body role from the scene: intruder, floor, left_wall, right_wall, hopper, or empty", ""},
    {"bodies/shape", "str", "B", "-", "the scene's shape kind", ""},  // (the kinds: writer/run_file_describe.cpp)
    {"bodies/vertex_count", "i4", "B", "-", "vertices of the body's core (2: a segment; >= 3: a polygon, counter-clockwise)", ""},
    {"bodies/thickness", "f8", "B", "m", "rounding diameter: the body is every point within thickness/2 of its core", ""},
    {"bodies/velocity", "f8", "B,2", "m/s", "prescribed velocity (vx, vy) at the end of the run", "", true},
    {"series/time", "f8", "T", "s", "time of the series row", "", true},
    {"series/step", "i8", "T", "-", "step of the series row", ""},
    {"series/body_force", "f8", "T,B,2", "N/m", "force (fx, fy) the grains exert on each body at that step", ""},
    {"series/body_force_mean", "f8", "T,B,2", "N/m", "mean force (fx, fy) on each body over the steps since the previous row", ""},
    {"series/body_torque", "f8", "T,B", "N", "torque of the grains on each body about its pivot (the scene's, else its core's vertex mean), counter-clockwise", ""},
    {"series/body_torque_mean", "f8", "T,B", "N", "mean torque on each body over the steps since the previous row", ""},
    {"series/body_vertices", "f8", "T,B,K,2", "m", "core vertices (x, y) of each body, padded by repeating the last", ""},
    {"series/kinetic_energy", "f8", "T", "J/m", "translational + rotational kinetic energy of the active grains", ""},
    {"series/max_overlap", "f8", "T", "m", "largest overlap of all contacts", ""},
    {"series/contacts", "i8", "T", "-", "number of touching contacts, grain-grain and grain-body", ""},
    {"snapshots/time", "f8", "S", "s", "time of the snapshot", ""},
    {"snapshots/step", "i8", "S", "-", "step of the snapshot", ""},
    {"snapshots/position", "f8", "S,N,2", "m", "grain centre (x, y)", ""},
    {"snapshots/velocity", "f8", "S,N,2", "m/s", "grain velocity (vx, vy)", ""},
    {"snapshots/displacement", "f8", "S,N,2", "m", "grain displacement over displacement_window before the snapshot; NaN: not recorded", "", true},
    {"snapshots/omega", "f8", "S,N", "rad/s", "grain angular velocity, counter-clockwise", ""},
    {"snapshots/theta", "f8", "S,N", "rad", "grain orientation (integrated omega)", "", true},
    {"snapshots/active", "u1", "S,N", "-", "1, or 0 once the grain has left the domain", ""},
    {"snapshots/body_vertices", "f8", "S,B,K,2", "m", "core vertices (x, y) of each body, padded by repeating the last", ""},
    {"snapshots/contact_start", "i8", "S+1", "-", "contacts of snapshot k: rows contact_start[k] .. contact_start[k+1]-1 of /contacts", ""},
    {"contacts/i", "i4", "C", "-", "grain", ""},
    {"contacts/j", "i4", "C", "-", "partner: grain j > i if j >= 0, else body -1-j", ""},
    {"contacts/fn", "f8", "C", "N/m", "normal force, > 0 repulsive", ""},
    {"contacts/ft", "f8", "C", "N/m", "tangential force on grain i along t = z x n", ""},
    {"contacts/overlap", "f8", "C", "m", "overlap, > 0 touching (< 0: attracting across a gap, with cohesion)", ""},
    {"contacts/nx", "f8", "C", "-", "x of the unit normal from the partner to grain i", ""},
    {"contacts/ny", "f8", "C", "-", "y of the unit normal from the partner to grain i", ""},
    {"contacts/mr", "f8", "C", "N", "rolling moment on grain i (the partner receives -mr)", ""},
    {"contacts/sliding", "u1", "C", "-", "1 if the tangential force is on the Coulomb cone |ft| >= mu F_load", ""},
    {"contacts/mu_star", "f8", "C", "-", "friction mobilisation |ft| / (mu F_load); NaN without friction or load", "", true},
    {"contacts/line", "f8", "C,2,2", "m", "the contact's line for drawing: grain i's centre to the partner grain's centre, or to the contact point on a body", "", true},
    {"lost/id", "i4", "L", "-", "particle that left the domain", "", true},
    {"lost/step", "i8", "L", "-", "step at which it was removed", "", true},
    {"lost/x", "f8", "L", "m", "its last x", "", true},
    {"lost/y", "f8", "L", "m", "its last y", "", true},
    {"events/jam_time", "f8", "J", "s", "times a jam of the hopper outlet was detected and tapped", "", true},
    {"xdmf/sequence", "i4", "Q", "-", "0, 1, 2, ...: connectivity of the contact lines in run.xdmf", ""},
    {"xdmf/body_outline", "i4", "B,K+1", "-", "each body's vertices in body_vertices, closed for polygons: its polyline in run.xdmf", ""},
};

constexpr ParameterShape kParameterShapes[] = {
    {"g", 2}, {"domain", 4}, {"velocity", 2}, {"amplitude", 2}, {"pivot", 2}, {"tap_velocity", 2}, {"vertices", 0},
};

}  // namespace

std::span<const AttributeSchema> run_file_attributes() { return kAttributes; }
std::span<const DatasetSchema> run_file_datasets() { return kDatasets; }
std::span<const DimensionSchema> run_file_dimensions() { return kDimensions; }
std::span<const ParameterShape> parameter_shapes() { return kParameterShapes; }

const ParameterShape* find_parameter_shape(std::string_view key) {
  for (const ParameterShape& p : kParameterShapes)
    if (p.key == key) return &p;
  return nullptr;
}

const DatasetSchema* find_dataset(std::string_view path) {
  for (const DatasetSchema& d : kDatasets)
    if (d.path == path) return &d;
  return nullptr;
}

std::vector<std::uint64_t> schema_shape(const DatasetSchema& d, const std::map<char, std::uint64_t>& sizes) {
  std::vector<std::uint64_t> out;
  std::string_view shape = d.shape;
  while (!shape.empty()) {
    const std::size_t comma = shape.find(',');
    const std::string_view part = shape.substr(0, comma);
    if (part.front() >= '0' && part.front() <= '9') {
      out.push_back(std::stoull(std::string(part)));
    } else {
      const auto size = sizes.find(part.front());
      if (size == sizes.end())
        throw std::logic_error("run-file schema: /" + std::string(d.path) + "'s dimension " + std::string(part) +
                               " is not known yet");
      out.push_back(size->second + (part.size() > 2 ? std::stoull(std::string(part.substr(2))) : 0));
    }
    if (comma == std::string_view::npos) break;
    shape.remove_prefix(comma + 1);
  }
  return out;
}

}  // namespace dem2d
