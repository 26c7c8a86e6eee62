// Model-based pole estimate from the great circles of equal DoLP (SkyPole SI eqs. 2–10).
//
// Why it works. For Rayleigh single scattering DoLP is a function of (s·P)² alone (s the sun, P
// the viewing direction), so between frames i and j, DoLP_i(P) = DoLP_j(P) ⟺ (s_i·P)² = (s_j·P)²
// ⟺ ((s_i − s_j)·P)((s_i + s_j)·P) = 0: two great circles, the *radial* one with normal s_i − s_j
// and the *plane* one with normal s_i + s_j (orthogonal normals). The sun turns about the pole at
// constant declination, s·p = sin δ, so every radial normal is ⟂ p: the pole is the common point
// of all radial circles (SI "The NCP is the only point ...").
//
// Steps, per pair of frames (i, j):
//  1. f = DoLP_i − DoLP_j (optionally disk-filtered); its sign changes between neighbouring valid
//     pixels give sub-pixel zero crossings (linear interpolation), turned into unit directions
//     through the lens model: points on the two circles, in 3-D, whatever the lens.
//  2. The pair of planes through the origin is fitted as one degenerate quadric Pᵀ M P = 0
//     (linear least squares, 6 unknowns), split into its two planes (eigenvectors of M), then
//     each plane is refined by robust (Tukey) total least squares on the points nearest to it.
//  3. Radial or plane circle, and the order of the two suns: the four hypotheses
//     s_i,j = cos h·A ± sin h·B with (A, B) ∈ {(n1, ±n2), (n2, ±n1)} are fitted to the two frames'
//     DoLP with the Rayleigh law Pmax·(1 − c²)/(1 + c²) (Pmax by least squares, h on a grid);
//     the best one names the radial normal B, oriented as s_i − s_j with A towards the sun
//     (above the horizon).
//  3b. The radial circle is refitted on its crossings away from the sun and the antisun
//     (sun_exclusion_deg), where a real sky's neutral points bend the equal-DoLP set.
//  4. The pole: the unit p that minimises Σ w_k (n_k·p − κ g_k)² over the radial normals n_k
//     (robust, Tukey-reweighted). κ models the sun's declination drift (≈ 0.4°/day near the
//     equinoxes, which tilts every radial circle by dδ/dω ≈ 0.06° off the pole): s_i·p = sin δ_i
//     gives n_k·p = (sin δ_i − sin δ_j)/|s_i − s_j| ≈ κ·g_k with g_k = (Δω/2)/sin(Δω/2), Δω the
//     pair's hour-angle step from the frame times (or from the fitted sun separation). With
//     DriftModel::none κ = 0 (p = smallest eigenvector of Σ w n nᵀ).
//  5. North: the sky turns about −NCP, and s_i × s_j ∝ n_r × n_p, so (n_r × n_p)·NCP < 0 (a vote
//     over pairs; a pair more than 12 h of hour angle apart, under a midnight sun, votes reversed:
//     from s_i to s_j the sun turned the short way round); the hint overrides it.
// The pole need not be in the field of view: the circles are fitted where they are seen.
// residual_deg: weighted RMS angular distance of the pole from the radial circles (after the
// drift term). Uncertainty: skypole/uncertainty.h.
//
// The sector jackknife, cheaply. The other methods' sector jackknife reruns them on the stack with
// one azimuth sector of the image masked (uncertainty.h); here that would redo steps 1–3 six more
// times, and step 3 (the DoLP fit that names the radial circle) is nearly all the cost. But a
// masked sector only removes the zero crossings between pixels of that sector, so the pairs keep
// their crossings with the sectors of their two pixels (GreatCircleParams::sectors), and a sub-run
// refits steps 2 and 3b on the crossings outside the sector (great_circle_pole_without_sector),
// keeping step 3's decision (which circle is radial, which way it faces, the suns' separation):
// the new radial circle is the one nearer the old. What it leaves out against the masked rerun:
// the disk filter still averages across the sector's edge, the radial/plane decision still reads
// the whole sky's DoLP, and a pair that failed on the whole sky stays unused. Measured against
// the masked reruns (great_circle_sectors_test): a sector σ of 8.44° against 8.43° on a sky wrong
// in one sector that moves the answer 6.4° (the frame jackknife: 0.13°), 0.015° against 0.014° on
// a clear day. It costs about a tenth more CPU than the method without it, where the masked reruns
// would cost ×7, and 4 MB for the crossings at 306×256 (docs/calibration-history.md).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "stack/frame.h"
#include "skypole/estimate.h"
#include "skypole/sky_images.h"
#include "skypole/stack_sky.h"

namespace skypol::skypole {

enum class DriftModel { none, fit, automatic };
DriftModel parse_drift_model(std::string_view name);  // "none" | "fit" | "automatic"
std::string_view drift_model_name(DriftModel m);

struct GreatCircleParams {
  InputOptions input;
  // Disk filter before the zero crossings; nullopt → default_filter_radius_px (it averages the
  // noise down and moves noise-free crossings by < 0.001°). 0 disables it.
  std::optional<double> filter_radius_px;
  PairMode pairs = PairMode::all;
  int interval = 1;
  int min_points = 30;            // zero crossings a circle needs to be used
  // Pairs whose suns are closer than this (fitted separation) are not used: their difference
  // image is weak against noise and their circles are nearly parallel to their neighbours'.
  double min_separation_deg = 0;
  // Step 3b: the radial circle is refitted on its crossings farther than this from the suns'
  // bisector and its antipode (0: not refitted). A real sky's neutral points, 15–25° from the
  // sun and the antisun, bend the equal-DoLP set well beyond them (on Berry's sky the error fell
  // from 0.92° to 0.51°, 0.33°, 0.24° for 0°, 40°, 60°, 70°: great_circle_test); the pole is
  // 66–114° from the sun, so 60° keeps the part of each circle that passes it. When fewer than
  // min_points crossings remain, 2/3 and 1/3 of it are tried, then every crossing (a camera that
  // sees little but the sun's side of the sky).
  double sun_exclusion_deg = 60;
  DriftModel drift = DriftModel::automatic;
  // automatic: fit the drift when ≥ 4 pairs are kept and their radial normals span ≥ this arc
  // about the pole (a short window cannot separate the drift from the pole).
  double auto_drift_min_arc_deg = 60;
  int model_samples = 3000;       // pixels used to tell the radial circle from the plane one
  bool keep_circles = false;      // fill GreatCircleResult::circles
  // > 0: keep each pair's zero crossings with their pixels' azimuth sectors (this many, about the
  // principal point: uncertainty.h sector_of), for great_circle_pole_without_sector.
  int sectors = 0;
};

// A zero crossing of a pair's DoLP difference (step 1): its direction (camera frame) and the sky
// sectors of the two pixels it lies between.
struct CircleCrossing {
  Eigen::Vector3d p;
  std::uint8_t sector_a = 0, sector_b = 0;
};

// One pair's fitted circles (for inspection and plots).
struct CirclePair {
  int i = 0, j = 0;
  Eigen::Vector3d radial_normal = Eigen::Vector3d::Zero();  // ∝ s_i − s_j, camera frame
  Eigen::Vector3d plane_normal = Eigen::Vector3d::Zero();   // ∝ s_i + s_j, towards the sun
  int radial_points = 0, plane_points = 0;
  double radial_rms_deg = 0;      // RMS distance of the radial circle's inlier points
  double sun_separation_deg = 0;  // 2h of the best hypothesis
  double hypothesis_ratio = 0;    // best SSE / second-best SSE of step 3 (small = clear)
  bool used = false;              // kept for the pole (enough points, inlier of the final fit)
};

struct GreatCircleResult {
  PoleEstimate estimate;
  std::vector<CirclePair> circles;  // when keep_circles
  double drift = 0;                 // κ (≈ −dδ/dω), 0 when not fitted
  bool drift_fitted = false;
};

// Needs at least 3 frames. Throws std::invalid_argument for unusable input (estimate.h).
// The same as great_circle_pole(great_circle_pairs(stack, params), params).
GreatCircleResult estimate_great_circle(const stack::Stack& stack,
                                        const GreatCircleParams& params = {});

// The method in two parts, so that a jackknife over frames refits only the pole (steps 4–5) from
// the pairs' circles (steps 1–3, nearly all the cost), which do not depend on the other frames.
struct GreatCirclePairs {
  SkyImages sky;
  std::vector<CirclePair> circles;
  std::vector<std::vector<CircleCrossing>> crossings;  // per circle pair, when params.sectors > 0
  int sectors = 0;                                     // params.sectors
  double seconds = 0;  // what steps 1–3 took
};
GreatCirclePairs great_circle_pairs(const stack::Stack& stack, const GreatCircleParams& params);
// The same on a view of a stack (stack_sky.h); params.input is the view's.
GreatCirclePairs great_circle_pairs(const SkyView& view, const GreatCircleParams& params);

// Steps 4–5 on the pairs both of whose frames `keep_frame` keeps (nullptr or empty: all).
GreatCircleResult great_circle_pole(const GreatCirclePairs& pairs, const GreatCircleParams& params,
                                    const std::vector<std::uint8_t>* keep_frame = nullptr);
// The answer of a stack with sky sector g (of pairs.sectors) masked, from the kept crossings: each
// pair with a crossing in the sector has steps 2 and 3b redone on its others, then steps 4–5 (see
// "The sector jackknife, cheaply" above). Throws std::invalid_argument when the crossings were not
// kept (params.sectors = 0) or g is not a sector.
GreatCircleResult great_circle_pole_without_sector(const GreatCirclePairs& pairs, const GreatCircleParams& params,
                                                   int g);

}  // namespace skypol::skypole
