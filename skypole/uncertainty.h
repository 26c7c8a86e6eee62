// How sure an estimate is, in one meaning for every method: a 1-σ uncertainty of the bearing and
// of the latitude and a 95 % cone on the sphere, all in degrees, derived from the method's own
// data by a frame-group jackknife, inflated by a per-method factor that the calibration study
// (`skypol tradeoff calibration`, docs/benchmarks.md) measured on scenes the checks do not use.
//
// The jackknife. The frames are dealt into K = min(frames, 6) interleaved groups (frame i goes to
// group i mod K); the method runs again K times, each time without one group. The K answers'
// scatter about their mean, as the delete-a-group jackknife prescribes (Efron & Tibshirani,
// ch. 11: cov = (K−1)/K·Σ(θk − θ̄)(θk − θ̄)ᵀ), is the covariance of the pole's direction in the
// tangent plane at the estimate (azimuth and altitude axes of the level frame). A method whose
// answer does not survive the loss of a group of frames — it declines, or finds another pole —
// is unstable, and the estimate declines with that reason: an answer that moves by more than its
// own window can support is not one to report.
//
// From covariance to numbers. σ_lat = √C_alt,alt; σ_bearing = √C_az,az / cos(altitude) (a
// tangent step d along the azimuth axis turns the azimuth by d/cos(alt)), capped at 180°;
// cone95 = √(χ²₂(0.95)·λmax) = 2.448·√λmax, the radius of a circle that holds the 95 % ellipse
// (conservative where the ellipse is elongated). σ_total = √λmax is the "σ" of the lie rate.
//
// What it cannot see: an error every frame shares (a bias from a cloud that stays put, a lens
// model that does not fit) moves every jackknife answer alike. The calibration factor carries
// the part of it the study measured; the gates in each method (skypole/README.md) the rest.
#pragma once

#include <functional>
#include <cstdint>
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

struct JackknifeOptions {
  int max_groups = 6;
  double inflation = 1.0;      // calibration factor on σ (the method's, evaluate.cpp)
  double floor_deg = 0.0;      // σ never below this (e.g. the pixel's angular size)
};

// The stack with only the frames whose keep[i] is 1 (keep has one entry per frame): what a
// jackknife's sub-run sees, and what a refit from cached work must agree with.
stack::Stack frames_kept(const stack::Stack& stack, const std::vector<std::uint8_t>& keep);

// Runs `method` on the stack with one frame group left out at a time and sets `e`'s uncertainty
// (set_uncertainty) or, if a sub-run fails or finds the other end of the axis, declines `e` with
// the reason. `e` must be the method's valid answer on the whole stack. Stacks of fewer than 3
// frames cannot be jackknifed: declined ("too few frames to measure the uncertainty").
void jackknife_uncertainty(
    PoleEstimate& e, const stack::Stack& stack,
    const std::function<PoleEstimate(const stack::Stack&)>& method, const JackknifeOptions& options);

// The same jackknife for a method that can refit from work cached on the whole stack (e.g.
// great_circle's per-pair circles, classic's per-frame images): `refit(keep)` answers with only
// the frames whose keep[i] is 1 (keep has `frames` entries). Same groups, covariance and declines.
void jackknife_uncertainty(PoleEstimate& e, int frames,
                           const std::function<PoleEstimate(const std::vector<std::uint8_t>& keep)>& refit,
                           const JackknifeOptions& options);

// The angle (degrees) between the rays of the principal point and of the pixel to its right: a
// pixel's angular size at the centre of the image, the scale below which no method working on the
// pixel grid can place the pole (classic's blob is a few pixels wide at any resolution).
double pixel_angle_deg(const camera::Camera& camera);

// Declines `e` when its 95 % cone is wider than `max_cone95_deg` (when that is finite), with the
// reason in numbers.
void apply_uncertainty_bound(PoleEstimate& e, double max_cone95_deg);

}  // namespace skypol::skypole
