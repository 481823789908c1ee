// Planted image pairs for PIV (the piv stage's planted truth and unit tests):
// random particle images (Gaussian spots, as PIV's standard synthetic images,
// Raffel et al. ch. 6) whose second frame has every particle moved by a known
// displacement field, the intensity computed exactly at each pixel (no
// interpolation), so that the field is the only truth.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "piv/piv_image.hpp"
#include "runfile/run_reader.hpp"

namespace dem2d::planted {

// (x, y) -> (u, v): a particle at (x, y) in the first frame is at (x + u, y + v) in the second (px, y down).
using Displacement = std::function<void(double x, double y, double& u, double& v)>;

struct ParticleImages {
  double diameter = 3.0;   // particle image diameter at e^-2 of the peak (px)
  double density = 0.03;   // particles per px^2
  double noise = 0.0;      // Gaussian sensor noise, rms of the peak intensity
  unsigned seed = 1;
};

// The pair (a, b) of width x height px.
void particle_pair(std::size_t width, std::size_t height, const ParticleImages& p, const Displacement& d,
                   analysis::Image& a, analysis::Image& b);

// A bed of glass beads as the study's (diameters uniform in [2, 4] mm) filling [0, w] x [0, h] (m):
// a triangular lattice of 4.1 mm pitch, each bead moved at random within 0.4 mm (drawn with `seed`).
struct Beads {
  std::vector<Vec2> position;
  std::vector<double> diameter;
  std::vector<std::uint8_t> active;
};
Beads bead_bed(double w, double h, unsigned seed);

}  // namespace dem2d::planted
