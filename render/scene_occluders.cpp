// The [occluders] section: a horizon profile, boxes and OBJ meshes (docs/scenes.md).
#include "render/scene.h"

namespace skypol::render {

OccluderSpec read_occluders(Fields& f) {
  f.fail("", "occluders are not supported yet");
}

}  // namespace skypol::render
