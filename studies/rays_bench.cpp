// Camera rays per second per lens model (rays_bench.h).
#include "studies/rays_bench.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <time.h>
#include <stdexcept>

#include <Eigen/Geometry>

#include "camera/calibration_import.h"
#include "camera/camera.h"
#include "camera/lens_factory.h"

namespace skypol::studies {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(path + ": cannot open calibration file");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// One full sensor through `row` (a ray_row), on this thread; CPU seconds of this thread, best of
// `repeats` (CPU time: on a machine that others load, wall time would count their share too).
template <class Row>
double best_frame_s(const camera::Lens& lens, int repeats, Row row) {
  const camera::Intrinsics& k = lens.intrinsics();
  // Blocks of 256 pixels, as Camera::ray_row hands them to the lens.
  constexpr std::size_t kBlock = 256;
  std::vector<double> dx(kBlock), dy(kBlock), dz(kBlock);
  std::vector<unsigned char> ok(kBlock);
  double best = 1e300;
  volatile double sink = 0;
  for (int r = 0; r < repeats; ++r) {
    timespec t0, t1;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
    for (int y = 0; y < k.height; ++y)
      for (int x = 0; x < k.width; x += static_cast<int>(kBlock)) {
        const std::size_t n = std::min<std::size_t>(kBlock, static_cast<std::size_t>(k.width - x));
        row(static_cast<double>(y), static_cast<double>(x), n, dx.data(), dy.data(), dz.data(), ok.data());
        sink = sink + dz[0];
      }
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
    best = std::min(best, static_cast<double>(t1.tv_sec - t0.tv_sec) + 1e-9 * static_cast<double>(t1.tv_nsec - t0.tv_nsec));
  }
  return best;
}

}  // namespace

std::vector<RaysBenchLens> rays_bench_lenses(const std::string& scenes_dir) {
  const std::string dir = scenes_dir + "/calibrations/";
  struct File {
    const char* format;
    const char* file;
    const char* camera;
  };
  const File files[] = {
      {"opencv", "fisheye.yaml", ""},          {"basalt", "basalt_calibration.json", ""},
      {"kalibr", "camchain.yaml", "cam0"},     {"kalibr", "camchain.yaml", "cam1"},
      {"ocamcalib", "calib_results.txt", ""},  {"colmap", "cameras.txt", "2"},
      {"opencv", "omnidir.yaml", ""},
  };
  std::vector<RaysBenchLens> out;
  camera::LensSpec eq;
  eq.model = "equidistant", eq.width = 2448, eq.height = 2048, eq.fx = 521.7, eq.fov_deg = 185;
  out.push_back({"SkyPole paper (f = 521.7 px, 185 deg)", camera::make_lens(eq)});
  for (const File& f : files) {
    camera::Calibration c{f.format, read_text(dir + f.file), "calibrations/" + std::string(f.file), f.camera};
    camera::LensSpec spec = camera::lens_spec_from_calibration(c);
    camera::fit_fov_to_sensor(spec);
    std::shared_ptr<const camera::Lens> lens = camera::make_lens(spec);
    std::string source = c.name + (c.camera.empty() ? "" : " " + c.camera);
    // The OCamCalib example is for a 2x2-binned sensor: back to the full 2448 x 2048.
    if (lens->intrinsics().width * 2 == 2448) {
      lens = lens->rescaled(2.0);
      source += ", x2";
    }
    out.push_back({source, lens});
  }
  return out;
}

RaysBenchRow bench_rays(const RaysBenchLens& l, int repeats) {
  const camera::Lens& lens = *l.lens;
  const camera::Intrinsics& k = lens.intrinsics();
  RaysBenchRow row;
  row.model = lens.name(), row.source = l.source, row.width = k.width, row.height = k.height;
  const double pixels = static_cast<double>(k.width) * k.height;
  const double base_s = best_frame_s(lens, repeats, [&](auto... a) { lens.camera::Lens::ray_row(a...); });
  const double row_s = best_frame_s(lens, repeats, [&](auto... a) { lens.ray_row(a...); });
  row.base_mrays_per_s = pixels / base_s / 1e6;
  row.row_mrays_per_s = pixels / row_s / 1e6;
  // What the renderer calls: Camera::ray_row, the lens's rows plus the rotation to the world and
  // the polarizer direction, as float planes (a tilted camera, so the rotation is not trivial).
  const camera::Camera cam(l.lens, (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX())).toRotationMatrix());
  {
    const std::size_t w = static_cast<std::size_t>(k.width);
    std::vector<float> planes(7 * w);
    float* p = planes.data();
    const camera::RayRowOut out{p, p + w, p + 2 * w, p + 3 * w, p + 4 * w, p + 5 * w, p + 6 * w};
    double best = 1e300;
    volatile float sink = 0;
    for (int r = 0; r < repeats; ++r) {
      timespec t0, t1;
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
      for (int y = 0; y < k.height; ++y) {
        cam.ray_row(y, 0, w, out);
        sink = sink + p[2 * w];
      }
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
      best = std::min(best, static_cast<double>(t1.tv_sec - t0.tv_sec) + 1e-9 * static_cast<double>(t1.tv_nsec - t0.tv_nsec));
    }
    row.camera_mrays_per_s = pixels / best / 1e6;
  }
  // Accuracy on every pixel of the sensor.
  const std::size_t w = static_cast<std::size_t>(k.width);
  std::vector<double> dx(w), dy(w), dz(w);
  std::vector<unsigned char> ok(w);
  for (int y = 0; y < k.height; ++y) {
    lens.ray_row(y, 0, w, dx.data(), dy.data(), dz.data(), ok.data());
    for (std::size_t x = 0; x < w; ++x) {
      const Eigen::Vector2d p(static_cast<double>(x), y);
      const auto ref = lens.ray(p);
      if (static_cast<bool>(ref) != (ok[x] != 0)) ++row.valid_mismatches;
      if (!ok[x]) continue;
      ++row.inside;
      const Eigen::Vector3d d(dx[x], dy[x], dz[x]);
      if (ref) row.max_vs_ray_rad = std::max(row.max_vs_ray_rad, std::atan2(d.cross(*ref).norm(), d.dot(*ref)));
      const auto back = lens.project(d);
      if (!back) {
        ++row.project_failures;
        continue;
      }
      row.max_round_trip_px = std::max(row.max_round_trip_px, (*back - p).norm());
    }
  }
  return row;
}

}  // namespace skypol::studies
