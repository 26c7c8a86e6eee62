// What the lens and camera tests share: the reference sensor (Sony IMX250, 2448×2048 pixels of
// 3.45 µm) behind the reference lens (Fujinon FE185C057HA-1, 1.8 mm, 185°), and directions in
// the camera frame by their angles.
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "camera/lens.h"

namespace skypol::testing {

// The Fujinon's 1.8 mm focal length in 3.45 µm pixels.
inline constexpr double kF = 521.739;

// The IMX250 with its principal point at the centre of the 2448×2048 pixels (OpenCV's pixel
// centres) and a focal length of f pixels. With f = kF, a 185° equidistant image circle
// (r = f·92.5°) fits in the 2048 rows.
inline camera::Intrinsics imx250(double f = kF) {
  camera::Intrinsics k;
  k.fx = k.fy = f;
  k.cx = 1223.5;
  k.cy = 1023.5;
  k.width = 2448;
  k.height = 2048;
  return k;
}

// Unit camera-frame direction θ off the optical axis, at azimuth φ from image right towards
// image down (docs/conventions.md).
inline Eigen::Vector3d dir(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

}  // namespace skypol::testing
