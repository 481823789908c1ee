#include "writer/run_xdmf.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "runfile/h5.hpp"

namespace dem2d {

namespace {

std::int64_t most_contacts(const XdmfLayout& l) {
  std::int64_t m = 0;
  for (std::size_t k = 0; k + 1 < l.contact_start.size(); ++k)
    m = std::max(m, l.contact_start[k + 1] - l.contact_start[k]);
  return m;
}

// Written for ParaView's Xdmf3 readers (S and T): they read a selection given
// as "file:/dataset|start:stride:count:dataspace" but not HyperSlab DataItems,
// which crash them. Connectivity comes from datasets: inline XML connectivity
// would be read for the first grid only.
class XdmfWriter {
 public:
  explicit XdmfWriter(const XdmfLayout& l) : l_(l) {}

  // A whole dataset of dimensions `dims`.
  std::string item(const std::string& dims, const std::string& type, const std::string& dataset) const {
    return "<DataItem Dimensions=\"" + dims + "\" " + type + " Format=\"HDF\">" + l_.h5_name + ":" + dataset +
           "</DataItem>";
  }
  // The block of a dataset of shape `space` from `start`, `count` entries per
  // dimension; the first dimension left out of the item's dimensions with `squeeze`.
  std::string select(const std::string& dataset, const std::string& type, const std::vector<std::uint64_t>& start,
                     const std::vector<std::uint64_t>& count, const std::vector<std::uint64_t>& space,
                     bool squeeze = false) const {
    const auto list = [](const std::vector<std::uint64_t>& v, std::size_t from = 0) {
      std::ostringstream o;  // (streams: GCC 12 warns falsely on some string concatenations)
      for (std::size_t d = from; d < v.size(); ++d) o << (d > from ? " " : "") << v[d];
      return o.str();
    };
    const std::string dims = list(count, squeeze && count.size() > 1 ? 1 : 0);
    return item(dims, type, dataset + "|" + list(start) + ":" + list(std::vector<std::uint64_t>(start.size(), 1)) + ":" +
                                list(count) + ":" + list(space));
  }
  // Rows first..first+count-1 of a dataset of `rows` rows of shape `row`.
  std::string rows(const std::string& dataset, const std::string& type, std::int64_t first, std::int64_t count,
                   std::int64_t rows, const std::vector<std::uint64_t>& row, bool squeeze = false) const {
    std::vector<std::uint64_t> start{static_cast<std::uint64_t>(first)}, cnt{static_cast<std::uint64_t>(count)},
        space{static_cast<std::uint64_t>(rows)};
    for (const std::uint64_t r : row) {
      start.push_back(0);
      cnt.push_back(r);
      space.push_back(r);
    }
    return select(dataset, type, start, cnt, space, squeeze);
  }
  // Record k of a per-snapshot dataset [S, row...], without the leading 1.
  std::string record(std::size_t k, const std::string& dataset, const std::string& type,
                     const std::vector<std::uint64_t>& row) const {
    return rows(dataset, type, static_cast<std::int64_t>(k), 1, static_cast<std::int64_t>(l_.times.size()), row, true);
  }
  static std::string attribute(const std::string& name, const std::string& kind, const std::string& centre,
                               const std::string& data) {
    return "        <Attribute Name=\"" + name + "\" AttributeType=\"" + kind + "\" Center=\"" + centre +
           "\">\n          " + data + "\n        </Attribute>\n";
  }
  static std::string topology(const std::string& type, std::uint64_t elements, std::uint64_t nodes,
                              const std::string& connectivity) {
    return "        <Topology TopologyType=\"" + type + "\" NumberOfElements=\"" + std::to_string(elements) +
           "\" NodesPerElement=\"" + std::to_string(nodes) + "\">\n          " + connectivity + "\n        </Topology>\n";
  }
  static std::string geometry(const std::string& data) {
    return "        <Geometry GeometryType=\"XY\">\n          " + data + "\n        </Geometry>\n";
  }

 private:
  const XdmfLayout& l_;
};

const std::string f8 = "NumberType=\"Float\" Precision=\"8\"", u1 = "NumberType=\"UChar\" Precision=\"1\"",
                  i4 = "NumberType=\"Int\" Precision=\"4\"";

}  // namespace

void write_xdmf_indices(const h5::File& f, const XdmfLayout& l) {
  std::vector<std::int32_t> sequence(static_cast<std::size_t>(std::max<std::int64_t>(2 * most_contacts(l), 1)));
  for (std::size_t k = 0; k < sequence.size(); ++k) sequence[k] = static_cast<std::int32_t>(k);
  h5::write(f, "xdmf/sequence", sequence);
  const std::uint64_t K = l.vertices, B = l.vertex_count.size();
  std::vector<std::int32_t> outline;
  for (std::uint64_t b = 0; b < B; ++b) {
    const auto n = static_cast<std::uint64_t>(std::max(l.vertex_count[b], 1));
    for (std::uint64_t v = 0; v <= K; ++v) {
      // its vertices in order, back to the first for a polygon, then its last repeated
      const std::uint64_t w = v < n ? v : (n >= 3 ? 0 : n - 1);
      outline.push_back(static_cast<std::int32_t>(b * K + w));
    }
  }
  h5::write(f, "xdmf/body_outline", outline, {B, K + 1});
}

void write_xdmf(const std::string& path, const XdmfLayout& l) {
  const XdmfWriter w(l);
  const std::uint64_t N = l.particles, B = l.vertex_count.size(), K = l.vertices;
  const std::int64_t C = l.contact_start.empty() ? 0 : l.contact_start.back();
  const std::int64_t seq = std::max<std::int64_t>(2 * most_contacts(l), 1);
  const std::string n = std::to_string(N);
  const std::string outline = w.item(std::to_string(B) + " " + std::to_string(K + 1), i4, "/xdmf/body_outline");
  std::ofstream out(path);
  out << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
      << "  <Grid Name=\"snapshots\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  char time[32];
  const auto grid = [&](const char* name) { out << "      <Grid Name=\"" << name << "\" GridType=\"Uniform\">\n"; };
  for (std::size_t k = 0; k < l.times.size(); ++k) {
    std::snprintf(time, sizeof time, "%.17g", l.times[k]);
    // unnamed: the Xdmf3 readers would rename the grids of a named collection particles[k], ...
    out << "    <Grid GridType=\"Collection\" CollectionType=\"Spatial\">\n"
        << "      <Time Value=\"" << time << "\"/>\n";
    grid("particles");
    out << XdmfWriter::topology("Polyvertex", N, 1, w.item(n, i4, "/particles/id"))
        << XdmfWriter::geometry(w.record(k, "/snapshots/position", f8, {N, 2}))
        << XdmfWriter::attribute("diameter", "Scalar", "Node", w.item(n, f8, "/particles/diameter"))
        << XdmfWriter::attribute("velocity", "Vector", "Node", w.record(k, "/snapshots/velocity", f8, {N, 2}))
        << XdmfWriter::attribute("omega", "Scalar", "Node", w.record(k, "/snapshots/omega", f8, {N}))
        << XdmfWriter::attribute("theta", "Scalar", "Node", w.record(k, "/snapshots/theta", f8, {N}))
        << XdmfWriter::attribute("active", "Scalar", "Node", w.record(k, "/snapshots/active", u1, {N}))
        << "      </Grid>\n";
    if (B > 0) {
      grid("bodies");
      out << XdmfWriter::topology("Polyline", B, K + 1, outline)
          << XdmfWriter::geometry(w.record(k, "/snapshots/body_vertices", f8, {B, K, 2}))
          << XdmfWriter::attribute("thickness", "Scalar", "Cell", w.item(std::to_string(B), f8, "/bodies/thickness"))
          << "      </Grid>\n";
    }
    const std::int64_t first = k + 1 < l.contact_start.size() ? l.contact_start[k] : 0,
                       count = k + 1 < l.contact_start.size() ? l.contact_start[k + 1] - first : 0;
    if (count > 0) {  // no contact, no grid: the readers crash on an empty one
      grid("contacts");
      out << XdmfWriter::topology("Polyline", static_cast<std::uint64_t>(count), 2,
                                  w.rows("/xdmf/sequence", i4, 0, 2 * count, seq, {}))
          << XdmfWriter::geometry(w.rows("/contacts/line", f8, first, count, C, {2, 2}));
      for (const char* a : {"fn", "ft", "mu_star", "overlap"})
        out << XdmfWriter::attribute(a, "Scalar", "Cell", w.rows(std::string("/contacts/") + a, f8, first, count, C, {}));
      out << XdmfWriter::attribute("sliding", "Scalar", "Cell", w.rows("/contacts/sliding", u1, first, count, C, {}))
          << "      </Grid>\n";
    }
    out << "    </Grid>\n";
  }
  out << "  </Grid>\n</Domain>\n</Xdmf>\n";
  out.close();
  if (!out) throw std::runtime_error(path + ": cannot write the XDMF file");
}

}  // namespace dem2d
