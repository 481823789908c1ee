// Writing /parameters (read back by runfile/run_parameters.hpp). In the engine's library: it
// holds the engine's contact law (its layout follows the law's list of terms).
#include "writer/run_parameters_write.hpp"

#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/motion.hpp"
#include "core/scene_keys.hpp"
#include "runfile/run_file_schema.hpp"
#include "runfile/run_parameters.hpp"

namespace dem2d {

namespace {

// units, description, and the rule every reader checks the value against ("> 0", "in (0, 1]": rule_text)
void describe(const h5::File& f, const std::string& name, const Num& spec) {
  h5::write_attr(f, name, "units", std::string(*spec.unit ? spec.unit : "-"));
  h5::write_attr(f, name, "description", std::string(spec.what));
  h5::write_attr(f, name, "valid", rule_text(spec));
}

void number(const h5::File& f, const std::string& name, double v, const Num& spec) {
  h5::write_scalar(f, name, v);
  describe(f, name, spec);
}

// A value of the schema's parameter_shapes (runfile/run_file_schema.hpp), in its shape there.
void vector(const h5::File& f, const std::string& name, const std::vector<double>& v, const Num& spec) {
  const ParameterShape* shape = find_parameter_shape(name.substr(name.rfind('/') + 1));
  if (!shape || (shape->count ? v.size() != shape->count : v.size() % 2 != 0))
    throw std::logic_error("/" + name + ": " + std::to_string(v.size()) + " numbers, not a shape of the run-file schema");
  h5::write(f, name, v, shape->count ? std::vector<hsize_t>{} : std::vector<hsize_t>{v.size() / 2, 2});
  describe(f, name, spec);
}

void flag(const h5::File& f, const std::string& name, bool on, const char* what) {
  number(f, name, on ? 1.0 : 0.0, {what, "", Rule::flag});
}

// The law's keys in use under `effects` (those a scene must give), each with its unit.
void law(const h5::File& f, const std::string& group, const ContactLaw& l, EffectSet effects) {
  for (const auto& k : contact_law_keys())
    if (!k.needs || has(effects, k.needs)) number(f, group + "/" + std::string(k.key), l.*k.field, k.spec);
}

void stop(const h5::File& f, const StopCondition& s) {
  number(f, "parameters/stop/duration", s.duration, scene_key::duration);
  if (s.kinetic_energy_below > 0.0)
    number(f, "parameters/stop/kinetic_energy_below", s.kinetic_energy_below, scene_key::kinetic_energy_below);
  if (s.kinetic_energy_per_grain_below > 0.0)
    number(f, "parameters/stop/kinetic_energy_per_grain_below", s.kinetic_energy_per_grain_below,
           scene_key::kinetic_energy_per_grain_below);
  if (s.energy_criterion()) number(f, "parameters/stop/all_below", s.all_below, scene_key::all_below);
  if (!s.body_free.empty()) {
    h5::write_attr(f, "parameters/stop", "body_free", s.body_free);
    number(f, "parameters/stop/free_time", s.free_time, scene_key::free_time);
  }
  if (s.energy_criterion() || !s.body_free.empty()) {
    number(f, "parameters/stop/check_interval", s.check_interval, scene_key::check_interval);
    number(f, "parameters/stop/min_time", s.min_time, scene_key::min_time);
  }
}

void motion(const h5::File& f, const std::string& group, const BodySpec& b) {
  if (b.motion.empty()) return;
  number(f, group + "/motion_repeat", b.motion_repeat, {"runs of the whole motion", "", Rule::positive});
  for (std::size_t j = 0; j < b.motion.size(); ++j) {
    const MotionSegment& m = b.motion[j];
    const std::string g = group + "/motion/" + std::to_string(j);
    const MotionKindSpec& spec = motion_kind(m.kind);
    // (a last constant segment that goes on for ever has no duration, as in the scene)
    if (spec.duration && std::isfinite(m.duration)) number(f, g + "/duration", m.duration, scene_key::segment_duration);
    if (spec.velocity) vector(f, g + "/velocity", {m.vx, m.vy}, scene_key::segment_velocity);
    if (spec.velocity && m.w != 0.0) number(f, g + "/angular_velocity", m.w, scene_key::angular_velocity);
    if (spec.amplitude) vector(f, g + "/amplitude", {m.ax, m.ay}, scene_key::amplitude);
    if (spec.amplitude && m.aw != 0.0) number(f, g + "/angle", m.aw, scene_key::angle);
    if (spec.period) number(f, g + "/period", m.period, scene_key::period);
    if (spec.cycles) number(f, g + "/cycles", m.cycles, {"number of cycles", "", Rule::positive});
    h5::write_attr(f, g, "kind", std::string(spec.name));
  }
  h5::write_attr(f, group + "/motion", "segments", static_cast<std::int64_t>(b.motion.size()));
}

void bodies(const h5::File& f, const std::vector<BodySpec>& all) {
  for (std::size_t k = 0; k < all.size(); ++k) {
    const BodySpec& b = all[k];
    const std::string g = "parameters/bodies/" + std::to_string(k);
    std::vector<double> xy;
    for (const Point& p : b.vertices) xy.insert(xy.end(), {p.x, p.y});
    vector(f, g + "/vertices", xy, scene_key::vertex);
    number(f, g + "/thickness", b.thickness, scene_key::thickness);
    vector(f, g + "/velocity", {b.vx, b.vy}, scene_key::body_velocity);
    if (b.remove_at >= 0.0) number(f, g + "/remove_at", b.remove_at, scene_key::remove_at);
    if (b.pivot) vector(f, g + "/pivot", {b.pivot->x, b.pivot->y}, scene_key::pivot);
    motion(f, g, b);
    h5::write_attr(f, g, "name", b.name);
    h5::write_attr(f, g, "role", b.role);
    h5::write_attr(f, g, "shape", b.shape);
  }
}

void jam(const h5::File& f, const JamControl& c) {
  if (!c.enabled) return;
  number(f, "parameters/jam/outlet_height", c.outlet_height, scene_key::outlet_height);
  number(f, "parameters/jam/start_time", c.start_time, scene_key::jam_start_time);
  number(f, "parameters/jam/no_flow_time", c.no_flow_time, scene_key::no_flow_time);
  number(f, "parameters/jam/check_interval", c.check_interval, scene_key::check_interval);
  vector(f, "parameters/jam/tap_velocity", {c.tap_vx, c.tap_vy}, scene_key::tap_velocity);
  number(f, "parameters/jam/tap_duration", c.tap_duration, scene_key::tap_duration);
  number(f, "parameters/jam/max_taps", c.max_taps, {"taps before giving up", "", Rule::positive});
  h5::write_strings(f, "parameters/jam/bodies", c.bodies);
  h5::write_attr(f, "parameters/jam/bodies", "units", std::string("-"));
  h5::write_attr(f, "parameters/jam/bodies", "description", std::string("the hopper walls tapped to clear a jam"));
}

}  // namespace

void write_parameters(const h5::File& f, const Scene& s) {
  for (const EffectName& e : kEffectNames)
    flag(f, "parameters/effects/" + std::string(e.key), has(s.effects, e.bit), "effect on (1) or off (0)");
  number(f, "parameters/time/dt", s.dt, scene_key::dt);
  flag(f, "parameters/time/dt_forced", s.dt_forced, "time step accepted above the stability limit");
  number(f, "parameters/material/density", s.density, scene_key::density);
  if (has(s.effects, effect::gravity)) vector(f, "parameters/gravity/g", {s.gx, s.gy}, scene_key::gravity);
  law(f, "parameters/contact/grain_grain", s.particle_particle, s.effects);
  if (has(s.effects, effect::walls)) law(f, "parameters/contact/grain_body", s.particle_wall, s.effects);
  stop(f, s.stop);
  const OutputSpec& o = s.output;
  number(f, "parameters/output/series_interval", o.series_interval, scene_key::output_interval);
  number(f, "parameters/output/snapshot_interval", o.snapshot_interval, scene_key::output_interval);
  number(f, "parameters/output/checkpoint_interval", o.checkpoint_interval, scene_key::checkpoint_interval);
  number(f, "parameters/output/displacement_window", o.displacement_window, scene_key::displacement_window);
  flag(f, "parameters/output/energy_balance", o.energy_balance, "energy ledger recorded in the series");
  vector(f, "parameters/domain", {s.domain.xmin, s.domain.ymin, s.domain.xmax, s.domain.ymax},
         {"domain (xmin, ymin, xmax, ymax)", "m", Rule::finite});
  number(f, "parameters/neighbour/skin", s.skin, scene_key::skin);
  bodies(f, s.bodies);
  jam(f, s.jam);
  // every group names the values it holds (attribute `keys`), so that any reader can tell one that is missing
  std::map<std::string, std::string> keys;
  for (const std::string& d : h5::datasets_under(f, "parameters")) {
    const std::size_t slash = d.rfind('/');
    std::string& list = keys[slash == std::string::npos ? "parameters" : "parameters/" + d.substr(0, slash)];
    if (!list.empty()) list += ',';
    list += d.substr(slash == std::string::npos ? 0 : slash + 1);
  }
  for (const auto& [group, list] : keys) h5::write_attr(f, group, "keys", list);
  h5::write_attr(f, "parameters", "format", std::string(kParametersFormat));
  h5::write_attr(f, "parameters", "scene", s.name);
  h5::write_attr(f, "parameters", "bodies", static_cast<std::int64_t>(s.bodies.size()));
}

}  // namespace dem2d
