// SkyPole (Kronland-Martinet et al., PNAS 2023, and its SI) recomputed on the set-up of
// scenes/skypole-marseille.toml (site, day, camera; the lens on a grid 4× coarser than the
// sensor, 16× with --small). Files written into the output folder:
//   skypole_fig1d.exr / .csv     Fig. 1D: DoLP at four times, the classic algorithm's absolute
//                                differences, binary images, their sum and the maximal blob
//                                (channels dolp.i, diff.k, binary.k, sum, maximum, mask); the
//                                csv holds the times, thresholds, true and found pole
//   skypole_set1.exr / .csv      SI Set 1 (eq. 7) over the simulated |ΔDoLP| of three pairs of
//   skypole_set1_curves.csv      times (channels absdiff.k), Set 2 (eq. 10) too; the curves'
//                                pixels, and |ΔDoLP| sampled along them
//   skypole_protocol.csv         Fig. 3's protocol: headings 0°–170° every 10°, every estimator,
//                                the day noise-free and through the DoFP sensor, and the
//                                observation-window sweep through the sensor (reproduction_protocol.h)
//   skypole_setup.csv            the numbers of the set-up, for the report
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <sstream>

#include "camera/presets.h"
#include "sky/units.h"
#include "studies/reproduce.h"
#include "stack/image_exr.h"
#include "render/recorded_stack.h"
#include "scene/scene.h"
#include "skypole/classic.h"
#include "skypole/evaluate.h"
#include "skypole/invariance_sets.h"
#include "studies/reproduction_protocol.h"

namespace skypol::studies {
namespace {

struct Setup {
  scene::Scene scene;
  render::RecordingSetup rec;  // the scene's site, camera (rescaled), Pmax 1
  double scale = 0.25;
  double t0 = 0;               // the scene's first time, unix seconds
};

Setup load(const ReproduceOptions& o) {
  Setup s;
  s.scene = scene::load_scene(o.scene);
  if (s.scene.times.empty()) throw std::invalid_argument(o.scene + ": no times");
  s.scale = o.small ? 1.0 / 16 : 0.25;
  const auto cam = scene::build_camera(s.scene.camera);
  s.rec.lens = cam->lens().rescaled(s.scale);
  s.rec.site = s.scene.site;
  s.rec.sun_options = s.scene.sun_options;
  s.rec.heading_deg = s.scene.camera.heading_deg;
  s.rec.tilt_deg = s.scene.camera.tilt_deg;
  s.rec.roll_deg = s.scene.camera.roll_deg;
  s.t0 = s.scene.times.front().unix_seconds;
  return s;
}

// The scene's first time plus whole hours and minutes.
sky::Instant at(const Setup& s, double hours) { return sky::Instant{s.t0 + hours * 3600.0}; }

std::vector<float> to_float(const std::vector<std::uint8_t>& v) { return {v.begin(), v.end()}; }

std::optional<double> bilinear(const std::vector<float>& img, const std::vector<float>& mask, int w,
                               int h, double u, double v) {
  const int x0 = static_cast<int>(std::floor(u)), y0 = static_cast<int>(std::floor(v));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= w || y0 + 1 >= h) return std::nullopt;
  const auto at_px = [&](int x, int y) {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
  };
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx)
      if (mask[at_px(x0 + dx, y0 + dy)] <= 0) return std::nullopt;
  const double fx = u - x0, fy = v - y0;
  const auto val = [&](int x, int y) { return static_cast<double>(img[at_px(x, y)]); };
  return (1 - fx) * (1 - fy) * val(x0, y0) + fx * (1 - fy) * val(x0 + 1, y0) +
         (1 - fx) * fy * val(x0, y0 + 1) + fx * fy * val(x0 + 1, y0 + 1);
}

void fig1d(const ReproduceOptions& o, const Setup& s) {
  const std::vector<sky::Instant> times = {at(s, 3), at(s, 4), at(s, 5), at(s, 6)};
  const stack::Stack stack = render::record_stack(s.rec, times);
  skypole::ClassicParams p;
  p.keep_intermediates = true;
  const skypole::ClassicResult r = skypole::estimate_classic(stack, p);
  const int w = stack.frames[0].width, h = stack.frames[0].height;
  std::map<std::string, std::vector<float>> ch;
  for (std::size_t i = 0; i < stack.frames.size(); ++i)
    ch["dolp." + std::to_string(i)] = stack.frames[i].channel("DoLP.Y");
  for (std::size_t k = 0; k < r.images.differences.size(); ++k) {
    ch["diff." + std::to_string(k)] = r.images.differences[k];
    ch["binary." + std::to_string(k)] = to_float(r.images.binaries[k]);
  }
  ch["sum"] = r.images.sum;
  ch["maximum"] = to_float(r.images.maximum);
  ch["mask"] = stack.frames[0].channel("mask");
  stack::write_image_exr(o.out_dir + "/skypole_fig1d.exr", w, h, ch,
                          "SkyPole Fig. 1D: classic algorithm on a noise-free Rayleigh sky");
  std::ostringstream os;
  os << "key,value\n";
  for (std::size_t i = 0; i < times.size(); ++i)
    os << "time." << i << ',' << sky::format_iso8601(times[i]) << '\n';
  for (std::size_t k = 0; k < r.images.thresholds.size(); ++k)
    os << "threshold." << k << ',' << csv_num(r.images.thresholds[k]) << '\n';
  const scene::Truth& t = stack.frames[0].truth;
  if (t.pole_pixel) os << "true_u," << csv_num(t.pole_pixel->x()) << "\ntrue_v," << csv_num(t.pole_pixel->y()) << '\n';
  os << "valid," << (r.estimate.valid ? 1 : 0) << '\n';
  if (r.estimate.valid) {
    if (r.estimate.pixel)
      os << "found_u," << csv_num(r.estimate.pixel->x()) << "\nfound_v," << csv_num(r.estimate.pixel->y()) << '\n';
    const skypole::Score sc = skypole::score(r.estimate, t);
    os << "bearing_error_deg," << (sc.bearing_error_deg ? csv_num(*sc.bearing_error_deg) : "") << '\n'
       << "latitude_error_deg," << csv_num(sc.latitude_error_deg) << '\n'
       << "angular_error_deg," << csv_num(sc.angular_error_deg) << '\n';
  }
  write_text(o.out_dir, "skypole_fig1d.csv", os.str());
}

void set1(const ReproduceOptions& o, const Setup& s) {
  // Three pairs of times, 1 h, 1 h and 2 h apart (the paper: 30 to 60 minutes).
  const std::vector<std::pair<double, double>> pairs_h = {{2, 3}, {4, 5}, {7, 9}};
  std::vector<sky::Instant> times;
  for (const auto& [a, b] : pairs_h) {
    times.push_back(at(s, a));
    times.push_back(at(s, b));
  }
  const stack::Stack stack = render::record_stack(s.rec, times);
  const int w = stack.frames[0].width, h = stack.frames[0].height;
  const std::vector<float>& mask = stack.frames[0].channel("mask");
  const camera::Camera& cam = *stack.camera;
  const double lat = s.rec.site.latitude_deg * kRadPerDeg;
  std::map<std::string, std::vector<float>> ch;
  std::ostringstream curves, stats;
  curves << "pair,set,azimuth_deg,altitude_deg,u,v\n";
  stats << "pair,time1,time2,hour_angle1_deg,hour_angle2_deg,curve_points,max_absdiff_on_curve,"
           "median_absdiff_image,max_rayleigh_absdiff_on_curve,pole_altitude_on_curve_deg\n";
  for (std::size_t k = 0; k < pairs_h.size(); ++k) {
    const stack::Frame& f1 = stack.frames[2 * k];
    const stack::Frame& f2 = stack.frames[2 * k + 1];
    const auto& d1 = f1.channel("DoLP.Y");
    const auto& d2 = f2.channel("DoLP.Y");
    std::vector<float> diff(d1.size(), 0.0f);
    std::vector<float> valid_diffs;
    for (std::size_t i = 0; i < diff.size(); ++i)
      if (mask[i] > 0) {
        diff[i] = std::abs(d1[i] - d2[i]);
        valid_diffs.push_back(diff[i]);
      }
    ch["absdiff." + std::to_string(k)] = diff;
    std::nth_element(valid_diffs.begin(), valid_diffs.begin() + static_cast<long>(valid_diffs.size() / 2),
                     valid_diffs.end());
    const double median = valid_diffs.empty() ? 0.0 : static_cast<double>(valid_diffs[valid_diffs.size() / 2]);
    const sky::Sun& s1 = f1.truth.sun;
    const sky::Sun& s2 = f2.truth.sun;
    const double dec = 0.5 * (s1.declination + s2.declination);
    double max_img = 0, max_rayleigh = 0;
    int points = 0;
    for (int set = 1; set <= 2; ++set)
      for (double az = 0; az < 360; az += 0.25) {
        const double alt = set == 1
                               ? skypole::radial_invariance_altitude(az * kRadPerDeg, lat, s1.hour_angle, s2.hour_angle)
                               : skypole::plane_invariance_altitude(az * kRadPerDeg, lat, dec, s1.hour_angle, s2.hour_angle);
        if (alt < 0) continue;
        const Eigen::Vector3d P = sky::enu_direction(az * kRadPerDeg, alt);
        const auto px = cam.project(P);
        if (!px || px->x() < 0 || px->y() < 0 || px->x() > w - 1 || px->y() > h - 1) continue;
        curves << k << ',' << set << ',' << csv_num(az) << ',' << csv_num(alt / kRadPerDeg) << ','
               << csv_num(px->x()) << ',' << csv_num(px->y()) << '\n';
        if (set != 1) continue;
        // Rayleigh DoLP depends on (s·P)² only: the analytic difference at the curve's points,
        // with ERFA's suns (whose declination drifts slightly between the two times).
        const auto dolp = [&](const sky::Sun& sun) {
          const double c = sun.direction.dot(P);
          return (1 - c * c) / (1 + c * c);
        };
        max_rayleigh = std::max(max_rayleigh, std::abs(dolp(s1) - dolp(s2)));
        if (const auto v = bilinear(diff, mask, w, h, px->x(), px->y())) {
          // |ΔDoLP| sampled from the rendered images (bilinear: it cannot follow the V-shaped zero
          // exactly, so this is an upper bound of the image's own value on the curve).
          max_img = std::max(max_img, *v);
          ++points;
        }
      }
    const double pole_alt = skypole::radial_invariance_altitude(0.0, lat, s1.hour_angle, s2.hour_angle);
    stats << k << ',' << sky::format_iso8601(f1.truth.time) << ',' << sky::format_iso8601(f2.truth.time)
          << ',' << csv_num(s1.hour_angle / kRadPerDeg) << ',' << csv_num(s2.hour_angle / kRadPerDeg) << ',' << points
          << ',' << csv_num(max_img) << ',' << csv_num(median) << ',' << csv_num(max_rayleigh) << ','
          << csv_num(pole_alt / kRadPerDeg) << '\n';
  }
  ch["mask"] = mask;
  stack::write_image_exr(o.out_dir + "/skypole_set1.exr", w, h, ch,
                          "SkyPole SI Set 1: |DoLP(t1) - DoLP(t2)| of a noise-free Rayleigh sky");
  write_text(o.out_dir, "skypole_set1_curves.csv", curves.str());
  write_text(o.out_dir, "skypole_set1.csv", stats.str());
}

camera::DofpSensor realistic_sensor() {
  camera::DofpSensor d = camera::sensor_preset("sony_imx250mzr").dofp;
  // Exposure: the brightest sky pixel (behind its polarizer, ≈ 1 radiance unit on this sky) at
  // 80 % of the full well, as an auto-exposed camera would set it.
  d.exposure_us = 1000;
  d.electrons_per_radiance_s = 0.8 * d.full_well_e / (d.exposure_us * 1e-6);
  return d;
}

void protocol(const ReproduceOptions& o, const Setup& s) {
  studies::ProtocolSpec spec;
  spec.setup = s.rec;
  spec.setup.sky.max_dolp = 0.7;
  spec.methods = skypole::method_names();
  // Windows from 3 h after the scene's first time (09:00 UTC on the paper's day), a frame every
  // 10 minutes, up to 4 hours.
  for (int m = 0; m <= 240; m += 10) spec.window_times.push_back(at(s, 3 + m / 60.0));
  if (o.small) {
    // The same rows on two headings, hourly day frames and two windows: seconds, not minutes.
    spec.headings_deg = {0, 90};
    for (std::size_t i = 0; i < s.scene.times.size(); i += 2) spec.day_times.push_back(s.scene.times[i]);
    spec.window_frames = {4, 10};
  } else {
    for (int hd = 0; hd <= 170; hd += 10) spec.headings_deg.push_back(hd);
    spec.day_times = s.scene.times;
    spec.window_frames = {4, 7, 10, 13, 19, 25};
  }
  spec.sensor = realistic_sensor();
  spec.seed = 20220923;
  const auto t = std::chrono::steady_clock::now();
  const auto rows = studies::run_protocol(spec, o.progress);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  write_text(o.out_dir, "skypole_protocol.csv", studies::protocol_csv(rows));

  const camera::Intrinsics& k = s.rec.lens->intrinsics();
  const camera::DofpSensor& d = spec.sensor;
  std::ostringstream os;
  os << "key,value\n"
     << "scene," << o.scene << '\n'
     << "latitude_deg," << csv_num(s.rec.site.latitude_deg) << '\n'
     << "longitude_deg," << csv_num(s.rec.site.longitude_deg) << '\n'
     << "width," << k.width << "\nheight," << k.height << '\n'
     << "scale," << csv_num(s.scale) << '\n'
     << "focal_px," << csv_num(k.fx) << '\n'
     << "deg_per_px," << csv_num(1.0 / k.fx / kRadPerDeg) << '\n'
     << "fov_deg," << csv_num(2 * s.rec.lens->max_field_angle() / kRadPerDeg) << '\n'
     << "max_dolp," << csv_num(spec.setup.sky.max_dolp) << '\n'
     << "day_first," << sky::format_iso8601(spec.day_times.front()) << '\n'
     << "day_last," << sky::format_iso8601(spec.day_times.back()) << '\n'
     << "day_frames," << spec.day_times.size() << '\n'
     << "window_first," << sky::format_iso8601(spec.window_times.front()) << '\n'
     << "window_step_min,10\n"
     << "headings," << spec.headings_deg.size() << '\n'
     << "sensor,sony_imx250mzr\n"
     << "full_well_e," << csv_num(d.full_well_e) << '\n'
     << "read_noise_e," << csv_num(d.read_noise_e) << '\n'
     << "adc_bits," << d.adc_bits << '\n'
     << "extinction_ratio," << csv_num(d.extinction_ratio) << '\n'
     << "electrons_per_radiance_unit," << csv_num(d.electrons_per_radiance_s * d.exposure_us * 1e-6) << '\n'
     << "protocol_seconds," << csv_num(seconds) << '\n';
  write_text(o.out_dir, "skypole_setup.csv", os.str());
}

}  // namespace

void reproduce_skypole(const ReproduceOptions& o) {
  const Setup s = load(o);
  fig1d(o, s);
  set1(o, s);
  if (!o.quiet) std::fprintf(stderr, "skypole: Fig. 1D and Set 1 written; protocol (%s)...\n",
                             o.small ? "small" : "full");
  protocol(o, s);
}

}  // namespace skypol::studies
