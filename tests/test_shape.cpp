// Convex sphero-polygon bodies (sim/shape/shape.hpp): the closest point
// against a brute-force distance, the scene's shape kinds, and disks resting
// on a flat face and on a corner.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "scene/scene_toml.hpp"
#include "scene_builder.hpp"
#include "shape/shape_kinds.hpp"

namespace dem2d::test {
namespace {

// Distance from p to the segment ab, written out independently of the engine.
double segment_distance(Point p, Point a, Point b) {
  const double ex = b.x - a.x, ey = b.y - a.y, len2 = ex * ex + ey * ey;
  double t = len2 > 0.0 ? ((p.x - a.x) * ex + (p.y - a.y) * ey) / len2 : 0.0;
  t = std::min(1.0, std::max(0.0, t));
  return std::hypot(p.x - (a.x + t * ex), p.y - (a.y + t * ey));
}

// Signed distance to a convex polygon: to the nearest edge, negative inside
// (inside: on the left of every counter-clockwise edge).
double brute_signed_distance(Point p, const std::vector<Point>& v) {
  double d = 1e300;
  bool inside = true;
  for (std::size_t k = 0; k < v.size(); ++k) {
    const Point a = v[k], b = v[(k + 1) % v.size()];
    d = std::min(d, segment_distance(p, a, b));
    inside = inside && (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x) > 0.0;
  }
  return inside ? -d : d;
}

std::vector<Point> rectangle(Point centre, double w, double h, double angle_deg, double thickness = 0.0) {
  ShapeArgs a;
  a.point["centre"] = centre;
  a.point["size"] = {w, h};
  a.number["angle"] = angle_deg;
  a.thickness = thickness;
  return find_shape_kind("rectangle")->outline(a);
}

// For many points around and inside a triangle, a turned rectangle and a
// hexagon: the signed distance matches the brute force to round-off, and
// stepping |dist| back along the normal lands on the boundary.
TEST(Shape, ClosestPointMatchesBruteForceDistance) {
  std::vector<std::vector<Point>> polygons{
      {{0.0, 0.0}, {0.01, 0.0}, {0.004, 0.007}},
      rectangle({0.002, -0.001}, 0.010, 0.002, 27.0),
  };
  std::vector<Point> hexagon;
  for (int k = 0; k < 6; ++k) hexagon.push_back({0.004 * std::cos(k * M_PI / 3), 0.004 * std::sin(k * M_PI / 3)});
  polygons.push_back(hexagon);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.012, 0.016);
  int inside = 0, checked = 0;
  for (const auto& v : polygons) {
    const Shape s = make_shape(convex_polygon(v, "test"));
    for (int q = 0; q < 20000; ++q) {
      const Point p{u(rng), u(rng)};
      const Proximity g = closest_point(s, p.x, p.y);
      const double want = brute_signed_distance(p, convex_polygon(v, "test"));
      ASSERT_NEAR(g.dist, want, 1e-16 + 1e-13 * std::abs(want)) << p.x << " " << p.y;
      ASSERT_NEAR(std::hypot(g.nx, g.ny), 1.0, 1e-14);
      // the closest point: back along the normal by the signed distance
      const Point on{p.x - g.dist * g.nx, p.y - g.dist * g.ny};
      ASSERT_NEAR(brute_signed_distance(on, convex_polygon(v, "test")), 0.0, 1e-15) << p.x << " " << p.y;
      inside += g.dist < 0.0;
      ++checked;
    }
  }
  EXPECT_GT(inside, 1000);  // the inside branch was exercised
  EXPECT_EQ(checked, 60000);
}

// Two vertices are exactly the sphero-line of the paper (docs/paper.md; the same arithmetic).
TEST(Shape, TwoVerticesAreTheSpheroLine) {
  const Shape s = make_shape({{0.01, 0.02}, {0.03, 0.035}});
  const Segment g = make_segment(0.01, 0.02, 0.03, 0.035);
  for (double x = -0.01; x < 0.05; x += 0.0031)
    for (double y = 0.0; y < 0.06; y += 0.0029) {
      EXPECT_EQ(closest_point(s, x, y).dist, closest_point(g, x, y).dist);
      EXPECT_EQ(closest_point(s, x, y).nx, closest_point(g, x, y).nx);
    }
}

TEST(Shape, ConvexPolygonIsCheckedAndOrdered) {
  const std::vector<Point> cw{{0, 0}, {0, 1}, {1, 1}, {1, 0}};
  const std::vector<Point> ccw = convex_polygon(cw, "vertices");
  EXPECT_EQ(ccw.front().x, 1.0);  // reversed
  EXPECT_THROW(convex_polygon({{0, 0}, {1, 0}, {2, 0}}, "vertices"), ShapeError);             // collinear
  EXPECT_THROW(convex_polygon({{0, 0}, {2, 0}, {1, 0.2}, {2, 1}, {0, 1}}, "vertices"), ShapeError);  // dent
  std::vector<Point> star;
  for (int k = 0; k < 5; ++k) star.push_back({std::cos(k * 4 * M_PI / 5), std::sin(k * 4 * M_PI / 5)});
  EXPECT_THROW(convex_polygon(star, "vertices"), ShapeError);  // every turn left, but twice around
  EXPECT_THROW(convex_polygon({{0, 0}, {1, 0}}, "vertices"), ShapeError);
}

// A glass disk (3 mm) on a rectangle's top face and on the apex of a
// triangle, both sharp-cornered (thickness 0), with normal damping: it comes
// to rest with its weight on the contact, F_n = m g, overlap m g / k_n, the
// normal vertical, at the height the geometry says.
struct Rest {
  double x, y;        // grain centre (m)
  double fx, fy;      // force on the body (N/m)
  double weight;      // m g (N/m)
};

Rest settle_on(const std::vector<Point>& core, double x0, double y0) {
  Scene s = glass_scene(effect::gravity | effect::normal_damping | effect::walls);
  s.particle_wall.restitution = 0.3;
  add_disk(s, x0, y0, kMeanD);
  BodySpec body;
  body.name = "block";
  body.shape = "polygon";
  body.vertices = core;
  body.thickness = 0.0;
  s.bodies.push_back(body);
  set_dt_fraction(s, 20.0);
  System sys(s);
  run_for(sys, 0.3);
  return {sys.state.p.x[0], sys.state.p.y[0], sys.state.bodies.fx[0], sys.state.bodies.fy[0], sys.state.p.mass[0] * 9.81};
}

TEST(Shape, DiskRestsOnAFlatFace) {
  const double kn = 1.92e6, r = 0.5 * kMeanD;
  const auto core = rectangle({0.0, -0.002}, 0.020, 0.004, 0.0);  // top face y = 0
  const Rest rest = settle_on(core, 0.003, r + 1e-4);             // dropped from 0.1 mm
  EXPECT_NEAR(rest.fy, -rest.weight, 1e-9 * rest.weight);
  EXPECT_NEAR(rest.fx, 0.0, 1e-12);
  EXPECT_EQ(rest.x, 0.003);  // a vertical normal: no sideways push at all
  EXPECT_NEAR(rest.y, r - rest.weight / kn, 1e-12);
}

TEST(Shape, DiskRestsOnACorner) {
  const double kn = 1.92e6, r = 0.5 * kMeanD;
  const std::vector<Point> triangle{{-0.005, -0.004}, {0.005, -0.004}, {0.0, 0.0}};  // apex at the origin
  const Rest rest = settle_on(triangle, 0.0, r + 1e-4);
  EXPECT_NEAR(rest.fy, -rest.weight, 1e-9 * rest.weight);
  EXPECT_EQ(rest.fx, 0.0);
  EXPECT_EQ(rest.x, 0.0);  // balanced on the vertex
  EXPECT_NEAR(rest.y, r - rest.weight / kn, 1e-12);
}

// A grain whose centre has got inside the core is pushed out through the
// nearest face, with the overlap continuing that of a grain on the face.
TEST(Shape, CentreInsideTheCoreIsPushedOutThroughTheNearestFace) {
  const auto core = rectangle({0.0, -0.005}, 0.020, 0.010, 0.0);  // top face y = 0
  const Shape s = make_shape(core);
  const Proximity above = closest_point(s, 0.001, 1e-4), below = closest_point(s, 0.001, -1e-4);
  EXPECT_NEAR(above.dist, 1e-4, 1e-18);
  EXPECT_NEAR(below.dist, -1e-4, 1e-18);
  EXPECT_EQ(below.nx, 0.0);
  EXPECT_EQ(below.ny, 1.0);
  const Proximity side = closest_point(s, 0.0099, -0.005);  // nearer the right face
  EXPECT_NEAR(side.dist, -1e-4, 1e-15);
  EXPECT_EQ(side.nx, 1.0);
}

// The scene's shape keys: a rectangle's size must exceed its rounding, a
// polygon must be convex, a key of another shape is refused.
TEST(Shape, SceneKeysAreValidated) {
  const std::string head = R"(name = "shapes"
[effects]
gravity = true
walls = true
[gravity]
g = [0.0, -9.81]
[material]
density = 2500.0
[contact]
kn = 1.92e6
[time]
duration = 0.01
dt_over_critical = 0.05
[domain]
xmin = -0.1
xmax = 0.1
ymin = -0.1
ymax = 0.1
[[particle]]
x = 0.0
y = 0.02
d = 3e-3
[[body]]
name = "block"
)";
  const Scene ok = parse_scene(head + "shape = \"rectangle\"\ncentre = [0, 0]\nsize = [0.01, 0.002]\nthickness = 0.001\n", "s.toml");
  ASSERT_EQ(ok.bodies[0].vertices.size(), 4u);
  EXPECT_NEAR(ok.bodies[0].vertices[2].x, 0.0045, 1e-15);  // core: size less the rounding
  EXPECT_NEAR(ok.bodies[0].vertices[2].y, 0.0005, 1e-15);
  const auto error = [&](const std::string& body) {
    try {
      parse_scene(head + body, "s.toml");
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("shape = \"rectangle\"\ncentre = [0, 0]\nsize = [0.01, 0.002]\nthickness = 0.002\n")
                .find("body[0].size = [0.01, 0.002]: width and height must exceed thickness"),
            std::string::npos);
  EXPECT_NE(error("shape = \"polygon\"\nvertices = [[0, 0], [0.01, 0], [0.005, 0.001], [0.01, 0.01], [0, 0.01]]\n"
                  "thickness = 0\n")
                .find("not a strictly convex polygon"),
            std::string::npos);
  EXPECT_NE(error("shape = \"rectangle\"\na = [0, 0]\ncentre = [0, 0]\nsize = [0.01, 0.002]\nthickness = 0\n")
                .find("body[0].a = [0, 0]: given but a rectangle does not take it"),
            std::string::npos);
  std::string allowed;  // every registered kind, in the registry's order
  for (const ShapeKind& k : shape_kinds()) allowed += (allowed.empty() ? "" : ", ") + std::string(k.name);
  EXPECT_EQ(allowed.rfind("segment, rectangle, polygon", 0), 0u) << allowed;
  EXPECT_NE(error("shape = \"disc\"\nthickness = 0\n").find("unknown shape kind (allowed: " + allowed + ")"),
            std::string::npos);
}

}  // namespace
}  // namespace dem2d::test
