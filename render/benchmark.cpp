#include "render/benchmark.h"

#include <chrono>
#include <filesystem>
#include <thread>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <Imath/half.h>
#include <tbb/info.h>

#include "render/pipeline.h"
#include "render/renderer.h"
#include "render/stack_io.h"
#include "render/truth.h"

namespace skypol::render {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// OpenEXR by itself: one single-part file with the same channels, pixel type and compression.
double openexr_write_seconds(const Frame& f, const std::vector<std::string>& channels, const WriteOptions& o,
                             const std::string& path) {
  const auto t0 = Clock::now();
  Imf::Header h(f.width, f.height);
  h.compression() = o.compression == "none" ? Imf::NO_COMPRESSION
                    : o.compression == "piz" ? Imf::PIZ_COMPRESSION
                    : o.compression == "zips" ? Imf::ZIPS_COMPRESSION
                                               : Imf::ZIP_COMPRESSION;
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
  return since(t0);
}

}  // namespace

BenchFigures bench_render(const Scene& scene_in, int frames, const std::string& scratch_dir) {
  namespace fs = std::filesystem;
  fs::create_directories(scratch_dir);
  Scene scene = scene_in;
  if (static_cast<int>(scene.times.size()) > frames) scene.times.resize(static_cast<std::size_t>(frames));
  BenchFigures b;
  b.spp = scene.render.spp;
  b.frames = static_cast<int>(scene.times.size());
  b.threads = tbb::info::default_concurrency();

  auto cam = build_camera(scene.camera);
  b.width = cam->width();
  b.height = cam->height();
  auto sky_model = build_sky(scene.sky);
  RenderOptions ro;
  ro.spp = scene.render.spp;
  ro.seed = scene.render.seed;
  ro.bands = scene.render.bands;
  ro.channels = scene.output.channels;
  auto t0 = Clock::now();
  const Renderer renderer(cam, ro);
  b.ray_setup_s = since(t0);

  const std::vector<std::string> channels = channel_names(ro);
  WriteOptions wo;
  wo.half = scene.output.half;
  wo.compression = scene.output.compression;
  double render_s = 0, exr_s = 0, skypol_s = 0;
  for (std::size_t i = 0; i < scene.times.size(); ++i) {
    const Truth truth = make_truth(scene, *cam, scene.times[i]);
    t0 = Clock::now();
    Frame f = renderer.render(*sky_model, truth.sun);
    render_s += since(t0);
    f.truth = truth;
    b.mb_per_frame = 0;
    for (const std::string& c : channels) b.mb_per_frame += static_cast<double>(f.channel(c).size() * sizeof(float)) / 1e6;
    exr_s += openexr_write_seconds(f, channels, wo, (fs::path(scratch_dir) / "openexr.exr").string());
    t0 = Clock::now();
    StackHeader header;
    header.bands = ro.bands;
    header.camera_description = scene.camera.description;
    header.scene_text = scene.text;
    header.sky_model = sky_model->name();
    write_stack((fs::path(scratch_dir) / "skypol.exr").string(), {truth}, channels, f.width, f.height, header, wo,
                [&](std::size_t) { return f; });
    skypol_s += since(t0);
  }
  const double n = static_cast<double>(scene.times.size());
  b.frame_render_ms = 1e3 * render_s / n;
  b.sky_mpix_per_s = static_cast<double>(b.width) * b.height * n / render_s / 1e6;
  b.openexr_write_ms = 1e3 * exr_s / n;
  b.skypol_write_ms = 1e3 * skypol_s / n;

  t0 = Clock::now();
  const RenderReport r = render_scene(scene, (fs::path(scratch_dir) / "stack.exr").string());
  b.end_to_end_ms = 1e3 * (r.render_seconds + r.write_seconds) / n;
  fs::remove_all(scratch_dir);
  return b;
}

}  // namespace skypol::render
