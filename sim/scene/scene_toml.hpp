// Reading a scene from a TOML file (format: docs/scene_format.md).
//
// Every problem -- unreadable file, TOML syntax, unknown key, wrong type, value
// out of range, inconsistent effects, particles overlapping or outside the
// domain, a time step above the stability bound -- throws SceneError with a
// message naming the file, the line and column where known, the dotted key
// (e.g. `contact.kn`, `body[2].thickness`), the value given and what is allowed.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.hpp"

namespace dem2d {

class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What the command line adds to a scene file.
struct SceneSources {
  // TOML files merged over the scene, in order (e.g. a preset): their tables
  // merge key by key into the scene's, any other value (numbers, strings,
  // arrays, arrays of tables) replaces the scene's.
  std::vector<std::string> overlays;
  // Run file whose final state the grains start from; sets [initial] run.
  std::string initial_run;
};

// Reads and validates the scene file at `path`, with `extra` merged in.
// Scene::path = path; Scene::text = the file's contents, or, when `extra`
// adds anything, the merged scene written out as TOML (what actually ran).
// Scene::threads is left 0 (the command line sets it).
Scene load_scene(const std::string& path, const SceneSources& extra = {});

// Parses and validates scene text; `path_for_messages` prefixes every error
// message and becomes Scene::path (its stem is the default Scene::name).
Scene parse_scene(std::string_view text, const std::string& path_for_messages);

}  // namespace dem2d
