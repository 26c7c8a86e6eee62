// What a scene's [occluders] section asks for, as checked plain values (docs/scenes.md). Empty
// when the scene names no occluders: then no Embree device or BVH is ever created.
//
// Positions are metres in ENU (x East, y North, z Up) with the ground under the observer at z = 0;
// the observer's eye is at (0, 0, observer_height_m). Angles are degrees, azimuth from North
// towards East (docs/conventions.md).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "scene/triangle_mesh.h"

namespace skypol::scene {

// One point of a horizon profile, as seen from the eye.
struct HorizonPoint {
  double azimuth_deg = 0;    // [0, 360), strictly increasing along the profile
  double elevation_deg = 0;  // (−90, 90)
};

// A building as a box standing on its base: the base's centre at position_m, extents size_m along
// its own axes (width, depth, height), turned by yaw_deg about Up from North towards East (as an
// azimuth): at yaw 0 the width runs East and the depth North; at yaw 90 the width runs South.
struct BoxSpec {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d size_m = Eigen::Vector3d::Ones();
  double yaw_deg = 0;
};

// A triangle mesh from an OBJ file, placed in ENU: a file vertex v becomes
// position_m + R(yaw_deg) · scale · A · v, with A the file's axes (up_axis "z": x East, y North,
// z Up; "y": x East, y Up, z South, the usual OBJ export convention).
struct MeshSpec {
  std::string path;          // absolute (resolved against the scene file's folder)
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  double yaw_deg = 0;
  double scale = 1;
  bool y_up = false;
  TriangleMesh triangles;    // loaded and checked when the scene is read; vertices as in the file
};

// What an occluded pixel holds (docs/scenes.md). masked: no light at all (S0..S3 = 0, DoLP = AoLP
// = 0) with mask = 0. shaded: mask = 0 still, and S0 is an unpolarized Lambertian surface lit by
// a uniform sky of unit radiance: S0 = surface_albedo · (1 + n_z) / 2, n the surface normal that
// faces the observer.
enum class OccludedPixels { masked, shaded };

struct OccluderSpec {
  double observer_height_m = 0;
  std::vector<HorizonPoint> horizon;  // empty: no horizon
  std::vector<BoxSpec> boxes;
  std::vector<MeshSpec> meshes;
  OccludedPixels occluded_pixels = OccludedPixels::masked;
  double surface_albedo = 0.3;

  bool empty() const { return horizon.empty() && boxes.empty() && meshes.empty(); }
};

}  // namespace skypol::scene
