// Renders the synthetic test stacks (see synthetic_stack.h).
#include "sky/units.h"
#include "synthetic_stack.h"

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <random>

#include "camera/camera.h"
#include "camera/orientation.h"
#include "camera/radial_lens.h"
#include "sky/rayleigh.h"
#include "sky/sky_spec.h"
#include "sky/sun.h"

namespace skypol::testing {

std::vector<sky::Instant> times_every(const std::string& start, const std::string& end,
                                      double step_min) {
  std::vector<sky::Instant> t;
  const double a = sky::parse_iso8601(start).unix_seconds;
  const double b = sky::parse_iso8601(end).unix_seconds;
  for (double s = a; s <= b + 1e-6; s += step_min * 60.0) t.push_back(sky::Instant{s});
  return t;
}

std::vector<sky::Instant> paper_times() {
  return times_every("2022-09-23T08:00:00Z", "2022-09-23T16:00:00Z", 30);
}

SyntheticSpec paper_day(int size, double heading_deg, double noise) {
  SyntheticSpec spec;
  spec.times = paper_times();
  spec.size = size;
  spec.heading_deg = heading_deg;
  spec.max_dolp = 0.7;
  spec.noise = noise;
  return spec;
}

stack::Stack make_stack(const SyntheticSpec& spec) {
  camera::Intrinsics k;
  k.width = k.height = spec.size;
  const double theta_max = 0.5 * spec.fov_deg * kRadPerDeg;
  k.fx = k.fy = 0.5 * spec.size / theta_max;
  k.cx = k.cy = 0.5 * (spec.size - 1);
  auto lens = std::make_shared<camera::RadialLens>(camera::Mapping::equidistant, k, theta_max);
  const Eigen::Matrix3d world_from_camera =
      camera::world_from_heading_tilt_roll(spec.heading_deg, spec.tilt_deg, spec.roll_deg);
  auto cam = std::make_shared<camera::Camera>(lens, world_from_camera);

  stack::Stack stack;
  stack.camera = cam;
  stack.bands = {spec.band};
  const sky::Site site{spec.latitude_deg, spec.longitude_deg, 0};
  // Rayleigh exactly as the tests were written against; other grey models through their spec.
  std::unique_ptr<sky::SkyModel> sky_model;
  if (spec.sky_model == "rayleigh") {
    sky_model = std::make_unique<sky::RayleighSky>(sky::RayleighParams{spec.max_dolp});
  } else {
    sky::SkySpec sky_spec;
    sky_spec.model = spec.sky_model;
    sky_spec.max_dolp = spec.max_dolp;
    sky_model = sky::make_sky(sky_spec);
  }
  const sky::SkyModel& model = *sky_model;
  const bool north = spec.latitude_deg >= 0;
  const double phi = spec.latitude_deg * kRadPerDeg;
  const Eigen::Vector3d ncp(0, std::cos(phi), std::sin(phi));
  std::mt19937 rng(spec.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);

  for (const sky::Instant t : spec.times) {
    stack::Frame f;
    f.width = f.height = spec.size;
    f.truth.time = t;
    f.truth.site = site;
    f.truth.sun = sky::sun_position(site, t);
    f.truth.world_from_camera = world_from_camera;
    f.truth.heading_deg = spec.heading_deg;
    f.truth.tilt_deg = spec.tilt_deg;
    f.truth.roll_deg = spec.roll_deg;
    f.truth.pole_enu = north ? ncp : Eigen::Vector3d(-ncp);
    f.truth.pole_is_north = north;
    if (auto px = cam->project(f.truth.pole_enu)) f.truth.pole_pixel = *px;
    const std::size_t n = static_cast<std::size_t>(spec.size) * static_cast<std::size_t>(spec.size);
    std::vector<float> dolp(n, 0.0f), aolp(n, 0.0f), mask(n, 0.0f);
    for (int y = 0; y < spec.size; ++y)
      for (int x = 0; x < spec.size; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(spec.size) +
                              static_cast<std::size_t>(x);
        const auto r = cam->ray(Eigen::Vector2d(x, y));
        if (!r) continue;
        sky::Stokes s = model.stokes(r->d, r->e0, f.truth.sun);
        if (spec.noise > 0) {
          // Four polarizer intensities I(θ) = ½(S0 + S1 cos 2θ + S2 sin 2θ), each with noise.
          const double s0 = s.s0;
          double i0 = 0.5 * (s0 + s.s1), i90 = 0.5 * (s0 - s.s1);
          double i45 = 0.5 * (s0 + s.s2), i135 = 0.5 * (s0 - s.s2);
          i0 += 0.5 * s0 * spec.noise * gauss(rng);
          i90 += 0.5 * s0 * spec.noise * gauss(rng);
          i45 += 0.5 * s0 * spec.noise * gauss(rng);
          i135 += 0.5 * s0 * spec.noise * gauss(rng);
          s = sky::Stokes{0.5 * (i0 + i90 + i45 + i135), i0 - i90, i45 - i135, 0};
        }
        dolp[i] = static_cast<float>(s.dolp());
        aolp[i] = static_cast<float>(cam->sensor_angle(*r, s.aolp()));
        mask[i] = 1.0f;
      }
    f.channels["DoLP." + spec.band] = std::move(dolp);
    if (spec.with_aolp) f.channels["AoLP." + spec.band] = std::move(aolp);
    f.channels["mask"] = std::move(mask);
    stack.frames.push_back(std::move(f));
  }
  return stack;
}

void veil_disc(stack::Stack& stack, const Eigen::Vector3d& centre, double radius_deg, const VeilPaint& paint,
               const std::string& band) {
  const double cos_r = std::cos(radius_deg * kRadPerDeg);
  for (std::size_t f = 0; f < stack.frames.size(); ++f) {
    stack::Frame& frame = stack.frames[f];
    std::vector<float>& dolp = frame.channels.at("DoLP." + band);
    std::vector<float>& aolp = frame.channels.at("AoLP." + band);
    for (int y = 0; y < frame.height; ++y)
      for (int x = 0; x < frame.width; ++x) {
        const auto ray = stack.camera->lens().ray(Eigen::Vector2d(x, y));
        if (!ray || ray->normalized().dot(centre) < cos_r) continue;
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(frame.width) + static_cast<std::size_t>(x);
        paint(f, ray->normalized(), dolp[i], aolp[i]);
      }
  }
}

Eigen::Vector3d true_pole_camera(const stack::Stack& stack) {
  const scene::Truth& t = stack.frames.front().truth;
  return (t.world_from_camera.transpose() * t.pole_enu).normalized();
}

void mask_disc(stack::Stack& stack, const Eigen::Vector3d& centre, double radius_deg, const std::string& band) {
  veil_disc(stack, centre, radius_deg,
            [](std::size_t, const Eigen::Vector3d&, float& dolp, float&) { dolp = std::numeric_limits<float>::quiet_NaN(); },
            band);
}

}  // namespace skypol::testing
