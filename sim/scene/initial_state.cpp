#include "scene/initial_state.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "io/run_reader.hpp"

namespace dem2d {

void load_initial_state(const std::string& run_path, Scene& scene) {
  const RunReader run(run_path);
  const Snapshot last = run.last_snapshot();
  std::vector<std::size_t> order;  // active grains of the run, in spatial order
  double row = 0.0;                // (m)
  for (std::size_t i = 0; i < last.size(); ++i)
    if (last.active[i]) {
      order.push_back(i);
      row = std::max(row, last.diameter[i]);
    }
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
}

}  // namespace dem2d
