// The result every skypole estimator returns, the options they share, and the score of a result
// against the renderer's truth. One page of conventions, written once (docs/conventions.md refers
// here for the estimators):
//
// What an estimator knows. The lens model (Stack::camera->lens()), the camera's tilt and roll (a
// level or an IMU measures gravity), the frames' DoLP (and AoLP for the sun-vector method) and
// their times. It does NOT know the heading. It works in the *level frame*
//     L = world_from_heading_tilt_roll(0, tilt, roll)        (camera/orientation.h)
// i.e. ENU turned about Up so that the camera's heading is 0. Since world_from_camera =
// Rz(−heading)·L, a direction's world azimuth is its level-frame azimuth + heading.
//
// What it reports. pole_camera: the unit direction, in the camera frame, of the celestial pole
// above the horizon (the NCP for a northern observer, the SCP for a southern one; is_north says
// which). α_rel = the pole's azimuth in the level frame, altitude = its elevation there;
//     latitude = +altitude (NCP) or −altitude (SCP);
//     heading  = (0° for the NCP, 180° for the SCP) − α_rel, wrapped to [0, 360).
// At a geographic pole the celestial pole is at the zenith and the heading is undefined: where the
// pole is within InputOptions::heading_undefined_within_deg of the zenith, heading_deg is nullopt
// and `note` says why (never a silent number). The latitude stays defined there.
//
// North or south. An estimator finds the pole's axis; which end is north comes from the sense of
// the sky's rotation: the sky turns about −NCP (the Earth turns about +NCP), so for sun directions
// s1 at t1 < s2 at t2, (s1 × s2)·NCP < 0. The DoLP gives the sun only up to sign (DoLP(s) =
// DoLP(−s)); skypole takes the end above the horizon (the daytime sun), and the sign would cancel
// anyway if both were flipped. InputOptions::hemisphere = north/south decides when the sun's
// rotation cannot; a rotation that decisively contradicts the hint wins, and the estimate's note
// says so (skypole/README.md, "North or south"). automatic fails with a clear reason if the sun's
// motion cannot be seen (no sun-like DoLP minimum above the horizon, or frames too close in time).
//
// Failures. Input that no estimator can use (no camera, fewer frames than the method needs, a
// frame without the DoLP channel, frames out of time order, image sizes that disagree) throws
// std::invalid_argument with a message naming the method, the frame and what was expected. Input
// that is well-formed but does not determine the pole (pole outside the field of view for the
// image-space methods, degenerate geometry) returns valid = false with why_invalid set; every
// number of an invalid estimate is meaningless and score() refuses it.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "stack/frame.h"

namespace skypol::skypole {

enum class Hemisphere { automatic, north, south };

// "automatic" | "north" | "south"; throws std::invalid_argument listing the legal names.
Hemisphere parse_hemisphere(std::string_view name);
std::string_view hemisphere_name(Hemisphere h);

// Whether the AoLP sun fits model the sensor's polarizer angle errors with the sun (sun_vector.h):
// from_stack, on the frames whose AoLP assumed the polarizers' nominal angles
// (stack::PolarizerAngles::nominal: an uncalibrated pipeline); always; never.
enum class PolarizerModel { from_stack, always, never };
// "stack" | "always" | "never"; throws std::invalid_argument listing the legal names.
PolarizerModel parse_polarizer_model(std::string_view name);
// What one frame's AoLP sun fits do: the plain fit, or the fit with the polarizer model. A type of
// its own, so that no number or flag converts to it by mistake.
enum class PolarizerFit : std::uint8_t { plain, modelled };
// Which of the two on this frame.
PolarizerFit polarizer_fit(const stack::Frame& frame, PolarizerModel model);
inline constexpr const char* kPolarizerModelHelp =
    "Fit the sensor's polarizer angle errors with each frame's sun: stack (where the stack says its AoLP assumed "
    "the polarizers' nominal angles, skypol:polarizerAngles), always, or never";

// The gravity-referenced part of the orientation (camera/orientation.h), degrees.
struct Attitude {
  double tilt_deg = 0;
  double roll_deg = 0;
};

// Options every estimator takes.
struct InputOptions {
  // Band whose "DoLP.<band>" channel is used. Empty: "B" if the stack has it (the paper used the
  // blue channel), else the stack's first band, else the first DoLP.* channel of frame 0.
  std::string band;
  // Tilt and roll the estimator may use. nullopt: frame 0's truth (tilt_deg, roll_deg), i.e. a
  // perfect level; pass measured values to study level errors.
  std::optional<Attitude> attitude;
  Hemisphere hemisphere = Hemisphere::automatic;
  // Pixels that look lower than this (level frame) are ground, not sky, and are not used.
  double min_elevation_deg = 0;
  // Pole closer than this to the zenith: the bearing is undefined (observer at a geographic pole).
  double heading_undefined_within_deg = 0.5;
  // The largest 95 % cone (degrees) an answer may have: a method whose stated uncertainty is
  // wider declines with the numbers (run_method). Infinity: no bound.
  double max_uncertainty_deg = std::numeric_limits<double>::infinity();
  // false: the jackknife's σ as measured, without the method's calibration factor
  // (Method::calibration, method_registry.h) — what the calibration study measures the factors from.
  bool calibrated = true;
  // false: skip the calibration's whole-sky cloud gate (cloud_share.h), to measure what the
  // methods do under cloud on their own (`tradeoff calibration --no-cloud-gate`).
  bool cloud_gate = true;
  // false: the methods fit every sky pixel, without the per-pixel sky mask (sky_mask.h); for
  // before/after measurements (`--no-sky-mask`). classic never uses the mask.
  bool sky_mask = true;
  // false: the methods do not use the stack's site and times, as on a capture whose site is unknown
  // (`--site unknown`): a method that needs them declines and auto is site-free (site_usable,
  // method_registry.h). Scoring against the truth is not affected.
  bool use_site = true;
  // The sensor's polarizer angle errors in the AoLP sun fits (`--polarizer-model`).
  PolarizerModel polarizer_model = PolarizerModel::from_stack;
};

struct PoleEstimate {
  std::string method;                 // "classic", "great_circle", "invariance", "sun_vector"
  bool valid = false;
  std::string why_invalid;            // set when !valid
  std::string note;                   // e.g. why heading_deg is undefined; hemisphere source
  Eigen::Vector3d pole_camera = Eigen::Vector3d::UnitZ();  // unit, camera frame, pole above horizon
  Eigen::Vector3d pole_level = Eigen::Vector3d::UnitZ();   // the same in the level frame
  std::optional<Eigen::Vector2d> pixel;  // where it images; nullopt outside the sensor/lens FOV
  double azimuth_rel_deg = 0;         // α_rel ∈ [0, 360)
  double altitude_deg = 0;            // ∈ [−90, 90]; ≥ min_elevation for image-space methods
  double latitude_deg = 0;            // +altitude (NCP) or −altitude (SCP)
  std::optional<double> heading_deg;  // [0, 360); nullopt when undefined (see top)
  bool is_north = true;               // pole_camera is the NCP (true) or the SCP (false)
  // The method's own fit residual in degrees (an angular spread or fit residual, documented with
  // each method; smaller is better). A diagnostic, not an uncertainty.
  double residual_deg = 0;
  // How far the sky departs from the method's model of it, as the method measures it (sun_dolp:
  // the rms of its Rayleigh fit's DoLP residual beyond the images' own noise, as a share of the
  // fitted Pmax, the median over frames: a multiply scattering sky's DoLP is not Rayleigh's law;
  // great_circle and sun_vector: the same, measured for them by sun_vector.h rayleigh_law_misfit,
  // evaluate.cpp run_method). 0: not measured. A diagnostic the calibration's gates and σ terms
  // read (calibration_gates.h, uncertainty.h).
  double model_misfit = 0;
  // An error of the method's own measurements that its data reveal but neither jackknife resolves,
  // as a shift of the pole in the tangent plane, degrees (sun_vector_ephemeris: its suns' elevations
  // against the ephemeris' — the heading rests on the suns' azimuths alone, so an error the frames
  // share along the azimuth moves the answer and leaves the residual small, while the same error
  // along the elevation shows: rms over frames of Δelevation/cos(elevation), times cos(latitude),
  // the pole's altitude; sun_vector.cpp). 0: not measured. A per-answer σ term of the calibration (evaluate.h).
  double sun_elevation_misfit_deg = 0;
  // The uncertainty, one meaning for every method (skypole/uncertainty.h): 1-σ of the bearing and
  // of the latitude, the radius of the 95 % cone about pole_camera on the sphere, and σ = √λmax of
  // the tangent-plane covariance, all in degrees. Set by run_method(); 0 = not measured (a method
  // called directly, without run_method, states none).
  double sigma_bearing_deg = 0;
  double sigma_latitude_deg = 0;
  double cone95_deg = 0;
  double sigma_deg = 0;
  // The raw jackknife covariances behind them (rad², tangent plane; uncertainty.h), before the
  // calibration's factors: over frame groups and over sky sectors. What the calibration study
  // fits the factors from. Zero: not measured (sectors: a method without a sector jackknife).
  Eigen::Matrix2d jackknife_frames_rad2 = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d jackknife_sectors_rad2 = Eigen::Matrix2d::Zero();
  int jackknife_frame_groups = 0;     // how many frame groups the first was measured from
  double seconds = 0;                 // wall-clock run time of the estimator
};

// Errors of one estimate against the truth of the stack's frames (take frame 0's truth: site
// and orientation do not change within a stack).
//  bearing_error_deg:  heading_est − truth.heading_deg wrapped to (−180, 180]; nullopt where the
//                      bearing is undefined (truth or estimate with the pole at the zenith).
//  latitude_error_deg: latitude_est − truth.site.latitude_deg.
//  angular_error_deg:  angle between the estimated NCP (placed in ENU with the true orientation)
//                      and the true NCP, [0, 180]; a wrong hemisphere shows as ≈ 180 − 2|lat|.
struct Score {
  std::optional<double> bearing_error_deg;
  double latitude_error_deg = 0;
  double angular_error_deg = 0;
};

// Throws std::invalid_argument for an invalid estimate (naming why it is invalid).
Score score(const PoleEstimate& estimate, const scene::Truth& truth);

// Angle wrapped to (−180, 180] and to [0, 360), degrees.
double wrap180(double deg);
double wrap360(double deg);
// A heading in [0, 360) with `decimals` decimals, rounded before it is wrapped: 359.9996 with 3
// decimals is "0.000", never "360.000".
std::string format_heading(double deg, int decimals);

}  // namespace skypol::skypole
