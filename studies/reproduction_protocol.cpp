// The Fig. 3 heading sweep and the observation-window sweep (reproduction_protocol.h).
#include "studies/reproduction_protocol.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "skypole/evaluate.h"

namespace skypol::studies {
namespace {

std::string num(double v) {
  if (!std::isfinite(v)) return "";
  std::ostringstream os;
  os << std::setprecision(8) << v;
  return os.str();
}


stack::Stack first_frames(const stack::Stack& s, int k) {
  stack::Stack p;
  p.camera = s.camera;
  p.bands = s.bands;
  p.frames.assign(s.frames.begin(), s.frames.begin() + k);
  return p;
}

double span_min(const stack::Stack& s) {
  return (s.frames.back().truth.time.unix_seconds - s.frames.front().truth.time.unix_seconds) / 60.0;
}

// Each method once; auto (and its site-free row) from the answers already computed.
void run_methods(const ProtocolSpec& spec, const stack::Stack& stack, const std::string& run,
                 bool sensor, double heading, std::vector<ProtocolRow>& rows) {
  std::vector<std::string> names = spec.methods;
  if (spec.auto_site_free) names.push_back(skypole::kAutoSiteFree);
  skypole::InputOptions site_free;
  site_free.use_site = false;
  // The stack's exposures, the same for every method's row.
  ProtocolRow first;
  for (const stack::Frame& f : stack.frames)
    if (sensor && f.exposure_us) {
      first.exposure_min_us = first.exposure_min_us > 0 ? std::min(first.exposure_min_us, *f.exposure_us) : *f.exposure_us;
      first.exposure_max_us = std::max(first.exposure_max_us, *f.exposure_us);
    }
  std::vector<skypole::PoleEstimate> done;
  for (const std::string& m : names) {
    ProtocolRow r = first;
    r.run = run;
    r.sensor = sensor;
    r.window_min = span_min(stack);
    r.frames = static_cast<int>(stack.frames.size());
    r.heading_deg = heading;
    r.estimate = m == skypole::kAutoSiteFree ? skypole::combine_estimates(stack, site_free, done)
                                             : skypole::run_or_combine(stack, m, {}, done);
    r.estimate.method = m;
    done.push_back(r.estimate);
    if (r.estimate.valid) r.score = skypole::score(r.estimate, stack.frames.front().truth);
    rows.push_back(std::move(r));
  }
}

}  // namespace

std::vector<ProtocolRow> run_protocol(
    const ProtocolSpec& spec, const std::function<void(std::size_t, std::size_t)>& progress) {
  for (int k : spec.window_frames)
    if (k < 3 || k > static_cast<int>(spec.window_times.size()))
      throw std::invalid_argument("run_protocol: window of " + std::to_string(k) +
                                  " frames (need 3 to " +
                                  std::to_string(spec.window_times.size()) + ")");
  std::vector<ProtocolRow> rows;
  for (std::size_t h = 0; h < spec.headings_deg.size(); ++h) {
    render::RecordingSetup setup = spec.setup;
    setup.heading_deg = spec.headings_deg[h];
    camera::DofpSensor sensor = spec.sensor;
    sensor.seed = spec.seed + h;
    if (!spec.day_times.empty()) {
      const stack::Stack ideal = render::record_stack(setup, spec.day_times);
      run_methods(spec, ideal, "day", false, setup.heading_deg, rows);
      run_methods(spec, render::through_sensor(ideal, sensor, spec.auto_exposure), "day", true, setup.heading_deg, rows);
    }
    if (!spec.window_frames.empty()) {
      // A different seed from the day's: the window's frames are other exposures.
      sensor.seed = spec.seed + 1000 + h;
      const stack::Stack noisy =
          render::through_sensor(render::record_stack(setup, spec.window_times), sensor, spec.auto_exposure);
      for (int k : spec.window_frames)
        run_methods(spec, first_frames(noisy, k), "window", true, setup.heading_deg, rows);
    }
    if (progress) progress(h + 1, spec.headings_deg.size());
  }
  return rows;
}

std::string protocol_csv(const std::vector<ProtocolRow>& rows) {
  std::ostringstream os;
  os << "run,sensor,window_min,frames,heading_deg,method,valid,why_invalid,bearing_error_deg,"
        "latitude_error_deg,angular_error_deg,residual_deg,seconds,exposure_min_us,exposure_max_us\n";
  for (const ProtocolRow& r : rows) {
    const bool ok = r.estimate.valid && r.score.has_value();
    os << r.run << ',' << (r.sensor ? 1 : 0) << ',' << num(r.window_min) << ',' << r.frames << ','
       << num(r.heading_deg) << ',' << r.estimate.method << ',' << (ok ? 1 : 0) << ','
       << skypole::csv_field(r.estimate.why_invalid) << ',';
    if (ok) {
      os << (r.score->bearing_error_deg ? num(*r.score->bearing_error_deg) : "") << ','
         << num(r.score->latitude_error_deg) << ',' << num(r.score->angular_error_deg) << ','
         << num(r.estimate.residual_deg);
    } else {
      os << ",,,";
    }
    os << ',' << num(r.estimate.seconds) << ',' << (r.exposure_max_us > 0 ? num(r.exposure_min_us) : "") << ','
       << (r.exposure_max_us > 0 ? num(r.exposure_max_us) : "") << '\n';
  }
  return os.str();
}

}  // namespace skypol::studies
