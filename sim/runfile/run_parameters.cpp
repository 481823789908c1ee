// Reading /parameters (runfile/run_parameters.hpp).
#include "runfile/run_parameters.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/motion.hpp"
#include "core/scene_keys.hpp"
#include "runfile/run_file_schema.hpp"

namespace dem2d {

namespace {

class Reader {
 public:
  explicit Reader(const h5::File& f) : f_(f) {}

  [[noreturn]] void fail(const std::string& name, const std::string& what) const {
    throw std::runtime_error(f_.path() + ": /" + name + ": " + what);
  }
  bool has(const std::string& name) const { return h5::exists(f_, name); }
  // a scalar float64
  double number(const std::string& name) const {
    if (!has(name)) fail(name, "missing");
    std::vector<hsize_t> dims;
    const std::vector<double> v = read_as_double(name, &dims);
    if (!dims.empty() || v.size() != 1) fail(name, "not a scalar");
    return v[0];
  }
  double number_or(const std::string& name, double fallback) const { return has(name) ? number(name) : fallback; }
  // an on/off flag: 1 or 0
  bool flag(const std::string& name) const {
    const double v = number(name);
    if (v != 0.0 && v != 1.0) fail(name, shortest(v) + ": must be 1 (on) or 0 (off)");
    return v == 1.0;
  }
  // a scalar the scene reader would accept under `spec`
  double checked(const std::string& name, const Num& spec) const {
    const double v = number(name);
    if (!obeys(spec, v)) fail(name, shortest(v) + ": must be " + range_text(spec));
    return v;
  }
  // a count the scene reader would accept: a whole number from 1 to kMaxMotionPieces (a value past an
  // int's range, cast, was undefined)
  int count(const std::string& name) const {
    const double v = number(name);
    if (!(v >= 1.0 && v <= static_cast<double>(kMaxMotionPieces) && v == std::floor(v)))
      fail(name, shortest(v) + ": must be a whole number from 1 to " + std::to_string(kMaxMotionPieces));
    return static_cast<int>(v);
  }
  // a value of the schema's parameter_shapes (runfile/run_file_schema.hpp), in its shape there
  std::vector<double> values(const std::string& name) const {
    if (!has(name)) fail(name, "missing");
    const ParameterShape* shape = find_parameter_shape(name.substr(name.rfind('/') + 1));
    if (!shape) throw std::logic_error("/" + name + " is a scalar in the run-file schema");
    std::vector<hsize_t> dims;
    const std::vector<double> v = read_as_double(name, &dims);
    if (shape->count && v.size() != shape->count)
      fail(name, std::to_string(v.size()) + " values, expected " + std::to_string(shape->count));
    if (!shape->count && (dims.size() != 2 || dims[1] != 2)) fail(name, "not a list of (x, y)");
    return v;
  }
  std::string text(const std::string& object, const std::string& attr) const {
    if (!h5::has_attr(f_, object, attr)) fail(object + "@" + attr, "missing");
    return h5::read_attr_string(f_, object, attr);
  }
  std::int64_t integer(const std::string& object, const std::string& attr) const {
    if (!h5::has_attr(f_, object, attr)) fail(object + "@" + attr, "missing");
    return h5::read_attr_int(f_, object, attr);
  }

 private:
  // every value checked against the rule the writer stored with it (attribute `valid`; finite without one)
  std::vector<double> read_as_double(const std::string& name, std::vector<hsize_t>* dims) const {
    if (h5::dtype(f_, name) != "f8") fail(name, "not float64");
    std::vector<double> v = h5::read<double>(f_, name, dims);
    const std::string rule = h5::has_attr(f_, name, "valid") ? h5::read_attr_string(f_, name, "valid") : "finite";
    const std::optional<Num> spec = rule_from_text(rule);
    if (!spec) fail(name + "@valid", "'" + rule + "' is not a rule this reader knows");
    for (const double x : v)
      if (!obeys(*spec, x)) fail(name, shortest(x) + ": must be " + rule);
    return v;
  }
  const h5::File& f_;
};

ContactLaw read_law(const Reader& r, const std::string& group, EffectSet effects) {
  ContactLaw law;
  for (const auto& k : contact_law_keys())
    if (!k.needs || has(effects, k.needs)) law.*k.field = r.checked(group + "/" + std::string(k.key), k.spec);
  return law;
}

StopCondition read_stop(const Reader& r) {
  StopCondition s;
  s.duration = r.checked("parameters/stop/duration", scene_key::duration);
  s.kinetic_energy_below = r.number_or("parameters/stop/kinetic_energy_below", -1.0);
  s.kinetic_energy_per_grain_below = r.number_or("parameters/stop/kinetic_energy_per_grain_below", -1.0);
  s.all_below = r.number_or("parameters/stop/all_below", 1e300);
  if (r.has("parameters/stop/free_time")) {
    s.body_free = r.text("parameters/stop", "body_free");
    s.free_time = r.checked("parameters/stop/free_time", scene_key::free_time);
  }
  if (s.energy_criterion() || !s.body_free.empty()) {  // written with a criterion that is checked
    s.check_interval = r.number("parameters/stop/check_interval");
    s.min_time = r.number("parameters/stop/min_time");
  }
  return s;
}

std::vector<MotionSegment> read_motion(const Reader& r, const std::string& group) {
  std::vector<MotionSegment> out;
  if (!r.has(group + "/motion")) return out;
  const std::int64_t n = r.integer(group + "/motion", "segments");
  for (std::int64_t j = 0; j < n; ++j) {
    const std::string g = group + "/motion/" + std::to_string(j);
    const std::string kind = r.text(g, "kind");
    const MotionKindSpec* spec = motion_kind_named(kind);
    if (!spec) r.fail(g + "@kind", "unknown motion kind '" + kind + "'");
    MotionSegment m;
    m.kind = spec->kind;
    if (spec->duration)  // none: a last constant segment that goes on for ever
      m.duration = spec->kind == MotionKind::constant && j + 1 == n && !r.has(g + "/duration")
                       ? std::numeric_limits<double>::infinity()
                       : r.number(g + "/duration");
    if (spec->velocity) {
      const std::vector<double> v = r.values(g + "/velocity");
      m.vx = v[0], m.vy = v[1];
      m.w = r.number_or(g + "/angular_velocity", 0.0);
    }
    if (spec->amplitude) {
      const std::vector<double> a = r.values(g + "/amplitude");
      m.ax = a[0], m.ay = a[1];
      m.aw = r.number_or(g + "/angle", 0.0);
    }
    if (spec->period) m.period = r.number(g + "/period");
    if (spec->cycles) m.cycles = r.count(g + "/cycles");
    out.push_back(m);
  }
  return out;
}

std::vector<BodySpec> read_bodies(const Reader& r) {
  std::vector<BodySpec> out;
  const std::int64_t n = r.integer("parameters", "bodies");
  for (std::int64_t k = 0; k < n; ++k) {
    const std::string g = "parameters/bodies/" + std::to_string(k);
    BodySpec b;
    b.name = r.text(g, "name");
    b.role = r.text(g, "role");
    b.shape = r.text(g, "shape");
    const std::vector<double> xy = r.values(g + "/vertices");
    for (std::size_t v = 0; v + 1 < xy.size(); v += 2) b.vertices.push_back({xy[v], xy[v + 1]});
    b.thickness = r.number(g + "/thickness");
    const std::vector<double> vel = r.values(g + "/velocity");
    b.vx = vel[0], b.vy = vel[1];
    b.remove_at = r.number_or(g + "/remove_at", -1.0);
    b.motion = read_motion(r, g);
    if (r.has(g + "/pivot")) {
      const std::vector<double> p = r.values(g + "/pivot");
      b.pivot = Point{p[0], p[1]};
    }
    b.motion_repeat = r.has(g + "/motion_repeat") ? r.count(g + "/motion_repeat") : 1;
    out.push_back(std::move(b));
  }
  return out;
}

}  // namespace

int RunParameters::find_role(std::string_view role) const {
  for (std::size_t b = 0; b < bodies.size(); ++b)
    if (bodies[b].role == role) return static_cast<int>(b);
  return -1;
}

bool has_parameters(const h5::File& f) { return h5::exists(f, "parameters"); }

namespace {

// Every value a group lists in its attribute `keys` is there (a reader that skips an optional value it
// misses would take a file with one deleted for one written without it).
void check_keys(const h5::File& f, const Reader& r) {
  std::vector<std::string> groups = {"parameters"};
  for (const std::string& g : h5::groups_under(f, "parameters")) groups.push_back("parameters/" + g);
  for (const std::string& g : groups) {
    if (!h5::has_attr(f, g, "keys")) continue;
    const std::string keys = h5::read_attr_string(f, g, "keys");
    for (std::size_t at = 0; at < keys.size();) {
      const std::size_t comma = std::min(keys.find(',', at), keys.size());
      const std::string key = keys.substr(at, comma - at);
      if (!key.empty() && !r.has(g + "/" + key)) r.fail(g + "/" + key, "missing");
      at = comma + 1;
    }
  }
}

}  // namespace

RunParameters read_parameters(const h5::File& f) {
  const Reader r(f);
  if (r.text("parameters", "format") != kParametersFormat)
    r.fail("parameters@format", std::string("'") + r.text("parameters", "format") + "', this reader knows " + kParametersFormat);
  check_keys(f, r);
  RunParameters p;
  p.name = r.text("parameters", "scene");
  for (const EffectName& e : kEffectNames)
    if (r.flag("parameters/effects/" + std::string(e.key))) p.effects |= e.bit;
  p.dt = r.checked("parameters/time/dt", scene_key::dt);
  p.dt_forced = r.flag("parameters/time/dt_forced");
  p.density = r.checked("parameters/material/density", scene_key::density);
  if (has(p.effects, effect::gravity)) {
    const std::vector<double> g = r.values("parameters/gravity/g");
    p.gx = g[0], p.gy = g[1];
  }
  p.grain_grain = read_law(r, "parameters/contact/grain_grain", p.effects);
  p.grain_body = has(p.effects, effect::walls) ? read_law(r, "parameters/contact/grain_body", p.effects) : p.grain_grain;
  p.stop = read_stop(r);
  p.output.series_interval = r.number("parameters/output/series_interval");
  p.output.snapshot_interval = r.number("parameters/output/snapshot_interval");
  p.output.checkpoint_interval = r.number("parameters/output/checkpoint_interval");
  p.output.displacement_window = r.number("parameters/output/displacement_window");
  p.output.energy_balance = r.flag("parameters/output/energy_balance");
  const std::vector<double> d = r.values("parameters/domain");
  p.domain = {d[0], d[1], d[2], d[3]};
  p.skin = r.number("parameters/neighbour/skin");
  p.bodies = read_bodies(r);
  if (r.has("parameters/jam")) {
    JamControl& c = p.jam;
    c.enabled = true;
    c.outlet_height = r.number("parameters/jam/outlet_height");
    c.start_time = r.number("parameters/jam/start_time");
    c.no_flow_time = r.number("parameters/jam/no_flow_time");
    c.check_interval = r.number("parameters/jam/check_interval");
    const std::vector<double> v = r.values("parameters/jam/tap_velocity");
    c.tap_vx = v[0], c.tap_vy = v[1];
    c.tap_duration = r.number("parameters/jam/tap_duration");
    c.max_taps = static_cast<int>(r.number("parameters/jam/max_taps"));
    c.bodies = h5::read_strings(f, "parameters/jam/bodies");
  }
  return p;
}

}  // namespace dem2d
