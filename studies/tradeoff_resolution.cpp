// Study 2: resolution. The paper's day (06:00–17:00 UTC, hourly: 12 frames) rendered at
// b×b binning of the paper's sensor, noise-free and through the sensor at its default exposure
// (larger binned pixels collect more light: studies/tradeoff_setup.h), three camera headings; every
// estimator's error and time per stack.
#include <filesystem>

#include "studies/tradeoff_scoring.h"
#include "studies/tradeoff_setup.h"
#include "studies/tradeoff_studies.h"

namespace skypol::studies::tradeoff {

void study_resolution(const StudyOptions& o) {
  const std::vector<int> binnings = o.small ? std::vector<int>{16} : std::vector<int>{16, 8, 4, 2, 1};
  const std::vector<double> headings = o.small ? std::vector<double>{15} : std::vector<double>{15, 140, 260};
  const std::vector<sky::Instant> times =
      o.small ? times_over("2022-09-23T12:00:00Z", 480, 5) : times_over("2022-09-23T11:30:00Z", 660, 12);
  Table t(with_score_columns({"binning", "width", "height", "frames", "noise", "heading_deg", "render_s", "is_default"}));
  int seed = 1;
  for (const int b : binnings) {
    for (const bool noisy : {false, true}) {
      for (const double heading : headings) {
        StackRecipe r;
        r.binning = b;
        r.heading_deg = heading;
        r.times = times;
        r.sky.max_dolp = 0.7;
        if (noisy) r.sensor = paper_sensor(b, 1000, static_cast<std::uint64_t>(seed++));
        stack::Stack stack;
        const double render_s = best_seconds(1, [&] { stack = render_stack(r); });
        score_every_method(stack, t, [&](Table& row) {
          row.set("binning", b)
              .set("width", stack.camera->width())
              .set("height", stack.camera->height())
              .set("frames", static_cast<int>(times.size()))
              .set("noise", noisy ? "sensor_1ms" : "none")
              .set("heading_deg", heading)
              .set("render_s", render_s)
              .set("is_default", b == 1);
        });
      }
    }
  }
  t.write((std::filesystem::path(o.out_dir) / "resolution.csv").string());
}

}  // namespace skypol::studies::tradeoff
