// Planted truth for the cg stage: the cone angle beta (R5) and the
// wall-mobility length H_c = (L_c - L)/2 tan beta (R6) of a planted cone,
// across per-grain PIV noise (independent or correlated in space); cones with
// edges of two angles or bent edges; nothing moving (both "none"); H_c's power
// against its found rate; the dilatancy (R11) of a planted dilated layer,
// across grain-position noise.
#include <cmath>
#include <cstdio>
#include <numbers>

#include "cg/cg_stage.hpp"
#include "planted/bed_snapshots.hpp"
#include "planted/planted.hpp"

namespace dem2d::planted {

namespace {

// A known limit of the cone's edge at the paper's kernel width (w = 1.5 d), measured on noise-free planted
// cones (analysis/cg/README.md, "The edge near the intruder"): an edge of 50 deg or flatter under noise of
// 0.3 V per grain or more is shown, not judged.
void flat_edge_limit(Row& row, double edge_deg, double noise) {
  if (edge_deg > 50.0 || noise < 0.3) return;
  row.judged = false;
  row.limit =
      "a 50 deg edge reads +4.6 deg high without noise (the coarse-grained 0.25 contour lies 1.7 mm outside the "
      "planted edge in the first 10 mm above the intruder, where the ramp to v* = 0 is narrower than the kernel, "
      "w = 1.5 d, and ~0 above 20 mm); noise of 0.3 V per grain or more raises the cone's level and takes it to "
      "+5 ... +6 deg. Not the fit's range: starting it 1-3 w higher or ending it 1-2 w from the walls leaves the "
      "bias (the study's cones, ~70 deg at 0.003 V, read 2.7-2.8 deg high)";
}

struct CgRun {
  analysis::CgInput in;
  nlohmann::ordered_json run(const Bed& bed, const ConeScenario& c) const {
    const analysis::MemorySource src = cone_run(bed, c);
    return analysis::compute_cg(src, nullptr, in).metrics["cg"];
  }
};

}  // namespace

std::vector<Row> cg_cases(const Settings& set, const std::string& data_dir) {
  CgRun cg;
  cg.in.config = analysis::load_cg_config(data_dir + "/cg.toml");
  cg.in.config_path = data_dir + "/cg.toml";
  cg.in.threads = 0;  // every thread, across one replica's snapshots: better balanced than 3 replicas on 2 cores
  // the cones' snapshots, one every cone_travel_mm of the intruder's travel
  ConeScenario plain;
  plain.travel = set.cone_travel_mm * 1e-3;
  const BedGeometry geometry;
  const double half_gap = 0.5 * (geometry.width - geometry.length);
  // the replicas of a scenario: bed and noise seeded alike, 1 ... set.replicas
  auto replicas = [&](const ConeScenario& scenario) {
    return Replicas(set.replicas, [&](unsigned seed) {
      BedGeometry g;
      g.seed = seed;
      ConeScenario c = scenario;
      c.seed = seed;
      return cg.run(make_bed(g), c);
    }, false);
  };
  std::vector<Row> rows;
  // beta and H_c of planted graded cones under noise of `noise` x V per grain,
  // correlated over `corr` mean diameters (0: independent)
  auto graded_cones = [&](double noise, double corr, bool beyond) {
    const std::string unit = corr > 0.0 ? "x V per grain, correlated over " + fmt("%g", corr) + " d" : "x V per grain";
    for (const double beta : set.cone_angles_deg) {
      ConeScenario cone = plain;
      cone.beta_deg = beta, cone.noise = noise, cone.correlation_d = corr;
      const Replicas reps = replicas(cone);
      Row b{"cone angle (R5)", "a cone of " + fmt("%g", beta) + " deg from the intruder's tips", "beta", "deg", beta,
            noise, unit};
      b.tolerance = 5.0;  // half the paper target's +-10 deg: a bias below it cannot decide R5 by itself
      b.note = "the coarse-grained v* = 0.25 contour of a graded edge lies outside the planted edge where the "
               "ramp to v* = 0 is narrower than the kernel (near the apex), so the fitted edge is steeper: beta "
               "comes out 2-5 deg high, more for flatter cones and as the noise raises the cone's level";
      if (corr == 0.0 && !beyond) flat_edge_limit(b, beta, noise);
      if (corr > 0.0) {
        b.judged = false;
        b.limit = "noise correlated over 2-5 d survives the kernel (w = 1.5 d): at 0.15 V per grain it lifts the "
                  "cone's level to 0.45-0.53 (0.25 with independent noise), and the edge, the v* = level contour, "
                  "lies inside the graded edge's 0.25 contour, the more so the higher: 50 / 60 / 70 deg read "
                  "58.4-59.0 / 66.2-66.3 / 73.5-73.6 deg (54.6 / 63.8 / 72.9 without noise); at 0.5 V beta is "
                  "undetermined. With cone.frame_snapshots = 4 (the fields averaged over 4 snapshots in the "
                  "intruder's frame, where the noise is independent between frames; not the default yet) the "
                  "level stays at 0.25 and a 60 deg cone reads 63.8 / 63.6 deg at 2 / 5 d, as without noise";
      }
      if (beyond) {
        b.min_found = 0.0;
        b.note = "beyond what one run can resolve: the cone shows in a few snapshots only and beta is undetermined "
                 "(cone.min_snapshots, cone.max_interval_deg); judged: a value given must be right";
      }
      reps.fill(b, [](const auto& m) { return metric(m, "cone_angle_deg"); });
      rows.push_back(b);
      const double hc = 1e3 * wall_meeting(beta, 0.0, half_gap);
      for (const bool fixed : {false, true}) {
        if (fixed && corr > 0.0) continue;
        Row h{"wall mobility H_c (R6)", "the same cone: H_c = (L_c - L)/2 tan beta" + std::string(fixed ? ": the fixed level 0.25" : ""),
              "wall-mobility length", "mm", hc, noise, unit};
        h.tolerance = 10.0;
        h.judged = !fixed;
        h.note = fixed ? "the definition before the noise calibration"
                       : "the planted value is where the cone's edge meets the wall at the surface; the detector "
                         "adds the intruder's half thickness (1 mm) and a mobile length of 1 d";
        if (corr > 0.0 && noise >= 0.5) {
          h.judged = false;
          h.limit = "at 0.5 V per grain correlated over 2-5 d (over three times the 0.15 V at which H_c holds) H_c "
                    "reads 20-30 mm too deep for 50 and 60 deg cones, and a 70 deg cone's 124 mm loss is found in "
                    "1-3 of 10: the walls' calibrated level is not yet proof against noise this strong and this "
                    "wide (cause not isolated)";
        }
        reps.fill(h, [fixed](const auto& m) { return metric(m, fixed ? "wall_mobility_length_fixed_level_mm" : "wall_mobility_length_mm"); });
        rows.push_back(h);
      }
    }
  };
  for (const double noise : set.correlated_piv_noise)
    for (const double corr : set.piv_correlation_d) graded_cones(noise, corr, false);
  for (const double noise : set.piv_noise_beyond) graded_cones(noise, 0.0, true);
  for (const double noise : set.piv_noise) {
    graded_cones(noise, 0.0, false);
    // the same cones with a step at the edge (v* = 1 inside, 0 outside): the
    // coarse-graining's response to a sharp edge, shown beside the graded ones
    if (noise == 0.0)
      for (const double beta : set.cone_angles_deg) {
        ConeScenario step = plain;
        step.beta_deg = beta, step.graded = false;
        const Replicas reps = replicas(step);
        Row b{"cone angle (R5)", "a step cone of " + fmt("%g", beta) + " deg (v* = 1 inside, 0 outside)", "beta", "deg",
              beta, noise, "x V per grain"};
        b.judged = false;
        b.note = "a step is widened by the kernel: its v* = 0.25 contour lies ~0.7 w outside the edge";
        reps.fill(b, [](const auto& m) { return metric(m, "cone_angle_deg"); });
        rows.push_back(b);
        Row h{"wall mobility H_c (R6)", "the same step cone", "wall-mobility length", "mm",
              1e3 * wall_meeting(beta, 0.0, half_gap), noise, "x V per grain"};
        h.judged = false;
        h.note = b.note;
        reps.fill(h, [](const auto& m) { return metric(m, "wall_mobility_length_mm"); });
        rows.push_back(h);
      }
    // nothing moves but the noise
    ConeScenario nothing = plain;
    nothing.moving = false, nothing.noise = noise;
    const Replicas still = replicas(nothing);
    Row nb{"cone angle (R5)", "nothing moves: the noise only", "beta", "deg", std::numeric_limits<double>::quiet_NaN(),
           noise, "x V per grain"};
    still.fill(nb, [](const auto& m) { return metric(m, "cone_angle_deg"); });
    rows.push_back(nb);
    Row nh{"wall mobility H_c (R6)", "nothing moves: the noise only", "wall-mobility length", "mm",
           std::numeric_limits<double>::quiet_NaN(), noise, "x V per grain"};
    still.fill(nh, [](const auto& m) { return metric(m, "wall_mobility_length_mm"); });
    rows.push_back(nh);
  }
  // cones of other shapes: edges of two angles; edges that bend
  for (const double noise : set.shape_piv_noise) {
    const double left = set.asymmetric_cone_deg[0], right = set.asymmetric_cone_deg[1];
    ConeScenario two = plain;
    two.beta_deg = left, two.beta_right_deg = right, two.noise = noise;
    const Replicas reps = replicas(two);
    const std::string name = "edges of " + fmt("%g", left) + " deg (left) and " + fmt("%g", right) + " deg (right)";
    for (const bool is_left : {true, false}) {
      Row b{"cone angle (R5)", name + ": the " + (is_left ? "left" : "right") + " edge", "beta of the side", "deg",
            is_left ? left : right, noise, "x V per grain"};
      b.tolerance = 5.0;
      b.note = "each side's angle is the mean over the snapshots of that side's fitted edge";
      flat_edge_limit(b, is_left ? left : right, noise);
      reps.fill(b, [is_left](const auto& m) { return metric(m, is_left ? "cone_angle_left_deg" : "cone_angle_right_deg"); });
      rows.push_back(b);
    }
    Row h{"wall mobility H_c (R6)", name + ": the walls' loss", "wall-mobility length", "mm",
          1e3 * wall_meeting(std::min(left, right), 0.0, half_gap), noise, "x V per grain"};
    h.tolerance = 10.0;
    h.note = "planted: where the flatter edge meets its wall (the steeper one meets its wall at " +
             fmt("%.1f", 1e3 * wall_meeting(std::max(left, right), 0.0, half_gap)) + " mm): a snapshot's walls are "
             "mobile while their mean mobile length is 1 d or more, so the loss follows the wall that stays mobile "
             "longer as the intruder rises";
    reps.fill(h, [](const auto& m) { return metric(m, "wall_mobility_length_mm"); });
    rows.push_back(h);
    for (const double bend : set.edge_bends) {
      ConeScenario bent = plain;
      bent.beta_deg = 60.0, bent.bend = bend, bent.noise = noise;
      const double meet = wall_meeting(bent.beta_deg, bend, half_gap);
      if (!std::isfinite(meet)) continue;
      const Replicas r = replicas(bent);
      const double chord = std::atan2(meet, half_gap) * 180.0 / std::numbers::pi;
      const std::string bname = "an edge leaving the tip at 60 deg, bent by " + fmt("%g", bend) + " (" +
                                (bend > 0.0 ? "flattening" : "steepening") + " upwards)";
      Row hc{"wall mobility H_c (R6)", bname + ": where it meets the wall", "wall-mobility length", "mm", 1e3 * meet,
             noise, "x V per grain"};
      hc.tolerance = 10.0;
      hc.note = "H_c is read from the walls, not from beta: it follows the edge whatever its shape";
      r.fill(hc, [](const auto& m) { return metric(m, "wall_mobility_length_mm"); });
      rows.push_back(hc);
      Row bc{"cone angle (R5)", bname + ": beta against the chord to the wall meeting", "beta", "deg", chord, noise,
             "x V per grain"};
      bc.judged = false;
      bc.note = "a straight line fitted to a bent edge: its angle lies between the edge's at the tip (60 deg) and "
                "at the wall; ½(L_c - L) tan beta then misses H_c by the bias times about " +
                fmt("%.1f", 1e3 * half_gap * std::numbers::pi / 180.0 / std::pow(std::cos(chord * std::numbers::pi / 180.0), 2)) +
                " mm per degree";
      r.fill(bc, [](const auto& m) { return metric(m, "cone_angle_deg"); });
      rows.push_back(bc);
    }
  }
  // H_c's power against its found rate: a cone at the angle the stage plants
  // its loss for (cg.toml's wall.power_cone_angle_deg) present in only some of
  // few snapshots (the walls' flags then miss at that rate), the power the
  // stage reports against how often it finds the loss
  for (const double rest : set.intermittent_at_rest) {
    ConeScenario cone = plain;
    cone.beta_deg = cg.in.config.wall_power_cone_angle_deg;
    cone.at_rest = rest, cone.travel = set.intermittent_travel_mm * 1e-3;
    const std::string name = "a " + fmt("%g", cone.beta_deg) + " deg cone at rest in " + fmt("%g", 100.0 * rest) +
                             " % of the snapshots, one every " + fmt("%g", set.intermittent_travel_mm) + " mm";
    const std::string limit =
        rest > 0.5 ? "a cone at rest in most snapshots: the walls' flags below the loss are mostly immobile, and the "
                     "flip rate (the minority on each side) reads them as a cone present in most snapshots with "
                     "fewer errors; the power is that of the paper's claim (walls mobile below H_c), too high for this case"
                   : "";
    const auto [found, power] = power_rows(replicas(cone), "H_c power", name, 0.0, "x V per grain",
                                           "wall_mobility_length_mm", 1e3 * wall_meeting(cone.beta_deg, 0.0, half_gap),
                                           10.0, "mm", "wall_mobility_power", limit);
    rows.push_back(found);
    rows.push_back(power);
  }
  // dilatancy: a layer above the intruder stretched at every snapshot after the first
  for (const double jitter : set.position_noise_d)
    for (const double dphi : set.dilatancy) {
      Row r{"dilatancy (R11)", "the layer above the intruder dilated by " + fmt("%g", dphi), "delta phi", "-", dphi,
            jitter, "d per grain (positions)"};
      r.tolerance = 0.005;
      summarise(r, set.replicas, [&](unsigned seed) {
        BedGeometry g;
        g.seed = seed;
        const Bed bed = make_bed(g);
        ConeScenario c;
        c.noise = 0.0, c.end = g.start + 0.008, c.jitter = jitter, c.seed = seed;
        c.dilation = -dphi / (bed.solid_fraction + dphi);  // phi / (1 + e) - phi = dphi
        return metric(cg.run(bed, c), "dilatancy_delta_phi");
      });
      rows.push_back(r);
    }
  return rows;
}

}  // namespace dem2d::planted
