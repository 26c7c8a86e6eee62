// `skypol lens SCENE`: a scene's camera, both ways — the pixel of a direction and the direction of
// a pixel — so that a user can check a calibration or an orientation without rendering.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "scene/scene.h"
#include "sky/units.h"

namespace skypol::cli {
namespace {

Eigen::Vector3d enu_of(double azimuth_deg, double elevation_deg) {
  const double az = azimuth_deg * kRadPerDeg, el = elevation_deg * kRadPerDeg;
  return {std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el)};
}

// One answer of the lens, kept for the text or the JSON form.
struct Row {
  bool from_pixel = false;        // pixel -> direction, else direction -> pixel
  double u = 0, v = 0;            // the pixel (given or found)
  double az = 0, el = 0;          // the direction (given or found), degrees
  double off_axis = 0;            // pixel -> direction: degrees from the optical axis
  bool found = false;             // a direction inside the field of view / a pixel inside the image circle
  bool on_sensor = true;          // direction -> pixel: the pixel lies on the sensor
};

Row direction_row(const camera::Camera& cam, double az, double el) {
  Row r;
  r.az = az;
  r.el = el;
  const std::optional<Eigen::Vector2d> px = cam.project(enu_of(az, el));
  if (!px) return r;
  r.found = true;
  r.u = px->x();
  r.v = px->y();
  r.on_sensor = px->x() >= -0.5 && px->y() >= -0.5 && px->x() < cam.width() - 0.5 && px->y() < cam.height() - 0.5;
  return r;
}

Row pixel_row(const camera::Camera& cam, double u, double v) {
  Row r;
  r.from_pixel = true;
  r.u = u;
  r.v = v;
  const std::optional<camera::CameraRay> ray = cam.ray(Eigen::Vector2d(u, v));
  if (!ray) return r;
  r.found = true;
  const Eigen::Vector3d d = ray->d.cast<double>();
  r.el = std::asin(std::clamp(d.z(), -1.0, 1.0)) / kRadPerDeg;
  r.az = std::atan2(d.x(), d.y()) / kRadPerDeg;
  if (r.az < 0) r.az += 360;
  if (std::hypot(d.x(), d.y()) < 1e-12) r.az = 0;  // the zenith's azimuth is 0 by convention
  const Eigen::Vector3d dc = cam.world_from_camera().transpose() * d;
  r.off_axis = std::acos(std::clamp(dc.z(), -1.0, 1.0)) / kRadPerDeg;
  return r;
}

void print_row(const Row& r) {
  if (r.from_pixel) {
    std::printf("pixel (%.4f, %.4f)  ->  ", r.u, r.v);
    if (!r.found) {
      std::printf("outside the image circle (masked)\n");
      return;
    }
    std::printf("direction az %8.3f el %7.3f deg (%.3f deg off the optical axis)\n", r.az, r.el, r.off_axis);
    return;
  }
  std::printf("direction az %8.3f el %7.3f deg  ->  ", r.az, r.el);
  if (!r.found) {
    std::printf("outside the lens's field of view\n");
    return;
  }
  std::printf("pixel (%.4f, %.4f)%s\n", r.u, r.v, r.on_sensor ? "" : "  (off the sensor)");
}

// %.17g: a double printed so that it reads back as the same double (calibrations checked to 1e-6 px).
std::string g17(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string row_json(const Row& r) {
  std::string s = std::string("{\"from\": \"") + (r.from_pixel ? "pixel" : "direction") + "\", ";
  const std::string px = "\"pixel\": [" + g17(r.u) + ", " + g17(r.v) + "]";
  const std::string dir = "\"azimuth_deg\": " + g17(r.az) + ", \"elevation_deg\": " + g17(r.el);
  if (r.from_pixel) {
    s += px + ", \"inside\": " + (r.found ? "true" : "false");
    if (r.found) s += ", " + dir + ", \"off_axis_deg\": " + g17(r.off_axis);
  } else {
    s += dir + ", \"inside\": " + (r.found ? "true" : "false");
    if (r.found) s += ", " + px + ", \"on_sensor\": " + (r.on_sensor ? "true" : "false");
  }
  return s + "}";
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
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* lens = app.add_subcommand("lens", "A scene's camera both ways: pixel of a direction, direction of a pixel");
  lens->add_option("scene", a->scene, "Scene file (its [camera] section is used)")->required();
  lens->add_option("-p,--pixel", a->pixels, "Pixel 'u,v' (OpenCV centres) -> world azimuth, elevation");
  lens->add_option("-d,--direction", a->directions, "World 'azimuth,elevation' in degrees -> pixel");
  lens->add_flag("--json", a->json, "Print the camera and every answer as JSON, numbers at full precision (%.17g)");
  lens->callback([a] {
    const scene::Scene scene = scene::load_scene(a->scene);
    const std::shared_ptr<const camera::Camera> cam = scene::build_camera(scene.camera);
    const camera::Intrinsics& k = cam->lens().intrinsics();
    std::vector<Row> rows;
    if (a->pixels.empty() && a->directions.empty()) {
      // Landmarks: the zenith, the four cardinal points on the horizon, the image centre.
      rows.push_back(direction_row(*cam, 0, 90));
      for (double az : {0.0, 90.0, 180.0, 270.0}) rows.push_back(direction_row(*cam, az, 0));
      rows.push_back(pixel_row(*cam, k.cx, k.cy));
    }
    for (const std::string& p : a->pixels) {
      const auto [u, v] = two_numbers(p, "--pixel");
      rows.push_back(pixel_row(*cam, u, v));
    }
    for (const std::string& d : a->directions) {
      const auto [az, el] = two_numbers(d, "--direction");
      if (el < -90 || el > 90) throw std::invalid_argument("--direction '" + d + "': elevation outside [-90, 90]");
      rows.push_back(direction_row(*cam, az, el));
    }
    if (a->json) {
      std::printf("{\"model\": \"%s\", \"width\": %d, \"height\": %d, \"fx\": %s, \"fy\": %s, \"cx\": %s, "
                  "\"cy\": %s, \"fov_deg\": %s,\n \"heading_deg\": %s, \"tilt_deg\": %s, \"roll_deg\": %s,\n "
                  "\"answers\": [",
                  cam->lens().name().c_str(), k.width, k.height, g17(k.fx).c_str(), g17(k.fy).c_str(),
                  g17(k.cx).c_str(), g17(k.cy).c_str(), g17(2 * cam->lens().max_field_angle() / kRadPerDeg).c_str(),
                  g17(scene.camera.heading_deg).c_str(), g17(scene.camera.tilt_deg).c_str(),
                  g17(scene.camera.roll_deg).c_str());
      for (std::size_t i = 0; i < rows.size(); ++i) std::printf("%s\n  %s", i ? "," : "", row_json(rows[i]).c_str());
      std::printf("]}\n");
      return;
    }
    std::printf("camera   %s, %dx%d px, fx %.4f fy %.4f, centre (%.4f, %.4f), field of view %.3f deg\n",
                cam->lens().name().c_str(), k.width, k.height, k.fx, k.fy, k.cx, k.cy,
                2 * cam->lens().max_field_angle() / kRadPerDeg);
    std::printf("heading %.3f tilt %.3f roll %.3f deg\n", scene.camera.heading_deg, scene.camera.tilt_deg,
                scene.camera.roll_deg);
    for (const Row& r : rows) print_row(r);
  });
}

}  // namespace skypol::cli
