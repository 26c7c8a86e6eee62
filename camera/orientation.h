// The camera's orientation: the rotation world(ENU) ← camera. docs/conventions.md draws it.
//
// heading/tilt/roll (proper Euler angles Z-X-Z), applied in this order to a camera that starts
// pointing at the zenith with image-up (−y) towards North (so image-right, +x, is West: the sky
// seen from below is mirrored):
//   1. heading ψ about Up: image-up turns from North towards East by ψ;
//   2. tilt    τ about the camera's +x axis: the optical axis tips from the zenith by τ towards
//      the image-up direction (azimuth ψ), so image-up tips down;
//   3. roll    ρ about the (tilted) optical axis: image-up turns by ρ towards the former
//      image-right (clockwise as seen on the image).
//   world_from_camera = Rz(−ψ) · C0 · Rx(τ) · Rz(ρ), C0 = [x→West, y→South, z→Up], R* the usual
//   right-handed rotation matrices.
// So tilt 0 is a zenith camera whose image top faces azimuth ψ − ρ (the SkyPole paper's "camera
// azimuth" α_cam = ψ with ρ = 0). Tilt 90° is a level camera looking at azimuth ψ, but upside
// down (image-up = Down, image-right = ψ − 90°); roll 180° makes it upright. Tilt 180° looks at
// the nadir. At tilt 0 (and 180) heading and roll turn about the same axis: only ψ − ρ (ψ + ρ)
// matters.
// Worked examples: ψ = 90°, τ = 0, ρ = 0 → camera +x = North, +y = West, +z = Up.
//                  ψ = 0, τ = 90°, ρ = 180° → camera +x = East, +y = Down, +z = North.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace skypol::camera {

// world_from_camera for the angles in degrees. Throws std::invalid_argument if tilt ∉ [0, 180]
// or an angle is not finite.
Eigen::Matrix3d world_from_heading_tilt_roll(double heading_deg, double tilt_deg, double roll_deg);

// The same from a unit quaternion (w, x, y, z), world ← camera, Hamilton convention (as Eigen;
// ROS and SciPy print (x, y, z, w): reorder). Normalised on input; throws for a zero or non-finite
// quaternion. Example: (cos 45°, 0, 0, sin 45°) is the ψ = 90° zenith camera above.
Eigen::Matrix3d world_from_quaternion(double w, double x, double y, double z);

// The camera heading ψ that a world_from_camera rotation implies, degrees in [0, 360): the
// azimuth of the optical axis' horizontal part when the camera is tilted; for a zenith camera
// (axis within 1e-9 rad of Up) the azimuth of image-up, for a nadir camera that of image-down
// (i.e. the heading with roll taken as 0). Inverts world_from_heading_tilt_roll for tilt in
// (0, 180) and for any tilt with roll 0.
double heading_deg_of(const Eigen::Matrix3d& world_from_camera);

}  // namespace skypol::camera
