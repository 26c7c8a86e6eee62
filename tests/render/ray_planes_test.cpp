// The renderer's ray storage: span-only planes hold exactly the pixels of each row between the
// first and last that see the sky (counted here from the lens's closed form), rays traced per
// tile (keep_rays = false) and planes handed from one renderer to the next give the bytes of a
// renderer that traced its own, and planes made for another camera are refused.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "camera/orientation.h"
#include "camera/radial_lens.h"
#include "render/ray_planes.h"
#include "render/renderer.h"
#include "sky/rayleigh.h"
#include "sky/units.h"
#include "sky/sky_test_util.h"

using namespace skypol;
using skypol::testing::sun_at;

namespace {
constexpr double kThetaMax = rad_from_deg(92.5);

camera::Intrinsics fisheye_intrinsics(int w, int h) {
  camera::Intrinsics k;
  k.width = w;
  k.height = h;
  k.fx = k.fy = 0.9 * (h / 2.0) / kThetaMax;
  k.cx = (w - 1) / 2.0 + 0.25;
  k.cy = (h - 1) / 2.0 - 0.5;
  return k;
}

std::shared_ptr<const camera::Camera> fisheye(int w, int h, double tilt_deg = 0) {
  auto lens = std::make_shared<camera::RadialLens>(camera::Mapping::equidistant, fisheye_intrinsics(w, h), kThetaMax);
  return std::make_shared<camera::Camera>(lens, camera::world_from_heading_tilt_roll(30, tilt_deg, 5));
}

void check_same_frames(const stack::Frame& a, const stack::Frame& b) {
  REQUIRE(a.channels.size() == b.channels.size());
  for (const auto& [name, values] : a.channels) {
    INFO(name);
    CHECK(values == b.channel(name));  // exact: the same floats
  }
}
}  // namespace

TEST_CASE("ray planes store each row's span of the image circle, and nothing else", "[renderer][rays]") {
  const int w = 130, h = 100;
  const auto cam = fisheye(w, h);
  const render::RayPlanes planes(*cam, 16, nullptr);
  const camera::Intrinsics k = fisheye_intrinsics(w, h);
  const double r_max = k.fx * kThetaMax;  // equidistant: the circle's radius in pixels
  std::size_t expected = 0;
  for (int y = 0; y < h; ++y) {
    // The circle's chord on this row, from its closed form (pixels within r_max of the centre).
    int x0 = w, x1 = 0;
    for (int x = 0; x < w; ++x) {
      if (std::hypot(x - k.cx, y - k.cy) <= r_max * (1 - 1e-9)) x0 = std::min(x0, x), x1 = x + 1;
    }
    const render::RayPlanes::Row row = planes.row(y);
    if (x1 <= x0) {
      CHECK(row.x1 == row.x0);
      continue;
    }
    INFO("row " << y);
    CHECK(row.x0 == x0);
    CHECK(row.x1 == x1);
    expected += static_cast<std::size_t>(x1 - x0);
    for (int x = row.x0; x < row.x1; ++x) {
      const auto ray = cam->ray(Eigen::Vector2d(x, y));
      REQUIRE(ray);
      CHECK(row.dx[x - row.x0] == static_cast<float>(ray->d.x()));
      CHECK(row.uz[x - row.x0] == static_cast<float>(ray->e0.z()));
      CHECK(row.weight[x - row.x0] == 1.0f);
    }
  }
  CHECK(planes.stored_pixels() == expected);
  CHECK(expected < static_cast<std::size_t>(w * h) * 3 / 4);  // the corners are not stored
}

TEST_CASE("rays traced per tile, or planes from an earlier renderer, render the same bytes", "[renderer][rays]") {
  const auto cam = fisheye(120, 90, 12);
  const sky::RayleighSky sky_model(sky::RayleighParams{0.9});
  const sky::Sun sun = sun_at(140, 25);
  render::RenderOptions kept;
  kept.tile_rows = 7;  // tiles that do not divide the height
  const render::Renderer own(cam, kept);
  const stack::Frame reference = own.render(sky_model, sun);

  render::RenderOptions streamed = kept;
  streamed.keep_rays = false;
  const render::Renderer per_tile(cam, streamed);
  CHECK_FALSE(per_tile.ray_planes());
  check_same_frames(reference, per_tile.render(sky_model, sun));

  const render::Renderer shared(cam, kept, nullptr, own.ray_planes());
  CHECK(shared.ray_planes() == own.ray_planes());  // the same planes, not a copy
  check_same_frames(reference, shared.render(sky_model, sun));
}

TEST_CASE("planes made for another camera size or tiling are refused", "[renderer][rays][errors]") {
  const auto cam = fisheye(120, 90);
  const render::Renderer own(cam, render::RenderOptions{});
  CHECK_THROWS_AS(render::Renderer(fisheye(100, 90), render::RenderOptions{}, nullptr, own.ray_planes()),
                  std::invalid_argument);
  render::RenderOptions other;
  other.tile_rows = 8;
  CHECK_THROWS_AS(render::Renderer(cam, other, nullptr, own.ray_planes()), std::invalid_argument);
}
