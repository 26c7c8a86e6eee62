// How sure an estimate is, in one meaning for every method: a 1-σ uncertainty of the bearing and
// of the latitude and a 95 % cone on the sphere, all in degrees, derived from the method's own
// data by two jackknives — one over frames, one over parts of the sky — each scaled by a
// per-method factor that the calibration study (`skypol tradeoff calibration`) measured on scenes
// the checks do not use.
//
// The frame jackknife. The frames are dealt into K = min(frames, max_groups) interleaved groups
// (frame i goes to group i mod K; max_groups is 6, or 24 for great_circle, whose refits are cheap:
// method_registry.h MethodTraits::frame_jackknife_max_groups); the method runs again K times, each time without one group. The K
// answers' scatter about their mean, as the delete-a-group jackknife prescribes (Efron &
// Tibshirani, ch. 11: cov = (K−1)/K·Σ(θk − θ̄)(θk − θ̄)ᵀ), plus its bias term (K−1)·θ̄θ̄ᵀ, is
// the covariance of the pole's direction in the tangent plane at the estimate (azimuth and
// altitude axes of the level frame). It sees what differs between frames (noise, a short window).
//
// The sector jackknife. The frame jackknife cannot see an error every frame shares — a cloud that
// stays over one part of the sky, the neutral points of a real sky, saturation near the sun — since
// every frame group carries it alike. So the usable sky pixels are dealt into K = 6 azimuth
// sectors about the principal point and the method runs again with one sector masked in every
// frame (sun_vector, sun_vector_ephemeris, sun_dolp: the methods that fit the whole sky per frame;
// great_circle refits its cached zero crossings outside the sector instead of rerunning;
// invariance reads only the sky around its pole, where a masked wedge of the whole sky would trip
// its edge checks, so it deals its own window's samples into six sectors about the pole and refits
// without each); the same formula gives a second covariance. An error that lives in one part of the sky moves
// the answer without that part; one spread evenly over the sky still does not show.
//
// A method whose answer does not survive the loss of a group (of frames or of sky) — it declines,
// or finds the other pole — is unstable, and the estimate declines with that reason.
//
// Few groups. A jackknife's covariance is itself an estimate, from K − 1 degrees of freedom (K = 3
// frames give 2), and an error measured against it has a heavier tail than against a known σ: the
// 95 % point of |error|²/(2σ̂²) is that of F(2, ν), 9.55 for ν = 3 and 5.79 for ν = 5, not the 3.00 of
// a known σ. So the jackknives' part of the covariance is widened by q95(ν)/q95(∞), ν the
// Welch–Satterthwaite degrees of freedom of a²λ_frames + b²λ_sectors (λ: the larger eigenvalue,
// ν_frames = K − 1, ν_sectors = 5): the stated cone is then the Student-like 95 % cone of what the
// jackknives measured. Without it the error-to-σ ratio of sun_vector_ephemeris on 1,100 random scenes
// has a tail 5–6 times its 95 % point (a few 3-frame windows), so that no factor gives both no lie
// and a coverage of at most 98 %.
//
// From covariances to numbers (stated_covariance, calibrated_covariance below):
//     C = w²·(a²·C_frames + b²·C_sectors) + s²·I,   s² = floor² + (any per-answer terms)²
// (a, b, s from the calibration, MethodCalibration below; w² = few_groups_widening2); σ_lat = √C_alt,alt; σ_bearing = √C_az,az / cos(alt)
// (a tangent step d along the azimuth axis turns the azimuth by d/cos(alt)), capped at 180°;
// cone95 = √(χ²₂(0.95)·λmax) = 2.448·√λmax, the radius of a circle that holds the 95 % ellipse
// (conservative where the ellipse is elongated). σ_total = √λmax is the "σ" of the lie rate.
//
// What neither sees: an error spread evenly over the sky and the frames (a lens model that does
// not fit, a sky model wrong everywhere). The calibration's floor and its gates carry that part,
// as far as the calibration population holds such cases.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "camera/camera.h"
#include "stack/frame.h"
#include "skypole/estimate.h"

namespace skypol::skypole {

// Fills sigma_bearing_deg, sigma_latitude_deg, cone95_deg, sigma_deg of `e` from a 2×2
// covariance (rad²) of the pole in the tangent plane at e.pole_level, axes (azimuth, altitude).
void set_uncertainty(PoleEstimate& e, const Eigen::Matrix2d& covariance_rad2);

// The tangent-plane offset (rad; azimuth axis, altitude axis) of `other`'s pole from `at`'s,
// both taken as the end of the axis that `at` reports (the NCP or the SCP above the horizon).
Eigen::Vector2d tangent_offset(const PoleEstimate& at, const PoleEstimate& other);
// Its inverse: the level-frame unit direction `offset` (rad; azimuth axis, altitude axis) away from
// `at`'s pole along the sphere (the exponential map), as the end `at` reports.
Eigen::Vector3d tangent_moved(const PoleEstimate& at, const Eigen::Vector2d& offset);

// The stack with only the frames whose keep[i] is 1 (keep has one entry per frame): what a
// frame jackknife's sub-run sees, and what a refit from cached work must agree with.
stack::Stack frames_kept(const stack::Stack& stack, const std::vector<std::uint8_t>& keep);

// The azimuth sector (0 … sectors−1) of pixel (x, y) about the image point `centre_px`: the
// angle atan2(y − cy, x − cx) from −180° cut into `sectors` equal parts.
int sector_of(double x, double y, const Eigen::Vector2d& centre_px, int sectors);

// sector_of for every pixel of a width × height image, row-major (1 ≤ sectors ≤ 255, else
// std::invalid_argument): what sector_left_out masks by and great_circle tags its crossings with.
std::vector<std::uint8_t> sector_map(int width, int height, const Eigen::Vector2d& centre_px, int sectors);

// The stack with the pixels of sector `g` of `sectors` (sector_of) masked ("mask" = 0) in every
// frame: what a sector jackknife's sub-run sees.
stack::Stack sector_left_out(const stack::Stack& stack, const Eigen::Vector2d& centre_px, int g, int sectors);

// The delete-a-group jackknife's covariance (rad², tangent plane at `e`) from K sub-answers,
// `sub(g)` being the answer without group g. Declines `e` and returns nullopt when a sub-run fails
// or finds the other end of the axis; the reason names the groups (`what`: "frame group", "sky
// sector") and what an unstable answer means for them (`cause`).
std::optional<Eigen::Matrix2d> group_jackknife(PoleEstimate& e, int groups,
                                               const std::function<PoleEstimate(int g)>& sub,
                                               const std::string& what, const std::string& cause);

// The frame jackknife: K = min(frames, max_groups) interleaved groups; `refit(keep)` answers with
// only the frames whose keep[i] is 1. Stacks of fewer than 3 frames cannot be jackknifed: `e` is
// declined ("too few frames to measure the uncertainty") and nullopt returned.
std::optional<Eigen::Matrix2d> frame_jackknife(PoleEstimate& e, int frames,
                                               const std::function<PoleEstimate(const std::vector<std::uint8_t>& keep)>& refit,
                                               int max_groups = 6);

// The sector jackknife from the method's answer without sector g of `sectors`: a run on a view of
// the stack with that sector left out (stack_sky.h SkyView::without_sector, the same as a run on
// sector_left_out), or great_circle's refit of its cached zero crossings outside it (great_circle.h).
std::optional<Eigen::Matrix2d> sector_jackknife(PoleEstimate& e, int sectors,
                                                const std::function<PoleEstimate(int g)>& without_sector);

// The number of groups frame_jackknife deals `frames` frames into: min(frames, max_groups).
int frame_jackknife_groups(int frames, int max_groups = 6);

// q95(ν)/q95(∞) (see "Few groups" above): the squared widening of a variance frames_var +
// sectors_var, the first measured by a jackknife of frame_groups groups and the second by one of
// sector_groups (both ≥ 0: the two terms' larger eigenvalues, already scaled by the calibration's
// a² and b²). A group count of 0 marks a term as absent. 1 when the sum is 0; 6.34 for 3 groups
// alone, 1.93 for 6.
double few_groups_widening2(double frames_var, int frame_groups, double sectors_var, int sector_groups);

// The jackknives behind one answer: their covariances (rad², tangent plane) and group counts.
struct Jackknives {
  Eigen::Matrix2d frames = Eigen::Matrix2d::Zero();
  int frame_groups = 0;
  Eigen::Matrix2d sectors = Eigen::Matrix2d::Zero();
  int sector_groups = 0;  // 0: no sector jackknife
};

// Sets `e`'s uncertainty from `covariance_rad2` (set_uncertainty) and keeps the raw jackknives `j`
// in `e` for the calibration study.
void set_stated_uncertainty(PoleEstimate& e, const Jackknives& j, const Eigen::Matrix2d& covariance_rad2);

// A method's calibration (each method's registry entry, method_registry.h), measured by the calibration study
// (docs/benchmarks.md section 7; how each value was found: docs/calibration-history.md). The
// stated covariance is
//     C = w²·(inflation²·C_frames + b²·C_sectors) + s²·I,
//     b = sector_inflation + sector_unpolarized·unpolarized_share + sector_clipped·clipped_share
// (w²: the widening for the jackknives' few groups, few_groups_widening2)
//     s² = floor_deg² + (residual_share·max(0, residual_deg − residual_pixels·pixel))²
//          + (unpolarized_deg·unpolarized_share)² + (elevation_share·sun_elevation_misfit_deg)²
//          + (misfit_deg·model_misfit)²
// (pixel: pixel_angle_deg of the stack's camera; the shares: cloud_share.h unreadable_sky)
// — the frame jackknife sees errors that differ between frames, the sector jackknife errors that
// live in one part of the sky in every frame, the unpolarized term how much of the sky a clear sky
// cannot explain, the floor the bias left (a sky unlike the method's model), the residual term a
// method whose own fit spreads (classic's blob at low resolution). Gates: where the study found the
// method's error unpredictable — a fit residual above max_residual_deg, a window shorter than
// min_window_min, a sky more than max_unpolarized_share unpolarized (cloud; skypole/cloud_share.h),
// and the others below — it declines, saying so. The functions after it are that model, once: run_method
// (evaluate.h) states its answers with them, and scripts/calibration_tune.py calls them through the
// Python module to try calibrations on the study's rows.
struct MethodCalibration {
  std::string method;
  double inflation = 1.0;
  double floor_deg = 0.0;
  double residual_share = 0.0;
  double max_residual_deg = std::numeric_limits<double>::infinity();
  double min_window_min = 0.0;
  double max_unpolarized_share = std::numeric_limits<double>::infinity();
  double residual_pixels = 0.0;  // the residual term counts residual_deg − this many pixel angles (≥ 0)
  // Decline a sky whose DoLP is not a function of the angle to the sun beyond this
  // (ring_anisotropy, skypole/cloud_share.h: neutral points moved by a real sky).
  double max_ring_anisotropy = std::numeric_limits<double>::infinity();
  // Decline a sky that departs from the method's own model beyond this (PoleEstimate::model_misfit).
  double max_model_misfit = std::numeric_limits<double>::infinity();
  // Decline a sky more than this share clipped by the sensor in some frame (clipped_share,
  // cloud_share.h), beyond which the method's calibration holds no answer (a method whose σ has
  // no term for the sky it lost).
  double max_clipped_share = std::numeric_limits<double>::infinity();
  // The factor on the sector jackknife's covariance (uncertainty.h; 0: not counted), and a σ term
  // unpolarized_deg·unpolarized_share (cloud_share.h: cloud, neutral points, saturation — errors
  // every frame shares, which neither jackknife sees in full).
  double sector_inflation = 0.0;
  double unpolarized_deg = 0.0;
  // The sector factor grows by this per unit of unpolarized share. A cloud's error is shared by every
  // frame (the cloud stands still) but not by every part of the sky, so under cloud the sector
  // jackknife measures a bias, where on a clear sky its spread overstates the error (hence factors
  // under 1).
  double sector_unpolarized = 0.0;
  // The sector factor grows by this per unit of clipped share (UnreadableSky::clipped): a sky whose
  // sun side the sensor masked leaves the six sectors unequal, so that their spread can understate
  // the error.
  double sector_clipped = 0.0;
  // A σ term elevation_share·sun_elevation_misfit_deg (PoleEstimate: the shared error of the
  // ephemeris' suns that their elevations show and no jackknife resolves).
  double elevation_share = 0.0;
  // A σ term misfit_deg·model_misfit, degrees per unit of misfit (PoleEstimate::model_misfit: how far
  // the sky departs from Rayleigh's law; a multiply scattering sky moves the suns a method finds
  // alike in every frame and sector, so that neither jackknife sees it, by more the further it
  // departs). 0: not counted.
  double misfit_deg = 0.0;
};

// The calibration's fields that are numbers, each with its name (the name `skypol methods --json`
// and the Python module give it), in the order of the struct.
const std::vector<std::pair<const char*, double MethodCalibration::*>>& calibration_fields();

// What a calibration reads of one answer besides its jackknives: the measures its σ terms and
// gates read.
struct CalibrationReadings {
  double residual_deg = 0;              // PoleEstimate::residual_deg
  double pixel_deg = 0;                 // pixel_angle_deg of the stack's camera
  double unpolarized_share = 0;         // UnreadableSky::unpolarized (cloud_share.h)
  double clipped_share = 0;             // UnreadableSky::clipped
  double sun_elevation_misfit_deg = 0;  // PoleEstimate::sun_elevation_misfit_deg
  double model_misfit = 0;              // PoleEstimate::model_misfit
  double window_min = 0;                // the time from the first frame to the last
  double ring_anisotropy = 0;           // ring_anisotropy (cloud_share.h)
};

// s (degrees), the root-sum-square of the isotropic terms:
// √(floor_deg² + (residual_share·max(0, residual_deg − residual_pixels·pixel_deg))²
//   + (unpolarized_deg·unpolarized_share)² + (elevation_share·sun_elevation_misfit_deg)² + (misfit_deg·model_misfit)²).
// A residual that is not a number counts 0.
double calibrated_floor_deg(const MethodCalibration& c, const CalibrationReadings& r);
// b, the factor on the sector jackknife: sector_inflation + sector_unpolarized·unpolarized_share
// + sector_clipped·clipped_share.
double calibrated_sector_factor(const MethodCalibration& c, const CalibrationReadings& r);
// Whether the factors read the sky's unpolarized or clipped share (then run_method measures them).
bool reads_unreadable_sky(const MethodCalibration& c);

// The gates, in the order run_method tries them (the first that declines gives the reason).
enum class Gate { none, residual, model_misfit, window, unpolarized, clipped, ring_anisotropy };
// The MethodCalibration field that sets gate g ("max_residual_deg", …; "" for Gate::none).
const char* gate_field(Gate g);
// Whether gate g is set: its bound is finite (min_window_min: above 0). run_method measures a
// gate's sky share only when it is.
bool gate_set(Gate g, const MethodCalibration& c);
// Whether gate g declines an answer with readings r: a reading beyond the gate's bound (above it;
// for the window, below it). A reading that is not a number passes.
bool gate_declines(Gate g, const MethodCalibration& c, const CalibrationReadings& r);
// The first gate of c that declines r (Gate::none when every one passes). cloud_gate = false leaves
// the unpolarized gate out (InputOptions::cloud_gate).
Gate first_declining_gate(const MethodCalibration& c, const CalibrationReadings& r, bool cloud_gate = true);

// C (rad²) = w²·(a²·frames + b²·sectors) + floor_deg²·I, w² = few_groups_widening2 of the two terms
// (widen = false: 1; a sector term of b = 0 counts no groups).
Eigen::Matrix2d stated_covariance(const Jackknives& j, double a, double b, double floor_deg, bool widen = true);
// The covariance calibration c states for an answer with jackknives j and readings r.
Eigen::Matrix2d calibrated_covariance(const MethodCalibration& c, const Jackknives& j, const CalibrationReadings& r);
// The uncalibrated statement (the calibration study's --uncalibrated run, from which calibrations
// are tried): both jackknives as measured, unwidened, and a floor of kUncalibratedFloorDeg.
inline constexpr double kUncalibratedFloorDeg = 0.05;
Eigen::Matrix2d uncalibrated_covariance(const Jackknives& j);

// √λmax of a covariance (rad²), in degrees (the answer's σ), and the 95 % cone √(χ²₂(0.95)·λmax)
// in degrees, at most 180.
double sigma_deg_of(const Eigen::Matrix2d& covariance_rad2);
double cone95_deg_of(const Eigen::Matrix2d& covariance_rad2);
// Whether a 95 % cone is within the bound apply_uncertainty_bound keeps (an infinite bound keeps all).
bool within_uncertainty_bound(double cone95_deg, double max_cone95_deg);

// The 95 % Wilson score interval of a share observed as `hits` of `n` (NaN for n ≤ 0): what the
// coverage of a method with few answers can say. 23 answers all inside their cones (coverage 1)
// are consistent with a true coverage of 0.86–1; a band of 90–98 % read off the point alone would
// call them over-covering. Wilson's interval, unlike the normal approximation, stays inside [0, 1]
// and is not empty at hits = n (E. B. Wilson, J. Am. Stat. Assoc. 22, 209 (1927)).
std::pair<double, double> wilson_interval95(double hits, double n);

// auto's rule (auto.h combine_estimates) on answers reduced to what it reads: each answer's
// 95 % cone and σ, whether its method answers alone (MethodTraits::auto_answers_alone), and the
// angle between any two (degrees).
struct AutoCandidate {
  double cone95_deg = 0;
  double sigma_deg = 0;
  bool answers_alone = false;
};
// Two answers agree unless they are apart by more than kAutoAgreeScale × the root-sum-square of
// their 95 % cones: the 99.9 % level of their combined uncertainty, √(χ²₂(0.999)/χ²₂(0.95)).
inline constexpr double kAutoAgreeScale = 1.5185;
bool answers_agree(double angle_deg, double cone95_a_deg, double cone95_b_deg);
struct AutoChoice {
  bool decided = false;              // false: no answer, or the group is no larger than the dissent
  std::size_t centre = 0;            // the answer most others agree with (ties: the narrowest cone)
  std::vector<std::size_t> members;  // the answers that agree with the centre, in the given order
  std::vector<std::size_t> dissent;  // the others
  std::size_t sharpest = 0;          // the member of smallest σ (the first of equal ones)
  std::optional<std::size_t> alone;  // the first member whose method answers alone
  std::size_t chosen = 0;            // alone if any, else sharpest: whose σ (and, alone, pole) auto states
  bool mean = false;                 // no member answers alone and there are several: the pole is their mean
};
AutoChoice auto_choice(std::span<const AutoCandidate> answers,
                       const std::function<double(std::size_t, std::size_t)>& angle_deg);
// The inverse-variance mean of tangent-plane offsets (any one origin and unit), the weights
// 1/max(σᵢ², 10⁻¹²): where auto places the pole when AutoChoice::mean.
Eigen::Vector2d inverse_variance_mean(std::span<const Eigen::Vector2d> offsets, std::span<const double> sigmas);

// The angle (degrees) between the rays of the principal point and of the pixel to its right: a
// pixel's angular size at the centre of the image, the scale below which no method working on the
// pixel grid can place the pole (classic's blob is a few pixels wide at any resolution).
double pixel_angle_deg(const camera::Camera& camera);

// Declines `e` when its 95 % cone is wider than `max_cone95_deg` (when that is finite), with the
// reason in numbers.
void apply_uncertainty_bound(PoleEstimate& e, double max_cone95_deg);

}  // namespace skypol::skypole
