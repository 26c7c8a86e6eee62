#include "studies/benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <thread>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <Imath/half.h>
#include <tbb/info.h>

#include "render/pipeline.h"
#include "render/renderer.h"
#include "stack/stack_io.h"
#include "scene/truth.h"

#ifndef SKYPOL_BUILD_TYPE
#define SKYPOL_BUILD_TYPE "unknown"
#endif

namespace skypol::studies {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// OpenEXR by itself: one single-part file with the same channels, pixel type and compression.
// zip_level > 0 sets zip's deflate level (OpenEXR's default otherwise).
double openexr_write_ms(const stack::Frame& f, const std::vector<std::string>& channels, const stack::WriteOptions& o,
                        const std::string& path, int zip_level = 0) {
  const auto t0 = Clock::now();
  Imf::Header h(f.width, f.height);
  h.compression() = o.compression == "none" ? Imf::NO_COMPRESSION
                    : o.compression == "piz" ? Imf::PIZ_COMPRESSION
                    : o.compression == "zips" ? Imf::ZIPS_COMPRESSION
                                               : Imf::ZIP_COMPRESSION;
  if (zip_level > 0) h.zipCompressionLevel() = zip_level;
  std::vector<std::vector<Imath::half>> halves;
  Imf::FrameBuffer fb;
  for (const std::string& c : channels) {
    const bool half = o.half && c != "mask";
    h.channels().insert(c, Imf::Channel(half ? Imf::HALF : Imf::FLOAT));
    const std::vector<float>& data = f.channel(c);
    if (half) {
      halves.emplace_back(data.begin(), data.end());
      fb.insert(c, Imf::Slice(Imf::HALF, reinterpret_cast<char*>(halves.back().data()), sizeof(Imath::half),
                              sizeof(Imath::half) * static_cast<std::size_t>(f.width)));
    } else {
      fb.insert(c, Imf::Slice(Imf::FLOAT, const_cast<char*>(reinterpret_cast<const char*>(data.data())), sizeof(float),
                              sizeof(float) * static_cast<std::size_t>(f.width)));
    }
  }
  Imf::OutputFile file(path.c_str(), h);
  file.setFrameBuffer(fb);
  file.writePixels(f.height);
  return ms_since(t0);
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("model name", 0) == 0) {
      const std::size_t colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(" \t", colon + 1));
    }
  }
  return "unknown";
}

double load_average() {
  std::ifstream in("/proc/loadavg");
  double one = -1;
  return in >> one ? one : -1;
}

// Mean and best of a series of measurements (on a shared machine others' load only adds time).
struct Timing {
  double sum = 0, best = 0;
  int count = 0;
  double add(double ms) {
    best = count == 0 ? ms : std::min(best, ms);
    sum += ms;
    ++count;
    return ms;
  }
  double mean() const { return count ? sum / count : 0; }
};

}  // namespace

BenchContext bench_context() {
  BenchContext c;
  c.cpu = cpu_model();
  c.hardware_threads = static_cast<int>(std::thread::hardware_concurrency());
  c.tbb_threads = tbb::info::default_concurrency();
  c.build_type = SKYPOL_BUILD_TYPE;
#if defined(__clang__)
  c.compiler = std::string("Clang ") + __clang_version__;
#elif defined(__GNUC__)
  c.compiler = std::string("GCC ") + __VERSION__;
#else
  c.compiler = "unknown";
#endif
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  c.date_utc = date;
  c.load_average = load_average();
  return c;
}

BenchFigures bench_render(const scene::Scene& scene_in, int frames, const std::string& scratch_dir, bool render_only,
                          const std::vector<int>& zip_levels) {
  namespace fs = std::filesystem;
  fs::create_directories(scratch_dir);
  scene::Scene scene = scene_in;
  if (static_cast<int>(scene.times.size()) > frames) scene.times.resize(static_cast<std::size_t>(frames));
  BenchFigures b;
  b.context = bench_context();
  b.spp = scene.render.spp;
  b.frames = frames;
  b.compression = scene.output.compression;
  b.half = scene.output.half;
  stack::use_all_cores_for_exr();  // OpenEXR alone and skypol's writer use the same thread pool

  auto cam = scene::build_camera(scene.camera);
  b.width = cam->width();
  b.height = cam->height();
  // One model per band (a vrte scene's tables solved into the scratch folder, never the user's cache).
  const sky::BandSkies skies = scene::build_band_skies(scene, fs::path(scratch_dir) / "tables");
  std::vector<const sky::SkyModel*> models;
  for (const auto& m : skies.skies) models.push_back(m.get());
  render::RenderOptions ro;
  ro.spp = scene.render.spp;
  ro.seed = scene.render.seed;
  ro.bands = scene.render.bands;
  ro.channels = scene.output.channels;
  auto t0 = Clock::now();
  const render::Renderer renderer(cam, ro);
  b.ray_setup_ms = ms_since(t0);
  t0 = Clock::now();
  stack::Frame f = renderer.new_frame();
  b.frame_alloc_ms = ms_since(t0);

  b.channels = render::channel_names(ro);
  for (const std::string& c : b.channels) b.mb_per_frame += static_cast<double>(f.channel(c).size() * sizeof(float)) / 1e6;
  stack::WriteOptions wo;
  wo.half = scene.output.half;
  wo.compression = scene.output.compression;
  wo.zip_level = scene.output.zip_level;
  stack::StackHeader header;
  header.bands = ro.bands;
  header.camera_description = scene.camera.description;
  header.scene_text = scene.text;
  header.sky_model = models.front()->name();
  // Each round renders one frame, writes it with OpenEXR alone, then with skypol's writer: the
  // three measurements of a round are seconds apart, so a round's ratio sees the same load.
  Timing render, exr, skypol, round;
  for (int i = 0; i < frames; ++i) {
    const scene::Truth truth = scene::make_truth(scene, *cam, scene.times[static_cast<std::size_t>(i) % scene.times.size()]);
    t0 = Clock::now();
    renderer.render(models, truth.sun, f);
    const double render_ms = render.add(ms_since(t0));
    if (render_only) continue;
    f.truth = truth;
    exr.add(openexr_write_ms(f, b.channels, wo, (fs::path(scratch_dir) / "openexr.exr").string()));
    t0 = Clock::now();
    stack::write_stack_reusing((fs::path(scratch_dir) / "skypol.exr").string(), {truth}, b.channels, f.width, f.height, header,
                        wo, [&](std::size_t) -> const stack::Frame& { return f; });
    round.add(render_ms + skypol.add(ms_since(t0)));
  }
  const double mpix = static_cast<double>(b.width) * b.height / 1e6;
  b.frame_render_ms = render.mean();
  b.frame_render_best_ms = render.best;
  b.sky_mpix_per_s = mpix / b.frame_render_ms * 1e3;
  b.sky_mpix_per_s_best = mpix / render.best * 1e3;
  b.openexr_write_ms = exr.mean();
  b.openexr_write_best_ms = exr.best;
  b.skypol_write_ms = skypol.mean();
  b.skypol_write_best_ms = skypol.best;
  b.render_and_write_best_ms = round.best;
  {
    // What a caller of the frame-returning render() pays: a new frame's memory every time.
    const scene::Truth truth = scene::make_truth(scene, *cam, scene.times.front());
    t0 = Clock::now();
    const stack::Frame fresh = renderer.render(models, truth.sun);
    b.fresh_frame_render_ms = ms_since(t0);
  }

  if (!render_only) {
    // Zip levels, on the last frame rendered, each the best of three writes.
    stack::WriteOptions zip = wo;
    zip.compression = "zip";
    const std::string zpath = (fs::path(scratch_dir) / "zip-level.exr").string();
    for (int level : zip_levels) {
      Timing t;
      for (int k = 0; k < 3; ++k) t.add(openexr_write_ms(f, b.channels, zip, zpath, level));
      b.zip_levels.push_back({level, t.best, static_cast<double>(fs::file_size(zpath)) / 1e6});
    }
    // Wall time less the once-per-stack set-up: what a user waits for per frame, whatever
    // render_scene overlaps inside (stack::write_stack_overlapped, for uncompressed stacks).
    t0 = Clock::now();
    const render::RenderReport r =
        render::render_scene(scene, (fs::path(scratch_dir) / "stack.exr").string(), {}, fs::path(scratch_dir) / "tables");
    b.end_to_end_ms = (ms_since(t0) - 1e3 * r.setup_seconds) / static_cast<double>(scene.times.size());
  }
  fs::remove_all(scratch_dir);
  return b;
}

}  // namespace skypol::studies
