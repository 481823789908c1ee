#include "common/events.hpp"

#include <cmath>
#include <filesystem>
#include <limits>

#include "core/number_text.hpp"
#include "runfile/h5.hpp"

namespace dem2d::analysis {

const std::vector<EventColumn>& event_columns() {
  static const std::vector<EventColumn> columns = {
      {"load_start_time", "s", "time of the drag minimum the event loads from", &RuptureEvent::load_start_time, true},
      {"load_start_height", "m", "intruder height then", &RuptureEvent::load_start_height, false},
      {"peak_time", "s", "time of the drag peak (the rupture)", &RuptureEvent::peak_time, true},
      {"peak_height", "m", "intruder height at the peak", &RuptureEvent::peak_height, true},
      {"peak_drag", "N/m", "drag at the peak", &RuptureEvent::peak_drag, false},
      {"drop_end_time", "s", "time of the drag minimum the drop ends at", &RuptureEvent::drop_end_time, true},
      {"drop_end_height", "m", "intruder height then", &RuptureEvent::drop_end_height, false},
      {"drop", "N/m", "peak drag minus the drag at drop_end", &RuptureEvent::drop, false},
  };
  return columns;
}

void add_events(H5Output& h, const std::vector<RuptureEvent>& events) {
  for (const EventColumn& c : event_columns()) {
    std::vector<double> v;
    for (const RuptureEvent& e : events) v.push_back(e.*c.field);
    h.add(std::string("events/") + c.name, std::move(v), c.unit, c.description);
  }
  std::vector<double> duration;
  for (const RuptureEvent& e : events) duration.push_back(e.peak_time - e.load_start_time);
  h.add("events/duration", std::move(duration), "s", "loading time: peak_time - load_start_time");
}

std::vector<RuptureEvent> read_events(const std::string& path) {
  const auto fail = [&](const std::string& what) { throw StageError(path + ": " + what); };
  if (!std::filesystem::exists(path)) fail("no such file (the events file of the spectrum stage)");
  std::vector<RuptureEvent> out;
  try {
    const h5::File f = h5::File::open_read(path);
    std::size_t rows = 0;
    bool first = true;
    for (const EventColumn& c : event_columns()) {
      const std::string name = std::string("events/") + c.name;
      if (!h5::exists(f, name)) {
        if (c.required) fail("dataset /" + name + " is missing (the spectrum stage's events file)");
        continue;
      }
      const std::vector<hsize_t> dims = h5::shape(f, name);
      if (dims.size() != 1 || h5::dtype(f, name) != "f8")
        fail("dataset /" + name + " is not a 1-D float64 column (the spectrum stage's events file)");
      if (first) rows = dims[0], out.resize(rows);
      if (dims[0] != rows)
        fail("dataset /" + name + " has " + std::to_string(dims[0]) + " rows, /events/" +
             event_columns().front().name + " has " + std::to_string(rows));
      first = false;
      const std::vector<double> v = h5::read<double>(f, name);
      for (std::size_t k = 0; k < rows; ++k) {
        if (!std::isfinite(v[k])) fail("dataset /" + name + ": event " + std::to_string(k) + " is not finite");
        out[k].*c.field = v[k];
      }
    }
    for (const EventColumn& c : event_columns())
      if (!c.required && !h5::exists(f, std::string("events/") + c.name))
        for (RuptureEvent& e : out) e.*c.field = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t k = 0; k < out.size(); ++k) {
      const RuptureEvent& e = out[k];
      if (!(e.load_start_time <= e.peak_time && e.peak_time <= e.drop_end_time))
        fail("event " + std::to_string(k) + ": load_start_time " + shortest(e.load_start_time) +
             " s, peak_time " + shortest(e.peak_time) + " s and drop_end_time " + shortest(e.drop_end_time) +
             " s are not in this order");
    }
  } catch (const StageError&) {
    throw;
  } catch (const std::exception& x) {
    const std::string what = x.what();
    throw StageError(what.rfind(path, 0) == 0 ? what : path + ": " + what);
  }
  return out;
}

}  // namespace dem2d::analysis
