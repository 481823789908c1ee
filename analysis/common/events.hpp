// The events file: the loading/rupture events of a pull-off's drag, group
// /events of the spectrum stage's spectrum.h5. One schema, written by the
// spectrum stage and read by the stages cg and network: one row per event,
// every column float64 [E] with `units` and `description` (analysis/spectrum/README.md).
#pragma once

#include <string>
#include <vector>

#include "common/stage_error.hpp"
#include "common/stage_output.hpp"

namespace dem2d::analysis {

// One event: the drag loads from its minimum (load_start) up to a peak, then
// drops to the next minimum (drop_end).
struct RuptureEvent {
  double load_start_time = 0.0, load_start_height = 0.0;  // (s), intruder height (m)
  double peak_time = 0.0, peak_height = 0.0, peak_drag = 0.0;  // (s), (m), (N/m)
  double drop_end_time = 0.0, drop_end_height = 0.0;     // (s), (m)
  double drop = 0.0;                                     // peak drag - drag at drop_end (N/m)
};

// A column of /events: its dataset name, unit, field, and whether a reader
// needs it (the others are read when present, NaN otherwise).
struct EventColumn {
  const char* name;
  const char* unit;
  const char* description;
  double RuptureEvent::*field;
  bool required;
};
const std::vector<EventColumn>& event_columns();

// /events/<column> for every column, plus /events/duration (peak - load start, s).
void add_events(H5Output& h, const std::vector<RuptureEvent>& events);

// The events of the file at `path`. StageError naming the file and the column
// unless every required column is there, float64, of one length, finite, and
// load_start_time <= peak_time <= drop_end_time for every event.
std::vector<RuptureEvent> read_events(const std::string& path);

}  // namespace dem2d::analysis
