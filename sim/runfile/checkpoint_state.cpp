#include "runfile/checkpoint_state.hpp"

#include <limits>
#include <stdexcept>

#include "runfile/h5.hpp"
#include "runfile/h5_seal.hpp"
#include "runfile/run_format.hpp"

namespace dem2d {

bool is_checkpoint(const std::string& path) {
  try {
    const h5::File f = h5::File::open_read(path);
    return h5::has_attr(f, "/", "format") && h5::read_attr_string(f, "/", "format").starts_with("dem2d-checkpoint");
  } catch (const std::exception&) {
    return false;
  }
}

Snapshot checkpoint_state(const std::string& path) {
  const h5::File f = h5::File::open_read(path);
  const std::string format = h5::read_attr_string(f, "/", "format");
  if (format != kCheckpointFormat)
    throw std::runtime_error(path + ": a checkpoint of format " + format + ", this dem2d reads " + kCheckpointFormat +
                             " (a checkpoint of another dem2d version)");
  h5::check_seal(f);
  Snapshot s;
  s.step = h5::read_attr_int(f, "/", "step");
  s.time = std::numeric_limits<double>::quiet_NaN();
  const auto column = [&](const char* name) { return h5::read<double>(f, std::string("particles/") + name); };
  const std::vector<double> x = column("x"), y = column("y"), vx = column("vx"), vy = column("vy");
  s.omega = column("omega");
  s.diameter = column("diameter");
  s.active = h5::read<std::uint8_t>(f, "particles/active");
  const std::size_t n = x.size();
  for (const std::size_t size : {y.size(), vx.size(), vy.size(), s.omega.size(), s.diameter.size(), s.active.size()})
    if (size != n) throw std::runtime_error(path + ": the particle arrays differ in length: the file is damaged");
  for (std::size_t i = 0; i < n; ++i) {
    s.position.push_back({x[i], y[i]});
    s.velocity.push_back({vx[i], vy[i]});
  }
  for (std::string& name : h5::read_strings(f, "bodies/name")) {
    Body b;
    b.name = std::move(name);
    s.bodies.push_back(std::move(b));
  }
  // pairs (row i, key partner j > i), then walls (row i, key body b): j = -1 - b, as in a run file
  for (const bool walls : {false, true}) {
    const std::string group = walls ? "walls/" : "pairs/";
    const auto row = h5::read<std::int32_t>(f, group + "row"), key = h5::read<std::int32_t>(f, group + "key");
    const auto ft = h5::read<double>(f, group + "ft"), mr = h5::read<double>(f, group + "mr");
    if (key.size() != row.size() || ft.size() != row.size() || mr.size() != row.size())
      throw std::runtime_error(path + ": " + group + " arrays differ in length: the file is damaged");
    for (std::size_t c = 0; c < row.size(); ++c) {
      const std::size_t limit = walls ? s.bodies.size() : n;
      const bool inside = row[c] >= 0 && static_cast<std::size_t>(row[c]) < n && key[c] >= 0 &&
                          static_cast<std::size_t>(key[c]) < limit;
      if (!inside)
        throw std::runtime_error(path + ": " + group + "contact " + std::to_string(c) + " names a " +
                                 (walls ? "body" : "grain") + " the checkpoint does not have: the file is damaged");
      s.contacts.add(row[c], walls ? -1 - key[c] : key[c], 0.0, 0.0, 0.0, 0.0, ft[c], false, mr[c]);
    }
  }
  return s;
}

}  // namespace dem2d
