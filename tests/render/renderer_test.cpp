// The renderer against independent evaluations: each pixel equals the sky model at that pixel's
// ray, the mask is the image circle, output is identical whatever the thread count, and a pole
// pixel's DoLP does not change over a day (SkyPole SI eq. 4).
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include <tbb/global_control.h>

#include "camera/orientation.h"
#include "camera/radial_lens.h"
#include "render/renderer.h"
#include "render/truth.h"
#include "sky/rayleigh.h"

using namespace skypol;

namespace {

std::shared_ptr<const camera::Camera> small_fisheye(double heading_deg = 0, int w = 96, int h = 80) {
  camera::Intrinsics k;
  k.width = w;
  k.height = h;
  k.fx = k.fy = 0.95 * (h / 2.0) / (92.5 * std::numbers::pi / 180);  // 185° circle just inside the height
  k.cx = (w - 1) / 2.0;
  k.cy = (h - 1) / 2.0;
  auto lens = std::make_shared<camera::RadialLens>(camera::Mapping::equidistant, k, 92.5 * std::numbers::pi / 180);
  return std::make_shared<camera::Camera>(lens, camera::world_from_heading_tilt_roll(heading_deg, 0, 0));
}

sky::Sun sun_at(double az_deg, double el_deg) {
  sky::Sun s;
  s.azimuth = az_deg * std::numbers::pi / 180;
  s.elevation = el_deg * std::numbers::pi / 180;
  s.direction = sky::enu_direction(s.azimuth, s.elevation);
  return s;
}

}  // namespace

TEST_CASE("each rendered pixel is the sky model at that pixel's ray", "[renderer]") {
  const auto cam = small_fisheye(37);
  const sky::RayleighSky sky_model(sky::RayleighParams{0.8});
  const sky::Sun sun = sun_at(120, 35);
  const render::Renderer r(cam, render::RenderOptions{});
  const render::Frame f = r.render(sky_model, sun);
  const auto& dolp = f.channel("DoLP.Y");
  const auto& aolp = f.channel("AoLP.Y");
  const auto& s0 = f.channel("S0.Y");
  const auto& mask = f.channel("mask");
  int sky_pixels = 0;
  for (int y = 0; y < cam->height(); ++y) {
    for (int x = 0; x < cam->width(); ++x) {
      const std::size_t i = static_cast<std::size_t>(y * cam->width() + x);
      const auto ray = cam->ray(Eigen::Vector2d(x, y));
      REQUIRE(mask[i] == (ray ? 1.0f : 0.0f));
      if (!ray) {
        CHECK(s0[i] == 0.0f);
        CHECK(dolp[i] == 0.0f);
        continue;
      }
      ++sky_pixels;
      const sky::Stokes s = sky_model.stokes(ray->d, ray->e0, sun);
      CHECK(s0[i] == Approx(s.s0).epsilon(1e-5));
      CHECK(dolp[i] == Approx(s.dolp()).margin(2e-6));
      if (s.dolp() > 1e-3) {
        double diff = double{aolp[i]} - s.aolp();  // AoLP is defined modulo π
        diff -= std::numbers::pi * std::round(diff / std::numbers::pi);
        CHECK(std::abs(diff) < 1e-5);
      }
    }
  }
  // The 185° circle of radius 0.95·h/2 covers π·r² pixels.
  const double r_px = 0.95 * cam->height() / 2.0;
  CHECK(sky_pixels == Approx(std::numbers::pi * r_px * r_px).epsilon(0.02));
}

TEST_CASE("the DoLP at the celestial pole's pixel is the same in every frame of a day", "[renderer][invariant]") {
  // Marseille, 23 Sep 2022: the pole is 43.3° up, at azimuth 0.
  const double lat = 43.28699;
  const auto cam = small_fisheye(0, 201, 201);
  const sky::RayleighSky sky_model;
  const render::Renderer r(cam, render::RenderOptions{});
  const Eigen::Vector3d pole = render::visible_pole(lat);
  const Eigen::Vector2d px = *cam->project(pole);
  const sky::Site site{lat, 5.40336, 60};
  std::vector<double> values;
  for (int hour = 6; hour <= 17; ++hour) {
    const sky::Sun sun = sky::sun_position(site, sky::Instant{1663891200.0 + 3600.0 * hour});
    const render::Frame f = r.render(sky_model, sun);
    // Bilinear interpolation at the pole's exact pixel position.
    const auto& d = f.channel("DoLP.Y");
    const int x0 = static_cast<int>(std::floor(px.x())), y0 = static_cast<int>(std::floor(px.y()));
    const double fx = px.x() - x0, fy = px.y() - y0;
    auto at = [&](int x, int y) { return double{d[static_cast<std::size_t>(y * f.width + x)]}; };
    values.push_back((1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) +
                     fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1)));
    // SkyPole SI eq. 4: cos γ at the pole = sin δ, so DoLP = cos²δ / (1 + sin²δ).
    const double sd = std::sin(sun.declination);
    CHECK(values.back() == Approx((1 - sd * sd) / (1 + sd * sd)).margin(2e-4));
  }
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  CHECK(*hi - *lo < 2e-4);
}

TEST_CASE("output is identical whatever the thread count", "[renderer][determinism]") {
  const auto cam = small_fisheye(10);
  const sky::RayleighSky sky_model;
  const sky::Sun sun = sun_at(200, 20);
  for (int spp : {1, 5}) {
    render::RenderOptions o;
    o.spp = spp;
    o.seed = 7;
    render::Frame one, two;
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
      one = render::Renderer(cam, o).render(sky_model, sun);
    }
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
      two = render::Renderer(cam, o).render(sky_model, sun);
    }
    for (const auto& [name, data] : one.channels) {
      INFO(name << " spp=" << spp);
      CHECK(data == two.channel(name));
    }
  }
}

TEST_CASE("supersampling converges on the pixel average and marks partial coverage", "[renderer][spp]") {
  const auto cam = small_fisheye();
  const sky::RayleighSky sky_model;
  const sky::Sun sun = sun_at(90, 10);
  render::RenderOptions o;
  o.spp = 64;
  const render::Frame f = render::Renderer(cam, o).render(sky_model, sun);
  const auto& mask = f.channel("mask");
  int partial = 0;
  for (float m : mask) {
    CHECK(m >= 0.0f);
    CHECK(m <= 1.0f);
    partial += (m > 0 && m < 1) ? 1 : 0;
  }
  CHECK(partial > 100);  // the rim of the image circle is partly covered
  // At the image centre (the zenith) a 64-sample average equals the centre value to second order.
  const std::size_t c = static_cast<std::size_t>((cam->height() / 2) * cam->width() + cam->width() / 2);
  const auto ray = cam->ray(Eigen::Vector2d(cam->width() / 2, cam->height() / 2));
  CHECK(f.channel("DoLP.Y")[c] == Approx(sky_model.stokes(ray->d, ray->e0, sun).dolp()).margin(1e-3));
}

TEST_CASE("no NaN or Inf for a sun at the zenith and below the horizon", "[renderer][hard]") {
  const auto cam = small_fisheye();
  const sky::RayleighSky sky_model;
  for (double el : {90.0, 0.0, -10.0, -90.0}) {
    const render::Frame f = render::Renderer(cam, render::RenderOptions{}).render(sky_model, sun_at(0, el));
    for (const auto& [name, data] : f.channels) {
      for (float v : data) REQUIRE(std::isfinite(v));
    }
  }
}
