// ParaView's view of a run file (docs/run_file.md, "ParaView"): run.xdmf, a
// temporal collection with one spatial collection per snapshot, of named grids:
//   particles  N points (polyvertex), point arrays diameter, velocity, omega, theta, active;
//   bodies     one polyline per body through its core's vertices (closed for polygons), cell array
//              thickness (if B > 0);
//   contacts   one line per acting contact, grain centre to grain centre or to the contact point
//              on a body, cell arrays fn, ft, mu_star, sliding, overlap (if the snapshot has any).
// Every array is a selection of the run file's datasets: the XDMF file holds no data.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace dem2d {

namespace h5 {
class File;
}

struct XdmfLayout {
  std::string h5_name;                      // the run file's name, relative to the XDMF file
  std::vector<double> times;                // /snapshots/time (s) [S]
  std::vector<std::int64_t> contact_start;  // /snapshots/contact_start [S+1]
  std::vector<int> vertex_count;            // core vertices of each body [B]
  std::uint64_t particles = 0, vertices = 1;  // N; K, the most core vertices of a body
};

// The index datasets the XDMF cells use, in the run file: /xdmf/sequence
// (0, 1, 2, ...: the contact lines' connectivity) and /xdmf/body_outline
// [B, K+1] (each body's vertices in /snapshots/body_vertices, closed for polygons).
void write_xdmf_indices(const h5::File& f, const XdmfLayout& layout);

// Writes the XDMF file; throws std::runtime_error if it cannot.
void write_xdmf(const std::string& path, const XdmfLayout& layout);

}  // namespace dem2d
