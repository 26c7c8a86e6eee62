// Step 4 of the invariance estimator (invariance.h): the sub-pixel minimum around the fine
// search's direction, by one of two local models. Internal to skypole/.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "skypole/sky_images.h"

namespace skypol::skypole {

struct SubPixel {
  bool ok = false;
  std::string why;        // set when !ok
  Eigen::Vector3d d;      // the minimum (camera frame)
  double v = 0;           // DoLP variance left there (DoLP² units)
  double sigma_rad = 0;   // 1-σ angular uncertainty
  double window_rad = 0;  // radius of the window fitted (corotating: after shrinking)
  // corotating: the sense the sky turns in about d that fits (−1: clockwise by the right-hand
  // rule, the NCP's sense; +1 the SCP's), and how much worse the other sense fits (ratio of the
  // residual sums, ≥ 1); 0 / 0 for per_frame.
  int sense = 0;
  double sense_contrast = 0;
  // corotating with sectors > 0: the minimum refitted without each azimuth sector of the window
  // about d (nullopt: the refit left the window), for the sector jackknife (uncertainty.h).
  std::vector<std::optional<Eigen::Vector3d>> without_sector;
};

// Tangent basis (e1, e2) at the unit vector c.
void tangent_basis(const Eigen::Vector3d& c, Eigen::Vector3d& e1, Eigen::Vector3d& e2);

// Angular size of one pixel at direction d (radians).
double pixel_angle(const SkyImages& sky, const Eigen::Vector3d& d);

// Per-frame model: each frame's DoLP within radius_px of c fitted by its own polynomial of
// total degree `degree` in tangent-plane coordinates; the minimum over the window of the
// variance over time (after the residual projector h: mean, or mean and linear trend) of these
// polynomials. Needs nothing but the images; its window must stay small (a few pixels) for a
// low-degree polynomial to follow each frame's DoLP, so sensor noise moves it.
SubPixel per_frame_refine(const SkyImages& sky, const Eigen::MatrixXd& h, Eigen::Vector3d c,
                          double radius_px, int degree);

// What the co-rotating model knows of the sun's motion, per frame: the change of its hour angle
// and of its declination since the middle instant (radians; from the frames' times, ERFA), and
// the sun's direction in the frames that show it (frame index, camera frame), which orient the
// declination drift: each is turned to the middle instant and their mean taken, so one badly
// placed sun (on the horizon) cannot reverse it. Without any the drift is not modelled.
struct SunMotion {
  std::vector<double> hour_angle_change;
  std::vector<double> declination_change;
  std::vector<std::pair<std::size_t, Eigen::Vector3d>> suns_in_frames;
};

// Co-rotating model: the sky's pattern is fixed to the sun, which turns about the pole. For a
// candidate pole P every pixel's direction in frame t is turned back about P by the sun's motion
// since the middle instant, and all frames' DoLP within radius_deg of P are fitted by ONE
// polynomial of total degree `degree` in the turned tangent-plane coordinates (plus a linear
// trend in time with `trend`); the pole is the P that leaves the least variance. The window is
// shrunk to what the usable image holds around c (down to min_radius_deg, else !ok). With
// sectors > 0 the window's samples are also dealt into that many azimuth sectors about the minimum
// and the fit redone without each (SubPixel::without_sector).
SubPixel corotating_refine(const SkyImages& sky, const SunMotion& motion, bool trend,
                           Eigen::Vector3d c, double radius_deg, double min_radius_deg, int degree,
                           int sectors = 0);

}  // namespace skypol::skypole
