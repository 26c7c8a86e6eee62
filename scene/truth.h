// The ground truth of a frame, from the scene: the sun from ERFA, the camera's orientation, and the
// celestial pole's direction and pixel that the estimators are scored against.
#pragma once

#include <optional>

#include <Eigen/Core>

#include "camera/camera.h"
#include "scene/scene.h"
#include "sky/sun.h"
#include "sky/time.h"

namespace skypol::scene {

// The truth of one frame, written into its EXR part's header by the stack format (docs/exr-format.md).
struct Truth {
  sky::Instant time;
  sky::Site site;
  sky::Sun sun;                       // radians inside; degrees in the header
  Eigen::Matrix3d world_from_camera = Eigen::Matrix3d::Identity();
  double heading_deg = 0;             // camera heading (camera/orientation.h)
  double tilt_deg = 0;
  double roll_deg = 0;
  // The celestial pole an observer at this site sees: north for latitude ≥ 0, south otherwise
  // (documented rule; at the equator both lie on the horizon and north is chosen).
  Eigen::Vector3d pole_enu = Eigen::Vector3d::UnitY();
  bool pole_is_north = true;
  std::optional<Eigen::Vector2d> pole_pixel;  // nullopt when the lens cannot image it
};

Truth make_truth(const Scene& scene, const camera::Camera& camera, sky::Instant t);

// The celestial pole an observer at `latitude_deg` sees (north for latitude ≥ 0, else south), ENU.
Eigen::Vector3d visible_pole(double latitude_deg);

}  // namespace skypol::scene
