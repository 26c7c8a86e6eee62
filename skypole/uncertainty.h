// How sure an estimate is, in one meaning for every method: a 1-σ uncertainty of the bearing and
// of the latitude and a 95 % cone on the sphere, all in degrees, derived from the method's own
// data by two jackknives — one over frames, one over parts of the sky — each scaled by a
// per-method factor that the calibration study (`skypol tradeoff calibration`,
// docs/benchmarks.md section 7) measured on scenes the checks do not use.
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
// had a tail 5–6 times its 95 % point (a few 3-frame windows), so no factor gave both no lie and a
// coverage of at most 98 % (docs/benchmarks.md, section 7).
//
// From covariances to numbers (set_calibrated_uncertainty):
//     C = w²·(a²·C_frames + b²·C_sectors) + s²·I,   s² = floor² + (any per-answer terms)²
// (a, b, s from the calibration, evaluate.h; w² = few_groups_widening²); σ_lat = √C_alt,alt; σ_bearing = √C_az,az / cos(alt)
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
#include <optional>
#include <string>
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

// √λmax of a covariance (rad²), in degrees: one jackknife's σ on its own.
double sigma_deg_of(const Eigen::Matrix2d& covariance_rad2);

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

// Sets `e`'s uncertainty from C = w²·(a²·frames + b²·sectors) + floor_deg²·I (w² =
// few_groups_widening2; floor_deg: the root-sum-square of every isotropic term) and keeps the raw
// covariances in `e` for the calibration study. widen = false states the jackknives as measured
// (the calibration study's uncalibrated run, from which scripts/calibration_tune.py recomputes w).
void set_calibrated_uncertainty(PoleEstimate& e, const Jackknives& j, double a, double b, double floor_deg,
                                bool widen = true);

// The angle (degrees) between the rays of the principal point and of the pixel to its right: a
// pixel's angular size at the centre of the image, the scale below which no method working on the
// pixel grid can place the pole (classic's blob is a few pixels wide at any resolution).
double pixel_angle_deg(const camera::Camera& camera);

// Declines `e` when its 95 % cone is wider than `max_cone95_deg` (when that is finite), with the
// reason in numbers.
void apply_uncertainty_bound(PoleEstimate& e, double max_cone95_deg);

}  // namespace skypol::skypole
