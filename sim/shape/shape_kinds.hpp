// The shape kinds a scene's [[body]] may name (`shape = "..."`), each a way
// of writing down the core of a convex sphero-polygon (shape/shape.hpp): a
// kind lists its keys and turns their values into the core's vertices. The
// body's `thickness` is the rounding diameter for every kind.
//
// A new kind is one file, shape/<kind>_shape.cpp, defining its ShapeKind,
// plus one line in shape/shape_list.inc; the build finds the file, and the
// scene reader, the engine, the run file and the analyses need nothing else.
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "shape/shape.hpp"

namespace dem2d {

struct ShapeKey {
  enum Type { number, point, points };
  const char* name;  // "centre"
  Type type;
  const char* what;  // "centre of the rectangle"
  const char* unit;  // "m"
  bool required = true;
  double fallback = 0.0;  // a number's value when not given
};

// The values of a body's keys, read and checked for finiteness by the scene reader.
struct ShapeArgs {
  std::map<std::string, double, std::less<>> number;
  std::map<std::string, Point, std::less<>> point;
  std::map<std::string, std::vector<Point>, std::less<>> points;
  double thickness = 0.0;  // rounding diameter (m)
};

// A value a kind cannot make a shape of; `key` names it for the scene's error.
struct ShapeError : std::invalid_argument {
  ShapeError(std::string key_, const std::string& what) : std::invalid_argument(what), key(std::move(key_)) {}
  std::string key;
};

struct ShapeKind {
  const char* name;
  std::vector<ShapeKey> keys;
  // The core's vertices at t = 0 in world coordinates (m): one, two, or a
  // convex polygon counter-clockwise (convex_polygon). Throws ShapeError.
  std::vector<Point> (*outline)(const ShapeArgs&);
};

// The registry, in the order the scene's error messages list the kinds.
const std::vector<ShapeKind>& shape_kinds();
const ShapeKind* find_shape_kind(std::string_view name);  // nullptr if unknown

// `v` as a strictly convex polygon in counter-clockwise order (reversed if
// given clockwise); throws ShapeError naming `key` if it is not one or has
// more than Shape::kMaxVertices vertices.
std::vector<Point> convex_polygon(std::vector<Point> v, const char* key);

}  // namespace dem2d
