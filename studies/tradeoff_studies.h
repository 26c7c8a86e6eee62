// The studies behind docs/benchmarks.md: each varies one knob of the paper's set-up
// (studies/tradeoff_setup.h), measures accuracy against a reference or the truth and the time it
// costs, and writes CSV tables (studies/tradeoff_table.h) into a folder. scripts/benchmarks runs them
// all, plots them and writes the report; the columns of each table are listed in
// docs/benchmarks.md's "Data" section.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace skypol::studies::tradeoff {

struct StudyOptions {
  std::string out_dir;  // CSV files go here (created if missing)
  bool small = false;   // tiny images and few settings: proves the study runs, in seconds
  // Studies that draw random scenes (calibration): the seed and the number of scenes (0: the
  // study's default), and whether to report progress on stderr.
  std::uint64_t seed = 2;
  int count = 0;
  int binning = 0;      // calibration, compression: binning of the 2448×2048 sensor (0: the study's default)
  // calibration: the --max-uncertainty every method is run with (95 % cone, degrees; infinity:
  // none). 2.5°, i.e. σ ≤ 1.02°: then 5° is at least 4.9σ, so an answer the bound lets through is
  // more than 5° off less than once in 10⁵ if its σ is honest, and a lie (valid, > 5° off) is one
  // the method did not warn of. With a bound of 5° (σ up to 2.04°) an honest answer at the bound is
  // more than 5° off 5 % of the time, and such answers would count as lies that are not.
  double max_uncertainty_deg = 2.5;
  bool progress = false;
  // calibration: state the methods' σ without their calibration factors (to measure them).
  bool uncalibrated = false;
  // calibration: without the whole-sky cloud gate / without the per-pixel sky mask (before/after).
  bool no_cloud_gate = false;
  bool no_sky_mask = false;
  // calibration: run only these methods (and auto over them); empty: every method. To re-measure
  // one method after a change to it without running the others again.
  std::vector<std::string> methods;
  // calibration: run only these scenes of the seeded population (their indices, the CSV's `stack`
  // column; each in [0, count), else std::invalid_argument); empty: all. The scenes are the same as
  // in the whole run: every scene is still drawn, in order, and only these are rendered. To replay
  // the answers a run found wrong.
  std::vector<int> scenes;
  // calibration: the sensor's noise draw. 0: each scene's own (the seed's); k > 0: another draw of
  // the shot, read and dark noise for the same scenes (sky, cloud, camera, window and exposure
  // unchanged), so that a calibration can be checked on the noise replicates of its tuning scenes:
  // a few-group jackknife's σ is itself noisy, and one draw of a scene shows only one of its tails.
  int noise_draw = 0;
  // calibration: which population the scenes are drawn from (tradeoff_calibration.cpp, draw_scene):
  // "mixed", single scattering in most scenes and a few vrte atmospheres; "realistic", the physically
  // based sky in most scenes, its atmosphere drawn from a climatology; "mismatch", skies and sensors
  // outside the families the calibration was read off (custom aerosol modes and overridden OPAC
  // optics, other vrte streams and grids, other Berry neutral points, every camera tilted, sensors
  // with polarizer angle errors, extinction ratios, PRNU and DSNU), to check the cones where no
  // model holds exactly. Its scenes are reported apart from the population's.
  std::string population = "mixed";
};

struct Study {
  std::string name;     // what `skypol tradeoff NAME` runs
  std::string summary;  // one line for --help
  void (*run)(const StudyOptions&);
};

// In the order the report presents them.
const std::vector<Study>& studies();

// One per file (tradeoff_<name>.cpp). Each writes <out_dir>/<name>.csv.
void study_spp(const StudyOptions& o);            // samples per pixel → Stokes error vs ms/frame
void study_resolution(const StudyOptions& o);     // binning → estimator error vs time
void study_window(const StudyOptions& o);         // frames and observation window → error
void study_noise(const StudyOptions& o);          // exposure (sensor noise) → estimator error
void study_lens_inverse(const StudyOptions& o);   // Newton iterations → round-trip error vs time
void study_sky_precision(const StudyOptions& o);  // float vs double sky evaluation
void study_throughput(const StudyOptions& o);     // Mpix/s, MB/s, s/stack and their scaling
// calibration: random scenes → yield, lies, 95 % cone coverage (calibration.csv, one row per scene
// and method, and its summaries; while it runs, the rows so far in calibration.partial.csv, every
// 10 scenes, removed when the run ends).
void study_calibration(const StudyOptions& o);
// The calibration study's number of scenes for these options (--count, else 300; --small 6), and
// the check of --scenes against it (std::invalid_argument naming the first index it lacks): the
// command line checks before it creates the output folder.
int calibration_count(const StudyOptions& o);
void check_calibration_scenes(const StudyOptions& o);
void study_compression(const StudyOptions& o);    // pixel type × compression → size, time, error

}  // namespace skypol::studies::tradeoff
