// Study 3: how long the sky must be watched. Windows from 20 min to 8 h centred on 11:30 UTC
// (about solar noon in Marseille on the paper's day), each with 3 to 17 frames spread evenly over
// it, plus the paper's own day (06:00–17:00 every 30 min: 660 min, 23 frames, the default), through
// the sensor at its default exposure, three headings; every estimator's error.
#include <filesystem>

#include "studies/tradeoff_scoring.h"
#include "studies/tradeoff_setup.h"
#include "studies/tradeoff_studies.h"

namespace skypol::studies::tradeoff {

void study_window(const StudyOptions& o) {
  const int b = o.small ? 16 : 8;
  const std::vector<double> windows =
      o.small ? std::vector<double>{60, 480} : std::vector<double>{20, 40, 60, 120, 240, 480};
  const std::vector<int> counts = o.small ? std::vector<int>{5} : std::vector<int>{3, 5, 9, 17};
  const std::vector<double> headings = o.small ? std::vector<double>{15} : std::vector<double>{15, 140, 260};
  struct Setting {
    double window_min;
    int frames;
  };
  std::vector<Setting> settings;
  for (const double w : windows)
    for (const int n : counts) settings.push_back({w, n});
  const Setting paper = o.small ? Setting{480, 5} : Setting{660, 23};
  if (!o.small) settings.push_back(paper);
  Table t(with_score_columns({"window_min", "frames", "step_min", "binning", "width", "height", "heading_deg",
                              "is_default"}));
  int seed = 1;
  for (const auto [w, n] : settings) {
    for (const double heading : headings) {
      StackRecipe r;
      r.binning = b;
      r.heading_deg = heading;
      r.times = times_over("2022-09-23T11:30:00Z", w, n);
      r.sky.max_dolp = 0.7;
      r.sensor = paper_sensor(b, 1000, static_cast<std::uint64_t>(seed++));
      const stack::Stack stack = render_stack(r);
      score_every_method(stack, t, [&](Table& row) {
        row.set("window_min", w)
            .set("frames", n)
            .set("step_min", w / (n - 1))
            .set("binning", b)
            .set("width", stack.camera->width())
            .set("height", stack.camera->height())
            .set("heading_deg", heading)
            .set("is_default", w == paper.window_min && n == paper.frames);
      });
    }
  }
  t.write((std::filesystem::path(o.out_dir) / "window.csv").string());
}

}  // namespace skypol::studies::tradeoff
