// The grains as the paper's camera sees the front face (a Dalsa CMOS camera,
// 1392 x 1024 px, following the intruder; "an individual glass bead is
// described approximately with 35 pixels"): glass beads drawn with Cairo as
// bright disks shaded towards a dark rim with a specular highlight towards
// the light, on a dark background; optional sensor noise, blur and uneven
// light. World coordinates in m (y up), the image's in px (rows down).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "piv/piv_image.hpp"
#include "runfile/run_reader.hpp"

namespace dem2d::analysis {

struct CameraSettings {
  std::size_t width = 1392, height = 1024;  // px
  double px_per_diameter = 35.0;            // the mean diameter's length in px
  double background = 0.08;                 // intensity between the beads (0..1)
  double bead = 0.55;                       // a bead's body
  double rim = 0.15;                        // its edge
  double highlight = 0.95;                  // its specular spot
  double highlight_offset = 0.35;           // the spot's offset from the centre towards the light (upper left), x radius
  double noise = 0.0;                       // sensor noise, rms of the full scale
  double blur_px = 0.0;                     // Gaussian blur (sigma, px): defocus
  double light_falloff = 0.0;               // uneven light: the intensity falls by this fraction from left to right
};

// World <-> pixel for a camera centred on `centre` (m) at `scale` px/m.
struct View {
  Vec2 centre;
  double scale = 1.0;  // px/m
  std::size_t width = 0, height = 0;
  Vec2 px(Vec2 w) const {
    return {(w.x - centre.x) * scale + 0.5 * (static_cast<double>(width) - 1.0),
            0.5 * (static_cast<double>(height) - 1.0) - (w.y - centre.y) * scale};
  }
  Vec2 world(Vec2 p) const {
    return {centre.x + (p.x - 0.5 * (static_cast<double>(width) - 1.0)) / scale,
            centre.y - (p.y - 0.5 * (static_cast<double>(height) - 1.0)) / scale};
  }
};

// The frame of the active grains (positions m, diameters m) seen through `view`; `seed` draws the noise.
// std::runtime_error if Cairo cannot make the surface.
Image render(const View& view, const CameraSettings& c, std::span<const Vec2> position, std::span<const double> diameter,
             std::span<const std::uint8_t> active, unsigned seed);

}  // namespace dem2d::analysis
