// What a body is for in a scene ([[body]] role): the analyses find bodies by
// role, never by name. A body's id is its index in the scene's [[body]] list,
// which is also its index in the run file's /bodies datasets.
//   intruder    the pulled body: drag, the frame of the mobility fields, a
//               network end
//   floor, left_wall, right_wall
//               the cell's faces: bed surface, bulk region, network ends
//   hopper      a wall of the pouring hopper (gate included)
//   ""          none (the default)
// intruder, floor, left_wall and right_wall name one body each at most.
#pragma once

#include <array>
#include <string>
#include <string_view>

namespace dem2d {

struct BodyRole {
  std::string_view name;
  bool unique;  // at most one body per scene
};

inline constexpr std::array<BodyRole, 5> kBodyRoles{{{"intruder", true},
                                                     {"floor", true},
                                                     {"left_wall", true},
                                                     {"right_wall", true},
                                                     {"hopper", false}}};

inline const BodyRole* find_body_role(std::string_view name) {
  for (const BodyRole& r : kBodyRoles)
    if (r.name == name) return &r;
  return nullptr;
}

inline std::string body_role_names() {
  std::string s;
  for (const BodyRole& r : kBodyRoles) s += (s.empty() ? "" : ", ") + std::string(r.name);
  return s;
}

// The role of a body in a run file written before roles (no /bodies/role):
// the study's scenes then named the bodies after their roles.
inline std::string legacy_body_role(std::string_view name) {
  if (name == "intruder" || name == "floor") return std::string(name);
  if (name == "left") return "left_wall";
  if (name == "right") return "right_wall";
  return "";
}

}  // namespace dem2d
