#include "network/network.hpp"

#include <boost/graph/connected_components.hpp>
#include <boost/graph/filtered_graph.hpp>
#include <boost/graph/push_relabel_max_flow.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "runfile/h5.hpp"

namespace dem2d::analysis {

namespace {

using Graph = ContactGraph::Graph;
using Edge = boost::graph_traits<Graph>::edge_descriptor;

// Grains left out of every path: none, or those touching the floor.
std::vector<std::uint8_t> excluded_grains(const ContactGraph& g, FloorRule rule) {
  std::vector<std::uint8_t> out(g.grains, 0);
  if (rule != FloorRule::bottom_layer_removed) return out;
  for (const Edge e : boost::make_iterator_range(boost::out_edges(g.floor(), g.graph))) {
    const std::size_t other = boost::target(e, g.graph);
    if (other < g.grains) out[other] = 1;
  }
  return out;
}

// The edges a path may use: fn > threshold and, for grain-grain edges, neither
// grain excluded. Body ends are filtered separately.
struct GrainEdge {
  const Graph* graph = nullptr;
  const std::vector<std::uint8_t>* excluded = nullptr;
  std::size_t grains = 0;
  double threshold = 0.0;
  bool operator()(const Edge& e) const {
    const std::size_t u = boost::source(e, *graph), v = boost::target(e, *graph);
    return u < grains && v < grains && !(*excluded)[u] && !(*excluded)[v] &&
           boost::get(boost::edge_weight, *graph, e) > threshold;
  }
};

// Integer capacities for the max-flow (exact arithmetic): fn in units of
// 1e-12 of the largest strong force.
using FlowTraits = boost::adjacency_list_traits<boost::vecS, boost::vecS, boost::directedS>;
using FlowGraph = boost::adjacency_list<
    boost::vecS, boost::vecS, boost::directedS, boost::no_property,
    boost::property<boost::edge_capacity_t, std::int64_t,
                    boost::property<boost::edge_residual_capacity_t, std::int64_t,
                                    boost::property<boost::edge_reverse_t, FlowTraits::edge_descriptor>>>>;

struct FlowNetwork {
  FlowGraph graph;
  double unit = 1.0;  // N/m per capacity unit

  explicit FlowNetwork(std::size_t vertices) : graph(vertices) {}
  // An undirected edge: an arc of capacity c each way, each with its own
  // reverse arc of capacity 0, as push_relabel_max_flow requires (its own
  // check, is_flow(), fails on two arcs of capacity c that are each other's
  // reverse: found with assertions on, in the ASan+UBSan build).
  void add(std::size_t u, std::size_t v, std::int64_t c) {
    arc(u, v, c);
    arc(v, u, c);
  }
  void arc(std::size_t u, std::size_t v, std::int64_t c) {
    auto cap = boost::get(boost::edge_capacity, graph);
    auto rev = boost::get(boost::edge_reverse, graph);
    const auto a = boost::add_edge(u, v, graph).first, b = boost::add_edge(v, u, graph).first;
    cap[a] = c;
    cap[b] = 0;
    rev[a] = b;
    rev[b] = a;
  }
  double max_flow(std::size_t source, std::size_t sink) {
    return unit * static_cast<double>(boost::push_relabel_max_flow(graph, source, sink));
  }
  // The max flow with vertex v's arcs closed (each arc out of v and its
  // reverse: every arc into v is the reverse of one out of it).
  double max_flow_without(std::size_t v, std::size_t source, std::size_t sink) {
    auto cap = boost::get(boost::edge_capacity, graph);
    auto rev = boost::get(boost::edge_reverse, graph);
    std::vector<std::pair<FlowTraits::edge_descriptor, std::int64_t>> saved;
    for (const auto a : boost::make_iterator_range(boost::out_edges(v, graph))) {
      saved.emplace_back(a, cap[a]);
      saved.emplace_back(rev[a], cap[rev[a]]);
      cap[a] = cap[rev[a]] = 0;
    }
    const double flow = max_flow(source, sink);
    for (const auto& [a, c] : saved) cap[a] = c;
    return flow;
  }
};

}  // namespace

const char* floor_rule_name(FloorRule r) {
  return r == FloorRule::vertex_removed ? "vertex_removed" : "bottom_layer_removed";
}

FloorRule floor_rule_from_name(const std::string& name) {
  if (name == "vertex_removed") return FloorRule::vertex_removed;
  if (name == "bottom_layer_removed") return FloorRule::bottom_layer_removed;
  throw StageError("unknown floor rule '" + name + "' (vertex_removed, bottom_layer_removed)");
}

ContactGraph build_contact_graph(const Snapshot& s, const std::vector<Partner>& partners) {
  ContactGraph g;
  g.grains = s.size();
  g.graph = Graph(g.grains + 4);
  const Contacts& c = s.contacts;
  double sum = 0.0;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!(c.fn[k] > 0.0) || partners[k] == Partner::other) continue;
    const auto i = static_cast<std::size_t>(c.i[k]);
    if (i >= g.grains || !s.active[i]) continue;
    std::size_t v = 0;
    switch (partners[k]) {
      case Partner::grain: v = static_cast<std::size_t>(c.j[k]); break;
      case Partner::left: v = g.left(); break;
      case Partner::right: v = g.right(); break;
      case Partner::floor: v = g.floor(); break;
      case Partner::intruder: v = g.intruder(); break;
      case Partner::other: continue;
    }
    if (partners[k] == Partner::grain && (v >= g.grains || !s.active[v])) continue;
    boost::add_edge(i, v, c.fn[k], g.graph);
    sum += c.fn[k];
  }
  g.mean_fn = g.edges() > 0 ? sum / static_cast<double>(g.edges()) : 0.0;
  return g;
}

std::int64_t ContactGraph::edges_above(double fn) const {
  std::int64_t n = 0;
  for (const Edge e : boost::make_iterator_range(boost::edges(graph))) n += boost::get(boost::edge_weight, graph, e) > fn;
  return n;
}

Percolation percolation(const ContactGraph& g, double threshold, FloorRule rule, std::size_t source) {
  const std::vector<std::uint8_t> excluded = excluded_grains(g, rule);
  const boost::filtered_graph<Graph, GrainEdge> paths(g.graph, GrainEdge{&g.graph, &excluded, g.grains, threshold});
  std::vector<std::size_t> component(boost::num_vertices(g.graph));
  const auto n = static_cast<std::size_t>(boost::connected_components(paths, component.data()));
  // Which bodies each grain cluster touches through edges above the threshold.
  constexpr std::uint8_t kSource = 1, kLeft = 2, kRight = 4;
  std::vector<std::uint8_t> touches(n, 0);
  for (const auto& [body, bit] : {std::pair{source, kSource}, std::pair{g.left(), kLeft}, std::pair{g.right(), kRight}}) {
    for (const Edge e : boost::make_iterator_range(boost::out_edges(body, g.graph))) {
      const std::size_t grain = boost::target(e, g.graph);
      if (grain < g.grains && !excluded[grain] && boost::get(boost::edge_weight, g.graph, e) > threshold)
        touches[component[grain]] |= bit;
    }
  }
  Percolation p;
  for (const std::uint8_t t : touches) {
    p.left = p.left || (t & (kSource | kLeft)) == (kSource | kLeft);
    p.right = p.right || (t & (kSource | kRight)) == (kSource | kRight);
  }
  return p;
}

void ForceSegments::add(const Snapshot& s, const std::vector<Partner>& partners, double strong_fn) {
  snapshot.push_back(static_cast<std::int64_t>(s.index));
  const Contacts& c = s.contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!(c.fn[k] > 0.0) || partners[k] == Partner::other) continue;
    const auto i = static_cast<std::size_t>(c.i[k]);
    const Vec2 p = s.position[i];
    Vec2 q;
    if (partners[k] == Partner::grain) {
      q = s.position[static_cast<std::size_t>(c.j[k])];
    } else {
      const double reach = 0.5 * s.diameter[i] - c.overlap[k];
      q = {p.x - c.nx[k] * reach, p.y - c.ny[k] * reach};
    }
    x0.push_back(p.x), y0.push_back(p.y), x1.push_back(q.x), y1.push_back(q.y), fn.push_back(c.fn[k]);
    partner.push_back(static_cast<std::uint8_t>(partners[k]));
    strong.push_back(c.fn[k] > strong_fn);
  }
  start.push_back(static_cast<std::int64_t>(x0.size()));
}

void ForceSegments::append(const ForceSegments& o) {
  const std::int64_t base = start.back();
  snapshot.insert(snapshot.end(), o.snapshot.begin(), o.snapshot.end());
  for (std::size_t m = 1; m < o.start.size(); ++m) start.push_back(base + o.start[m]);
  for (auto [to, from] : {std::pair{&x0, &o.x0}, {&y0, &o.y0}, {&x1, &o.x1}, {&y1, &o.y1}, {&fn, &o.fn}})
    to->insert(to->end(), from->begin(), from->end());
  partner.insert(partner.end(), o.partner.begin(), o.partner.end());
  strong.insert(strong.end(), o.strong.begin(), o.strong.end());
}

void ForceSegments::write(H5Output& h) const {
  h.add("figure/snapshot", snapshot, "-", "snapshots with force-network segments");
  h.add("figure/start", start, "-", "segments of figure/snapshot[m]: rows start[m] .. start[m+1]-1");
  h.add("figure/x0", x0, "m", "grain i centre");
  h.add("figure/y0", y0, "m", "grain i centre");
  h.add("figure/x1", x1, "m", "partner grain centre, or the body's surface");
  h.add("figure/y1", y1, "m", "partner grain centre, or the body's surface");
  h.add("figure/fn", fn, "N/m", "normal force");
  h.add("figure/partner", partner, "-", "0 grain, 1 left, 2 right, 3 floor, 4 intruder");
  h.add("figure/strong", strong, "-", "1: fn > strong_threshold x mean_fn");
}

Fabric fabric(const std::vector<Vec2>& normals, std::size_t min_contacts) {
  Fabric f;
  f.contacts = static_cast<std::int64_t>(normals.size());
  if (normals.empty() || normals.size() < min_contacts) return f;
  double xx = 0.0, yy = 0.0, xy = 0.0;
  for (const Vec2& n : normals) {
    const double len2 = n.x * n.x + n.y * n.y;  // normalised, in case
    xx += n.x * n.x / len2, yy += n.y * n.y / len2, xy += n.x * n.y / len2;
  }
  const double count = static_cast<double>(normals.size());
  xx /= count, yy /= count, xy /= count;
  const double diff = std::sqrt((xx - yy) * (xx - yy) + 4.0 * xy * xy);  // l1 - l2
  f.anisotropy = 2.0 * diff / (xx + yy);
  double angle = 0.5 * std::atan2(2.0 * xy, xx - yy) * 180.0 / std::numbers::pi;
  if (angle < 0.0) angle += 180.0;
  f.angle_deg = angle;
  f.noise = std::sqrt(std::numbers::pi / count);
  f.debiased = std::sqrt(std::max(0.0, f.anisotropy * f.anisotropy - 4.0 / count));
  return f;
}

Fabric region_fabric(const Snapshot& s, const std::vector<Partner>& partners, double threshold, double y_min,
                     double y_max, std::size_t min_contacts) {
  std::vector<Vec2> normals;
  const Contacts& c = s.contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (partners[k] != Partner::grain || !(c.fn[k] > threshold)) continue;
    const double y = contact_point(s, k).y;
    if (y >= y_min && y < y_max) normals.push_back({c.nx[k], c.ny[k]});
  }
  return fabric(normals, min_contacts);
}

std::vector<std::int32_t> KeystoneAnalysis::keystones(double min_share) const {
  std::vector<std::int32_t> out;
  for (const KeystoneCandidate& k : candidates)
    if (k.share() > 0.0 && k.share() >= min_share) out.push_back(k.grain);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

KeystoneAnalysis analyse_keystones(const ContactGraph& g, const Snapshot& s, const PulloffGeometry& geo,
                                   double threshold, FloorRule rule, double end_zone) {
  KeystoneAnalysis out;
  const std::vector<std::uint8_t> excluded = excluded_grains(g, rule);
  const auto usable = [&](std::size_t v) { return v >= g.grains || !excluded[v]; };
  double largest = 0.0;
  for (const Edge e : boost::make_iterator_range(boost::edges(g.graph)))
    largest = std::max(largest, boost::get(boost::edge_weight, g.graph, e));
  if (!(largest > threshold)) return out;

  // Candidates: grains on a strong contact with an intruder end.
  const double reach = 0.5 * geo.core_length - end_zone;
  for (const Edge e : boost::make_iterator_range(boost::out_edges(g.intruder(), g.graph))) {
    const std::size_t grain = boost::target(e, g.graph);
    if (grain >= g.grains || !usable(grain) || !(boost::get(boost::edge_weight, g.graph, e) > threshold)) continue;
    const double along = geo.axial(s.position[grain]);
    if (std::abs(along) >= reach) out.candidates.push_back({static_cast<std::int32_t>(grain), along < 0.0 ? -1 : 1});
  }

  for (const std::size_t wall : {g.left(), g.right()}) {
    FlowNetwork net(boost::num_vertices(g.graph));
    net.unit = largest * 1e-12;
    for (const Edge e : boost::make_iterator_range(boost::edges(g.graph))) {
      const double fn = boost::get(boost::edge_weight, g.graph, e);
      std::size_t u = boost::source(e, g.graph), v = boost::target(e, g.graph);
      if (u > v) std::swap(u, v);  // u is a grain
      const bool allowed = v < g.grains || v == g.intruder() || v == wall;
      if (fn > threshold && allowed && usable(u) && usable(v)) net.add(u, v, std::llround(fn / net.unit));
    }
    const double flow = net.max_flow(g.intruder(), wall);
    (wall == g.left() ? out.flow_left : out.flow_right) = flow;
    if (!(flow > 0.0)) continue;
    for (KeystoneCandidate& k : out.candidates) {
      const double share = (flow - net.max_flow_without(static_cast<std::size_t>(k.grain), g.intruder(), wall)) / flow;
      (wall == g.left() ? k.share_left : k.share_right) = share;
    }
  }
  return out;
}

PercolationProfile percolation_profile(const HeightBins& bins, const std::vector<double>& heights,
                                       const std::vector<std::uint8_t>& flags) {
  std::vector<double> as_double(flags.begin(), flags.end());
  const BinnedMean m = binned_mean(bins, heights, as_double);
  PercolationProfile p;
  for (std::size_t b = 0; b < m.mean.size(); ++b) {
    if (m.count[b] == 0) continue;
    p.lower.push_back(bins.lower(b));
    p.upper.push_back(bins.lower(b + 1));
    p.snapshots.push_back(m.count[b]);
    p.fraction.push_back(m.mean[b]);
  }
  return p;
}

std::optional<double> loss_height(const PercolationProfile& p, double level) {
  if (p.fraction.empty()) return std::nullopt;
  for (std::size_t b = p.fraction.size(); b-- > 0;) {
    if (p.fraction[b] < level) continue;
    if (b + 1 == p.fraction.size()) return std::nullopt;  // still percolating in the highest bin
    return p.upper[b];
  }
  return p.lower.front();
}

double flagged_fraction(const std::vector<double>& heights, const std::vector<std::uint8_t>& flags, double lo,
                        double hi, std::int64_t* used) {
  std::vector<double> as_double(flags.begin(), flags.end());
  return mean_in_band(heights, as_double, lo, hi, used);
}

EventWindow event_window(const std::vector<double>& times, const RuptureEvent& e, double max_gap) {
  EventWindow w;
  const auto after = std::lower_bound(times.begin(), times.end(), e.drop_end_time);
  const auto past_peak = std::upper_bound(times.begin(), times.end(), e.peak_time);
  if (past_peak != times.begin()) w.before = static_cast<std::int64_t>(past_peak - times.begin()) - 1;
  if (after != times.end()) w.after = static_cast<std::int64_t>(after - times.begin());
  w.resolved = w.before >= 0 && w.after >= 0 && e.peak_time - times[static_cast<std::size_t>(w.before)] <= max_gap &&
               times[static_cast<std::size_t>(w.after)] - e.drop_end_time <= max_gap;
  return w;
}

Displacement largest_displacement(const std::vector<std::int32_t>& grains, const std::vector<Vec2>& from,
                                  const std::vector<Vec2>& to, const std::vector<double>& diameter) {
  Displacement out;
  for (const std::int32_t g : grains) {
    const auto i = static_cast<std::size_t>(g);
    const double dx = to[i].x - from[i].x, dy = to[i].y - from[i].y;
    const double over_d = std::hypot(dx, dy) / diameter[i];
    if (out.grain < 0 || over_d > out.over_d) out = {g, over_d, dx, dy};
  }
  return out;
}

}  // namespace dem2d::analysis
