// A horizon profile (mountains, a distant skyline) as a closed mesh around the eye: for every
// azimuth, everything from the profile's elevation down to the nadir is covered, so no ray below
// the profile escapes, whichever way the camera points.
//
// The mesh is a wall and a floor at radius R: the wall runs down from the profile to a ring 1°
// below the profile's lowest point, the floor is a flat disc closing that ring. (A fan from the
// profile straight to the nadir would cover the same directions, but every one of its long
// triangles' bounding boxes would contain the eye, and Embree would test each of them for every
// ray; these boxes hold only the directions near their own piece of the profile.)
//
// The rule (docs/scenes.md): between two profile points the elevation is linear in azimuth,
// wrapping through 360°; a single point is a constant elevation. The mesh samples that rule every
// ≤ 0.5° of azimuth, finer on steep slopes, and joins the samples by straight edges (great-circle
// arcs seen from the eye) that stay within 0.0001° of it.
#pragma once

#include <vector>

#include "scene/occluder_spec.h"
#include "scene/triangle_mesh.h"

namespace skypol::render {

// The wall and floor at radius_m around the origin (the eye).
// profile: non-empty, azimuths strictly increasing in [0, 360), elevations in (−90, 90).
scene::TriangleMesh horizon_mesh(const std::vector<scene::HorizonPoint>& profile, double radius_m);

// The rule above: the profile's elevation at azimuth_deg (any real value), in degrees.
double horizon_elevation_deg(const std::vector<scene::HorizonPoint>& profile, double azimuth_deg);

}  // namespace skypol::render
