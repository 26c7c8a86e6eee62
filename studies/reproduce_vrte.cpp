// The SkyPole set-up under the VRTE sky (multiple scattering by molecules and a clean continental
// aerosol; sky/README.md), beside single scattering. Files written into the output folder:
//   vrte_pole.csv            DoLP at the visible celestial pole over the SkyPole day: VRTE (550 nm)
//                            and single scattering (Pmax 1), with the sun's elevation
//   vrte_neutral_points.csv  Babinet (above the sun), Brewster (below it) and Arago (above the
//                            anti-sun) in the solar vertical: angular distance against sun elevation
//   vrte_max_dolp.csv        maximum DoLP in the solar vertical against wavelength and τ(550),
//                            sun at 30°
//   vrte_protocol.csv        Fig. 3's protocol (reproduction_protocol.h) with every estimator on the
//                            VRTE sky, noise-free and through the colour DoFP sensor, auto-exposed
//   vrte_setup.csv           the numbers of the set-up, for the report
// Tables come from sky::default_table_cache_dir() (the tests point SKYPOL_CACHE_DIR at a
// temporary folder): a second run reads them.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <limits>
#include <optional>
#include <utility>
#include <sstream>

#include "camera/presets.h"
#include "render/recorded_stack.h"
#include "scene/scene.h"
#include "scene/truth.h"
#include "sky/rayleigh.h"
#include "sky/sky_spec.h"
#include "sky/units.h"
#include "skypole/evaluate.h"
#include "studies/reproduce.h"
#include "studies/reproduction_protocol.h"

namespace skypol::studies {
namespace {

// The atmosphere of this section: OPAC continental_clean, τ(550) = 0.1, ground albedo 0.1.
sky::SkySpec vrte_spec(bool small) {
  sky::SkySpec s;
  s.model = "vrte";
  s.aerosol.type = "continental_clean";
  s.aerosol.tau_550 = 0.1;
  s.ground_albedo = 0.1;
  if (small) {
    s.streams = 6;
    s.grid = 13;
    s.aerosol.angle_nodes = 96;
  }
  return s;
}

std::unique_ptr<sky::SkyModel> one_band(const sky::SkySpec& spec, const scene::Scene& scene, double wavelength_nm) {
  sky::SkySpec s = spec;
  s.wavelengths_nm = {wavelength_nm};
  const std::string band[] = {"Y"};
  sky::BandSkies b = sky::make_band_skies(s, band, scene::site_atmosphere(scene), sky::default_table_cache_dir());
  return std::move(b.skies.front());
}

// Stokes at d with e0 = the horizontal normal of the solar vertical (S1 > 0: E horizontal, the
// ordinary sign of skylight in that plane; S1 < 0: negative polarization beyond a neutral point).
sky::Stokes in_vertical(const sky::SkyModel& m, const sky::Sun& sun, double alpha) {
  const Eigen::Vector3d h(std::sin(sun.azimuth), std::cos(sun.azimuth), 0.0);  // sun's horizontal direction
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d d = std::cos(alpha) * h + std::sin(alpha) * z;
  const Eigen::Vector3d n = h.cross(z);  // ⟂ the vertical plane
  return m.stokes(d, n, sun);
}

sky::Sun sun_at(double azimuth_deg, double elevation_deg) {
  sky::Sun s;
  s.azimuth = azimuth_deg * kRadPerDeg;
  s.elevation = elevation_deg * kRadPerDeg;
  s.direction = sky::enu_direction(s.azimuth, s.elevation);
  return s;
}

// The first sign change of S1 from + to − walking from a to b (radians) in steps; nullopt if none.
std::optional<double> zero_crossing(const sky::SkyModel& m, const sky::Sun& sun, double a, double b, double step) {
  const int n = std::max(2, static_cast<int>(std::abs(b - a) / step));
  double prev_x = a, prev = in_vertical(m, sun, a).s1;
  for (int i = 1; i <= n; ++i) {
    const double x = a + (b - a) * i / n;
    const double v = in_vertical(m, sun, x).s1;
    if (prev > 0 && v <= 0) return prev_x + (x - prev_x) * prev / (prev - v);
    prev_x = x, prev = v;
  }
  return std::nullopt;
}

// A unit vector ⟂ d (horizontal; any at the zenith).
Eigen::Vector3d horizontal_e0(const Eigen::Vector3d& d) {
  const Eigen::Vector3d e = Eigen::Vector3d::UnitZ().cross(d);
  return e.norm() > 1e-9 ? Eigen::Vector3d(e.normalized()) : Eigen::Vector3d::UnitX();
}

std::string opt_num(const std::optional<double>& v) { return v ? csv_num(*v) : ""; }

void pole_over_day(const ReproduceOptions& o, const scene::Scene& scene, const sky::SkyModel& vrte) {
  const sky::RayleighSky single(sky::RayleighParams{1.0});
  const Eigen::Vector3d pole = scene::visible_pole(scene.site.latitude_deg);
  const Eigen::Vector3d e0 = horizontal_e0(pole);
  std::ostringstream os;
  os << "time,sun_elevation_deg,dolp_single,dolp_vrte,s0_vrte\n";
  for (const sky::Instant t : scene.times) {
    const sky::Sun sun = sky::sun_position(scene.site, t, scene.sun_options);
    const sky::Stokes a = single.stokes(pole, e0, sun), b = vrte.stokes(pole, e0, sun);
    os << sky::format_iso8601(t) << ',' << csv_num(sun.elevation / kRadPerDeg) << ',' << csv_num(a.dolp()) << ','
       << csv_num(b.dolp()) << ',' << csv_num(b.s0) << '\n';
  }
  write_text(o.out_dir, "vrte_pole.csv", os.str());
}

void neutral_points(const ReproduceOptions& o, const sky::SkyModel& vrte) {
  std::ostringstream os;
  os << "sun_elevation_deg,babinet_from_sun_deg,brewster_from_sun_deg,arago_from_antisun_deg\n";
  const double step = 0.05 * kRadPerDeg;
  for (double el = 0.5; el <= 60.0 + 1e-9; el += (o.small ? 10.0 : 0.5)) {
    const sky::Sun sun = sun_at(180, el);
    const double s = el * kRadPerDeg;
    // Babinet: walking up from near the sun towards the zenith, polarization turns from negative
    // (next to the sun) to positive; Brewster: the same walking down towards the horizon; Arago:
    // walking down from the zenith on the anti-sun side towards the horizon, + to −.
    std::optional<double> babinet, brewster, arago;
    // From the zenith side towards the sun: the first + → − crossing is the Babinet point.
    if (auto x = zero_crossing(vrte, sun, std::min(s + 60 * kRadPerDeg, std::numbers::pi / 2 + s), s + 0.5 * kRadPerDeg, step))
      babinet = (*x - s) / kRadPerDeg;
    // From the horizon (just above it) towards the sun: Brewster, if the sun is high enough.
    if (s > 2 * kRadPerDeg) {
      if (auto x = zero_crossing(vrte, sun, std::max(0.2 * kRadPerDeg, s - 60 * kRadPerDeg), s - 0.5 * kRadPerDeg, step))
        brewster = (s - *x) / kRadPerDeg;
    }
    // From the zenith towards the anti-sun horizon (α → π): Arago, while it is above the horizon.
    if (auto x = zero_crossing(vrte, sun, std::numbers::pi / 2 + 1 * kRadPerDeg, std::numbers::pi - 0.2 * kRadPerDeg, step))
      arago = (std::numbers::pi + s - *x) / kRadPerDeg;
    os << csv_num(el) << ',' << opt_num(babinet) << ',' << opt_num(brewster) << ',' << opt_num(arago) << '\n';
  }
  write_text(o.out_dir, "vrte_neutral_points.csv", os.str());
}

void max_dolp(const ReproduceOptions& o, const scene::Scene& scene) {
  const std::vector<double> wavelengths =
      o.small ? std::vector<double>{450, 650} : std::vector<double>{400, 450, 500, 550, 600, 650, 700};
  const std::vector<double> taus =
      o.small ? std::vector<double>{0.0, 0.3} : std::vector<double>{0.0, 0.05, 0.1, 0.2, 0.4, 0.8};
  std::ostringstream os;
  os << "wavelength_nm,tau_550,tau_rayleigh,tau_aerosol,max_dolp,at_from_sun_deg\n";
  const sky::Sun sun = sun_at(180, 30);
  for (double tau : taus) {
    for (double wl : wavelengths) {
      sky::SkySpec s = vrte_spec(o.small);
      s.aerosol.tau_550 = tau;
      const auto m = one_band(s, scene, wl);
      const sky::SiteAtmosphere air = scene::site_atmosphere(scene);
      const sky::LayerOptics optics = sky::layer_optics(wl, air.pressure_hpa, air.altitude_m, air.latitude_deg, s.aerosol);
      double best = 0, at = 0;
      for (double a = 0.5; a < 179.5; a += 0.25) {  // the solar vertical, horizon to horizon
        const sky::Stokes st = in_vertical(*m, sun, a * kRadPerDeg);
        if (st.dolp() > best) best = st.dolp(), at = std::abs(a - 30.0);
      }
      os << csv_num(wl) << ',' << csv_num(tau) << ',' << csv_num(optics.tau_rayleigh) << ','
         << csv_num(optics.tau_aerosol) << ',' << csv_num(best) << ',' << csv_num(at) << '\n';
    }
  }
  write_text(o.out_dir, "vrte_max_dolp.csv", os.str());
}

void protocol(const ReproduceOptions& o, const scene::Scene& scene, const sky::SkySpec& spec_sky) {
  const double scale = o.small ? 1.0 / 16 : 0.25;
  const auto cam = scene::build_camera(scene.camera);
  studies::ProtocolSpec spec;
  spec.setup.lens = cam->lens().rescaled(scale);
  spec.setup.site = scene.site;
  spec.setup.sun_options = scene.sun_options;
  spec.setup.tilt_deg = scene.camera.tilt_deg;
  spec.setup.roll_deg = scene.camera.roll_deg;
  spec.setup.sky = spec_sky;
  // The paper's camera: the colour IMX250MYR (Lucid PHX050S-QC), each band its own VRTE table at
  // the band's wavelength; the estimators read band B, as the paper did.
  spec.setup.bands = {"R", "G", "B"};
  spec.methods = skypole::method_names();
  spec.auto_site_free = true;
  const double t0 = scene.times.front().unix_seconds;
  for (int m = 0; m <= 240; m += 10) spec.window_times.push_back(sky::Instant{t0 + (3 + m / 60.0) * 3600.0});
  if (o.small) {
    spec.headings_deg = {0, 90};
    for (std::size_t i = 0; i < scene.times.size(); i += 2) spec.day_times.push_back(scene.times[i]);
    spec.window_frames = {4, 10};
  } else {
    for (int hd = 0; hd <= 170; hd += 10) spec.headings_deg.push_back(hd);
    spec.day_times = scene.times;
    spec.window_frames = {4, 7, 10, 13, 19, 25};
  }
  // The colour DoFP sensor as the camera meters it (camera/dofp_sensor.h, AutoExposure: the 99.5th
  // percentile of the sky's S0 at 80 % of the full well, frame by frame): the vrte sky's S0 is I/F,
  // and no hand scaling is needed.
  spec.sensor = camera::sensor_preset("lucid_phx050s_qc").dofp;
  spec.auto_exposure = camera::AutoExposure{};
  spec.seed = 20220923;
  const auto t = std::chrono::steady_clock::now();
  const auto rows = studies::run_protocol(spec, o.progress);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  write_text(o.out_dir, "vrte_protocol.csv", studies::protocol_csv(rows));
  std::pair<double, double> exposures{std::numeric_limits<double>::infinity(), 0};
  for (const ProtocolRow& r : rows)
    if (r.sensor && r.exposure_max_us > 0)
      exposures = {std::min(exposures.first, r.exposure_min_us), std::max(exposures.second, r.exposure_max_us)};

  const sky::SiteAtmosphere air = scene::site_atmosphere(scene);
  const sky::LayerOptics optics =
      sky::layer_optics(550, air.pressure_hpa, air.altitude_m, air.latitude_deg, spec_sky.aerosol);
  std::ostringstream os;
  os << "key,value\n"
     << "aerosol," << spec_sky.aerosol.type << '\n'
     << "tau_550," << csv_num(spec_sky.aerosol.tau_550) << '\n'
     << "angstrom," << csv_num(sky::effective_angstrom(spec_sky.aerosol)) << '\n'
     << "ssa_550," << csv_num(optics.aerosol_ssa) << '\n'
     << "tau_rayleigh_550," << csv_num(optics.tau_rayleigh) << '\n'
     << "depolarization," << csv_num(optics.depolarization) << '\n'
     << "pressure_hpa," << csv_num(air.pressure_hpa) << '\n'
     << "ground_albedo," << csv_num(spec_sky.ground_albedo) << '\n'
     << "streams," << spec_sky.streams << "\ngrid," << spec_sky.grid << '\n'
     << "width," << spec.setup.lens->intrinsics().width << "\nheight," << spec.setup.lens->intrinsics().height << '\n'
     << "headings," << spec.headings_deg.size() << '\n'
     << "day_frames," << spec.day_times.size() << '\n'
     << "sensor,lucid_phx050s_qc\n"
     << "meter_percentile," << csv_num(spec.auto_exposure->percentile) << '\n'
     << "meter_target," << csv_num(spec.auto_exposure->target) << '\n'
     << "exposure_min_us," << csv_num(exposures.first) << '\n'
     << "exposure_max_us," << csv_num(exposures.second) << '\n'
     << "protocol_seconds," << csv_num(seconds) << '\n';
  write_text(o.out_dir, "vrte_setup.csv", os.str());
}

}  // namespace

void reproduce_vrte(const ReproduceOptions& o) {
  const scene::Scene scene = scene::load_scene(o.scene);
  if (scene.times.empty()) throw std::invalid_argument(o.scene + ": no times");
  const sky::SkySpec spec = vrte_spec(o.small);
  const auto vrte = one_band(spec, scene, 550);
  pole_over_day(o, scene, *vrte);
  neutral_points(o, *vrte);
  max_dolp(o, scene);
  if (!o.quiet) std::fprintf(stderr, "vrte: pole, neutral points, max DoLP written; protocol (%s)...\n",
                             o.small ? "small" : "full");
  protocol(o, scene, spec);
}

}  // namespace skypol::studies
