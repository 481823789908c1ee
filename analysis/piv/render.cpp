#include "piv/render.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

namespace dem2d::analysis {


Image render(const View& view, const CameraSettings& c, std::span<const Vec2> position, std::span<const double> diameter,
             std::span<const std::uint8_t> active, unsigned seed) {
  const int W = static_cast<int>(view.width), H = static_cast<int>(view.height);
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, W, H);
  if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
    cairo_surface_destroy(surface);
    throw std::runtime_error("Cairo: cannot make a " + std::to_string(W) + " x " + std::to_string(H) + " px image");
  }
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, c.background, c.background, c.background);
  cairo_paint(cr);
  for (std::size_t g = 0; g < position.size(); ++g) {
    if (!active[g]) continue;
    const Vec2 p = view.px(position[g]);
    const double r = 0.5 * diameter[g] * view.scale;
    if (p.x + r < 0 || p.y + r < 0 || p.x - r > W || p.y - r > H) continue;
    // Cairo's pixel (i, j) covers [i, i+1): its centre is at i + 0.5
    const double cx = p.x + 0.5, cy = p.y + 0.5, h = c.highlight_offset * r;
    cairo_pattern_t* shade = cairo_pattern_create_radial(cx - h, cy - h, 0.0, cx, cy, r);
    cairo_pattern_add_color_stop_rgb(shade, 0.0, c.highlight, c.highlight, c.highlight);
    cairo_pattern_add_color_stop_rgb(shade, 0.2, c.bead, c.bead, c.bead);
    cairo_pattern_add_color_stop_rgb(shade, 0.8, 0.5 * (c.bead + c.rim), 0.5 * (c.bead + c.rim), 0.5 * (c.bead + c.rim));
    cairo_pattern_add_color_stop_rgb(shade, 1.0, c.rim, c.rim, c.rim);
    cairo_arc(cr, cx, cy, r, 0.0, 2.0 * std::numbers::pi);
    cairo_set_source(cr, shade);
    cairo_fill(cr);
    cairo_pattern_destroy(shade);
  }
  cairo_surface_flush(surface);
  const unsigned char* data = cairo_image_surface_get_data(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  Image im(view.width, view.height);
  for (int j = 0; j < H; ++j) {
    const auto* row = reinterpret_cast<const std::uint32_t*>(data + static_cast<std::size_t>(j) * stride);
    for (int i = 0; i < W; ++i) im.at(i, j) = static_cast<float>(((row[i] >> 8) & 0xff) / 255.0);  // green
  }
  cairo_destroy(cr);
  cairo_surface_destroy(surface);
  if (c.blur_px > 0.0) im = gaussian_blur(im, c.blur_px);
  if (c.light_falloff != 0.0 || c.noise > 0.0) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0.0, c.noise > 0.0 ? c.noise : 1.0);
    for (std::size_t j = 0; j < im.height; ++j)
      for (std::size_t i = 0; i < im.width; ++i) {
        double v = im.at(i, j) * (1.0 - c.light_falloff * static_cast<double>(i) / static_cast<double>(im.width));
        if (c.noise > 0.0) v += n(rng);
        im.at(i, j) = static_cast<float>(std::clamp(v, 0.0, 1.0));
      }
  }
  return im;
}

}  // namespace dem2d::analysis
