// `skypol lens SCENE`: a scene's camera, both ways — the pixel of a direction and the direction of
// a pixel — so that a user can check a calibration or an orientation without rendering.
#include <cmath>
#include <cstdio>
#include <numbers>

#include "cli/commands.h"
#include "scene/scene.h"

namespace skypol::cli {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

Eigen::Vector3d enu_of(double azimuth_deg, double elevation_deg) {
  const double az = azimuth_deg * kDeg, el = elevation_deg * kDeg;
  return {std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el)};
}

void print_direction(const camera::Camera& cam, double az, double el) {
  const std::optional<Eigen::Vector2d> px = cam.project(enu_of(az, el));
  std::printf("direction az %8.3f el %7.3f deg  ->  ", az, el);
  if (!px) {
    std::printf("outside the lens's field of view\n");
    return;
  }
  const bool on_sensor = px->x() >= -0.5 && px->y() >= -0.5 && px->x() < cam.width() - 0.5 &&
                         px->y() < cam.height() - 0.5;
  std::printf("pixel (%.4f, %.4f)%s\n", px->x(), px->y(), on_sensor ? "" : "  (off the sensor)");
}

void print_pixel(const camera::Camera& cam, double u, double v) {
  std::printf("pixel (%.4f, %.4f)  ->  ", u, v);
  const std::optional<camera::CameraRay> r = cam.ray(Eigen::Vector2d(u, v));
  if (!r) {
    std::printf("outside the image circle (masked)\n");
    return;
  }
  const Eigen::Vector3d d = r->d.cast<double>();
  const double el = std::asin(std::clamp(d.z(), -1.0, 1.0)) / kDeg;
  double az = std::atan2(d.x(), d.y()) / kDeg;
  if (az < 0) az += 360;
  if (std::hypot(d.x(), d.y()) < 1e-12) az = 0;  // the zenith's azimuth is 0 by convention
  const Eigen::Vector3d dc = cam.world_from_camera().transpose() * d;
  const double theta = std::acos(std::clamp(dc.z(), -1.0, 1.0)) / kDeg;
  std::printf("direction az %8.3f el %7.3f deg (%.3f deg off the optical axis)\n", az, el, theta);
}

std::pair<double, double> two_numbers(const std::string& text, const char* what) {
  double a = 0, b = 0;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf%c", &a, &b, &extra) != 2 || !std::isfinite(a) || !std::isfinite(b)) {
    throw std::invalid_argument(std::string(what) + " '" + text + "': expected two numbers separated by a comma");
  }
  return {a, b};
}

}  // namespace

void add_lens(CLI::App& app) {
  struct Args {
    std::string scene;
    std::vector<std::string> pixels, directions;
  };
  auto a = std::make_shared<Args>();
  CLI::App* lens = app.add_subcommand("lens", "A scene's camera both ways: pixel of a direction, direction of a pixel");
  lens->add_option("scene", a->scene, "Scene file (its [camera] section is used)")->required();
  lens->add_option("-p,--pixel", a->pixels, "Pixel 'u,v' (OpenCV centres) -> world azimuth, elevation");
  lens->add_option("-d,--direction", a->directions, "World 'azimuth,elevation' in degrees -> pixel");
  lens->callback([a] {
    const scene::Scene scene = scene::load_scene(a->scene);
    const std::shared_ptr<const camera::Camera> cam = scene::build_camera(scene.camera);
    const camera::Intrinsics& k = cam->lens().intrinsics();
    std::printf("camera   %s, %dx%d px, fx %.4f fy %.4f, centre (%.4f, %.4f), field of view %.3f deg\n",
                cam->lens().name().c_str(), k.width, k.height, k.fx, k.fy, k.cx, k.cy,
                2 * cam->lens().max_field_angle() / kDeg);
    std::printf("heading %.3f tilt %.3f roll %.3f deg\n", scene.camera.heading_deg, scene.camera.tilt_deg,
                scene.camera.roll_deg);
    if (a->pixels.empty() && a->directions.empty()) {
      // Landmarks: the zenith, the four cardinal points on the horizon, the image centre.
      print_direction(*cam, 0, 90);
      for (double az : {0.0, 90.0, 180.0, 270.0}) print_direction(*cam, az, 0);
      print_pixel(*cam, k.cx, k.cy);
    }
    for (const std::string& p : a->pixels) {
      const auto [u, v] = two_numbers(p, "--pixel");
      print_pixel(*cam, u, v);
    }
    for (const std::string& d : a->directions) {
      const auto [az, el] = two_numbers(d, "--direction");
      if (el < -90 || el > 90) throw std::invalid_argument("--direction '" + d + "': elevation outside [-90, 90]");
      print_direction(*cam, az, el);
    }
  });
}

}  // namespace skypol::cli
