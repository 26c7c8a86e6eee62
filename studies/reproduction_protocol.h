// The SkyPole paper's Fig. 3 protocol in simulation: one zenith camera whose azimuth (heading) is
// stepped over a list (the paper: 0° to 170° in 10° steps), the estimators run on each heading's
// stack and scored against the truth, without and with a DoFP sensor; and, on a second list of
// times, the same over growing observation windows (the first k frames), to find how short a
// window each estimator needs. Rows only: statistics, tables and figures are the report's job
// (scripts/reproduce). Each heading's stacks are rendered once and shared by every method and
// window; the sensor's noise seed is seed + heading index, so rows are reproducible.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "camera/dofp_sensor.h"
#include "render/recorded_stack.h"
#include "skypole/estimate.h"

namespace skypol::studies {

struct ProtocolSpec {
  render::RecordingSetup setup;              // heading is overridden per row
  std::vector<double> headings_deg;
  std::vector<std::string> methods;          // evaluate.h names ("auto" combines the others' answers)
  // Also auto with the site withheld, as skypole::kAutoSiteFree rows (after the methods').
  bool auto_site_free = false;
  std::vector<sky::Instant> day_times;       // the day: run noise-free and through the sensor
  std::vector<sky::Instant> window_times;    // windows: prefixes, through the sensor only
  std::vector<int> window_frames;            // prefix lengths (each ≥ 3, ≤ window_times.size())
  camera::DofpSensor sensor;                 // width/height taken from the lens
  // Each sensor frame metered instead of taken at sensor.exposure_us (render::through_sensor).
  std::optional<camera::AutoExposure> auto_exposure;
  std::uint64_t seed = 1;
};

struct ProtocolRow {
  std::string run;          // "day" or "window"
  bool sensor = false;      // through the DoFP sensor (noise) or ideal Stokes
  double window_min = 0;    // last frame time − first frame time
  int frames = 0;
  double heading_deg = 0;
  double exposure_min_us = 0, exposure_max_us = 0;  // through the sensor: its frames' exposures (0: none)
  skypole::PoleEstimate estimate;
  std::optional<skypole::Score> score;  // nullopt for an invalid estimate
};

// progress(done, total) after each heading (may be empty).
std::vector<ProtocolRow> run_protocol(
    const ProtocolSpec& spec, const std::function<void(std::size_t, std::size_t)>& progress = {});

// Columns: run,sensor,window_min,frames,heading_deg,method,valid,why_invalid,bearing_error_deg,
// latitude_error_deg,angular_error_deg,residual_deg,seconds,exposure_min_us,exposure_max_us. Undefined
// values (and the exposures of a noise-free run) are empty fields.
std::string protocol_csv(const std::vector<ProtocolRow>& rows);

}  // namespace skypol::studies
