// The calibration study's populations and their scenes (tradeoff_calibration.h): what each
// population draws, one scene drawn from the seeded generator, and its frames rendered through its
// camera, sky and sensor.
#include <algorithm>
#include <array>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "camera/lens_factory.h"
#include "camera/orientation.h"
#include "camera/presets.h"
#include "render/renderer.h"
#include "render/sensor_stage.h"
#include "scene/scene.h"
#include "scene/truth.h"
#include "sky/sky_spec.h"
#include "sky/sun.h"
#include "sky/units.h"
#include "studies/tradeoff_calibration.h"
#include "studies/tradeoff_setup.h"

namespace skypol::studies::tradeoff::calibration {
namespace {

double sun_elevation_deg(const sky::Site& site, double unix_s) {
  return sky::sun_position(site, sky::Instant{unix_s}).elevation / kRadPerDeg;
}

constexpr Population kMixed{70, 20, 660, 0.45, 0.25, 0.15, 0.65, false, 0};
constexpr Population kRealistic{80, 30, 720, 0.15, 0.15, 0.1, 0.45, true, 0.6};
constexpr Population kMismatch{80, 30, 720, 0.1, 0.25, 0, 0.45, true, 0.6, 0, 3, true};

// The mismatch population's own draws, each outside what the calibration was read off:
// - vrte: in 60 % of the scenes one custom log-normal mode (median radius log-uniform on
//   0.02–1.5 µm, σ_g 1.4–2.5, m = n + ik with n 1.33–1.65 and k 0 or log-uniform on 10⁻⁴–0.05),
//   else the drawn OPAC type with its Ångström exponent (0–2.2) and single-scattering albedo
//   (0.8–1) each overridden in half of the scenes; the solver at 6, 8 or 16 streams and a grid of
//   13, 17 or 33 nodes (the others: 12 and 25);
// - berry: neutral points 10–35° from the sun (the others: 20°), either normalisation;
// - the sensor: each micro-polarizer ±2° off its nominal angle, extinction ratio log-uniform on
//   20–500 (the others: the preset's 100), PRNU 0.3–3 % and DSNU 0–30 e⁻ rms per binned pixel,
//   demosaiced as an uncalibrated pipeline does (ideal polarizers assumed).
void draw_off_family(std::mt19937_64& rng, Draw& d) {
  std::uniform_real_distribution<double> u(0, 1);
  const auto log_uniform = [&](double lo, double hi) { return lo * std::exp(u(rng) * std::log(hi / lo)); };
  const auto pick = [&](std::size_t n) { return static_cast<std::size_t>(u(rng) * static_cast<double>(n)) % n; };
  d.off_family = true;
  sky::AerosolSpec& a = d.aerosol_optics;
  if (u(rng) < 0.6) {
    d.aerosol = "custom";
    a.median_radius_um = log_uniform(0.02, 1.5);
    a.geometric_std = 1.4 + 1.1 * u(rng);
    a.refractive_real = 1.33 + 0.32 * u(rng);
    a.refractive_imag = u(rng) < 0.3 ? 0.0 : log_uniform(1e-4, 0.05);
  } else {
    if (u(rng) < 0.5) a.angstrom = 2.2 * u(rng);
    if (u(rng) < 0.5) a.ssa = 0.8 + 0.2 * u(rng);
  }
  const std::array<int, 3> streams = {6, 8, 16}, grids = {13, 17, 33};
  d.streams = streams[pick(streams.size())];
  d.grid = grids[pick(grids.size())];
  d.separation_deg = 10 + 25 * u(rng);
  d.berry_normalisation = u(rng) < 0.5 ? "split_rayleigh" : "opensky";
  for (double& e : d.angle_error_deg) e = 4 * u(rng) - 2;
  d.extinction_ratio = log_uniform(20, 500);
  d.prnu_rms = 0.003 + 0.027 * u(rng);
  d.dsnu_e = 30 * u(rng);
}

// The 99th percentile of a frame's S0 over the pixels that see sky (mask > 0.5).
double bright_s0(const stack::Frame& f, const std::string& band) {
  const auto& s0 = f.channels.at("S0." + band);
  const auto& mask = f.channels.at("mask");
  std::vector<float> v;
  for (std::size_t i = 0; i < s0.size(); ++i)
    if (mask[i] > 0.5f && std::isfinite(s0[i]) && s0[i] > 0) v.push_back(s0[i]);
  if (v.empty()) return 1.0;
  const auto k = v.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), k, v.end());
  return std::max(static_cast<double>(*k), 1e-6);
}

std::shared_ptr<const camera::Camera> make_camera(const Draw& d, int binning) {
  const camera::SensorPreset& sp = camera::sensor_preset("sony_imx250mzr");
  camera::LensSpec spec;
  spec.model = d.lens;
  spec.width = sp.width / binning;
  spec.height = sp.height / binning;
  const double theta_max = (d.lens == "orthographic" ? 90.0 : 92.5) * kRadPerDeg;
  spec.fov_deg = 2 * theta_max / kRadPerDeg;
  // The image circle just inside the sensor's height.
  const double r = 0.49 * spec.height;
  if (d.lens == "equidistant") spec.fx = r / theta_max;
  if (d.lens == "equisolid") spec.fx = r / (2 * std::sin(theta_max / 2));
  if (d.lens == "stereographic") spec.fx = r / (2 * std::tan(theta_max / 2));
  if (d.lens == "orthographic") spec.fx = r / std::sin(theta_max);
  if (d.lens == "kannala_brandt") {
    spec.coefficients = {-0.02, 0.001, 0, 0};
    const double t = theta_max;
    spec.fx = r / (t * (1 - 0.02 * t * t + 0.001 * t * t * t * t));
  }
  return std::make_shared<camera::Camera>(camera::make_lens(spec),
                                          camera::world_from_heading_tilt_roll(d.heading, d.tilt, d.roll));
}

}  // namespace

const Population& population_of(const std::string& name) {
  if (name == "mixed") return kMixed;
  if (name == "realistic") return kRealistic;
  if (name == "mismatch") return kMismatch;
  throw std::invalid_argument("tradeoff calibration: unknown population \"" + name +
                              "\" (expected one of mixed, realistic, mismatch)");
}

Draw draw_scene(std::mt19937_64& rng, int index, const Population& pop) {
  std::uniform_real_distribution<double> u(0, 1);
  const std::vector<std::string> lenses = {"equidistant", "equisolid", "stereographic", "orthographic",
                                           "kannala_brandt"};
  for (int attempt = 0;; ++attempt) {
    Draw d;
    d.index = index;
    d.site = sky::Site{-pop.max_abs_latitude_deg + 2 * pop.max_abs_latitude_deg * u(rng), -180 + 360 * u(rng), 0};
    const int doy = static_cast<int>(365 * u(rng));
    const double jan1_2023 = 1672531200.0;
    const double day0 = jan1_2023 + doy * 86400.0;
    // log-uniform window; step 2 … 30 min; at most 24 frames (the step grows).
    d.window_min = pop.min_window_min * std::exp(u(rng) * std::log(pop.max_window_min / pop.min_window_min));
    d.step_min = std::clamp(2 + 28 * u(rng), 2.0, d.window_min / 2);
    d.frames = static_cast<int>(std::floor(d.window_min / d.step_min)) + 1;
    if (d.frames > 24) {
      d.frames = 24;
      d.step_min = d.window_min / 23;
    }
    // Local solar noon ≈ 12:00 − longitude/15 h UTC; the window's centre within ±5 h of it.
    const double noon = day0 + (12.0 - d.site.longitude_deg / 15.0) * 3600.0;
    const double centre = noon + (u(rng) - 0.5) * 10 * 3600.0;
    d.start_unix = centre - d.window_min * 30.0;
    bool up = true;
    for (int i = 0; i < d.frames && up; ++i)
      up = sun_elevation_deg(d.site, d.start_unix + i * d.step_min * 60.0) >= 3.0;
    if (!up && attempt < 200) continue;
    d.heading = 360 * u(rng);
    d.tilt = u(rng) < pop.level_share ? 0.0 : pop.min_tilt_deg + (15 - pop.min_tilt_deg) * u(rng);
    d.roll = u(rng) < 0.4 ? 0.0 : 360 * u(rng);  // the tilt's direction
    d.lens = lenses[static_cast<std::size_t>(u(rng) * static_cast<double>(lenses.size())) % lenses.size()];
    // Every sky model: single scattering (Rayleigh), Berry's neutral points, and the physically
    // based multiple-scattering sky (vrte: molecules, one OPAC aerosol, a Lambertian ground).
    const double which_sky = u(rng);
    d.sky_model = which_sky < pop.rayleigh_share                    ? "rayleigh"
                  : which_sky < pop.rayleigh_share + pop.berry_share ? "berry"
                                                                     : "vrte";
    d.max_dolp = 0.5 + 0.3 * u(rng);
    const auto pick = [&](std::size_t n) { return static_cast<std::size_t>(u(rng) * static_cast<double>(n)) % n; };
    if (pop.climatology) {
      const std::vector<std::string> aerosols = sky::aerosol_type_names();
      d.aerosol = aerosols[pick(aerosols.size())];
      d.tau_550 = 0.02 * std::exp(u(rng) * std::log(0.8 / 0.02));
      d.ground_albedo = 0.35 * u(rng);
    } else {
      const std::vector<std::string> aerosols = {"continental_clean", "maritime_clean", "urban"};
      const std::vector<double> taus = {0.05, 0.3}, albedos = {0.1, 0.3};
      d.aerosol = aerosols[pick(aerosols.size())];
      d.tau_550 = taus[pick(taus.size())];
      d.ground_albedo = albedos[pick(albedos.size())];
    }
    d.cloud = u(rng) < 0.35 ? 0.0 : 0.5 * u(rng);
    const double s = u(rng);
    d.sensor = s < pop.no_sensor_share ? "none" : s < pop.no_sensor_share + pop.mono_share ? "mono" : "colour";
    d.exposure_us = 250 * std::exp(u(rng) * std::log(12.0));  // 0.25 … 3 ms
    d.gain_factor = std::exp((u(rng) - 0.5) * std::log(8.0));  // ×0.35 … ×2.8
    if (pop.auto_exposure_share > 0) d.auto_exposure = u(rng) < pop.auto_exposure_share && d.sensor != "none";
    d.seed = rng();
    char buf[16];
    const std::time_t t = static_cast<std::time_t>(day0);
    std::strftime(buf, sizeof buf, "%Y-%m-%d", std::gmtime(&t));
    d.date = buf;
    if (pop.off_family) draw_off_family(rng, d);
    return d;
  }
}

stack::Stack render_draw(const Draw& d, int binning, int noise_draw, const Population& pop) {
  auto cam = make_camera(d, binning);
  sky::SkySpec sky;
  sky.model = d.sky_model;
  sky.max_dolp = d.max_dolp;
  sky.clouds.coverage = d.cloud;
  sky.clouds.seed = d.seed;
  const bool colour = d.sensor == "colour";
  render::RenderOptions ro;
  ro.bands = colour ? std::vector<std::string>{"R", "G", "B"} : std::vector<std::string>{"Y"};
  const bool vrte = d.sky_model == "vrte";
  if (vrte) {
    sky.max_dolp = 1.0;  // the solver gives the degree itself
    if (d.off_family) sky.aerosol = d.aerosol_optics;
    sky.aerosol.type = d.aerosol;
    sky.aerosol.tau_550 = d.tau_550;
    sky.ground_albedo = d.ground_albedo;
    sky.streams = d.streams;
    sky.grid = d.grid;
  }
  sky.separation_deg = d.separation_deg;
  sky.berry_normalisation = d.berry_normalisation;
  // One model per band (vrte), or one grey model. The vrte atmosphere is the standard one at
  // 45° latitude for every site (the Rayleigh depth's latitude term is < 0.3 %), so that a table
  // serves every scene with the same aerosol, depth and albedo.
  const sky::BandSkies skies = sky::make_band_skies(sky, ro.bands, sky::SiteAtmosphere{},
                                                    pop.climatology ? std::filesystem::path{} : sky::default_table_cache_dir());
  std::vector<const sky::SkyModel*> band_skies;
  for (const auto& m : skies.skies) band_skies.push_back(m.get());
  ro.channels = {"S0", "S1", "S2", "DoLP", "AoLP", "mask"};
  const render::Renderer renderer(cam, ro);
  scene::Scene scene;
  scene.site = d.site;
  scene.camera.heading_deg = d.heading;
  scene.camera.tilt_deg = d.tilt;
  scene.camera.roll_deg = d.roll;
  stack::Stack stack;
  stack.camera = cam;
  stack.bands = ro.bands;
  stack.frames.resize(static_cast<std::size_t>(d.frames));
  for (int i = 0; i < d.frames; ++i) {
    const sky::Instant t{d.start_unix + i * d.step_min * 60.0};
    const scene::Truth truth = scene::make_truth(scene, *cam, t);
    stack.frames[static_cast<std::size_t>(i)] = renderer.render(band_skies, truth.sun);
    stack.frames[static_cast<std::size_t>(i)].truth = truth;
  }
  if (d.sensor != "none") {
    scene::SensorSpec sensor;
    // Noise draw k > 0 keys the sensor's noise off the scene's seed + k·1000003 (the scenes' seeds
    // are random 64-bit numbers: no two draws of the population share a key in practice).
    sensor.dofp = paper_sensor(binning, d.exposure_us, d.seed + static_cast<std::uint64_t>(noise_draw) * 1000003ULL);
    sensor.dofp.gain_dn_per_e *= d.gain_factor;
    if (d.off_family) {
      sensor.dofp.angle_error_deg = d.angle_error_deg;
      sensor.dofp.extinction_ratio = d.extinction_ratio;
      sensor.dofp.prnu_rms = d.prnu_rms;
      sensor.dofp.dsnu_e = d.dsnu_e;
    }
    // The vrte sky's S0 is I/F (≈ 0.01–1 sr⁻¹), not the grey models' unit (docs/scenes.md): at a
    // fixed exposure it is exposed as the grey skies are, its brightest sky (99th percentile of
    // frame 0's S0) at the radiance the sensor's preset puts at 70 % of the full well in 1 ms. An
    // auto-exposed sensor needs no such scaling: the meter finds each frame's exposure (the sky
    // above the camera's horizon, camera/dofp_sensor.h's AutoExposure defaults).
    if (d.auto_exposure) sensor.auto_exposure = camera::AutoExposure{};
    else if (vrte) sensor.dofp.electrons_per_radiance_s /= bright_s0(stack.frames.front(), ro.bands.front());
    if (colour) sensor.dofp.color_filter = camera::ColorFilter::rggb_blocks;
    const std::vector<std::uint8_t> meter_sky = d.auto_exposure ? render::sky_pixels(*cam) : std::vector<std::uint8_t>{};
    tbb::parallel_for(std::size_t{0}, stack.frames.size(), [&](std::size_t i) {
      render::apply_sensor(sensor, ro.bands, i, stack.frames[i], false, meter_sky);
    });
  }
  // S1 and S2 are not read by any method (DoLP and AoLP are); S0 is: the sky mask's saturated and
  // dark tests read it (sky_mask.h), as they do on a user's stack.
  for (stack::Frame& f : stack.frames)
    for (const std::string& b : ro.bands)
      for (const char* c : {"S1.", "S2."}) f.channels.erase(c + b);
  return stack;
}

}  // namespace skypol::studies::tradeoff::calibration
