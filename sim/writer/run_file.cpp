#include "writer/run_file.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "contact/contact_model.hpp"
#include "engine/diagnostics.hpp"
#include "engine/energy_ledger.hpp"
#include "runfile/h5.hpp"
#include "runfile/h5_seal.hpp"
#include "writer/run_file_describe.hpp"
#include "writer/run_parameters_write.hpp"
#include "writer/run_xdmf.hpp"

namespace dem2d {

namespace fs = std::filesystem;

namespace {

// Per-snapshot contact counts: kept in the segments, turned into
// /snapshots/contact_start in the run file.
const std::string kContactCount = "snapshots/contact_count";
const std::string kDisplacement = "snapshots/displacement";  // NaN where a grain has no displacement yet

std::vector<hsize_t> stacked(std::uint64_t rows, const std::vector<std::uint64_t>& record) {
  std::vector<hsize_t> dims{rows};
  dims.insert(dims.end(), record.begin(), record.end());
  return dims;
}

// Most core vertices of any body (>= 1): the second dimension of /.../body_vertices.
std::uint64_t max_vertices(const Bodies& B) {
  int k = 1;
  for (const Shape& s : B.shape) k = std::max(k, s.n);
  return static_cast<std::uint64_t>(k);
}

// Every body's core vertices (x, y), padded to k by repeating the last one.
void append_vertices(std::vector<double>& out, const Bodies& B, std::uint64_t k) {
  for (const Shape& s : B.shape)
    for (std::uint64_t v = 0; v < k; ++v) {
      const Point q = s.vertex(std::min(static_cast<int>(v), s.n - 1));
      out.insert(out.end(), {q.x, q.y});
    }
}

void write_header(const h5::File& f, const System& sys, const RunInfo& info, const std::string& stop_reason) {
  if (!info.scene) throw std::logic_error("RunRecorder::finish: RunInfo::scene is required (the run's /parameters)");
  write_parameters(f, *info.scene);
  const auto i64 = [](auto v) { return static_cast<std::int64_t>(v); };
  h5::write_attr(f, "/", "format", kRunFileFormat);
  h5::write_attr(f, "/", "scene_text", info.scene_text);
  h5::write_attr(f, "/", "scene_path", info.scene_path);
  h5::write_attr(f, "/", "code_version", info.code_version);
  h5::write_attr(f, "/", "threads", i64(info.threads));
  h5::write_attr(f, "/", "dt", sys.config.dt);
  h5::write_attr(f, "/", "steps", i64(sys.state.step));
  h5::write_attr(f, "/", "end_time", sys.time());
  h5::write_attr(f, "/", "stop_reason", stop_reason);
  h5::write_attr(f, "/", "stopped_by", info.stopped_by);
  h5::write_attr(f, "/", "effects", effect_names(sys.config.effects));
  h5::write_attr(f, "/", "n_particles", i64(sys.size()));
  h5::write_attr(f, "/", "n_bodies", i64(sys.state.bodies.size()));
  h5::write_attr(f, "/", "lost_particles", i64(sys.state.lost.size()));
  h5::write_attr(f, "/", "initial_run", info.initial_run);
  h5::write_attr(f, "/", "initial_source", info.scene->initial_source);
  h5::write_attr(f, "/", "initial_digest", info.scene->initial_digest);
  h5::write_attr(f, "/", "jams", i64(info.jam_times.size()));
  h5::write_attr(f, "/", "wall_seconds", info.wall_seconds);
  h5::write_attr(f, "/", "displacement_window", info.displacement_window);
  h5::write(f, "events/jam_time", info.jam_times);

  const Particles& p = sys.state.p;
  std::vector<std::int32_t> ids;
  std::vector<double> diameter, inertia;
  for (std::size_t i = 0; i < p.size(); ++i) {
    ids.push_back(static_cast<std::int32_t>(i));
    diameter.push_back(2.0 * p.radius[i]);
    inertia.push_back(1.0 / p.inv_inertia[i]);
  }
  h5::write(f, "particles/id", ids);
  h5::write(f, "particles/diameter", diameter);
  h5::write(f, "particles/mass", p.mass);
  h5::write(f, "particles/inertia", inertia);

  const Bodies& B = sys.state.bodies;
  std::vector<double> thickness, velocity;
  for (std::size_t b = 0; b < B.size(); ++b) {
    thickness.push_back(2.0 * B.radius[b]);
    velocity.insert(velocity.end(), {B.vx[b], B.vy[b]});
  }
  std::vector<std::int32_t> vertices;
  for (const Shape& s : B.shape) vertices.push_back(s.n);
  h5::write_strings(f, "bodies/name", B.name);
  h5::write_strings(f, "bodies/role", B.role);
  h5::write_strings(f, "bodies/shape", B.kind);
  h5::write(f, "bodies/vertex_count", vertices);
  h5::write(f, "bodies/thickness", thickness);
  h5::write(f, "bodies/velocity", velocity, {B.size(), 2});

  write_lost(f, sys.state.lost);
}

}  // namespace

RunRecorder::RunRecorder(const System& sys, std::string work_dir)
    : work_dir_(std::move(work_dir)),
      n_(sys.size()),
      nb_(sys.state.bodies.size()),
      nv_(max_vertices(sys.state.bodies)),
      energy_(sys.state.energy.on) {}

std::string RunRecorder::segment_path(int k) const {
  char name[32];
  std::snprintf(name, sizeof name, "segment_%06d.h5", k);
  return (fs::path(work_dir_) / name).string();
}

std::vector<RunRecorder::Column> RunRecorder::columns() {
  const std::size_t t = series_.time.size(), s = snap_.time.size(), c = contact_.i.size();
  const std::uint64_t n = n_, b = nb_, v = nv_;
  std::vector<Column> out{
      {"series/time", {}, &series_.time, t},
      {"series/step", {}, &series_.step, t},
      {"series/body_force", {b, 2}, &series_.force, t},
      {"series/body_force_mean", {b, 2}, &series_.force_mean, t},
      {"series/body_torque", {b}, &series_.torque, t},
      {"series/body_torque_mean", {b}, &series_.torque_mean, t},
      {"series/body_vertices", {b, v, 2}, &series_.vertices, t},
      {"series/kinetic_energy", {}, &series_.kinetic_energy, t},
      {"series/max_overlap", {}, &series_.max_overlap, t},
      {"series/contacts", {}, &series_.contacts, t},
      {"snapshots/time", {}, &snap_.time, s},
      {"snapshots/step", {}, &snap_.step, s},
      {"snapshots/position", {n, 2}, &snap_.position, s},
      {"snapshots/velocity", {n, 2}, &snap_.velocity, s},
      {kDisplacement, {n, 2}, &snap_.displacement, s},
      {"snapshots/omega", {n}, &snap_.omega, s},
      {"snapshots/theta", {n}, &snap_.theta, s},
      {"snapshots/active", {n}, &snap_.active, s},
      {"snapshots/body_vertices", {b, v, 2}, &snap_.vertices, s},
      {kContactCount, {}, &snap_.contact_count, s},
      {"contacts/i", {}, &contact_.i, c},
      {"contacts/j", {}, &contact_.j, c},
      {"contacts/fn", {}, &contact_.fn, c},
      {"contacts/ft", {}, &contact_.ft, c},
      {"contacts/overlap", {}, &contact_.overlap, c},
      {"contacts/nx", {}, &contact_.nx, c},
      {"contacts/ny", {}, &contact_.ny, c},
      {"contacts/mr", {}, &contact_.mr, c},
      {"contacts/sliding", {}, &contact_.sliding, c},
      {"contacts/mu_star", {}, &contact_.mu_star, c},
      {"contacts/line", {2, 2}, &contact_.line, c},
  };
  if (energy_) {
    const auto names = EnergyBalance{}.terms();
    for (std::size_t k = 0; k < names.size(); ++k)
      out.push_back({"series/energy/" + std::string(names[k].first), {}, &series_.energy[k], t});
  }
  return out;
}

void RunRecorder::record_series(System& sys) {
  const Bodies& B = sys.state.bodies;
  series_.time.push_back(sys.time());
  series_.step.push_back(sys.state.step);
  const auto steps = static_cast<double>(sys.state.body_sum_steps);
  for (std::size_t b = 0; b < B.size(); ++b) {
    series_.force.insert(series_.force.end(), {B.fx[b], B.fy[b]});
    series_.torque.push_back(B.torque[b]);
    if (sys.state.body_sum_steps > 0) {
      series_.force_mean.insert(series_.force_mean.end(), {sys.state.body_fx_sum[b] / steps, sys.state.body_fy_sum[b] / steps});
      series_.torque_mean.push_back(sys.state.body_torque_sum[b] / steps);
    } else {
      series_.force_mean.insert(series_.force_mean.end(), {B.fx[b], B.fy[b]});
      series_.torque_mean.push_back(B.torque[b]);
    }
  }
  append_vertices(series_.vertices, B, nv_);
  series_.kinetic_energy.push_back(kinetic_energy(sys));
  series_.max_overlap.push_back(max_overlap(sys));
  series_.contacts.push_back(static_cast<std::int64_t>(contact_count(sys)));
  if (energy_) {
    const auto terms = energy::balance(sys).terms();
    for (std::size_t k = 0; k < terms.size(); ++k) series_.energy[k].push_back(terms[k].second);
  }
  ++series_rows_;
  sys.reset_body_sums();
}

void RunRecorder::record_snapshot(const System& sys, const std::vector<double>* reference) {
  const Particles& p = sys.state.p;
  snap_.time.push_back(sys.time());
  snap_.step.push_back(sys.state.step);
  for (std::size_t i = 0; i < p.size(); ++i) {
    snap_.position.insert(snap_.position.end(), {p.x[i], p.y[i]});
    snap_.velocity.insert(snap_.velocity.end(), {p.vx[i], p.vy[i]});
    if (reference)
      snap_.displacement.insert(snap_.displacement.end(), {p.x[i] - (*reference)[2 * i], p.y[i] - (*reference)[2 * i + 1]});
    else
      snap_.displacement.insert(snap_.displacement.end(), 2, std::numeric_limits<double>::quiet_NaN());
    snap_.omega.push_back(p.omega[i]);
    snap_.theta.push_back(p.theta[i]);
    snap_.active.push_back(p.active[i]);
  }
  append_vertices(snap_.vertices, sys.state.bodies, nv_);

  // acting slots, pairs then walls, in slot order: touching ones, and with
  // cohesion also those attracting across a gap (overlap < 0)
  const bool friction = has(sys.config.effects, effect::friction);
  const bool gaps = reaches_beyond_contact(sys.config.effects);
  const std::size_t before = contact_.i.size();
  // (ex, ey): the far end of the contact's line from grain i's centre (a grain's centre, a point on a body)
  const auto add = [&](std::size_t i, std::int32_t j, double fn, double ft, double overlap, double nx,
                       double ny, double mr, const LawCoefficients& c, double ex, double ey) {
    const double load = friction_load(c, sys.config.effects, fn, overlap);  // what caps friction
    contact_.mu_star.push_back(friction && overlap > 0.0 && load > 0.0 ? std::abs(ft) / (c.mu * load)
                                                                       : std::numeric_limits<double>::quiet_NaN());
    contact_.line.insert(contact_.line.end(), {p.x[i], p.y[i], ex, ey});
    contact_.i.push_back(static_cast<std::int32_t>(i));
    contact_.j.push_back(j);
    contact_.fn.push_back(fn);
    contact_.ft.push_back(ft);
    contact_.overlap.push_back(overlap);
    contact_.nx.push_back(nx);
    contact_.ny.push_back(ny);
    contact_.mr.push_back(mr);
    contact_.sliding.push_back(friction && is_sliding(load, ft, c.mu) ? 1 : 0);
  };
  const PairList& P = sys.state.lists.pairs;
  for (std::size_t i = 0; i + 1 < P.start.size(); ++i)
    for (auto sl = static_cast<std::size_t>(P.start[i]); sl < static_cast<std::size_t>(P.start[i + 1]); ++sl) {
      if (!acted(P.overlap[sl], gaps)) continue;
      const auto j = static_cast<std::size_t>(P.partner[sl]);
      const double dx = p.x[i] - p.x[j], dy = p.y[i] - p.y[j], dist = std::sqrt(dx * dx + dy * dy);
      add(i, P.partner[sl], P.fn[sl], P.ft[sl], P.overlap[sl], dist > 0.0 ? dx / dist : 1.0,
          dist > 0.0 ? dy / dist : 0.0, P.mr[sl], sys.config.pp, p.x[j], p.y[j]);
    }
  const WallList& W = sys.state.lists.walls;
  for (std::size_t i = 0; i + 1 < W.start.size(); ++i)
    for (auto sl = static_cast<std::size_t>(W.start[i]); sl < static_cast<std::size_t>(W.start[i + 1]); ++sl) {
      if (!acted(W.overlap[sl], gaps)) continue;
      const Proximity g = closest_point(sys.state.bodies.shape[static_cast<std::size_t>(W.body[sl])], p.x[i], p.y[i]);
      const double reach = p.radius[i] - 0.5 * W.overlap[sl];  // centre to the contact point
      add(i, -1 - W.body[sl], W.fn[sl], W.ft[sl], W.overlap[sl], g.nx, g.ny, W.mr[sl], sys.config.pw,
          p.x[i] - reach * g.nx, p.y[i] - reach * g.ny);
    }
  snap_.contact_count.push_back(static_cast<std::int64_t>(contact_.i.size() - before));
  ++snapshots_;
}

void RunRecorder::flush_segment() {
  if (series_.time.empty() && snap_.time.empty()) return;
  h5::write_atomically(segment_path(segments_), [&](const h5::File& f) {
    for (const Column& c : columns())
      std::visit([&](auto* v) { h5::write(f, c.name, *v, stacked(c.rows, c.record)); }, c.data);
    h5::seal(f);
  });
  ++segments_;
  for (const Column& c : columns()) std::visit([](auto* v) { v->clear(); }, c.data);
}

void RunRecorder::restore_counts(int segments, std::int64_t series_rows, std::int64_t snapshots) {
  for (const Column& c : columns()) std::visit([](auto* v) { v->clear(); }, c.data);
  segments_ = segments;
  series_rows_ = series_rows;
  snapshots_ = snapshots;
  // segments written after the checkpoint, and unfinished ones
  for (const fs::directory_entry& e : fs::directory_iterator(work_dir_)) {
    const std::string name = e.path().filename().string();
    if (name.starts_with("segment_") && (name.ends_with(".tmp") || std::atoi(name.c_str() + 8) >= segments))
      fs::remove(e.path());
  }
  // The segments kept go into the run file as they are: each must be the
  // one this run wrote, whole and unchanged (its checksum, h5_seal.hpp).
  for (int k = 0; k < segments; ++k) {
    const std::string path = segment_path(k);
    if (!fs::exists(path)) throw std::runtime_error(path + ": missing: the unfinished run's files are incomplete");
    h5::check_seal(h5::File::open_read(path));
  }
}

void RunRecorder::finish(const System& sys, const RunInfo& info, const std::string& out_path,
                         const std::string& stop_reason) {
  flush_segment();
  const fs::path out(out_path), xdmf = fs::path(out_path).replace_extension(".xdmf");
  // assembled in the working folder (no temporary beside the user's files), then renamed into place
  const std::string out_tmp = (fs::path(work_dir_) / "run.h5.partial").string(),
                    xdmf_tmp = (fs::path(work_dir_) / "run.xdmf.partial").string();
  try {
    h5::File f = h5::File::create(out_tmp);
    write_header(f, sys, info, stop_reason);

    std::vector<h5::File> segs;
    for (int k = 0; k < segments_; ++k) segs.push_back(h5::File::open_read(segment_path(k)));
    // one column at a time: the concatenation of its segment parts
    for (const Column& c : columns()) {
      if (c.name == kContactCount) continue;
      std::visit(
          [&](auto* v) {
            using T = typename std::remove_pointer_t<decltype(v)>::value_type;
            hsize_t rows = 0;
            for (const h5::File& s : segs) {
              std::vector<hsize_t> dims;
              const std::vector<T> part = h5::read<T>(s, c.name, &dims);
              rows += dims.at(0);
              v->insert(v->end(), part.begin(), part.end());
            }
            h5::write(f, c.name, *v, stacked(rows, c.record));
            std::vector<T>().swap(*v);
          },
          c.data);
    }
    std::vector<std::int64_t> start{0};
    for (const h5::File& s : segs)
      for (const std::int64_t count : h5::read<std::int64_t>(s, kContactCount)) start.push_back(start.back() + count);
    h5::write(f, "snapshots/contact_start", start);

    const std::vector<double> times = h5::read<double>(f, "snapshots/time");
    if (static_cast<std::int64_t>(times.size()) != snapshots_ ||
        static_cast<std::int64_t>(h5::shape(f, "series/time").at(0)) != series_rows_ ||
        static_cast<hsize_t>(start.back()) != h5::shape(f, "contacts/i").at(0))
      throw std::runtime_error(work_dir_ + ": the segment files do not hold the recorded rows");
    XdmfLayout view{out.filename().string(), times, start, {}, n_, nv_};
    for (const Shape& shape : sys.state.bodies.shape) view.vertex_count.push_back(shape.n);
    write_xdmf_indices(f, view);
    describe_run_file(f);
    write_xdmf(xdmf_tmp, view);
    f.close();
    // the XDMF first: a run file that exists is complete, its XDMF included
    h5::rename_checked(xdmf_tmp, xdmf.string());
    h5::rename_checked(out_tmp, out.string());
  } catch (...) {
    h5::remove_quietly(out_tmp);
    h5::remove_quietly(xdmf_tmp);
    throw;
  }
  for (int k = 0; k < segments_; ++k) fs::remove(segment_path(k));
}

void write_lost(const h5::File& f, const std::vector<LostParticle>& lost) {
  std::vector<std::int32_t> id;
  std::vector<std::int64_t> step;
  std::vector<double> x, y;
  for (const LostParticle& l : lost) {
    id.push_back(l.id);
    step.push_back(l.step);
    x.push_back(l.x);
    y.push_back(l.y);
  }
  h5::write(f, "lost/id", id);
  h5::write(f, "lost/step", step);
  h5::write(f, "lost/x", x);
  h5::write(f, "lost/y", y);
}

}  // namespace dem2d
