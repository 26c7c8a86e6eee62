// Everything a scene's [occluders] section names, as triangle meshes in the eye's frame: ENU
// axes with the observer's eye (0, 0, observer_height_m) at the origin, which is where the
// camera rays start.
#pragma once

#include <vector>

#include "scene/occluder_spec.h"
#include "scene/triangle_mesh.h"

namespace skypol::render {

// How far out the horizon mesh is placed. Any distance would do for the occlusion test (a ray
// either passes below the profile or not); far beyond any building so that, for the shaded rule,
// the nearest surface a ray hits is a building before the horizon.
inline constexpr double kHorizonRadiusM = 100e3;

// One mesh per kind that is present: the horizon, all boxes together, each OBJ mesh.
std::vector<scene::TriangleMesh> occluder_meshes(const scene::OccluderSpec& spec);

std::size_t triangle_count(const std::vector<scene::TriangleMesh>& meshes);

}  // namespace skypol::render
