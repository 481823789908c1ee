#include "scene/initial_state.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/fnv.hpp"
#include "core/number_text.hpp"
#include "runfile/checkpoint_state.hpp"
#include "runfile/run_reader.hpp"

namespace dem2d {

void load_initial_state(const std::string& run_path, Scene& scene) {
  const bool checkpoint = is_checkpoint(run_path);
  const Snapshot last = checkpoint ? checkpoint_state(run_path) : RunReader(run_path).last_snapshot();
  const std::size_t first_grain = scene.particles.size(), first_contact = scene.initial_contacts.size();
  std::vector<std::size_t> order;  // active grains of the run, in spatial order
  double row = 0.0;                // (m)
  for (std::size_t i = 0; i < last.size(); ++i)
    if (last.active[i]) {
      order.push_back(i);
      row = std::max(row, last.diameter[i]);
    }
  if (order.empty())
    throw std::runtime_error(std::string("its ") + (checkpoint ? "checkpoint (step " : "last snapshot (step ") +
                             std::to_string(last.step) + ") has no active grain: all " + std::to_string(last.size()) +
                             " left the domain, and a run cannot start from none");
  auto row_of = [&](std::size_t i) { return std::floor(last.position[i].y / row); };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return row_of(a) != row_of(b) ? row_of(a) < row_of(b) : last.position[a].x < last.position[b].x;
  });
  std::vector<std::int32_t> renumber(last.size(), -1);
  const auto first = static_cast<std::int32_t>(scene.particles.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t i = order[k];
    renumber[i] = first + static_cast<std::int32_t>(k);
    scene.particles.push_back({last.position[i].x, last.position[i].y, last.diameter[i], last.velocity[i].x,
                               last.velocity[i].y, last.omega[i]});
  }
  const Contacts& c = last.contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    InitialContact ic;
    ic.i = renumber[static_cast<std::size_t>(c.i[k])];
    ic.ft = c.ft[k];
    ic.mr = c.mr[k];
    if (c.j[k] >= 0) {
      ic.j = renumber[static_cast<std::size_t>(c.j[k])];
      if (ic.j < ic.i) {  // the engine stores a pair as (lower index, higher index)
        std::swap(ic.i, ic.j);
        ic.mr = -ic.mr;   // the rolling moment on the other grain
      }
    } else {
      ic.body = last.bodies[static_cast<std::size_t>(-1 - c.j[k])].name;
    }
    if (ic.i >= 0) scene.initial_contacts.push_back(ic);
  }
  scene.initial_run = run_path;
  scene.initial_source = checkpoint ? "checkpoint at step " + std::to_string(last.step)
                                    : "last snapshot, t = " + shortest(last.time) + " s (step " +
                                          std::to_string(last.step) + ")";
  // what the run starts from, whatever the file's other content: the identity a rerun compares (run/finished_run.hpp)
  Fnv1a digest;
  for (std::size_t k = first_grain; k < scene.particles.size(); ++k) {
    const ParticleInit& q = scene.particles[k];
    for (const double v : {q.x, q.y, q.d, q.vx, q.vy, q.omega}) digest.add(&v, sizeof v);
  }
  for (std::size_t k = first_contact; k < scene.initial_contacts.size(); ++k) {
    const InitialContact& ic = scene.initial_contacts[k];
    digest.add(&ic.i, sizeof ic.i);
    digest.add(&ic.j, sizeof ic.j);
    digest.add(ic.body);
    digest.add(&ic.ft, sizeof ic.ft);
    digest.add(&ic.mr, sizeof ic.mr);
  }
  scene.initial_digest = digest.hex();
}

}  // namespace dem2d
