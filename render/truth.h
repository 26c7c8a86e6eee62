// The ground truth of a frame, from the scene: the sun from ERFA, the camera's orientation, and the
// celestial pole's direction and pixel that the estimators are scored against.
#pragma once

#include "camera/camera.h"
#include "render/frame.h"
#include "render/scene.h"

namespace skypol::render {

Truth make_truth(const Scene& scene, const camera::Camera& camera, sky::Instant t);

// The celestial pole an observer at `latitude_deg` sees (north for latitude ≥ 0, else south), ENU.
Eigen::Vector3d visible_pole(double latitude_deg);

}  // namespace skypol::render
