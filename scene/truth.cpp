#include "scene/truth.h"

namespace skypol::scene {

Eigen::Vector3d visible_pole(double latitude_deg) {
  const Eigen::Vector3d ncp = sky::north_celestial_pole(latitude_deg);
  return latitude_deg >= 0 ? ncp : Eigen::Vector3d(-ncp);
}

Truth make_truth(const Scene& scene, const camera::Camera& camera, sky::Instant t) {
  Truth truth;
  truth.time = t;
  truth.site = scene.site;
  truth.sun = sky::sun_position(scene.site, t, scene.sun_options);
  truth.world_from_camera = camera.world_from_camera();
  truth.heading_deg = scene.camera.heading_deg;
  truth.tilt_deg = scene.camera.tilt_deg;
  truth.roll_deg = scene.camera.roll_deg;
  truth.pole_is_north = scene.site.latitude_deg >= 0;
  truth.pole_enu = visible_pole(scene.site.latitude_deg);
  if (std::optional<Eigen::Vector2d> px = camera.project(truth.pole_enu)) {
    const bool inside = px->x() >= -0.5 && px->y() >= -0.5 && px->x() < camera.width() - 0.5 &&
                        px->y() < camera.height() - 0.5;
    if (inside) truth.pole_pixel = px;
  }
  return truth;
}

}  // namespace skypol::scene
