#include "scene/scene_toml.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <sstream>
#include <set>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/body_roles.hpp"
#include "core/key_spec.hpp"
#include "core/scene_keys.hpp"
#include "core/step_count.hpp"
#include "neighbour/cell_grid.hpp"
#include "scene/generators.hpp"
#include "scene/initial_state.hpp"
#include "shape/shape_kinds.hpp"
#include "toml/toml_reader.hpp"

namespace dem2d {
namespace {

using Pair = std::array<double, 2>;  // the TOML reader's [x, y]
constexpr double kOverlapTolerance = 1e-12;  // m: exact touching is not an overlap

// The scene's errors: SceneError (scene_toml.hpp), raised by the shared reader.
struct File : TomlFile {
  using TomlFile::TomlFile;

 protected:
  void raise(const std::string& message) const override { throw SceneError(message); }
};

// ---------------------------------------------------------------- sections

std::string effect_key(EffectSet bit) {
  for (const auto& e : kEffectNames)
    if (e.bit == bit) return "effects." + std::string(e.key);
  return "effects.?";
}

std::vector<std::string_view> law_keys(bool with_wall) {
  std::vector<std::string_view> keys;
  for (const auto& k : contact_law_keys()) keys.push_back(k.key);
  if (with_wall) keys.push_back("wall");
  return keys;
}

// base == nullptr: the particle-particle law (keys of enabled effects required);
// otherwise overrides of base (all optional).
ContactLaw read_law(const TableReader& r, EffectSet effects, const ContactLaw* base) {
  ContactLaw law = base ? *base : ContactLaw{};
  for (const LawKey<ContactLaw>& k : contact_law_keys()) {
    if (k.needs && !has(effects, k.needs)) {
      r.forbid(k.key, effect_key(k.needs) + " is false");
      continue;
    }
    const std::string why = k.needs ? "; required because " + effect_key(k.needs) + " is true" : "";
    if (!base)
      law.*k.field = r.required(k.key, k.spec, why);
    else if (const auto v = r.number(k.key, k.spec))
      law.*k.field = *v;
  }
  // conditions across the law's terms, named at the first of their keys the
  // table gives (a [contact.wall] law that gives none of them equals
  // [contact]'s, already checked)
  for (const LawIssue& issue : law_issues(law, effects))
    for (const std::string_view key : issue.keys)
      if (r.has(key)) r.fail(key, issue.message);
  return law;
}

// Where each particle came from, for messages.
struct Origin {
  std::size_t first;  // index of its first particle
  std::string label;  // "particle[3]" or "generator[0]"
  bool generated;
  const toml::source_region* where;
};

class SceneParser {
 public:
  SceneParser(const File& f, const toml::table& root, Scene& s)
      : f_(f),
        s_(s),
        top_(f, &root, "",
             {"name", "description", "allow_initial_overlap", "effects", "gravity", "material",
              "contact", "time", "stop", "domain", "neighbour", "initial", "particle", "generator",
              "body", "jam", "output"}) {}

  void run() {
    const auto stem = std::filesystem::path(s_.path).stem().string();
    s_.name = top_.string("name").value_or(stem.empty() ? "scene" : stem);
    top_.string("description");  // documentation only, kept in Scene::text
    const bool allow_overlap = top_.boolean("allow_initial_overlap").value_or(false);
    read_effects_and_physics();
    const TableReader time = read_time();
    read_stop_domain_output();
    read_initial();
    read_particles();
    read_generators();
    read_bodies();
    read_jam();
    if (s_.particles.empty())
      f_.fail(nullptr, "the scene has no particles: add [[particle]] entries or a [[generator]]");
    check_domain();
    if (!allow_overlap) check_overlaps();
    set_time_step(time);
    check_step_counts();
    check_neighbour_cells();
  }

 private:
  void read_effects_and_physics() {
    std::vector<std::string_view> keys;
    for (const auto& e : kEffectNames) keys.push_back(e.key);
    effects_ = top_.table("effects", keys);
    for (const auto& e : kEffectNames)
      if (effects_.boolean(e.key).value_or(false)) s_.effects |= e.bit;
    for (const EffectName& e : kEffectNames)
      if (has(s_.effects, e.bit) && e.needs != 0 && !has(s_.effects, e.needs))
        effects_.fail(e.key, "needs " + effect_key(e.needs) + " = true (" + effect_key(e.bit) + " acts on what it adds)");

    if (has(s_.effects, effect::gravity)) {
      const Pair g = top_.table("gravity", {"g"})
                         .required_vec2("g", scene_key::gravity,
                                        "; required because effects.gravity is true");
      s_.gx = g[0];
      s_.gy = g[1];
    } else {
      top_.forbid("gravity", "effects.gravity is false");
    }
    s_.density = top_.table("material", {"density"})
                     .required("density", scene_key::density);

    const TableReader contact = top_.table("contact", law_keys(true));
    s_.particle_particle = read_law(contact, s_.effects, nullptr);
    s_.particle_wall = s_.particle_particle;
    if (has(s_.effects, effect::walls))
      s_.particle_wall =
          read_law(contact.table("wall", law_keys(false)), s_.effects, &s_.particle_particle);
    else
      contact.forbid("wall", "effects.walls is false");
  }

  TableReader read_time() {
    TableReader t = top_.table("time", {"duration", "dt", "dt_over_critical", "force_dt"});
    s_.stop.duration = t.required("duration", scene_key::duration);
    time_key(t, "duration", s_.stop.duration, "to run without end, stop it by [stop] and give a duration it does not reach");
    t.number("dt", scene_key::dt);
    t.number("dt_over_critical",
             {"time step as a fraction of dt_c = sqrt(m_min/k_n)", "", Rule::positive});
    if (t.has("dt") && t.has("dt_over_critical"))
      t.fail("dt_over_critical",
             "time.dt is also given: give exactly one of time.dt and time.dt_over_critical");
    if (!t.has("dt") && !t.has("dt_over_critical"))
      t.missing("dt",
                "time step in s, > 0; or give time.dt_over_critical, a fraction of dt_c, > 0");
    s_.dt_forced = t.boolean("force_dt").value_or(false);
    return t;
  }

  void read_stop_domain_output() {
    stop_ = top_.table("stop", {"kinetic_energy_below", "kinetic_energy_per_grain_below", "all_below", "body_free",
                                "free_time", "check_interval", "min_time"});
    const TableReader& st = stop_;
    StopCondition& stop = s_.stop;
    if (st.has("kinetic_energy_below") && st.has("kinetic_energy_per_grain_below"))
      st.fail("kinetic_energy_per_grain_below",
              "stop.kinetic_energy_below is also given: give one of the two (total, or per active grain)");
    const auto ke = st.number("kinetic_energy_below", scene_key::kinetic_energy_below);
    const auto ke_grain = st.number("kinetic_energy_per_grain_below",
                                    scene_key::kinetic_energy_per_grain_below);
    if (ke || ke_grain) {
      stop.kinetic_energy_below = ke.value_or(-1.0);
      stop.kinetic_energy_per_grain_below = ke_grain.value_or(-1.0);
      stop.all_below = st.number_or("all_below", scene_key::all_below, 1e300);
    } else {
      st.forbid("all_below", "no kinetic energy criterion (kinetic_energy_below, kinetic_energy_per_grain_below) is");
    }
    if (const auto body = st.string("body_free")) {
      stop.body_free = *body;
      stop.free_time = st.required("free_time", scene_key::free_time,
                                   "; required because stop.body_free is given");
      time_key(st, "free_time", stop.free_time, "to never stop this way, leave stop.body_free out");
    } else {
      st.forbid("free_time", "stop.body_free is not");
    }
    if (stop.energy_criterion() || !stop.body_free.empty()) {
      stop.check_interval = st.required("check_interval", scene_key::check_interval,
                                        "; required because a stop criterion is given");
      stop.min_time = st.number_or("min_time", scene_key::min_time, 0.0);
      time_key(st, "check_interval", stop.check_interval, "to never check, leave the stop criteria out");
      time_key(st, "min_time", stop.min_time, "to never check, leave the stop criteria out");
    } else {
      const std::string none = "no stop criterion (kinetic_energy_below, kinetic_energy_per_grain_below, body_free) is";
      st.forbid("check_interval", none);
      st.forbid("min_time", none);
    }

    const TableReader d = top_.table("domain", {"xmin", "xmax", "ymin", "ymax"});
    const Num coord = scene_key::domain_bound;
    s_.domain = {d.required("xmin", coord), d.required("ymin", coord), d.required("xmax", coord),
                 d.required("ymax", coord)};
    if (!(s_.domain.xmax > s_.domain.xmin))
      d.fail("xmax", "must be > domain.xmin = " + shortest(s_.domain.xmin) + " (m)");
    if (!(s_.domain.ymax > s_.domain.ymin))
      d.fail("ymax", "must be > domain.ymin = " + shortest(s_.domain.ymin) + " (m)");

    skin_ = top_.table("neighbour", {"skin"})
                .number_or("skin", scene_key::skin, -1.0);

    const TableReader o = top_.table(
        "output", {"series_interval", "snapshot_interval", "checkpoint_interval", "displacement_window", "energy_balance"});
    const Num every = scene_key::output_interval;
    s_.output = {o.number_or("series_interval", every, 0.0),
                 o.number_or("snapshot_interval", every, 0.0),
                 o.number_or("checkpoint_interval", scene_key::checkpoint_interval,
                             scene_key::kDefaultCheckpointInterval),
                 o.number_or("displacement_window",
                             scene_key::displacement_window,
                             0.0),
                 o.boolean("energy_balance").value_or(false)};
    time_key(o, "series_interval", s_.output.series_interval, "to write none, set 0 (off)");
    time_key(o, "snapshot_interval", s_.output.snapshot_interval, "to write none, set 0 (off)");
    time_key(o, "displacement_window", s_.output.displacement_window, "to record none, set 0 (off)");
    if (s_.output.energy_balance && s_.output.series_interval <= 0.0)
      o.fail("energy_balance", "the balance is recorded in the time series: set output.series_interval > 0");
    if (s_.output.energy_balance && has(s_.effects, effect::cohesion))
      o.fail("energy_balance", "the energy ledger does not yet count the cohesive potential "
                               "(effects.cohesion is true): remove one of the two");
    if (s_.output.displacement_window > s_.output.snapshot_interval)
      o.fail("displacement_window", "must be <= output.snapshot_interval = " +
                                        shortest(s_.output.snapshot_interval) + " s (and snapshots on)");
  }

  void read_initial() {
    const TableReader t = top_.table("initial", {"run"});
    if (!top_.has("initial")) return;
    const auto run = t.string("run");
    if (!run) t.missing("run", "run file whose final state the grains start from");
    if (top_.has("particle") || top_.has("generator"))
      t.fail("run", "the grains come from this run: remove [[particle]] and [[generator]]");
    std::filesystem::path file(*run);
    if (file.is_relative()) file = std::filesystem::path(s_.path).parent_path() / file;
    try {
      load_initial_state(file.lexically_normal().string(), s_);
    } catch (const std::exception& e) {
      t.fail("run", std::string("cannot start from it: ") + e.what());
    }
    origins_.push_back({0, "the initial run " + file.lexically_normal().string(), true, t.where()});
  }

  void read_particles() {
    const Num coord{"centre coordinate", "m", Rule::finite}, vel{"velocity", "m/s", Rule::finite};
    for (const TableReader& p : top_.entries("particle", {"x", "y", "d", "vx", "vy", "omega"})) {
      origins_.push_back({s_.particles.size(),
                          "particle[" + std::to_string(s_.particles.size()) + "]", false,
                          p.where()});
      s_.particles.push_back(
          {p.required("x", coord), p.required("y", coord),
           p.required("d", {"diameter", "m", Rule::positive}), p.number_or("vx", vel, 0.0),
           p.number_or("vy", vel, 0.0),
           p.number_or("omega", {"angular velocity", "rad/s", Rule::finite}, 0.0)});
    }
  }

  void read_generators() {
    const auto gens = top_.entries(
        "generator", {"kind", "count", "seed", "diameter", "region", "spacing", "velocity"});
    for (std::size_t k = 0; k < gens.size(); ++k) {
      const TableReader& g = gens[k];
      const auto kind = g.string("kind");
      if (!kind) g.missing("kind", "generator kind, one of: triangular_lattice");
      if (*kind != "triangular_lattice")
        g.fail("kind", "unknown generator kind (allowed: triangular_lattice)");
      LatticeSpec spec;
      spec.count = g.integer("count", 1, "number of grains");
      spec.seed = static_cast<std::uint64_t>(g.integer("seed", 0, "random seed of the diameters"));
      if (!g.has("diameter"))
        g.missing("diameter", "{ min = ..., max = ... }, diameters in m, 0 < min <= max");
      const TableReader dm = g.table("diameter", {"min", "max"});
      spec.d_min = dm.required("min", {"smallest diameter", "m", Rule::positive});
      spec.d_max = dm.required("max", {"largest diameter", "m", Rule::positive});
      if (spec.d_max < spec.d_min)
        dm.fail("max", "must be >= " + dm.path("min") + " = " + shortest(spec.d_min) + " (m)");
      spec.region = read_polygon(g);
      if (const auto sp = g.number("spacing", {"lattice spacing", "m", Rule::positive})) {
        if (*sp < spec.d_max)
          g.fail("spacing", "must be >= " + dm.path("max") + " = " + shortest(spec.d_max) + " (m)");
        spec.spacing = *sp;
      }
      const Pair v =
          g.vec2("velocity", {"initial velocity", "m/s", Rule::finite}).value_or(Pair{0.0, 0.0});
      spec.vx = v[0];
      spec.vy = v[1];
      std::vector<ParticleInit> grains;
      try {
        grains = triangular_lattice(spec);
      } catch (const std::invalid_argument& e) {
        f_.fail(g.where(), "generator[" + std::to_string(k) + "]: " + e.what());
      }
      origins_.push_back(
          {s_.particles.size(), "generator[" + std::to_string(k) + "]", true, g.where()});
      s_.particles.insert(s_.particles.end(), grains.begin(), grains.end());
    }
  }

  std::vector<Pair> read_polygon(const TableReader& g) const {
    return read_points(g, "region", {"polygon vertex", "m", Rule::finite}, 3);
  }

  // A list of points [[x0, y0], [x1, y1], ...] of at least `min` entries.
  std::vector<Pair> read_points(const TableReader& g, std::string_view key, const Num& spec, std::size_t min = 1) const {
    const std::string what = std::string("list of points [[x0, y0], [x1, y1], ...] in ") + spec.unit + ", >= " +
                             std::to_string(min) + (min == 1 ? " point" : " points");
    const toml::node* n = g.node(key);
    if (!n) g.missing(key, what);
    const toml::array* a = n->as_array();
    if (!a || a->size() < min) g.fail(key, "must be a " + what);
    std::vector<Pair> pts;
    for (std::size_t k = 0; k < a->size(); ++k)
      pts.push_back(g.vec2_at(*a->get(k), g.path(key) + "[" + std::to_string(k) + "]", spec));
    return pts;
  }

  void read_bodies() {
    std::vector<std::string_view> keys{"name", "role", "shape", "thickness", "velocity", "motion", "motion_repeat", "pivot",
                                       "remove_at"};
    std::vector<std::string_view> kinds;
    for (const ShapeKind& k : shape_kinds()) {
      kinds.push_back(k.name);
      for (const ShapeKey& key : k.keys)
        if (std::find(keys.begin(), keys.end(), key.name) == keys.end()) keys.push_back(key.name);
    }
    const auto bodies = top_.entries("body", keys);
    if (!bodies.empty() && !has(s_.effects, effect::walls))
      f_.fail(bodies.front().where(),
              "[[body]] given but effects.walls is false (bodies need effects.walls = true)");
    if (bodies.empty() && has(s_.effects, effect::walls))
      effects_.fail("walls", "the scene has no [[body]] (walls need at least one body)");
    bool any_moving = false;
    for (std::size_t k = 0; k < bodies.size(); ++k) {
      const TableReader& b = bodies[k];
      BodySpec body;
      const auto name = b.string("name");
      if (!name) b.missing("name", "a unique, non-empty string");
      for (std::size_t j = 0; j < k; ++j)
        if (s_.bodies[j].name == *name)
          b.fail("name", "duplicate name: body[" + std::to_string(j) + "] has it already");
      body.name = *name;
      body.role = b.string("role").value_or("");
      if (const BodyRole* role = find_body_role(body.role); !body.role.empty()) {
        if (!role) b.fail("role", "unknown role (allowed: " + body_role_names() + ")");
        for (std::size_t j = 0; j < k; ++j)
          if (role->unique && s_.bodies[j].role == body.role)
            b.fail("role", "body[" + std::to_string(j) + "] '" + s_.bodies[j].name + "' has this role already (one body at most)");
      }
      body.shape = b.string("shape").value_or("segment");
      const ShapeKind* kind = find_shape_kind(body.shape);
      if (!kind) b.fail("shape", "unknown shape kind (allowed: " + join(kinds) + ")");
      body.thickness = b.required("thickness", scene_key::thickness);
      body.vertices = read_shape(b, *kind, body.thickness);
      const Pair v =
          b.vec2("velocity", scene_key::body_velocity).value_or(Pair{0.0, 0.0});
      body.vx = v[0], body.vy = v[1];
      if ((v[0] != 0.0 || v[1] != 0.0) && !has(s_.effects, effect::moving_bodies))
        b.fail("velocity", "a non-zero velocity needs effects.moving_bodies = true");
      any_moving = any_moving || v[0] != 0.0 || v[1] != 0.0;
      read_motion(b, body);
      any_moving = any_moving || !body.motion.empty();
      body.remove_at = b.number_or("remove_at", scene_key::remove_at, -1.0);
      time_key(b, "remove_at", body.remove_at, "to keep the body, leave remove_at out");
      s_.bodies.push_back(body);
    }
    if (has(s_.effects, effect::moving_bodies) && !any_moving && !top_.has("jam"))
      effects_.fail("moving_bodies",
                    "no [[body]] has a non-zero velocity and there is no [jam] to tap bodies (remove the "
                    "effect or give a body a velocity)");
    const auto turns = [](const BodySpec& q) {
      return std::any_of(q.motion.begin(), q.motion.end(), [](const MotionSegment& m) { return m.w != 0.0 || m.aw != 0.0; });
    };
    if (has(s_.effects, effect::rotating_bodies) && std::none_of(s_.bodies.begin(), s_.bodies.end(), turns))
      effects_.fail("rotating_bodies", "no [[body]] motion turns (remove the effect or give a segment an angular_velocity or angle)");
    if (!s_.stop.body_free.empty() && !has_body(s_.stop.body_free))
      stop_.fail("body_free", "names no [[body]]");
  }

  // The keys of the body's shape kind (shape/shape_kinds.hpp) and its core outline.
  std::vector<Point> read_shape(const TableReader& b, const ShapeKind& kind, double thickness) const {
    for (const ShapeKind& other : shape_kinds())
      for (const ShapeKey& key : other.keys)
        if (std::none_of(kind.keys.begin(), kind.keys.end(), [&](const ShapeKey& k) { return k.name == std::string_view(key.name); }))
          b.forbid(key.name, std::string("a ") + kind.name + " does not take it");
    ShapeArgs args;
    args.thickness = thickness;
    const std::string why = std::string(" (shape = \"") + kind.name + "\")";
    for (const ShapeKey& key : kind.keys) {
      const Num spec{key.what, key.unit, Rule::finite};
      if (key.required && !b.has(key.name)) b.missing(key.name, range_text(spec) + why);
      if (key.type == ShapeKey::number) {
        args.number[key.name] = b.number_or(key.name, spec, key.fallback);
      } else if (key.type == ShapeKey::point) {
        const Pair v = b.required_vec2(key.name, spec, why);
        args.point[key.name] = {v[0], v[1]};
      } else {
        std::vector<Point>& pts = args.points[key.name];
        for (const Pair& v : read_points(b, key.name, spec)) pts.push_back({v[0], v[1]});
      }
    }
    try {
      return kind.outline(args);
    } catch (const ShapeError& e) {
      b.fail(e.key, e.what());
    }
  }

  // [[body]] motion = [{ kind = "...", ... }, ...] and motion_repeat (core/motion.hpp).
  void read_motion(const TableReader& b, BodySpec& body) {
    if (!b.has("motion")) {
      b.forbid("motion_repeat", "the body has no motion");
      b.forbid("pivot", "the body has no motion to turn it");
      return;
    }
    if (b.has("velocity")) b.fail("motion", "give either velocity or motion, not both");
    if (!has(s_.effects, effect::moving_bodies)) b.fail("motion", "a motion needs effects.moving_bodies = true");
    std::vector<std::string_view> kinds;
    for (const MotionKindSpec& k : kMotionKinds) kinds.push_back(k.name);
    const auto segments =
        b.entries("motion", {"kind", "duration", "velocity", "angular_velocity", "amplitude", "angle", "period", "cycles"});
    if (segments.empty()) b.fail("motion", "must list at least one segment");
    for (std::size_t k = 0; k < segments.size(); ++k) {
      const TableReader& m = segments[k];
      const auto kind = m.string("kind");
      if (!kind) m.missing("kind", "one of " + join(kinds));
      const MotionKindSpec* spec = motion_kind_named(*kind);
      if (!spec) m.fail("kind", "unknown motion kind (allowed: " + join(kinds) + ")");
      MotionSegment seg;
      seg.kind = spec->kind;
      const std::string why = " (" + *kind + ")";
      const auto take = [&](bool takes, std::string_view key) {
        if (!takes) m.forbid(key, "a " + *kind + " segment does not take it");
        return takes;
      };
      const bool last = k + 1 == segments.size();
      if (take(spec->duration, "duration")) {
        // a last constant segment may go on for ever (until the run stops)
        if (spec->kind == MotionKind::constant && last && !m.has("duration"))
          seg.duration = std::numeric_limits<double>::infinity();
        else
          seg.duration = m.required("duration", scene_key::segment_duration, why);
      }
      // a rate or an amplitude: its translation, its turn, or both (the one left out is 0)
      const auto pair = [&](bool takes, std::string_view move, const Num& move_spec, std::string_view turn,
                            const Num& turn_spec, double& x, double& y, double& w) {
        const bool takes_move = take(takes, move), takes_turn = take(takes, turn);  // (both: each unwanted key refused)
        if (!takes_move || !takes_turn) return;
        if (!m.has(move) && !m.has(turn))
          m.missing(move, range_text(move_spec) + why + ", or " + std::string(turn) + " (" + range_text(turn_spec) + ")");
        const Pair v = m.vec2(move, move_spec).value_or(Pair{0.0, 0.0});
        x = v[0], y = v[1];
        w = m.number_or(turn, turn_spec, 0.0);
        if (w != 0.0 && !has(s_.effects, effect::rotating_bodies))
          m.fail(turn, "turning a body needs effects.rotating_bodies = true");
      };
      pair(spec->velocity, "velocity", scene_key::segment_velocity, "angular_velocity", scene_key::angular_velocity,
           seg.vx, seg.vy, seg.w);
      pair(spec->amplitude, "amplitude", scene_key::amplitude, "angle", scene_key::angle, seg.ax, seg.ay, seg.aw);
      if (take(spec->period, "period")) seg.period = m.required("period", scene_key::period, why);
      const char* forever = "to move on for ever, leave the last constant segment's duration out";
      if (std::isfinite(seg.duration)) time_key(m, "duration", seg.duration, forever, true);
      time_key(m, "period", seg.period, forever, true);
      if (take(spec->cycles, "cycles"))
        seg.cycles = static_cast<int>(m.integer_or("cycles", 1, "number of cycles", 1, kMaxMotionPieces));
      if (std::isinf(seg.duration) && b.has("motion_repeat"))
        b.fail("motion_repeat", "the last segment lasts for ever (constant without a duration): it cannot repeat");
      body.motion.push_back(seg);
    }
    body.motion_repeat = static_cast<int>(b.integer_or("motion_repeat", 1, "runs of the whole motion", 1, kMaxMotionPieces));
    if (const std::int64_t pieces = motion_pieces(body.motion, body.motion_repeat); pieces > kMaxMotionPieces)
      b.fail("motion_repeat", "runs of the motion times its segments' cycles: more than " +
                                  std::to_string(kMaxMotionPieces) + " pieces, the schedule's limit");
    if (const auto p = b.vec2("pivot", scene_key::pivot)) {
      // within the domain widened by its own size on every side: a body turned about a point much farther
      // away sweeps out of the domain at once, and far enough its vertices lose their digits (a pivot at 1e300
      // collapsed a wall to a point)
      const Box& d = s_.domain;
      const double w = d.xmax - d.xmin, h = d.ymax - d.ymin;
      if (!Box{d.xmin - w, d.ymin - h, d.xmax + w, d.ymax + h}.contains((*p)[0], (*p)[1]))
        b.fail("pivot", "lies farther from the domain [" + shortest(d.xmin) + ", " + shortest(d.xmax) + "] x [" +
                            shortest(d.ymin) + ", " + shortest(d.ymax) + "] m than its own width or height: put it "
                            "within [" + shortest(d.xmin - w) + ", " + shortest(d.xmax + w) + "] x [" +
                            shortest(d.ymin - h) + ", " + shortest(d.ymax + h) + "] m");
      body.pivot = Point{(*p)[0], (*p)[1]};
    }
  }

  bool has_body(const std::string& name) const {
    return std::any_of(s_.bodies.begin(), s_.bodies.end(), [&](const BodySpec& b) { return b.name == name; });
  }

  void read_jam() {
    const TableReader j = top_.table("jam", {"outlet_height", "start_time", "no_flow_time", "check_interval",
                                             "bodies", "tap_velocity", "tap_duration", "max_taps"});
    if (!top_.has("jam")) return;
    if (!has(s_.effects, effect::moving_bodies))
      f_.fail(j.where(), "[jam] taps hopper walls, which needs effects.moving_bodies = true");
    JamControl& c = s_.jam;
    c.enabled = true;
    c.outlet_height = j.required("outlet_height", scene_key::outlet_height);
    c.start_time = j.number_or("start_time", scene_key::jam_start_time, 0.0);
    c.no_flow_time = j.required("no_flow_time", scene_key::no_flow_time);
    c.check_interval = j.number_or("check_interval", scene_key::check_interval,
                                   c.no_flow_time / 10.0);
    c.bodies = j.strings("bodies", "the hopper walls tapped to clear a jam");
    for (const std::string& name : c.bodies)
      if (!has_body(name)) j.fail("bodies", "'" + name + "' names no [[body]]");
    const Pair v = j.required_vec2("tap_velocity", scene_key::tap_velocity);
    c.tap_vx = v[0];
    c.tap_vy = v[1];
    c.tap_duration = j.required("tap_duration", scene_key::tap_duration);
    c.max_taps = static_cast<int>(j.integer_or("max_taps", 1, "taps before giving up", 20, 1000000));
    time_key(j, "start_time", c.start_time, "to never watch for jams, leave [jam] out");
    time_key(j, "no_flow_time", c.no_flow_time, "to never watch for jams, leave [jam] out");
    time_key(j, "check_interval", c.check_interval, "to never watch for jams, leave [jam] out");
    time_key(j, "tap_duration", c.tap_duration, "to never tap, leave [jam] out");
  }

  // ------------------------------------------------------------ whole-scene checks

  // A time (s) the engine counts in steps (core/step_count.hpp): checked once
  // dt is known. `never`: how to say "never" instead (the message's end).
  struct TimeKey {
    TableReader table;
    std::string key;
    double seconds;
    const char* never;
    bool resolved = false;  // at least one step of dt (a motion segment: its rate follows from its duration)
  };
  void time_key(const TableReader& t, std::string_view key, double seconds, const char* never, bool resolved = false) {
    if (t.has(key)) times_.push_back({t, std::string(key), seconds, never, resolved});
  }

  // Every time at most kMaxSteps steps of dt (> 0, set_time_step): a larger
  // count overflowed (a run that spun at step 0, or wrote a row every step).
  void check_step_counts() const {
    for (const TimeKey& t : times_) {
      if (!(t.seconds / s_.dt <= static_cast<double>(kMaxSteps)))
        t.table.fail(t.key, "is " + sig3(t.seconds / s_.dt) + " steps of dt = " + sig3(s_.dt) + " s, more than the " +
                                sig3(static_cast<double>(kMaxSteps)) + " a run can count; " + t.never);
      if (t.resolved && !(t.seconds >= s_.dt))
        t.table.fail(t.key, "is " + sig3(t.seconds / s_.dt) + " steps of dt = " + sig3(s_.dt) +
                                " s: a motion segment shorter than one time step cannot be followed (its rates "
                                "would be its displacement over less than a step)");
    }
  }

  const Origin& origin(std::size_t i) const {
    return *(std::upper_bound(origins_.begin(), origins_.end(), i,
                              [](std::size_t v, const Origin& o) { return v < o.first; }) -
             1);
  }
  std::string who(std::size_t i) const {  // "particle 57 (grain 3 of generator[0], line 20)"
    const Origin& o = origin(i);
    std::string s = "particle " + std::to_string(i) + " (";
    if (o.generated) s += "grain " + std::to_string(i - o.first) + " of ";
    s += o.label;
    if (o.where && o.where->begin.line > 0) s += ", line " + std::to_string(o.where->begin.line);
    return s + ")";
  }

  void check_domain() const {
    const Box& d = s_.domain;
    for (std::size_t i = 0; i < s_.particles.size(); ++i) {
      const ParticleInit& p = s_.particles[i];
      if (d.contains(p.x, p.y)) continue;
      f_.fail(origin(i).where, who(i) + " at (x, y) = (" + shortest(p.x) + ", " + shortest(p.y) +
                                   ") m lies outside the domain [xmin, xmax] x [ymin, ymax] = [" +
                                   shortest(d.xmin) + ", " + shortest(d.xmax) + "] x [" +
                                   shortest(d.ymin) + ", " + shortest(d.ymax) + "] m");
    }
  }

  // The neighbour search's cells (d_max + skin + range wide) must fit in
  // CellGrid::kMaxCells: a domain far larger than the grains is refused here,
  // by `check` as by `run`.
  void check_neighbour_cells() const {
    const Box& d = s_.domain;
    const double cell = s_.neighbour_cell_size();
    const double cells = CellGrid::cell_count(d.xmin, d.ymin, d.xmax, d.ymax, cell);
    if (cells <= CellGrid::kMaxCells) return;
    top_.table("domain", {"xmin", "xmax", "ymin", "ymax"})
        .fail("xmax", "the domain [" + shortest(d.xmin) + ", " + shortest(d.xmax) + "] x [" + shortest(d.ymin) + ", " +
                shortest(d.ymax) + "] m holds " + sig3(cells) + " neighbour-search cells of " + sig3(cell) +
                " m (the largest grain plus the skin and the contact range), more than the " + sig3(CellGrid::kMaxCells) +
                " the engine can index: shrink [domain] to where the grains can go");
  }

  // Grains overlapping each other or a body at t = 0. The grains of an
  // initial run touch each other and the bodies they touched there: that is
  // their state. A body that overlaps a grain it did not touch (one placed
  // into the bed) is refused like a generated grain's overlap.
  void check_overlaps() const {
    if (s_.initial_run.empty()) check_grain_overlaps();
    check_body_overlaps();
  }

  void check_grain_overlaps() const {
    const auto& ps = s_.particles;
    const std::size_t n = ps.size();
    double d_max = 0.0, x0 = ps[0].x, x1 = x0, y0 = ps[0].y, y1 = y0;
    for (const auto& p : ps) {
      d_max = std::max(d_max, p.d);
      x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y),
      y1 = std::max(y1, p.y);
    }
    // Hashed cells of width >= d_max: every overlapping partner lies in the 3x3
    // block around a grain's cell, and empty cells cost nothing however sparse
    // the scene. Each cell lists its grains in ascending order (head / next).
    const double cell = std::max({d_max, (x1 - x0) * 0x1.0p-30, (y1 - y0) * 0x1.0p-30});
    const auto coord = [&](double v, double v0) {
      return static_cast<std::int64_t>((v - v0) / cell);
    };
    const auto key = [](std::int64_t cx, std::int64_t cy) {
      return static_cast<std::uint64_t>(cx << 32 | cy);
    };
    std::unordered_map<std::uint64_t, std::size_t> head;
    head.reserve(n);
    std::vector<std::size_t> next(n, n);
    for (std::size_t i = n; i-- > 0;) {
      auto [it, fresh] = head.try_emplace(key(coord(ps[i].x, x0), coord(ps[i].y, y0)), i);
      if (!fresh) next[i] = std::exchange(it->second, i);
    }
    const auto depth = [&](std::size_t i, std::size_t j) {
      return 0.5 * (ps[i].d + ps[j].d) - std::hypot(ps[i].x - ps[j].x, ps[i].y - ps[j].y);
    };
    for (std::size_t i = 0; i < n; ++i) {
      std::size_t first = n;  // lowest j > i overlapping i
      const std::int64_t cx = coord(ps[i].x, x0), cy = coord(ps[i].y, y0);
      for (std::int64_t gy = cy - 1; gy <= cy + 1; ++gy)
        for (std::int64_t gx = cx - 1; gx <= cx + 1; ++gx) {
          if (gx < 0 || gy < 0) continue;
          const auto it = head.find(key(gx, gy));
          for (std::size_t j = it == head.end() ? n : it->second; j < first; j = next[j])
            if (j > i && depth(i, j) > kOverlapTolerance) first = j;
        }
      if (first == n) continue;
      f_.fail(origin(first).where,
              who(i) + " and " + who(first) + " overlap by " + sig3(depth(i, first)) + " m (" +
                  sig3(100.0 * depth(i, first) / std::min(ps[i].d, ps[first].d)) +
                  "% of the smaller diameter); set allow_initial_overlap = true to accept");
    }
  }

  void check_body_overlaps() const {
    const auto& ps = s_.particles;
    std::set<std::pair<std::int32_t, std::string_view>> touched;  // (grain, body) in contact in the initial run
    for (const InitialContact& c : s_.initial_contacts)
      if (c.j < 0) touched.emplace(c.i, c.body);
    std::size_t count = 0, worst_i = 0, worst_k = 0;
    double worst = 0.0;
    for (std::size_t k = 0; k < s_.bodies.size(); ++k) {
      const BodySpec& b = s_.bodies[k];
      const Shape shape = make_shape(b.vertices);
      for (std::size_t i = 0; i < ps.size(); ++i) {
        const double overlap = 0.5 * (ps[i].d + b.thickness) - closest_point(shape, ps[i].x, ps[i].y).dist;
        if (!(overlap > kOverlapTolerance) || touched.contains({static_cast<std::int32_t>(i), b.name})) continue;
        ++count;
        if (overlap > worst) worst = overlap, worst_i = i, worst_k = k;
      }
    }
    if (count == 0) return;
    const std::string others = count > 1 ? " (the deepest of " + std::to_string(count) + " such overlaps)" : "";
    f_.fail(origin(worst_i).where,
            who(worst_i) + " overlaps body '" + s_.bodies[worst_k].name + "' by " + sig3(worst) + " m (" +
                sig3(100.0 * worst / ps[worst_i].d) + "% of its diameter)" + others +
                (s_.initial_run.empty() ? "" : ", a contact the initial run did not have: the body was placed into "
                                               "the bed; move it, or take out the grains it overlaps") +
                "; set allow_initial_overlap = true to accept (overlapping grains are pushed out at once)");
  }

  void set_time_step(const TableReader& t) {
    std::size_t smallest = 0;
    for (std::size_t i = 1; i < s_.particles.size(); ++i)
      if (s_.particles[i].d < s_.particles[smallest].d) smallest = i;
    const double d_min = s_.particles[smallest].d;
    s_.skin = skin_ > 0.0 ? skin_ : 0.25 * d_min;

    const double dt_c = s_.critical_dt();
    const bool fraction = t.has("dt_over_critical");
    if (!(dt_c > 0.0))
      t.fail(fraction ? "dt_over_critical" : "dt",
             "the smallest grain, " + who(smallest) + " (d = " + sig3(d_min) + " m), has dt_c = sqrt(m_min/k_n) = " +
                 sig3(dt_c) + " s: its mass underflows, no time step resolves it");
    const double given = *t.number(fraction ? "dt_over_critical" : "dt", {"", "", Rule::positive});
    s_.dt = fraction ? given * dt_c : given;
    if (!(s_.dt > 0.0))  // a fraction of dt_c that underflows
      t.fail("dt_over_critical", "gives dt = " + sig3(s_.dt) + " s (dt_c = " + sig3(dt_c) + " s): the time step must be > 0");
    const StabilityLimit limit = s_.stability_limit();
    if (s_.dt <= limit.dt || s_.dt_forced) return;
    const std::string bound =
        "the stability limit dt_s = " + sig3(limit.dt) + " s = " + sig3(limit.dt / dt_c) +
        " dt_c (dt_c = sqrt(m_min/k_n) = " + sig3(dt_c) +
        " s): above it velocity Verlet, with dashpots fed the half-step velocity, is unstable on a dense "
        "(hexagonal) packing of the smallest grains (d = " + sig3(d_min) + " m) under this contact law; its "
        "fastest mode is " + limit.mode;
    if (fraction)
      t.fail("dt_over_critical", "must be <= " + sig3(limit.dt / dt_c) + ": it gives dt = " + sig3(s_.dt) +
                                     " s, above " + bound +
                                     "; use a smaller fraction, or set time.force_dt = true");
    t.fail_after("dt",
                 " s exceeds " + bound +
                     "; use a smaller dt, time.dt_over_critical, or set time.force_dt = true");
  }

  const File& f_;
  Scene& s_;
  TableReader top_;
  TableReader effects_{f_, nullptr, "effects", {}};
  TableReader stop_{f_, nullptr, "stop", {}};
  std::vector<Origin> origins_;
  std::vector<TimeKey> times_;
  double skin_ = -1.0;
};


toml::table parse_toml(std::string_view text, const std::string& path) {
  return File(path.empty() ? "<scene>" : path).parse(text);
}

Scene parse_table(const toml::table& root, std::string text, const std::string& path) {
  const File f(path.empty() ? "<scene>" : path);
  Scene s;
  s.path = path;
  s.text = std::move(text);
  SceneParser(f, root, s).run();
  return s;
}

// An array of tables each with a string `name` (e.g. [[body]]).
bool named_tables(const toml::node& n) {
  const toml::array* a = n.as_array();
  if (!a || a->empty() || !a->is_array_of_tables()) return false;
  for (const toml::node& e : *a)
    if (!e.as_table()->get_as<std::string>("name")) return false;
  return true;
}

// Overlay tables merge key by key; arrays of named tables merge element by
// element by name (an unknown name is appended); anything else replaces. An
// overlay [[body]] that changes the body's shape replaces its outline: the
// old shape's keys are dropped.
// Nodes are moved, not copied: a copy would lose its source (file, line),
// and error messages name the overlay a key came from.
void merge_into(toml::table& base, toml::table&& over);

void merge_by_name(toml::array& base, toml::array&& over) {
  for (toml::node& e : over) {
    toml::table& t = *e.as_table();
    const std::string name = t.get_as<std::string>("name")->get();
    toml::table* match = nullptr;
    for (toml::node& b : base)
      if (b.as_table()->get_as<std::string>("name")->get() == name) match = b.as_table();
    const auto shape_of = [](const toml::table& b) { return b.get_as<std::string>("shape") ? b.get_as<std::string>("shape")->get() : std::string("segment"); };
    if (match && t.contains("shape") && shape_of(t) != shape_of(*match))
      for (const ShapeKind& kind : shape_kinds())
        for (const ShapeKey& key : kind.keys) match->erase(key.name);
    if (match)
      merge_into(*match, std::move(t));
    else
      base.push_back(std::move(t));
  }
}

void merge_into(toml::table& base, toml::table&& over) {
  for (auto&& [key, value] : over) {
    toml::node* old = base.get(key);
    if (old && old->is_table() && value.is_table())
      merge_into(*old->as_table(), std::move(*value.as_table()));
    else if (old && named_tables(*old) && named_tables(value))
      merge_by_name(*old->as_array(), std::move(*value.as_array()));
    else
      value.visit([&base, &key](auto&& v) { base.insert_or_assign(key, std::move(v)); });
  }
}

}  // namespace

Scene parse_scene(std::string_view text, const std::string& path_for_messages) {
  return parse_table(parse_toml(text, path_for_messages), std::string(text), path_for_messages);
}

Scene load_scene(const std::string& path, const SceneSources& extra) {
  std::string text = File(path).read("scene file");
  if (extra.overlays.empty() && extra.initial_run.empty()) return parse_scene(text, path);
  toml::table root = parse_toml(text, path);
  for (const std::string& overlay : extra.overlays)
    merge_into(root, parse_toml(File(overlay).read("overlay file"), overlay));
  if (!extra.initial_run.empty()) {
    if (!root.contains("initial")) root.insert("initial", toml::table{});
    root.get_as<toml::table>("initial")->insert_or_assign(
        "run", std::filesystem::absolute(extra.initial_run).lexically_normal().string());
  }
  std::ostringstream merged;
  merged << "# " << path;
  for (const std::string& overlay : extra.overlays) merged << " + " << overlay;
  if (!extra.initial_run.empty()) merged << " + initial run " << extra.initial_run;
  merged << "\n" << root << "\n";
  return parse_table(root, merged.str(), path);
}

}  // namespace dem2d
