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

#include "scene/scene.hpp"

namespace dem2d {

class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reads and validates the scene file at `path`. Scene::path = path, Scene::text
// = the file's contents. Scene::threads is left 0 (the command line sets it).
Scene load_scene(const std::string& path);

// Parses and validates scene text; `path_for_messages` prefixes every error
// message and becomes Scene::path (its stem is the default Scene::name).
Scene parse_scene(std::string_view text, const std::string& path_for_messages);

}  // namespace dem2d
