// The occluders of a scene as one Embree scene (triangles only: horizon fan, boxes, OBJ meshes),
// built once per stack and queried in streams of coherent rays (Embree packs them into SIMD packets). The only file that includes
// embree3/rtcore.h is occluders_embree.cpp.
#pragma once

#include <cstddef>
#include <memory>

#include "scene/occluder_spec.h"
#include "render/occluders.h"

namespace skypol::render {

// Null when the spec is empty: then no Embree device and no BVH exist. Throws std::runtime_error
// if Embree reports an error while building.
std::shared_ptr<const Occluders> make_occluders(const scene::OccluderSpec& spec);

// Embree devices this process has created so far (a scene without occluders adds none).
std::size_t embree_devices_created();

}  // namespace skypol::render
