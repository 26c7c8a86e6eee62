// Sun et al. 2019 (Sensors 19:4844) recomputed: files written into the output folder
//   sun2019_fig7.exr           their Fig. 7: DoP and AoP (the paper's α, degrees) of the four
//                              imaging modes at solar elevation 0°, and each mode minus the vertical
//                              projection: channels dop.M, aop.M, ddop.M, daop.M, inside
//                              (M = equidistant, equisolid, stereographic, orthographic)
//   sun2019_sun_positions.csv  the sun at their Table 1 times (scenes/sun2019-hefei.toml), from ERFA
//   sun2019_epsilon.csv        ε of every mode (as the camera) against the vertical projection
//                              (as the model), and of an equidistant camera against every model,
//                              140° full circle (Tables 1, 3) and 100° anti-sun half (Tables 2, 4),
//                              for two ways of putting the modes on one grid (normalization)
//   sun2019_magnification.csv  eqs. 22–28: β_r, β_t from camera::magnification (numerical
//                              derivatives of project()) beside the closed forms, in units of f
#include <array>
#include <cstdio>
#include <map>
#include <numbers>
#include <sstream>

#include "camera/ideal_magnification.h"
#include "camera/magnification.h"
#include "camera/radial_lens.h"
#include "sky/units.h"
#include "studies/reproduce.h"
#include "stack/image_exr.h"
#include "studies/imaging_modes.h"
#include "scene/scene.h"
#include "sky/rayleigh.h"
#include "sky/sun.h"
#include "sky/time.h"

namespace skypol::studies {
namespace {

using camera::Mapping;

// The four modes of their Fig. 7; the vertical projection (orthographic) is the reference.
constexpr std::array<Mapping, 4> kModes = {Mapping::equidistant, Mapping::equisolid,
                                           Mapping::stereographic, Mapping::orthographic};

// The paper's site, atmosphere (for the sun's refraction, as their SPA) and the six times of their
// Table 1 come from the scene (scenes/sun2019-hefei.toml).
struct Setup {
  sky::Site site;
  sky::SunOptions sun_options;
  std::vector<sky::Instant> times;
};

Setup load(const ReproduceOptions& o) {
  const scene::Scene scene = scene::load_scene(o.sun2019_scene);
  if (scene.times.empty()) throw std::invalid_argument(o.sun2019_scene + ": no times");
  return {scene.site, scene.sun_options, scene.times};
}

std::string name(Mapping m) { return std::string(camera::mapping_name(m)); }

void fig7(const ReproduceOptions& o, const Setup& setup) {
  const int size = o.small ? 101 : 401;
  // The paper's φs = 90° is counted from East towards North in the frame of its eqs. 3 and 9–21
  // (tests/sky/fisheye_forms_test.cpp): the sun on the horizon due North, skypol azimuth 0°.
  const sky::Sun sun = sky::sun_from_horizontal(0.0, 0.0, setup.site.latitude_deg);
  const sky::RayleighSky sky_model;  // Pmax = 1, the paper's theoretical value
  std::map<Mapping, studies::ModeImage> img;
  for (Mapping m : kModes) img[m] = studies::render_mode(m, size, 180.0, sky_model, sun);
  const studies::ModeImage& vp = img.at(Mapping::orthographic);
  std::map<std::string, std::vector<float>> ch;
  for (Mapping m : kModes) {
    ch["dop." + name(m)] = img[m].dop;
    ch["aop." + name(m)] = img[m].aop_deg;
    ch["ddop." + name(m)] = studies::dop_difference(img[m], vp);
    ch["daop." + name(m)] = studies::aop_difference_deg(img[m], vp);
  }
  std::vector<float> inside(vp.inside.begin(), vp.inside.end());
  ch["inside"] = inside;
  stack::write_image_exr(o.out_dir + "/sun2019_fig7.exr", size, size, ch,
                          "Sun et al. 2019 Fig. 7: Rayleigh sky, sun on the horizon due North; "
                          "180 deg field of view; image top = North, right = West (seen from below)");
}

void epsilon_tables(const ReproduceOptions& o, const Setup& setup) {
  const int size = o.small ? 201 : 1001;
  const sky::RayleighSky sky_model;
  std::ostringstream pos, eps;
  pos << "time_utc,elevation_deg,azimuth_deg\n";
  eps << "time_utc,normalization,fov_deg,region,camera,model,epsilon_pct,pixels\n";
  for (const sky::Instant when : setup.times) {
    const sky::Sun sun = sky::sun_position(setup.site, when, setup.sun_options);
    const std::string utc = sky::format_iso8601(when);
    pos << utc << ',' << csv_num(sun.elevation / kRadPerDeg) << ',' << csv_num(sun.azimuth / kRadPerDeg) << '\n';
    // Two ways to put the modes on one grid: the 140° field-of-view edge on the image circle of
    // every mode (a camera of that mapping filling the same sensor circle), or the horizon on the
    // unit circle as the paper's eqs. 10, 14, 18 normalise (the 140° view then a disk that differs
    // per mode). The field of view that counts is the compared mode's own (studies/imaging_modes.h).
    for (const auto& [norm, fov] : {std::pair{"fov_circle", 140.0}, std::pair{"horizon_circle", 180.0}}) {
      std::map<Mapping, studies::ModeImage> img;
      for (Mapping m : kModes) img[m] = studies::render_mode(m, size, fov, sky_model, sun);
      struct Case {
        double fov;
        const char* region;
        studies::Region r;
      };
      const Case cases[] = {{140, "full", {70, false}}, {100, "anti_sun", {50, true}}};
      // (camera, model): every mode against the vertical projection; and the paper's own
      // comparisons, an equidistant camera (their Sigma lens) against each model.
      std::vector<std::pair<Mapping, Mapping>> pairs;
      for (Mapping m : kModes) pairs.emplace_back(m, Mapping::orthographic);
      for (Mapping m : kModes)
        if (m != Mapping::orthographic) pairs.emplace_back(Mapping::equidistant, m);
      for (const Case& c : cases)
        for (const auto& [cam, model] : pairs) {
          const studies::Similarity s = studies::similarity(img[cam], img[model], sun, c.r);
          eps << utc << ',' << norm << ','
              << csv_num(c.fov) << ',' << c.region << ',' << name(cam) << ',' << name(model) << ','
              << csv_num(100 * s.epsilon) << ',' << s.pixels << '\n';
        }
    }
  }
  write_text(o.out_dir, "sun2019_sun_positions.csv", pos.str());
  write_text(o.out_dir, "sun2019_epsilon.csv", eps.str());
}

void magnification_table(const ReproduceOptions& o) {
  const double f = 1000.0;  // pixels; the table is in units of f
  std::ostringstream os;
  os << "mode,theta_deg,radial_numeric,radial_closed,tangential_numeric,tangential_closed\n";
  const int step = o.small ? 5 : 1;
  for (Mapping m : {Mapping::equidistant, Mapping::equisolid, Mapping::stereographic,
                    Mapping::orthographic, Mapping::perspective}) {
    const double theta_max = (m == Mapping::perspective ? 80.0 : 90.0) * kRadPerDeg;
    camera::Intrinsics k;
    k.fx = k.fy = f;
    k.width = k.height = 4000;
    k.cx = k.cy = 1999.5;
    const camera::RadialLens lens(m, k, theta_max);
    for (int deg = 0; deg * kRadPerDeg <= theta_max + 1e-9; deg += step) {
      const double theta = deg * kRadPerDeg;
      const auto num = camera::magnification(lens, theta, 0.3);
      const camera::Magnification ref = camera::ideal_magnification(m, theta, f);
      if (!num) continue;
      os << name(m) << ',' << deg << ',' << csv_num(num->radial_px / f) << ','
         << csv_num(ref.radial_px / f) << ',' << csv_num(num->tangential_px / f) << ','
         << csv_num(ref.tangential_px / f) << '\n';
    }
  }
  write_text(o.out_dir, "sun2019_magnification.csv", os.str());
}

}  // namespace

void reproduce_sun2019(const ReproduceOptions& o) {
  const Setup setup = load(o);
  fig7(o, setup);
  epsilon_tables(o, setup);
  magnification_table(o);
  if (!o.quiet) std::fprintf(stderr, "sun2019: Fig. 7, epsilon tables, magnifications written\n");
}

}  // namespace skypol::studies
