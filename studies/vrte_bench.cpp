#include "studies/vrte_bench.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <thread>

#include "render/pipeline.h"
#include "render/renderer.h"
#include "scene/truth.h"
#include "sky/sky_spec.h"

namespace skypol::studies {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

struct RenderTimes {
  double mean_ms = 0, best_ms = 0, cpu_ms = 0;
};

// Mean and best sky-render wall time per frame of `skies` over the scene's first frames, and the
// mean CPU time (all threads).
RenderTimes render_ms(const scene::Scene& s, const sky::BandSkies& skies, int frames) {
  auto cam = scene::build_camera(s.camera);
  render::RenderOptions ro;
  ro.spp = s.render.spp;
  ro.seed = s.render.seed;
  ro.bands = s.render.bands;
  ro.channels = s.output.channels;
  const render::Renderer renderer(cam, ro);
  stack::Frame f = renderer.new_frame();
  std::vector<const sky::SkyModel*> models;
  for (const auto& m : skies.skies) models.push_back(m.get());
  double sum = 0, best = 0, cpu = 0;
  for (int i = 0; i < frames; ++i) {
    const scene::Truth truth = scene::make_truth(s, *cam, s.times[static_cast<std::size_t>(i) % s.times.size()]);
    const std::clock_t c0 = std::clock();
    const auto t0 = Clock::now();
    renderer.render(models, truth.sun, f);
    const double ms = ms_since(t0);
    cpu += 1e3 * static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    sum += ms;
    best = i == 0 ? ms : std::min(best, ms);
  }
  return {sum / frames, best, cpu / frames};
}

}  // namespace

VrteBenchFigures bench_vrte(const scene::Scene& scene_in, int frames, const std::string& scratch_dir,
                            const std::vector<int>& streams_sweep) {
  namespace fs = std::filesystem;
  const fs::path scratch = fs::path(scratch_dir) / "vrte-bench";
  const fs::path cache = scratch / "tables";
  fs::remove_all(scratch);
  fs::create_directories(scratch);
  scene::Scene vrte = scene_in;
  if (static_cast<int>(vrte.times.size()) > frames) vrte.times.resize(static_cast<std::size_t>(frames));
  if (vrte.sky.model != "vrte") {
    const sky::SkySpec defaults;
    vrte.sky = defaults;
    vrte.sky.model = "vrte";
  }
  scene::Scene single = vrte;
  single.sky = sky::SkySpec{};  // rayleigh, Pmax 1: the single-scattering sky

  VrteBenchFigures b;
  b.bands = vrte.render.bands;
  b.wavelengths_nm = sky::band_wavelengths_nm(vrte.sky, vrte.render.bands);
  b.aerosol = vrte.sky.aerosol.type;
  b.tau_550 = vrte.sky.aerosol.tau_550;
  b.streams = vrte.sky.streams;
  b.grid = vrte.sky.grid;
  b.solver_threads = static_cast<int>(std::thread::hardware_concurrency());
  b.frames = frames;
  const sky::BandSkies cold = scene::build_band_skies(vrte, cache);
  b.cold_build_s = cold.build_seconds;
  const sky::BandSkies warm = scene::build_band_skies(vrte, cache);
  b.warm_read_s = warm.build_seconds;

  const sky::BandSkies grey = scene::build_band_skies(single, {});
  const RenderTimes st = render_ms(single, grey, frames), vt = render_ms(vrte, warm, frames);
  b.single_render_ms = st.mean_ms, b.single_render_best_ms = st.best_ms, b.single_render_cpu_ms = st.cpu_ms;
  b.vrte_render_ms = vt.mean_ms, b.vrte_render_best_ms = vt.best_ms, b.vrte_render_cpu_ms = vt.cpu_ms;

  const double n = static_cast<double>(vrte.times.size());
  const render::RenderReport rs = render::render_scene(single, (scratch / "single.exr").string(), {}, cache);
  b.single_end_to_end_ms = 1e3 * (rs.render_seconds + rs.write_seconds) / n;
  const render::RenderReport rv = render::render_scene(vrte, (scratch / "vrte.exr").string(), {}, cache);
  b.vrte_end_to_end_ms = 1e3 * (rv.render_seconds + rv.write_seconds) / n;
  for (const int streams : streams_sweep) {
    scene::Scene one = vrte;
    one.sky.streams = streams;
    one.render.bands = {vrte.render.bands.front()};
    one.sky.wavelengths_nm = {b.wavelengths_nm.front()};
    const sky::BandSkies t = scene::build_band_skies(one, {});
    b.sweep_streams.push_back(streams);
    b.sweep_build_s.push_back(t.build_seconds.front());
  }
  fs::remove_all(scratch);
  std::error_code ec;
  fs::remove(scratch_dir, ec);  // only if empty: a folder the caller had kept stays
  return b;
}

}  // namespace skypol::studies
