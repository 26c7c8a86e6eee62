// The renderer against independent evaluations: each pixel equals the sky model at that pixel's
// ray, the mask is the image circle, output is identical whatever the thread count, and a pole
// pixel's DoLP does not change over a day (SkyPole SI eq. 4). Rendering into a reused frame gives
// the same bytes as into a new one, and a scene pays only for the channels it asks for.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

#include <tbb/global_control.h>

#include "camera/orientation.h"
#include "camera/radial_lens.h"
#include "render/renderer.h"
#include "scene/truth.h"
#include "sky/rayleigh.h"
#include "sky/units.h"
#include "sky/sky_test_util.h"

using namespace skypol;
using skypol::testing::sun_at;

namespace {

std::shared_ptr<const camera::Camera> small_fisheye(double heading_deg = 0, int w = 96, int h = 80,
                                                    camera::Transport transport = camera::Transport::meridional) {
  camera::Intrinsics k;
  k.width = w;
  k.height = h;
  k.fx = k.fy = 0.95 * (h / 2.0) / rad_from_deg(92.5);  // 185° circle just inside the height
  k.cx = (w - 1) / 2.0;
  k.cy = (h - 1) / 2.0;
  auto lens = std::make_shared<camera::RadialLens>(camera::Mapping::equidistant, k, rad_from_deg(92.5));
  return std::make_shared<camera::Camera>(lens, camera::world_from_heading_tilt_roll(heading_deg, 0, 0), transport);
}

}  // namespace

TEST_CASE("each rendered pixel is the sky model at that pixel's ray", "[renderer]") {
  const auto cam = small_fisheye(37);
  const sky::RayleighSky sky_model(sky::RayleighParams{0.8});
  const sky::Sun sun = sun_at(120, 35);
  const render::Renderer r(cam, render::RenderOptions{});
  const stack::Frame f = r.render(sky_model, sun);
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
  const Eigen::Vector3d pole = scene::visible_pole(lat);
  const Eigen::Vector2d px = *cam->project(pole);
  const sky::Site site{lat, 5.40336, 60};
  std::vector<double> values;
  for (int hour = 6; hour <= 17; ++hour) {
    const sky::Sun sun = sky::sun_position(site, sky::Instant{1663891200.0 + 3600.0 * hour});
    const stack::Frame f = r.render(sky_model, sun);
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
    stack::Frame one, two;
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
  const stack::Frame f = render::Renderer(cam, o).render(sky_model, sun);
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
    const stack::Frame f = render::Renderer(cam, render::RenderOptions{}).render(sky_model, sun_at(0, el));
    for (const auto& [name, data] : f.channels) {
      for (float v : data) REQUIRE(std::isfinite(v));
    }
  }
}

namespace {

// Bytes, not values: -0 and +0 differ, NaN equals itself.
bool same_bytes(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// Blocks every direction less than 0.15 from the north–south plane (|d.x| < 0.15): a band across
// the middle of the image, so blocked pixels lie between seen ones on the same rows.
class MeridianBand final : public render::Occluders {
 public:
  void occluded(std::span<const Eigen::Vector3f> dirs, std::span<std::uint8_t> out) const override {
    for (std::size_t i = 0; i < dirs.size(); ++i) out[i] = std::abs(dirs[i].x()) < 0.15f ? 1 : 0;
  }
};

}  // namespace

TEST_CASE("rendering into a used frame gives the bytes of a new frame and keeps its memory", "[renderer][reuse]") {
  const auto cam = small_fisheye(25);
  const sky::RayleighSky sky_model(sky::RayleighParams{0.9});
  const sky::Sun sun_a = sun_at(70, 30), sun_b = sun_at(250, 5);
  for (int spp : {1, 4}) {
    INFO("spp=" << spp);
    render::RenderOptions o;
    o.spp = spp;
    o.channels = {"S0", "S1", "S2", "S3", "DoLP", "AoLP", "mask"};
    const render::Renderer r(cam, o);
    const stack::Frame fresh = r.render(sky_model, sun_a);

    stack::Frame used = r.new_frame();
    // Garbage everywhere, a channel the options do not name, then another sun first.
    for (auto& [name, data] : used.channels) std::fill(data.begin(), data.end(), std::numeric_limits<float>::quiet_NaN());
    used.channels["junk"] = std::vector<float>(5, 1.0f);
    r.render(sky_model, sun_b, used);
    std::map<std::string, const float*> storage;
    for (const auto& [name, data] : used.channels) storage[name] = data.data();
    r.render(sky_model, sun_a, used);

    CHECK_FALSE(used.has("junk"));
    REQUIRE(used.channels.size() == fresh.channels.size());
    for (const auto& [name, data] : fresh.channels) {
      INFO(name);
      CHECK(same_bytes(data, used.channel(name)));
      CHECK(used.channel(name).data() == storage.at(name));  // no allocation on the second frame
    }
  }
}

TEST_CASE("with reuse_cleared, a frame the renderer left keeps its zeros outside the circle; another writer's frame is cleared",
          "[renderer][reuse]") {
  const auto cam = small_fisheye(25);
  const sky::RayleighSky sky_model(sky::RayleighParams{0.9});
  const sky::Sun sun_a = sun_at(70, 30), sun_b = sun_at(250, 5);
  render::RenderOptions o;
  o.channels = {"S0", "S1", "S2", "DoLP", "AoLP", "mask"};
  o.reuse_cleared = true;
  const render::Renderer r(cam, o);
  const stack::Frame fresh = r.render(sky_model, sun_a);
  const auto nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<float>& mask = fresh.channel("mask");
  auto scribble_outside = [&](stack::Frame& f) {
    for (auto& [name, data] : f.channels)
      for (std::size_t i = 0; i < data.size(); ++i)
        if (mask[i] == 0) data[i] = nan;
  };
  auto same_as_fresh = [&](const stack::Frame& f) {
    for (const auto& [name, data] : fresh.channels) {
      INFO(name);
      CHECK(same_bytes(data, f.channel(name)));
    }
  };

  stack::Frame used = r.new_frame();
  for (auto& [name, data] : used.channels) std::fill(data.begin(), data.end(), nan);
  r.render(sky_model, sun_b, used);
  CHECK(used.zero_outside != 0);
  r.render(sky_model, sun_a, used);  // the outside is not cleared again, and is still zeros
  same_as_fresh(used);

  // A writer that resets the token: cleared again.
  scribble_outside(used);
  used.zero_outside = 0;
  r.render(sky_model, sun_a, used);
  same_as_fresh(used);

  // Another renderer's token, or one whose caller does not allow the reuse: cleared.
  scribble_outside(used);
  const render::Renderer other(cam, o);
  other.render(sky_model, sun_a, used);
  same_as_fresh(used);
  scribble_outside(used);
  render::RenderOptions careful = o;
  careful.reuse_cleared = false;
  const render::Renderer plain(cam, careful);
  plain.render(sky_model, sun_b, used);
  plain.render(sky_model, sun_a, used);
  same_as_fresh(used);

  // The token is trusted: pixels changed behind it stay changed (what reuse_cleared asks of a caller).
  r.render(sky_model, sun_a, used);
  scribble_outside(used);
  r.render(sky_model, sun_a, used);
  CHECK(std::isnan(used.channel("DoLP.Y")[0]));
}

TEST_CASE("render_rows gives the rows of the whole frame, into bands reused for other rows", "[renderer][bands]") {
  const auto cam = small_fisheye(25);
  const sky::RayleighSky sky_model(sky::RayleighParams{0.9});
  const sky::Sun suns[] = {sun_at(70, 30), sun_at(250, 5)};
  const sky::SkyModel* one[] = {&sky_model};
  for (bool keep_rays : {true, false}) {    // the planes' spans, or rays traced per tile
    for (bool reuse : {true, false}) {      // bands cleared only where the old rows' spans were wider, or fully
      for (int band_rows : {24, 80, 7}) {   // not a multiple of the 16-row tiles; the whole frame; odd
        INFO("keep_rays " << keep_rays << ", reuse_cleared " << reuse << ", band_rows " << band_rows);
        render::RenderOptions o;
        o.channels = {"S0", "S1", "S2", "DoLP", "AoLP", "mask"};
        o.keep_rays = keep_rays;
        o.reuse_cleared = reuse;
        const render::Renderer r(cam, o);
        std::array<stack::Frame, 2> bands;
        int k = 0;
        for (const sky::Sun& sun : suns) {
          const stack::Frame whole = r.render(sky_model, sun);
          for (int y0 = 0; y0 < cam->height(); y0 += band_rows, ++k) {
            const int y1 = std::min(cam->height(), y0 + band_rows);
            stack::Frame& band = bands[static_cast<std::size_t>(k % 2)];
            r.render_rows(one, sun, y0, y1, band);
            REQUIRE(band.width == cam->width());
            REQUIRE(band.height == y1 - y0);
            REQUIRE(band.channels.size() == whole.channels.size());
            for (const auto& [name, data] : whole.channels) {
              INFO(name << " rows " << y0 << "-" << y1);
              const auto from = static_cast<std::ptrdiff_t>(y0) * cam->width(), to = static_cast<std::ptrdiff_t>(y1) * cam->width();
              CHECK(same_bytes(std::vector<float>(data.begin() + from, data.begin() + to), band.channel(name)));
            }
          }
        }
      }
    }
  }
  render::RenderOptions sampled;
  sampled.spp = 4;
  stack::Frame band;
  CHECK_THROWS_AS(render::Renderer(cam, sampled).render_rows(one, suns[0], 0, 8, band), std::logic_error);
  CHECK_THROWS_AS(render::Renderer(cam, {}).render_rows(one, suns[0], 8, 8, band), std::invalid_argument);
  CHECK_THROWS_AS(render::Renderer(cam, {}).render_rows(one, suns[0], 0, cam->height() + 1, band), std::invalid_argument);
}

TEST_CASE("a frame holds only the channels asked for, with the same values", "[renderer][pay-for-what-you-ask]") {
  const auto cam = small_fisheye(5);
  const sky::RayleighSky sky_model;
  const sky::Sun sun = sun_at(160, 40);
  const stack::Frame all = render::Renderer(cam, render::RenderOptions{}).render(sky_model, sun);
  render::RenderOptions only;
  only.channels = {"AoLP"};
  const stack::Frame f = render::Renderer(cam, only).render(sky_model, sun);
  REQUIRE(f.channels.size() == 1);
  CHECK(same_bytes(f.channel("AoLP.Y"), all.channel("AoLP.Y")));
}

TEST_CASE("every band carries the first band's values; RGB adds R, G, B", "[renderer][bands]") {
  const auto cam = small_fisheye(5);
  const sky::RayleighSky sky_model;
  render::RenderOptions o;
  o.bands = {"R", "G", "B"};
  const stack::Frame f = render::Renderer(cam, o).render(sky_model, sun_at(10, 50));
  for (const char* c : {"S0", "S1", "S2", "DoLP", "AoLP"}) {
    for (const char* b : {"G", "B"}) CHECK(same_bytes(f.channel(std::string(c) + "." + b), f.channel(std::string(c) + ".R")));
  }
  for (const char* c : {"R", "G", "B"}) CHECK(same_bytes(f.channel(c), f.channel("S0.R")));
}

TEST_CASE("occluded pixels inside the image circle are black, unpolarized and +0", "[renderer][occluders]") {
  const auto cam = small_fisheye(0);
  const sky::RayleighSky sky_model;
  const sky::Sun sun = sun_at(200, 25);
  const render::Renderer r(cam, render::RenderOptions{}, std::make_shared<MeridianBand>());
  const stack::Frame f = r.render(sky_model, sun);
  int blocked = 0, open = 0;
  for (int y = 0; y < cam->height(); ++y) {
    for (int x = 0; x < cam->width(); ++x) {
      const std::size_t i = static_cast<std::size_t>(y * cam->width() + x);
      const auto ray = cam->ray(Eigen::Vector2d(x, y));
      if (!ray) continue;
      const bool hidden = std::abs(ray->d.cast<float>().x()) < 0.15f;
      REQUIRE(f.channel("mask")[i] == (hidden ? 0.0f : 1.0f));
      if (hidden) {
        ++blocked;
        for (const char* c : {"S0.Y", "S1.Y", "S2.Y", "DoLP.Y", "AoLP.Y"}) {
          INFO(c);
          CHECK(f.channel(c)[i] == 0.0f);
          CHECK_FALSE(std::signbit(f.channel(c)[i]));
        }
      } else {
        ++open;
        CHECK(f.channel("S0.Y")[i] == Approx(sky_model.stokes(ray->d, ray->e0, sun).s0).epsilon(1e-5));
      }
    }
  }
  CHECK(blocked > 300);
  CHECK(open > 2000);
}

TEST_CASE("projected transport: DoLP as the model, AoLP mapped by the camera", "[renderer][transport]") {
  const auto cam = small_fisheye(30, 96, 80, camera::Transport::projected);
  const sky::RayleighSky sky_model;
  const sky::Sun sun = sun_at(300, 15);
  const stack::Frame f = render::Renderer(cam, render::RenderOptions{}).render(sky_model, sun);
  int checked = 0;
  for (int y = 0; y < cam->height(); y += 3) {
    for (int x = 0; x < cam->width(); x += 3) {
      const std::size_t i = static_cast<std::size_t>(y * cam->width() + x);
      const auto ray = cam->ray(Eigen::Vector2d(x, y));
      if (!ray) continue;
      const sky::Stokes s = sky_model.stokes(ray->d, ray->e0, sun);
      CHECK(f.channel("DoLP.Y")[i] == Approx(s.dolp()).margin(2e-6));
      if (s.dolp() < 1e-3) continue;
      double diff = double{f.channel("AoLP.Y")[i]} - cam->sensor_angle(*ray, s.aolp());
      diff -= std::numbers::pi * std::round(diff / std::numbers::pi);
      CHECK(std::abs(diff) < 1e-5);
      ++checked;
    }
  }
  CHECK(checked > 300);
}
