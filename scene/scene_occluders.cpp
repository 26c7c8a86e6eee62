// The [occluders] section: a horizon profile, boxes and OBJ meshes (docs/scenes.md). OBJ files
// are read here, so that a bad mesh is a scene error at its key, never a failure in the renderer.
#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "scene/box_mesh.h"
#include "scene/obj_mesh.h"
#include "scene/scene.h"

namespace skypol::scene {
namespace {

constexpr double kMaxDistanceM = 1e6;  // 1000 km: beyond that float precision blurs a facade

// Three numbers, each in [lo, hi]; fallback when the key is absent.
Eigen::Vector3d vector3(Fields& f, std::string_view key, const Eigen::Vector3d& fallback, double lo, double hi,
                        const char* what) {
  if (!f.has(key)) return fallback;
  const std::vector<double> v = f.numbers(key, {});
  if (v.size() != 3) f.fail(key, std::string("needs 3 numbers ") + what);
  for (double x : v) {
    if (!(x >= lo && x <= hi)) {
      std::ostringstream os;
      os << "each number must be in [" << lo << ", " << hi << "], found " << x;
      f.fail(key, os.str());
    }
  }
  return {v[0], v[1], v[2]};
}

std::vector<HorizonPoint> read_horizon(Fields& f) {
  std::vector<HorizonPoint> profile;
  for (const Fields::Row& r : f.rows("horizon", 2)) {
    HorizonPoint p{r[0], r[1]};
    if (!(p.azimuth_deg >= 0 && p.azimuth_deg < 360)) {
      f.fail("horizon", "azimuth " + std::to_string(p.azimuth_deg) + " is outside [0, 360) degrees");
    }
    if (!(p.elevation_deg > -90 && p.elevation_deg < 90)) {
      f.fail("horizon", "elevation " + std::to_string(p.elevation_deg) + " is outside (-90, 90) degrees");
    }
    if (!profile.empty() && !(p.azimuth_deg > profile.back().azimuth_deg)) {
      f.fail("horizon", "azimuths must be strictly increasing ([azimuth_deg, elevation_deg] pairs, in order)");
    }
    profile.push_back(p);
  }
  if (f.has("horizon") && profile.empty()) f.fail("horizon", "needs at least one [azimuth_deg, elevation_deg] pair");
  return profile;
}

BoxSpec read_box(Fields& b, const Eigen::Vector3d& eye) {
  BoxSpec box;
  for (const char* key : {"position_m", "size_m"}) {
    if (!b.has(key)) b.fail(key, "missing (position_m = [east, north, up] of the base's centre, size_m = [width, depth, height])");
  }
  box.position_m = vector3(b, "position_m", box.position_m, -kMaxDistanceM, kMaxDistanceM, "[east, north, up] in metres");
  box.size_m = vector3(b, "size_m", box.size_m, 1e-3, kMaxDistanceM, "[width, depth, height] in metres");
  box.yaw_deg = b.number("yaw_deg", 0, -360, 360);
  b.finish();
  if (box_contains(box, eye)) b.fail("position_m", "the observer's eye is inside this box: every ray would be blocked");
  return box;
}

MeshSpec read_mesh(Fields& m) {
  MeshSpec mesh;
  std::filesystem::path path(m.required_string("path"));
  if (path.is_relative()) path = std::filesystem::path(m.file()).parent_path() / path;
  mesh.path = std::filesystem::absolute(path).lexically_normal().string();
  mesh.position_m = vector3(m, "position_m", mesh.position_m, -kMaxDistanceM, kMaxDistanceM, "[east, north, up] in metres");
  mesh.yaw_deg = m.number("yaw_deg", 0, -360, 360);
  mesh.scale = m.number("scale", 1, 1e-6, 1e6);
  mesh.y_up = m.choice("up_axis", "z", {"z", "y"}) == "y";
  m.finish();
  if (!std::filesystem::is_regular_file(mesh.path)) m.fail("path", "no such file: " + mesh.path);
  try {
    mesh.triangles = load_obj(mesh.path);
  } catch (const std::invalid_argument& e) {
    m.fail("path", e.what());
  }
  return mesh;
}

}  // namespace

OccluderSpec read_occluders(Fields& f) {
  OccluderSpec spec;
  spec.observer_height_m = f.number("observer_height_m", 0, -1000, 1e4);
  const Eigen::Vector3d eye(0, 0, spec.observer_height_m);
  spec.horizon = read_horizon(f);
  for (Fields& b : f.tables("box")) spec.boxes.push_back(read_box(b, eye));
  for (Fields& m : f.tables("mesh")) spec.meshes.push_back(read_mesh(m));
  spec.occluded_pixels =
      f.choice("occluded_pixels", "masked", {"masked", "shaded"}) == "shaded" ? OccludedPixels::shaded : OccludedPixels::masked;
  // Read (and checked) whatever the rule: a scene that sets it may be rendered with
  // --set occluders.occluded_pixels=masked, and an override cannot remove a key.
  spec.surface_albedo = f.number("surface_albedo", spec.surface_albedo, 0, 1);
  f.finish();
  if (spec.empty()) f.fail("horizon", "the section names no occluders: give 'horizon', [[occluders.box]] or [[occluders.mesh]] (or drop the section)");
  return spec;
}

}  // namespace skypol::scene
