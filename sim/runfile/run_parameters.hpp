// The run's parameters as the engine ran them: the run file's /parameters
// group (docs/run_file.md), every value typed and with its unit. Written
// from the scene after validation (writer/run_parameters_write.hpp), with the key tables the scene reader
// validates with (the contact law's keys, core/effects.hpp, core/motion.hpp,
// core/body_roles.hpp, core/scene_keys.hpp); read back by RunReader and the
// Python package, so that no stage parses the scene's text.
#pragma once

#include <string>
#include <vector>

#include "contact/contact_law.hpp"
#include "core/box.hpp"
#include "core/effects.hpp"
#include "core/run_spec.hpp"
#include "runfile/h5.hpp"

namespace dem2d {

// The layout's name (attribute /parameters@format).
inline constexpr const char* kParametersFormat = "dem2d-parameters-1";

struct RunParameters {
  std::string name;  // the scene's
  EffectSet effects = 0;
  double dt = 0.0;  // time step (s)
  bool dt_forced = false;
  double density = 0.0;       // grain density (kg/m^3)
  double gx = 0.0, gy = 0.0;  // gravity (m/s^2), 0 without the effect
  ContactLaw grain_grain;     // the law between grains
  ContactLaw grain_body;      // between grains and bodies (= grain_grain without walls)
  StopCondition stop;         // duration and the criteria
  OutputSpec output;
  Box domain;
  double skin = 0.0;  // Verlet-list skin (m)
  std::vector<BodySpec> bodies;  // as the scene gave them at t = 0 (vertices, velocity, schedule)
  JamControl jam;                // enabled with the scene's [jam]

  // Index of the body with this role, or -1.
  int find_role(std::string_view role) const;
};

// Reads /parameters; a std::runtime_error naming the file and the dataset if
// one is missing or malformed. `has_parameters`: whether the group exists.
RunParameters read_parameters(const h5::File& f);
bool has_parameters(const h5::File& f);

}  // namespace dem2d
