// The camera's orientation: the rotation world(ENU) ← camera. docs/conventions.md draws it.
//
// heading/tilt/roll, applied to a camera that starts pointing at the zenith with image-up (−y)
// towards North (so image-right, +x, is West: the sky seen from below is mirrored):
//   1. roll  ρ about the optical axis: the image turns so that image-up points ρ clockwise (as
//      seen on the image) from where it was;
//   2. tilt  τ: the optical axis tips from the zenith by τ towards the image-up direction;
//   3. heading ψ about Up: image-up (tilted: the optical axis' horizontal part) turns from North
//      towards East by ψ.
// So tilt 0 is a zenith camera whose image top faces azimuth ψ (the SkyPole paper's "camera
// azimuth" α_cam = ψ), and tilt 90° is a level camera looking at azimuth ψ, image-up = Up.
// Worked example: ψ = 90°, τ = 0, ρ = 0 → camera +x = North, +y = West, +z = Up.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace skypol::camera {

// world_from_camera for the angles in degrees. Throws std::invalid_argument if tilt ∉ [0, 180].
Eigen::Matrix3d world_from_heading_tilt_roll(double heading_deg, double tilt_deg, double roll_deg);

// The same from a unit quaternion (w, x, y, z), world ← camera; normalised on input, throws for
// a zero or non-finite quaternion.
Eigen::Matrix3d world_from_quaternion(double w, double x, double y, double z);

// The camera heading (azimuth of image-up projected on the horizon, or of the optical axis for a
// tilted camera; see above) that a world_from_camera rotation implies, degrees in [0, 360).
double heading_deg_of(const Eigen::Matrix3d& world_from_camera);

}  // namespace skypol::camera
