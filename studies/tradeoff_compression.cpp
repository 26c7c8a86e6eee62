// Study 9: what a stack's pixel type and compression cost and lose. The paper's day (06:00–17:00
// UTC every 30 min, 23 frames) at b×b binning (default 8: 306×256), at two of the Fig. 3
// protocol's headings (0° and 90°), as two stacks: the ideal Stokes stack the default scene
// writes (S0 S1 S2 DoLP AoLP mask) and the DoFP sensor's stack (DoLP AoLP mask, 1 ms exposure:
// studies/tradeoff_setup.h). Each is written with every pixel type × compression (zip at several
// deflate levels) through stack::write_stack, read back with stack::read_stack, and compared with
// the in-memory floats, which is what float + none stores. Two tables:
//   compression.csv            per setting and stack: file size, write and read time (the mean
//                              over headings), max and RMS error of each channel over the sky
//                              pixels (AoLP in degrees), and `exact`: every pixel decoded equals the
//                              in-memory value rounded to the pixel type (the half clamp included),
//                              i.e. the compression itself lost nothing
//   compression_estimates.csv  per decoded stack, heading and method: the estimator's error on the
//                              stack read back (tradeoff_scoring.h). Every exact setting of a pixel
//                              type decodes to the same pixels, so they share one set of rows with
//                              compression "lossless" (float lossless is the in-memory stack, the
//                              reference); each lossy setting has its own.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>

#include <Imath/half.h>
#include <OpenEXR/ImfHeader.h>

#include "render/recorded_stack.h"
#include "scene/scene.h"
#include "sky/units.h"
#include "stack/stack_io.h"
#include "studies/tradeoff_scoring.h"
#include "studies/tradeoff_setup.h"
#include "studies/tradeoff_studies.h"

namespace skypol::studies::tradeoff {
namespace {

namespace fs = std::filesystem;

struct Setting {
  bool half;
  std::string compression;
  int zip_level;  // 0: OpenEXR's default
};

std::vector<Setting> settings(bool small) {
  std::vector<Setting> out;
  for (const bool half : {false, true}) {
    if (small) {  // one lossy setting per pixel type, and a zip level
      for (const char* c : {"none", "zip", half ? "b44" : "pxr24"}) out.push_back({half, c, 0});
      if (half) out.push_back({half, "zip", 9});
      continue;
    }
    for (const char* c : {"none", "rle", "zips", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"})
      out.push_back({half, c, 0});
    for (const int level : {1, 4, 6, 9}) out.push_back({half, "zip", level});
  }
  return out;
}

// The camera of the paper's set-up at b×b binning as scene text: a stack's header stores its
// camera that way, and read_stack rebuilds the camera from it.
scene::Scene paper_scene(int b, double heading_deg) {
  char text[512];
  std::snprintf(text, sizeof text,
                "[site]\nlatitude_deg = %.6f\nlongitude_deg = %.6f\n[time]\ninstants = [\"2022-09-23T12:00:00Z\"]\n"
                "[camera]\nmodel = \"equidistant\"\nfocal_mm = 1.8\npitch_um = %g\nwidth = %d\nheight = %d\n"
                "fov_deg = 185\nheading_deg = %g\n",
                paper_site().latitude_deg, paper_site().longitude_deg, 3.45 * b, 2448 / b, 2048 / b, heading_deg);
  return scene::parse_scene(text, "tradeoff-compression");
}

// The value a lossless encoding of `pixel type` gives back: the float itself, or the half the
// writer makes of it (clamped to ±65504, stack_io.h).
float stored(float v, bool half) {
  if (!half) return v;
  return static_cast<float>(Imath::half(std::clamp(v, -65504.0f, 65504.0f)));
}

struct ChannelError {
  double max = 0, ss = 0;
  long long n = 0;
  bool exact = true;
};

// Differences over the sky pixels (mask > 0); AoLP's (stored in radians, docs/conventions.md)
// modulo 180°, in degrees.
void compare(const stack::Stack& mem, const stack::Stack& back, const std::string& ch, bool half, bool stays_float,
             ChannelError& e) {
  const bool angle = ch.rfind("AoLP", 0) == 0;
  for (std::size_t f = 0; f < mem.frames.size(); ++f) {
    const auto& a = mem.frames[f].channel(ch);
    const auto& b = back.frames[f].channel(ch);
    const auto& mask = mem.frames[f].channel("mask");
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (b[i] != stored(a[i], half && !stays_float)) e.exact = false;
      if (mask[i] <= 0) continue;
      double d = std::abs(static_cast<double>(b[i]) - static_cast<double>(a[i]));
      if (angle) d = deg_from_rad(std::min(d, std::numbers::pi - std::fmod(d, std::numbers::pi)));
      if (!std::isfinite(d)) d = HUGE_VAL;
      e.max = std::max(e.max, d);
      e.ss += d * d;
      ++e.n;
    }
  }
}

std::vector<std::string> table_columns() {
  std::vector<std::string> c = {"pixel_type", "compression", "zip_level", "stack", "width", "height", "frames",
                                "headings", "channels", "raw_mb", "file_mb", "ratio", "write_s", "read_s",
                                "write_mb_s", "read_mb_s", "exact"};
  for (const char* ch : {"S0", "S1", "S2", "DoLP", "AoLP_deg"}) {
    c.push_back(std::string(ch) + "_max");
    c.push_back(std::string(ch) + "_rms");
  }
  return c;
}

}  // namespace

void study_compression(const StudyOptions& o) {
  // The estimators dominate the cost (great_circle and auto most): the sizes keep a full run
  // near 20 minutes on the shared 2-core machine, and --small to seconds.
  const int b = o.binning > 0 ? o.binning : (o.small ? 16 : 8);
  const std::vector<double> headings = o.small ? std::vector<double>{0} : std::vector<double>{0, 90};
  const std::vector<sky::Instant> times =
      o.small ? times_over("2022-09-23T11:30:00Z", 660, 5) : times_over("2022-09-23T11:30:00Z", 660, 23);
  const int default_zip_level = Imf::Header().zipCompressionLevel();
  const std::vector<Setting> all = settings(o.small);
  const fs::path scratch = fs::path(o.out_dir) / "compression-scratch";
  fs::create_directories(scratch);
  const std::string path = (scratch / "stack.exr").string();

  struct Sum {
    double write_s = 0, read_s = 0, file_mb = 0, raw_mb = 0;
    std::map<std::string, ChannelError> errors;
    bool exact = true;
  };
  // Per setting, per stack kind ("ideal", "sensor").
  std::vector<std::map<std::string, Sum>> sums(all.size());
  Table est(with_score_columns({"pixel_type", "compression", "zip_level", "stack", "heading_deg", "width", "height",
                                "frames"}));

  int seed = 1;
  for (const double heading : headings) {
    const scene::Scene sc = paper_scene(b, heading);
    render::RecordingSetup setup;
    setup.site = paper_site();
    setup.lens = scene::build_camera(sc.camera)->lens().rescaled(1.0);
    setup.heading_deg = heading;
    setup.sky.max_dolp = 0.7;
    stack::Stack ideal = render::record_stack(setup, times);
    ideal.camera_description = sc.camera.description;
    stack::Stack noisy = render::through_sensor(ideal, paper_sensor(b, 1000, static_cast<std::uint64_t>(seed++)));
    noisy.camera_description = sc.camera.description;
    const int w = ideal.camera->width(), h = ideal.camera->height();

    for (const auto& [kind, mem] : {std::pair<std::string, const stack::Stack*>{"ideal", &ideal},
                                    std::pair<std::string, const stack::Stack*>{"sensor", &noisy}}) {
      auto fill = [&, kind = kind](const std::string& type, const Setting* s) {
        return [&, kind, type, s](Table& row) {
          row.set("pixel_type", type).set("compression", s ? s->compression : "lossless").set("stack", kind)
              .set("heading_deg", heading).set("width", w).set("height", h)
              .set("frames", static_cast<int>(times.size()));
          if (s && s->compression.rfind("zip", 0) == 0)
            row.set("zip_level", s->zip_level ? s->zip_level : default_zip_level);
        };
      };
      bool scored_lossless[2] = {false, false};  // float, half
      const std::vector<std::string> channels =
          kind == "ideal" ? std::vector<std::string>{"S0.Y", "S1.Y", "S2.Y", "DoLP.Y", "AoLP.Y", "mask"}
                          : std::vector<std::string>{"DoLP.Y", "AoLP.Y", "mask"};
      std::vector<scene::Truth> truths;
      for (const stack::Frame& f : mem->frames) truths.push_back(f.truth);
      stack::StackHeader header;
      header.bands = {"Y"};
      header.camera_description = mem->camera_description;
      header.sky_model = "rayleigh";
      header.polarizer_angles = mem->frames.front().polarizer_angles;
      for (std::size_t k = 0; k < all.size(); ++k) {
        const Setting& s = all[k];
        stack::WriteOptions wo;
        wo.half = s.half;
        wo.compression = s.compression;
        wo.zip_level = s.zip_level;
        Sum& sum = sums[k][kind];
        sum.write_s += best_seconds(1, [&] {
          stack::write_stack(path, truths, channels, w, h, header, wo, [&](std::size_t i) {
            stack::Frame f;
            f.width = w;
            f.height = h;
            f.truth = mem->frames[i].truth;
            for (const std::string& c : channels) f.channels[c] = mem->frames[i].channel(c);
            return f;
          });
        });
        sum.file_mb += static_cast<double>(fs::file_size(path)) / 1e6;
        sum.raw_mb += static_cast<double>(w) * h * static_cast<double>(times.size() * channels.size()) * 4 / 1e6;
        stack::Stack back;
        sum.read_s += best_seconds(1, [&] { back = stack::read_stack(path); });
        for (const std::string& c : channels) {
          ChannelError& e = sum.errors[c];
          compare(*mem, back, c, s.half, c == "mask", e);
          sum.exact = sum.exact && e.exact;
        }
        // Exact so far (this heading and those before): decoded as every lossless setting decodes.
        if (!sum.exact) {
          score_every_method(back, est, fill(s.half ? "half" : "float", &s));
        } else if (!scored_lossless[s.half ? 1 : 0]) {
          score_every_method(back, est, fill(s.half ? "half" : "float", nullptr));
          scored_lossless[s.half ? 1 : 0] = true;
        }
        fs::remove(path);
      }
    }
    if (o.progress) std::fprintf(stderr, "compression: heading %g done\n", heading);
  }
  fs::remove_all(scratch);

  Table t(table_columns());
  const double n = static_cast<double>(headings.size());
  for (std::size_t k = 0; k < all.size(); ++k) {
    for (const auto& [kind, sum] : sums[k]) {
      const Setting& s = all[k];
      const int w = 2448 / b, h = 2048 / b;
      t.row().set("pixel_type", s.half ? "half" : "float").set("compression", s.compression).set("stack", kind)
          .set("width", w).set("height", h).set("frames", static_cast<int>(times.size()))
          .set("headings", static_cast<int>(headings.size()))
          .set("channels", static_cast<int>(sum.errors.size())).set("raw_mb", sum.raw_mb / n)
          .set("file_mb", sum.file_mb / n).set("ratio", sum.raw_mb / sum.file_mb).set("write_s", sum.write_s / n)
          .set("read_s", sum.read_s / n).set("write_mb_s", sum.raw_mb / sum.write_s)
          .set("read_mb_s", sum.raw_mb / sum.read_s).set("exact", sum.exact);
      if (s.compression.rfind("zip", 0) == 0) t.set("zip_level", s.zip_level ? s.zip_level : default_zip_level);
      for (const auto& [ch, e] : sum.errors) {
        if (ch == "mask") continue;
        std::string base = ch.substr(0, ch.find('.'));
        if (base == "AoLP") base = "AoLP_deg";
        t.set(base + "_max", e.max).set(base + "_rms", e.n ? std::sqrt(e.ss / static_cast<double>(e.n)) : 0.0);
      }
    }
  }
  t.write((fs::path(o.out_dir) / "compression.csv").string());
  est.write((fs::path(o.out_dir) / "compression_estimates.csv").string());
}

}  // namespace skypol::studies::tradeoff
