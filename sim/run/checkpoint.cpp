#include "run/checkpoint.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "contact/contact_model.hpp"
#include "core/version.hpp"
#include "runfile/h5.hpp"
#include "runfile/h5_seal.hpp"
#include "runfile/run_format.hpp"
#include "writer/run_file.hpp"

namespace dem2d {

namespace {

// The particle arrays a checkpoint stores, by name.
template <class P>
auto particle_arrays(P& p) {
  return std::array{std::pair{"x", &p.x},         std::pair{"y", &p.y},     std::pair{"vx", &p.vx},
                    std::pair{"vy", &p.vy},       std::pair{"theta", &p.theta},
                    std::pair{"omega", &p.omega}, std::pair{"fx", &p.fx},   std::pair{"fy", &p.fy},
                    std::pair{"torque", &p.torque}};
}

// The body motion state a checkpoint stores (positions follow from it).
template <class B>
auto body_arrays(B& b) {
  return std::array{std::pair{"vx", &b.vx},       std::pair{"vy", &b.vy},       std::pair{"omega", &b.omega},
                    std::pair{"angle", &b.angle}, std::pair{"anchor_x", &b.anchor_x}, std::pair{"anchor_y", &b.anchor_y}};
}

// Acting contacts of a list (contact_model.hpp's `acted`): (row, key) and
// every carried per-slot array (history, last evaluation) as columns.
template <class List>
void write_history(const h5::File& f, const std::string& group, const List& L,
                   const AlignedVector<std::int32_t>& key, bool gaps) {
  std::vector<std::int32_t> row, col;
  std::vector<std::size_t> slots;
  for (std::size_t i = 0; i + 1 < L.start.size(); ++i)
    for (auto s = static_cast<std::size_t>(L.start[i]); s < static_cast<std::size_t>(L.start[i + 1]); ++s)
      if (acted(L.overlap[s], gaps)) {
        row.push_back(static_cast<std::int32_t>(i));
        col.push_back(key[s]);
        slots.push_back(s);
      }
  h5::write(f, group + "/row", row);
  h5::write(f, group + "/key", col);
  for (const auto& [name, a] : List::carried()) {
    std::vector<double> column;
    for (const std::size_t s : slots) column.push_back((L.*a)[s]);
    h5::write(f, group + "/" + name, column);
  }
}

// Puts the stored contacts back into the freshly rebuilt lists.
template <class List>
void read_history(const h5::File& f, const std::string& group, List& L, const NeighbourLists& lists, bool walls) {
  const auto row = h5::read<std::int32_t>(f, group + "/row");
  const auto col = h5::read<std::int32_t>(f, group + "/key");
  std::vector<std::int64_t> slot(row.size());
  for (std::size_t c = 0; c < row.size(); ++c) {
    slot[c] = walls ? lists.wall_slot(row[c], col[c]) : lists.pair_slot(row[c], col[c]);
    if (slot[c] < 0)
      throw std::runtime_error(f.path() + ": contact " + std::to_string(row[c]) + "-" +
                               std::to_string(col[c]) + " of the checkpoint is not a neighbour-list candidate");
  }
  for (const auto& [name, a] : List::carried()) {
    const auto column = h5::read<double>(f, group + "/" + name);
    if (column.size() != row.size()) throw std::runtime_error(f.path() + ": " + group + "/" + name + " has the wrong length");
    for (std::size_t c = 0; c < row.size(); ++c) (L.*a)[static_cast<std::size_t>(slot[c])] = column[c];
  }
}

template <class List>
void clear_carried(List& L) {
  for (const auto& [name, a] : List::carried()) std::fill((L.*a).begin(), (L.*a).end(), 0.0);
}

std::string controller_group(const Controller* c) { return "controllers/" + c->name(); }

}  // namespace

void ControllerState::put(const std::string& key, std::int64_t value) const {
  h5::write(file_, group_ + "/" + key, std::vector<std::int64_t>{value});
}
void ControllerState::put(const std::string& key, double value) const {
  h5::write(file_, group_ + "/" + key, std::vector<double>{value});
}
void ControllerState::put(const std::string& key, const std::vector<double>& values) const {
  h5::write(file_, group_ + "/" + key, values);
}
std::vector<double> ControllerState::get_doubles(const std::string& key) const {
  return h5::read<double>(file_, group_ + "/" + key);
}
std::int64_t ControllerState::get_int(const std::string& key) const {
  const auto v = h5::read<std::int64_t>(file_, group_ + "/" + key);
  if (v.size() != 1) throw std::runtime_error(file_.path() + ": " + group_ + "/" + key + " is not one value");
  return v[0];
}
double ControllerState::get_double(const std::string& key) const {
  const auto v = get_doubles(key);
  if (v.size() != 1) throw std::runtime_error(file_.path() + ": " + group_ + "/" + key + " is not one value");
  return v[0];
}

void write_checkpoint(const std::string& path, const System& sys, std::span<Controller* const> controllers,
                      double wall_seconds, const std::string& scene_text) {
  h5::write_atomically(path, [&](const h5::File& f) {
    h5::write_attr(f, "/", "format", std::string(kCheckpointFormat));
    h5::write_attr(f, "/", "scene_text", scene_text);
    h5::write_attr(f, "/", "code_version", code_version());
    h5::write_attr(f, "/", "step", sys.state.step);
    h5::write_attr(f, "/", "wall_seconds", wall_seconds);
    for (Controller* c : controllers) c->save(ControllerState(f, controller_group(c)));
    for (const auto& [name, v] : particle_arrays(sys.state.p)) h5::write(f, std::string("particles/") + name, *v);
    h5::write(f, "particles/active", sys.state.p.active);
    // what makes a checkpoint a starting state of its own (--initial, runfile/checkpoint_state.hpp)
    std::vector<double> diameter(sys.size());
    for (std::size_t i = 0; i < diameter.size(); ++i) diameter[i] = 2.0 * sys.state.p.radius[i];
    h5::write(f, "particles/diameter", diameter);
    const bool gaps = reaches_beyond_contact(sys.config.effects);
    write_history(f, "pairs", sys.state.lists.pairs, sys.state.lists.pairs.partner, gaps);
    write_history(f, "walls", sys.state.lists.walls, sys.state.lists.walls.body, gaps);
    const Bodies& B = sys.state.bodies;
    for (const auto& [name, v] : body_arrays(B)) h5::write(f, std::string("bodies/") + name, *v);
    h5::write(f, "bodies/anchor_step", B.anchor_step);
    h5::write_strings(f, "bodies/name", B.name);
    h5::write(f, "bodies/active", B.active);
    h5::write(f, "bodies/removing", B.removing);
    h5::write_attr(f, "/", "rebuild_pending", static_cast<std::int64_t>(sys.state.rebuild_pending));
    h5::write(f, "bodies/fx_sum", sys.state.body_fx_sum);
    h5::write(f, "bodies/fy_sum", sys.state.body_fy_sum);
    h5::write(f, "bodies/torque_sum", sys.state.body_torque_sum);
    h5::write_attr(f, "/", "body_sum_steps", sys.state.body_sum_steps);
    write_lost(f, sys.state.lost);
    for (const auto& [name, v] : accumulators(sys.state.energy)) h5::write(f, "energy/" + std::string(name), *v);
    h5::write_attr(f, "/", "energy_removed", sys.state.energy.removed);
    h5::write_attr(f, "/", "energy_error_offset", sys.state.energy.error_offset);
    h5::seal(f);
  });
}

std::string checkpoint_scene_text(const std::string& path) {
  if (!std::filesystem::exists(path)) return "";
  const h5::File f = h5::File::open_read(path);
  if (!h5::has_attr(f, "/", "format") || h5::read_attr_string(f, "/", "format") != kCheckpointFormat) return "";
  return h5::read_attr_string(f, "/", "scene_text");
}

double read_checkpoint(const std::string& path, System& sys, std::span<Controller* const> controllers) {
  const h5::File f = h5::File::open_read(path);
  if (h5::read_attr_string(f, "/", "format") != kCheckpointFormat)
    throw std::runtime_error(path + ": not a dem2d checkpoint");
  h5::check_seal(f);
  const std::size_t n = sys.size();
  for (const auto& [name, v] : particle_arrays(sys.state.p)) {
    const std::vector<double> column = h5::read<double>(f, std::string("particles/") + name);
    v->assign(column.begin(), column.end());
    if (v->size() != n) throw std::runtime_error(path + ": particle count differs from the scene's");
  }
  const std::vector<std::uint8_t> active = h5::read<std::uint8_t>(f, "particles/active");
  sys.state.p.active.assign(active.begin(), active.end());
  sys.freeze_lost();
  sys.state.step = h5::read_attr_int(f, "/", "step");
  sys.state.lost.clear();
  const auto id = h5::read<std::int32_t>(f, "lost/id");
  const auto step = h5::read<std::int64_t>(f, "lost/step");
  const auto x = h5::read<double>(f, "lost/x"), y = h5::read<double>(f, "lost/y");
  for (std::size_t k = 0; k < id.size(); ++k) sys.state.lost.push_back({id[k], step[k], x[k], y[k]});

  Bodies& B = sys.state.bodies;
  for (const auto& [name, v] : body_arrays(B)) *v = h5::read<double>(f, std::string("bodies/") + name);
  B.anchor_step = h5::read<std::int64_t>(f, "bodies/anchor_step");
  B.active = h5::read<std::uint8_t>(f, "bodies/active");
  // a body removed at the checkpoint's step is still in the lists: rebuild
  // with it, as the uninterrupted run has them, and remove it at the next step
  const std::vector<std::uint8_t> removing = h5::read<std::uint8_t>(f, "bodies/removing");
  if (B.vx.size() != B.size()) throw std::runtime_error(path + ": body count differs from the scene's");
  B.removing.assign(B.size(), 0);
  sys.place_bodies();
  sys.rebuild();
  // the lists this process had (from the scene's start) carry nothing into the checkpoint's state: every
  // slot starts empty, then the checkpoint's contacts are put back (a contact that was open at the checkpoint
  // has no history, as in the uninterrupted run)
  clear_carried(sys.state.lists.pairs);
  clear_carried(sys.state.lists.walls);
  B.removing = removing;
  sys.state.rebuild_pending = h5::read_attr_int(f, "/", "rebuild_pending") != 0;
  read_history(f, "pairs", sys.state.lists.pairs, sys.state.lists, false);
  if (has(sys.config.effects, effect::walls)) read_history(f, "walls", sys.state.lists.walls, sys.state.lists, true);
  for (const auto& [name, v] : accumulators(sys.state.energy)) {
    const std::vector<double> column = h5::read<double>(f, "energy/" + std::string(name));
    v->assign(column.begin(), column.end());
  }
  sys.state.energy.removed = h5::read_attr_double(f, "/", "energy_removed");
  sys.state.energy.error_offset = h5::read_attr_double(f, "/", "energy_error_offset");
  sys.state.body_fx_sum = h5::read<double>(f, "bodies/fx_sum");
  sys.state.body_fy_sum = h5::read<double>(f, "bodies/fy_sum");
  sys.state.body_torque_sum = h5::read<double>(f, "bodies/torque_sum");
  sys.state.body_sum_steps = h5::read_attr_int(f, "/", "body_sum_steps");

  for (Controller* c : controllers) c->restore(ControllerState(f, controller_group(c)));
  return h5::read_attr_double(f, "/", "wall_seconds");
}

}  // namespace dem2d
