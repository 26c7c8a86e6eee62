#include "render/occluders_embree.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>

#include <embree3/rtcore.h>

#include "render/occluder_geometry.h"

namespace skypol::render {
namespace {

std::atomic<std::size_t> g_devices_created{0};

// Embree reports errors through one callback per device (its tutorials' pattern) rather than a
// return code per call; the first message is kept and turned into an exception after the build.
struct DeviceErrors {
  std::mutex mutex;
  std::string first;
};

void on_error(void* user, RTCError code, const char* message) {
  auto* errors = static_cast<DeviceErrors*>(user);
  const std::lock_guard lock(errors->mutex);
  if (errors->first.empty()) {
    errors->first = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
  }
}

// Rays go to Embree as streams of this many (rtcOccluded1M): Embree forms packets of the width the
// CPU supports (16 with AVX-512, 8 with AVX2) from coherent streams; small enough to stay in L1.
constexpr std::size_t kChunk = 256;

class EmbreeOccluders final : public Occluders {
 public:
  EmbreeOccluders(const std::vector<scene::TriangleMesh>& meshes, bool shaded, double albedo)
      : shaded_(shaded), albedo_(static_cast<float>(albedo)) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw std::runtime_error("cannot create an Embree device");
    ++g_devices_created;
    rtcSetDeviceErrorFunction(device_, on_error, &errors_);
    scene_ = rtcNewScene(device_);
    // Robust traversal makes the fans and boxes watertight along shared edges: a ray through an
    // edge or a corner (the nadir of the horizon fan, a box's vertical edge) never slips through.
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    for (const scene::TriangleMesh& m : meshes) {
      RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
      rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_HIGH);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                            3 * sizeof(float), m.vertices.size()));
      auto* t = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
          g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), m.triangles.size()));
      if (!v || !t) break;  // the error callback has the reason
      for (std::size_t i = 0; i < m.vertices.size(); ++i) std::memcpy(v + 3 * i, m.vertices[i].data(), 3 * sizeof(float));
      for (std::size_t i = 0; i < m.triangles.size(); ++i) std::memcpy(t + 3 * i, m.triangles[i].data(), 3 * sizeof(std::uint32_t));
      rtcCommitGeometry(g);
      rtcAttachGeometry(scene_, g);
      rtcReleaseGeometry(g);  // the scene holds its own reference
    }
    rtcCommitScene(scene_);
    if (!errors_.first.empty()) {
      const std::string message = errors_.first;
      release();
      throw std::runtime_error(message);
    }
  }
  EmbreeOccluders(const EmbreeOccluders&) = delete;
  EmbreeOccluders& operator=(const EmbreeOccluders&) = delete;
  ~EmbreeOccluders() override { release(); }

  void occluded(std::span<const Eigen::Vector3f> dirs, std::span<std::uint8_t> out) const override {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;  // neighbouring pixels: neighbouring rays
    std::array<RTCRay, kChunk> rays;
    for (std::size_t first = 0; first < dirs.size(); first += kChunk) {
      const std::size_t n = std::min(kChunk, dirs.size() - first);
      for (std::size_t i = 0; i < n; ++i) rays[i] = ray_along(dirs[first + i]);
      rtcOccluded1M(scene_, &context, rays.data(), static_cast<unsigned>(n), sizeof(RTCRay));
      // An occluded ray comes back with tfar = −∞.
      for (std::size_t i = 0; i < n; ++i) out[first + i] = rays[i].tfar < 0 ? 1 : 0;
    }
  }

  bool shaded() const override { return shaded_; }

  void surface_s0(std::span<const Eigen::Vector3f> dirs, std::span<float> out) const override {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    std::array<RTCRayHit, kChunk> hits;
    for (std::size_t first = 0; first < dirs.size(); first += kChunk) {
      const std::size_t n = std::min(kChunk, dirs.size() - first);
      for (std::size_t i = 0; i < n; ++i) {
        hits[i].ray = ray_along(dirs[first + i]);
        hits[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
        hits[i].hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect1M(scene_, &context, hits.data(), static_cast<unsigned>(n), sizeof(RTCRayHit));
      for (std::size_t i = 0; i < n; ++i) {
        const RTCHit& h = hits[i].hit;
        if (h.geomID == RTC_INVALID_GEOMETRY_ID) {
          out[first + i] = 0;
          continue;
        }
        Eigen::Vector3f normal(h.Ng_x, h.Ng_y, h.Ng_z);
        normal.normalize();
        if (normal.dot(dirs[first + i]) > 0) normal = -normal;  // the side the observer sees
        out[first + i] = albedo_ * 0.5f * (1.0f + normal.z());
      }
    }
  }

 private:
  // A ray from the eye (the origin) along d, over its whole length.
  static RTCRay ray_along(const Eigen::Vector3f& d) {
    RTCRay r;
    r.org_x = r.org_y = r.org_z = 0;
    r.tnear = 0;
    r.dir_x = d.x();
    r.dir_y = d.y();
    r.dir_z = d.z();
    r.time = 0;
    r.tfar = std::numeric_limits<float>::infinity();
    r.mask = 0xffffffffu;
    r.id = 0;
    r.flags = 0;
    return r;
  }

  void release() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
    scene_ = nullptr;
    device_ = nullptr;
  }

  bool shaded_;
  float albedo_;
  DeviceErrors errors_;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

}  // namespace

std::shared_ptr<const Occluders> make_occluders(const scene::OccluderSpec& spec) {
  if (spec.empty()) return nullptr;
  return std::make_shared<EmbreeOccluders>(occluder_meshes(spec), spec.occluded_pixels == scene::OccludedPixels::shaded,
                                           spec.surface_albedo);
}

std::size_t embree_devices_created() { return g_devices_created.load(); }

}  // namespace skypol::render
