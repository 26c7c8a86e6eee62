// The calibration study's parts (study_calibration, tradeoff_calibration.cpp): the populations and
// the scenes drawn from them, rendered (tradeoff_calibration_draw.cpp), and the summaries of the
// answers per method, per method and sky, and auto against each method
// (tradeoff_calibration_summary.cpp). Internal to studies/.
#pragma once

#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "sky/vrte/aerosol_types.h"
#include "sky/sun.h"
#include "stack/frame.h"
#include "studies/tradeoff_studies.h"

namespace skypol::studies::tradeoff::calibration {

// One scene of a population: where, when, how the camera looks, the sky and the sensor.
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
  // Outside the calibration's families (the mismatch population; Population::off_family): the
  // defaults below are the other populations' values, which they never draw.
  bool off_family = false;
  sky::AerosolSpec aerosol_optics;  // vrte: a custom mode's size and index, Ångström and ω overrides
  int streams = 12, grid = 25;      // vrte: the solver's Gauss nodes and table grid
  double separation_deg = 20;       // berry: the neutral points' distance from the sun
  std::string berry_normalisation = "split_rayleigh";
  std::array<double, 4> angle_error_deg{};  // the sensor's micro-polarizers, per mosaic position
  double extinction_ratio = 0;              // 0: the preset's
  double prnu_rms = 0, dsnu_e = 0;          // fixed-pattern noise, per binned pixel
};

// What a population draws from (StudyOptions::population). "mixed": sites within 70° of the
// equator, windows of 20 min to 11 h, Rayleigh in 45 % of the scenes and Berry in 25 %, the vrte
// sky in 30 % with one of 12 atmospheres (3 aerosols × τ(550) 0.05 or 0.3 × albedo 0.1 or 0.3,
// whose tables the disk cache keeps). "realistic": the physically based sky in most scenes, its
// atmosphere drawn from a climatology — every OPAC type, τ(550) log-uniform on 0.02–0.8 (73 % of
// the draws below 0.3, as sun photometer networks see clear-sky loads), ground albedo uniform on
// 0–0.35 — sites up to 80° from the equator and windows of 30 min to 12 h, and 60 % of its sensors
// auto-exposed, as a camera left to meter sets itself; its tables are solved per scene and not
// cached (each atmosphere is new). "mismatch": skies and sensors outside the families the
// calibration was read off (draw_off_family), so that a stated cone is checked where no method's
// model holds exactly: the realistic population's sites, windows, loads and meter, every camera
// tilted 3–15°, a sensor in every scene, and its own aerosols, solver settings, Berry skies and
// manufacturing errors.
struct Population {
  double max_abs_latitude_deg, min_window_min, max_window_min;
  double rayleigh_share, berry_share;  // the rest is vrte
  double no_sensor_share, mono_share;  // the rest is colour
  bool climatology;
  double auto_exposure_share;  // of the scenes with a sensor; 0: no draw (the mixed population's scenes stay as they were)
  double level_share = 0.4;    // cameras set level; the others tilt min_tilt_deg … 15°
  double min_tilt_deg = 0;
  bool off_family = false;     // draw_off_family's draws, after every other draw of the scene
};
// The population a --population name names; std::invalid_argument listing the legal names.
const Population& population_of(const std::string& name);

// One scene of the population; the sun stays ≥ 3° above the horizon in every frame.
Draw draw_scene(std::mt19937_64& rng, int index, const Population& pop);

// The scene's frames at this binning, through its sensor (if any) with noise draw noise_draw
// (StudyOptions::noise_draw); S1 and S2 dropped.
stack::Stack render_draw(const Draw& d, int binning, int noise_draw, const Population& pop);

// One answer of one method on one scene, as the summaries read it.
struct Outcome {
  std::size_t method = 0;
  int stack = 0;
  std::string sky;
  bool valid = false, inside = false, lie = false;
  double error = 0, ratio = 0;  // angular error; error / cone95
};

// calibration_summary.csv (per method), calibration_by_sky.csv (per method and sky model) and
// calibration_auto.csv (auto against each method on the scenes both answer) in o.out_dir, from the
// outcomes of every scene run, method by method in the order of `methods` (auto and auto_site_free
// last).
void write_summaries(const std::vector<Outcome>& outcomes, const std::vector<std::string>& methods,
                     const StudyOptions& o, int binning);

}  // namespace skypol::studies::tradeoff::calibration
