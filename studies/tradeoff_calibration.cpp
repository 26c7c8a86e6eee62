// Study: are the stated uncertainties honest? A seeded random population of scenes unlike the
// shipped ones — sites from −70° to 70° latitude, dates through the year, windows of 20 min to
// 11 h with a frame every 2–30 min, any heading, tilts up to 15°, every analytic lens model, the
// mono or colour DoFP sensor at various exposures and gains (or none), 0–50 % cloud, the Rayleigh,
// Berry and multiple-scattering (vrte: a few atmospheres, tables from the disk cache) skies —
// each rendered small (binning 8: 306×256; --small: binning 16, 153×128) and
// given to every method and to auto, with --max-uncertainty (default 5°: StudyOptions). Per stack and method: the error against the truth, the
// stated σ and 95 % cone. Per method: the yield (share of valid answers), the lie rate (valid
// with error > 5°, or > 5σ), the coverage (share of valid answers whose 95 % cone holds the
// truth, with its 95 % Wilson interval), the error distribution, and the σ factor that would have
// made the coverage exactly 95 % (how skypole/evaluate.cpp's calibration is read, by
// scripts/calibration_tune.py, off --uncalibrated runs of tuning seeds; docs/benchmarks.md,
// section 7, holds seeds out for each method). The same per
// sky model (calibration_by_sky.csv), and auto against each method on the scenes both answer
// (calibration_auto.csv).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <utility>

#include <tbb/parallel_for.h>

#include "camera/lens_factory.h"
#include "camera/orientation.h"
#include "camera/presets.h"
#include "render/renderer.h"
#include "render/sensor_stage.h"
#include "scene/scene.h"
#include "scene/truth.h"
#include "sky/aerosol_types.h"
#include "sky/sky_spec.h"
#include "sky/sun.h"
#include "sky/units.h"
#include "skypole/cloud_share.h"
#include "skypole/estimate.h"
#include "skypole/sky_images.h"
#include "skypole/evaluate.h"
#include "skypole/uncertainty.h"
#include "studies/tradeoff_setup.h"
#include "studies/tradeoff_studies.h"
#include "studies/tradeoff_table.h"

namespace skypol::studies::tradeoff {
namespace {

constexpr double kLieDeg = 5.0;    // an answer this far off, while valid, is a lie
constexpr double kLieSigma = 5.0;  // … or this many of its own σ off

struct Draw {
  int index = 0;
  sky::Site site;
  std::string date;  // YYYY-MM-DD
  double start_unix = 0, window_min = 0, step_min = 0;
  int frames = 0;
  double heading = 0, tilt = 0, roll = 0;
  std::string lens;
  std::string sky_model;
  double max_dolp = 0.7;
  // vrte only: one of a few atmospheres, so that the solver's tables (one per atmosphere and
  // band, cached on disk) are reused across scenes and runs.
  std::string aerosol;
  double tau_550 = 0, ground_albedo = 0;
  double cloud = 0;
  std::string sensor;  // none | mono | colour
  double exposure_us = 0, gain_factor = 1;
  bool auto_exposure = false;  // the meter sets each frame's exposure (exposure_us is then unused)
  std::uint64_t seed = 0;
};

double sun_elevation_deg(const sky::Site& site, double unix_s) {
  return sky::sun_position(site, sky::Instant{unix_s}).elevation / kRadPerDeg;
}

// What a population draws from (StudyOptions::population). "mixed": sites within 70° of the
// equator, windows of 20 min to 11 h, Rayleigh in 45 % of the scenes and Berry in 25 %, the vrte
// sky in 30 % with one of 12 atmospheres (3 aerosols × τ(550) 0.05 or 0.3 × albedo 0.1 or 0.3,
// whose tables the disk cache keeps). "realistic": the physically based sky in most scenes, its
// atmosphere drawn from a climatology — every OPAC type, τ(550) log-uniform on 0.02–0.8 (73 % of
// the draws below 0.3, as sun photometer networks see clear-sky loads), ground albedo uniform on
// 0–0.35 — sites up to 80° from the equator and windows of 30 min to 12 h, and 60 % of its sensors
// auto-exposed, as a camera left to meter sets itself; its tables are solved per scene and not
// cached (each atmosphere is new).
struct Population {
  double max_abs_latitude_deg, min_window_min, max_window_min;
  double rayleigh_share, berry_share;  // the rest is vrte
  double no_sensor_share, mono_share;  // the rest is colour
  bool climatology;
  double auto_exposure_share;  // of the scenes with a sensor; 0: no draw (the mixed population's scenes stay as they were)
};
constexpr Population kMixed{70, 20, 660, 0.45, 0.25, 0.15, 0.65, false, 0};
constexpr Population kRealistic{80, 30, 720, 0.15, 0.15, 0.1, 0.45, true, 0.6};

const Population& population_of(const std::string& name) {
  if (name == "mixed") return kMixed;
  if (name == "realistic") return kRealistic;
  throw std::invalid_argument("tradeoff calibration: unknown population \"" + name +
                              "\" (expected one of mixed, realistic)");
}

// One scene of the population; the sun stays ≥ 3° above the horizon in every frame.
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
    d.tilt = u(rng) < 0.4 ? 0.0 : 15 * u(rng);
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
    return d;
  }
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
    sky.aerosol.type = d.aerosol;
    sky.aerosol.tau_550 = d.tau_550;
    sky.ground_albedo = d.ground_albedo;
  }
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

}  // namespace

int calibration_count(const StudyOptions& o) { return o.count > 0 ? o.count : (o.small ? 6 : 300); }

void check_calibration_scenes(const StudyOptions& o) {
  const int count = calibration_count(o);
  for (int k : o.scenes)
    if (k < 0 || k >= count)
      throw std::invalid_argument("tradeoff calibration: --scenes " + std::to_string(k) +
                                  " is not a scene of this run (0 to " + std::to_string(count - 1) + ")");
}

void study_calibration(const StudyOptions& o) {
  const int binning = o.binning > 0 ? o.binning : o.small ? 16 : 8;
  const int count = calibration_count(o);
  check_calibration_scenes(o);
  const Population& pop = population_of(o.population);
  std::mt19937_64 rng(o.seed);
  Table rows({"stack", "seed", "latitude_deg", "longitude_deg", "date", "window_min", "step_min", "frames",
              "heading_deg", "tilt_deg", "lens", "sky", "max_dolp", "aerosol", "tau_550", "ground_albedo", "cloud",
              "sensor", "exposure_us", "auto_exposure", "gain_factor", "binning", "pixel_deg", "method", "valid", "why_invalid", "angular_error_deg", "bearing_error_deg",
              "latitude_error_deg", "sigma_bearing_deg", "sigma_latitude_deg", "sigma_deg", "cone95_deg",
              "inside_cone", "lie", "residual_deg", "model_misfit", "sun_elevation_misfit_deg", "unpolarized_share", "clipped_share", "ring_anisotropy", "pole_x", "pole_y", "pole_z", "is_north",
              "offset_az_deg", "offset_alt_deg", "sigma_frames_deg", "frame_groups", "sigma_sectors_deg", "frames_aa_deg2", "frames_ab_deg2", "frames_bb_deg2",
              "sectors_aa_deg2", "sectors_ab_deg2", "sectors_bb_deg2", "estimate_s"});
  // One record per (scene, method), summarised per method and per method and sky model.
  struct Outcome {
    std::size_t method = 0;
    int stack = 0;
    std::string sky;
    bool valid = false, inside = false, lie = false;
    double error = 0, ratio = 0;  // angular error; error / cone95
  };
  std::vector<Outcome> outcomes;
  // The methods (all, or a subset in the order given, checked by the command line), then auto over
  // them twice: with the site where the stack knows it, and site-free (as `--site unknown`), last.
  std::vector<std::string> methods = o.methods;
  if (methods.empty())
    for (const skypole::Method& m : skypole::methods()) methods.push_back(m.name);
  methods.push_back("auto");
  methods.push_back(skypole::kAutoSiteFree);
  skypole::InputOptions input;
  input.max_uncertainty_deg = o.max_uncertainty_deg;
  input.calibrated = !o.uncalibrated;
  input.cloud_gate = !o.no_cloud_gate;
  input.sky_mask = !o.no_sky_mask;
  skypole::InputOptions site_free = input;
  site_free.use_site = false;
  const auto chosen = [&](int k) { return o.scenes.empty() || std::ranges::find(o.scenes, k) != o.scenes.end(); };
  const std::filesystem::path partial = std::filesystem::path(o.out_dir) / "calibration.partial.csv";
  int scenes_run = 0;
  for (int k = 0; k < count; ++k) {
    const Draw d = draw_scene(rng, k, pop);  // drawn even when not chosen: the next scenes stay the same
    if (!chosen(k)) continue;
    const stack::Stack stack = render_draw(d, binning, o.noise_draw, pop);
    // The cloud gate's measure (skypole/cloud_share.h), written for every row so that its
    // threshold can be read off this table; undefined (empty) for a stack with no usable sky
    // pixel (a sensor clipped everywhere), which every method then declines.
    double unpolarized = std::nan(""), clipped = std::nan(""), anisotropy = std::nan("");
    try {
      const skypole::SkyImages sky = skypole::prepare_sky_images(stack, input, 1, "calibration");
      const skypole::UnreadableSky unread = skypole::unreadable_sky(sky);
      unpolarized = unread.unpolarized;
      clipped = unread.clipped;
      anisotropy = skypole::ring_anisotropy(sky);
    } catch (const std::invalid_argument&) {
      // no usable sky pixel: the measures stay undefined
    }
    const double pixel_deg = skypole::pixel_angle_deg(*stack.camera);
    std::vector<skypole::PoleEstimate> done;
    for (std::size_t m = 0; m < methods.size(); ++m) {
      skypole::PoleEstimate e;
      try {
        e = methods[m] == "auto"          ? skypole::combine_estimates(stack, input, done)
            : methods[m] == skypole::kAutoSiteFree ? skypole::combine_estimates(stack, site_free, done)
                                          : skypole::run_method(stack, methods[m], input);
      } catch (const std::invalid_argument& err) {
        e = skypole::PoleEstimate{};
        e.method = methods[m];
        e.why_invalid = err.what();
      }
      done.push_back(e);
      rows.row()
          .set("stack", k)
          .set("seed", static_cast<int>(o.seed))
          .set("latitude_deg", d.site.latitude_deg)
          .set("longitude_deg", d.site.longitude_deg)
          .set("date", d.date)
          .set("window_min", d.window_min)
          .set("step_min", d.step_min)
          .set("frames", d.frames)
          .set("heading_deg", d.heading)
          .set("tilt_deg", d.tilt)
          .set("lens", d.lens)
          .set("sky", d.sky_model)
          .set("max_dolp", d.max_dolp)
          .set("aerosol", d.aerosol)
          .set("tau_550", d.tau_550)
          .set("ground_albedo", d.ground_albedo)
          .set("pixel_deg", pixel_deg)
          .set("cloud", d.cloud)
          .set("sensor", d.sensor)
          .set("exposure_us", d.auto_exposure ? stack.frames.front().exposure_us.value_or(0) : d.exposure_us)
          .set("auto_exposure", d.auto_exposure)
          .set("gain_factor", d.gain_factor)
          .set("binning", binning)
          .set("unpolarized_share", unpolarized)
          .set("clipped_share", clipped)
          .set("ring_anisotropy", anisotropy)
          .set("method", methods[m])
          .set("valid", e.valid)
          .set("estimate_s", e.seconds);
      Outcome out;
      out.method = m;
      out.stack = k;
      out.sky = d.sky_model;
      if (!e.valid) {
        rows.set("why_invalid", e.why_invalid);
        outcomes.push_back(out);
        continue;
      }
      const skypole::Score s = skypole::score(e, stack.frames.front().truth);
      const bool inside = s.angular_error_deg <= e.cone95_deg;
      const bool lie = s.angular_error_deg > kLieDeg || s.angular_error_deg > kLieSigma * e.sigma_deg;
      out.valid = true;
      out.inside = inside;
      out.lie = lie;
      out.error = s.angular_error_deg;
      out.ratio = e.cone95_deg > 0 ? s.angular_error_deg / e.cone95_deg : 1e9;
      outcomes.push_back(out);
      rows.set("angular_error_deg", s.angular_error_deg)
          .set("latitude_error_deg", std::abs(s.latitude_error_deg))
          .set("sigma_bearing_deg", e.sigma_bearing_deg)
          .set("sigma_latitude_deg", e.sigma_latitude_deg)
          .set("sigma_deg", e.sigma_deg)
          .set("cone95_deg", e.cone95_deg)
          .set("inside_cone", inside)
          .set("lie", lie)
          .set("residual_deg", e.residual_deg)
          .set("model_misfit", e.model_misfit)
          .set("sun_elevation_misfit_deg", e.sun_elevation_misfit_deg)
          .set("pole_x", e.pole_level.x())
          .set("pole_y", e.pole_level.y())
          .set("pole_z", e.pole_level.z())
          .set("is_north", e.is_north);
      // The raw jackknife covariances (uncertainty.h; deg², axes azimuth and altitude), so that
      // scripts/calibration_tune.py can try any factors on them without running anything again.
      const double d2 = 1.0 / (kRadPerDeg * kRadPerDeg);
      const Eigen::Matrix2d& cf = e.jackknife_frames_rad2;
      const Eigen::Matrix2d& cs = e.jackknife_sectors_rad2;
      // The answer's offset from the true NCP in the tangent plane there (azimuth and altitude axes of
      // the level frame, degrees): with it an average of answers can be scored to the digit, which
      // the 6-digit truth columns cannot do for errors of 0.001°.
      skypole::PoleEstimate truth_pole;
      {
        const double h = -d.heading * kRadPerDeg, lat = d.site.latitude_deg * kRadPerDeg;
        truth_pole.pole_level = Eigen::Vector3d(std::sin(h) * std::cos(lat), std::cos(h) * std::cos(lat), std::sin(lat));
        truth_pole.is_north = true;
      }
      const Eigen::Vector2d off = skypole::tangent_offset(truth_pole, e) / kRadPerDeg;
      rows.set("offset_az_deg", off.x()).set("offset_alt_deg", off.y());
      rows.set("sigma_frames_deg", skypole::sigma_deg_of(cf))
          .set("frame_groups", e.jackknife_frame_groups)
          .set("sigma_sectors_deg", skypole::sigma_deg_of(cs))
          .set("frames_aa_deg2", cf(0, 0) * d2)
          .set("frames_ab_deg2", cf(0, 1) * d2)
          .set("frames_bb_deg2", cf(1, 1) * d2)
          .set("sectors_aa_deg2", cs(0, 0) * d2)
          .set("sectors_ab_deg2", cs(0, 1) * d2)
          .set("sectors_bb_deg2", cs(1, 1) * d2);
      if (s.bearing_error_deg) rows.set("bearing_error_deg", std::abs(*s.bearing_error_deg));
    }
    if (o.progress) std::fprintf(stderr, "calibration %d/%d\n", k + 1, count);
    // A run of hundreds of scenes takes minutes to hours: its rows so far, every 10 scenes, under a
    // name that says they are not the whole run (removed when calibration.csv is written).
    if (++scenes_run % 10 == 0) rows.write(partial.string());
  }
  const auto quantile = [](std::vector<double> v, double q) {
    return v.empty() ? std::nan("") : skypole::quantile(std::move(v), q, skypole::QuantileRank::nearest);
  };
  const std::vector<std::string> skies = {"rayleigh", "berry", "vrte"};
  Table summary({"method", "stacks", "valid", "yield", "lies", "lie_rate", "inside_cone", "coverage",
                 "coverage_low95", "coverage_high95", "median_error_deg", "p90_error_deg", "p95_error_deg",
                 "max_error_deg", "factor_for_95", "seed", "binning", "max_uncertainty_deg"});
  // The same per sky model: what a physically based sky (or Berry's neutral points) does to each.
  Table by_sky({"method", "sky", "stacks", "valid", "yield", "lies", "lie_rate", "inside_cone", "coverage",
                "coverage_low95", "coverage_high95", "median_error_deg", "p95_error_deg", "max_error_deg"});
  const auto fill = [&](Table& t, std::size_t m, const std::string& sky) {
    int stacks = 0, valid = 0, lies = 0, inside = 0;
    std::vector<double> errors, ratios;
    for (const Outcome& r : outcomes) {
      if (r.method != m || (!sky.empty() && r.sky != sky)) continue;
      ++stacks;
      if (!r.valid) continue;
      ++valid;
      lies += r.lie ? 1 : 0;
      inside += r.inside ? 1 : 0;
      errors.push_back(r.error);
      ratios.push_back(r.ratio);
    }
    t.row()
        .set("method", methods[m])
        .set("stacks", stacks)
        .set("valid", valid)
        .set("yield", stacks ? static_cast<double>(valid) / stacks : std::nan(""))
        .set("lies", lies)
        .set("lie_rate", valid ? static_cast<double>(lies) / valid : std::nan(""))
        .set("inside_cone", inside)
        .set("coverage", valid ? static_cast<double>(inside) / valid : std::nan(""))
        .set("coverage_low95", skypole::wilson_interval95(inside, valid).first)
        .set("coverage_high95", skypole::wilson_interval95(inside, valid).second)
        .set("median_error_deg", quantile(errors, 0.5))
        .set("p95_error_deg", quantile(errors, 0.95))
        .set("max_error_deg", quantile(errors, 1.0));
    if (sky.empty())
      t.set("p90_error_deg", quantile(errors, 0.9))
          .set("factor_for_95", quantile(ratios, 0.95))
          .set("seed", static_cast<int>(o.seed))
          .set("binning", binning)
          .set("max_uncertainty_deg", o.max_uncertainty_deg);
    else
      t.set("sky", sky);
  };
  for (std::size_t m = 0; m < methods.size(); ++m) {
    fill(summary, m, "");
    for (const std::string& sky : skies) fill(by_sky, m, sky);
  }
  // auto against each method on the scenes where both answer: medians over the same scenes, so
  // that auto's wider reach (scenes only one method answers) does not decide the comparison.
  Table common({"method", "common", "method_median_error_deg", "auto_median_error_deg", "method_only",
                "auto_only"});
  const std::size_t auto_index = methods.size() - 2;
  for (std::size_t m = 0; m < auto_index; ++m) {
    std::vector<double> mine, theirs;
    int method_only = 0, auto_only = 0;
    for (std::size_t k = 0; k < outcomes.size() / methods.size(); ++k) {  // the scenes run
      const Outcome& a = outcomes[k * methods.size() + m];
      const Outcome& b = outcomes[k * methods.size() + auto_index];
      if (a.valid && b.valid) {
        mine.push_back(a.error);
        theirs.push_back(b.error);
      }
      method_only += a.valid && !b.valid ? 1 : 0;
      auto_only += b.valid && !a.valid ? 1 : 0;
    }
    common.row()
        .set("method", methods[m])
        .set("common", static_cast<int>(mine.size()))
        .set("method_median_error_deg", quantile(mine, 0.5))
        .set("auto_median_error_deg", quantile(theirs, 0.5))
        .set("method_only", method_only)
        .set("auto_only", auto_only);
  }
  rows.write((std::filesystem::path(o.out_dir) / "calibration.csv").string());
  std::filesystem::remove(partial);
  summary.write((std::filesystem::path(o.out_dir) / "calibration_summary.csv").string());
  by_sky.write((std::filesystem::path(o.out_dir) / "calibration_by_sky.csv").string());
  common.write((std::filesystem::path(o.out_dir) / "calibration_auto.csv").string());
}

}  // namespace skypol::studies::tradeoff
