// Study 1: samples per pixel. Each spp renders one frame (10:00 UTC, sun 38° high); its Stokes
// images are compared with a reference, inside the image circle (pixels the reference sees whole)
// and on its edge (pixels it sees in part, where the mask is the coverage). The reference does not
// use the renderer's sampler: it is the midpoint rule on a regular k×k grid in each pixel (error
// O(h²/k²) for a smooth sky; the renderer's N-rooks jitter has its own, random, error).
// Two skies: the clear Rayleigh sky (smooth: spp buys little inside) and the same with the sun's
// disc (a 0.27° source, smaller than a binned pixel: spp decides its energy).
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "studies/tradeoff_setup.h"
#include "studies/tradeoff_studies.h"
#include "studies/tradeoff_table.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "stack/polarization_math.h"
#include "scene/truth.h"

#include <tbb/parallel_for.h>

namespace skypol::studies::tradeoff {
namespace {

double D(float v) { return static_cast<double>(v); }

struct Errors {
  double stokes_rms = 0, stokes_max = 0, dolp_rms = 0, dolp_max = 0;
  int edge_pixels = 0;
  double coverage_rms = 0, coverage_max = 0;
};

Errors compare(const stack::Frame& f, const stack::Frame& ref) {
  const auto& s0 = f.channel("S0.Y");
  const auto& s1 = f.channel("S1.Y");
  const auto& s2 = f.channel("S2.Y");
  const auto& dl = f.channel("DoLP.Y");
  const auto& m = f.channel("mask");
  const auto& r0 = ref.channel("S0.Y");
  const auto& r1 = ref.channel("S1.Y");
  const auto& r2 = ref.channel("S2.Y");
  const auto& rd = ref.channel("DoLP.Y");
  const auto& rm = ref.channel("mask");
  Errors e;
  double ss = 0, sd = 0, sc = 0;
  int inside = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (rm[i] == 1.0f && m[i] == 1.0f) {
      // Relative to the reference's radiance: |ΔS| / S0.
      const double d0 = D(s0[i]) - D(r0[i]), d1 = D(s1[i]) - D(r1[i]), d2 = D(s2[i]) - D(r2[i]);
      const double rel = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2) / D(r0[i]);
      const double dd = std::abs(D(dl[i]) - D(rd[i]));
      ss += rel * rel;
      sd += dd * dd;
      e.stokes_max = std::max(e.stokes_max, rel);
      e.dolp_max = std::max(e.dolp_max, dd);
      ++inside;
    } else if (rm[i] > 0 || m[i] > 0) {
      const double dc = std::abs(D(m[i]) - D(rm[i]));
      sc += dc * dc;
      e.coverage_max = std::max(e.coverage_max, dc);
      ++e.edge_pixels;
    }
  }
  e.stokes_rms = inside ? std::sqrt(ss / inside) : 0;
  e.dolp_rms = inside ? std::sqrt(sd / inside) : 0;
  e.coverage_rms = e.edge_pixels ? std::sqrt(sc / e.edge_pixels) : 0;
  return e;
}

// The pixel means of S0, S1, S2 and the covered fraction by the midpoint rule on a k×k grid,
// DoLP from the means: what the renderer's channels converge to.
stack::Frame reference_frame(const camera::Camera& cam, const sky::SkyModel& sky, const sky::Sun& sun, int k) {
  const int w = cam.width(), h = cam.height();
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  stack::Frame f;
  f.width = w;
  f.height = h;
  for (const char* c : {"S0.Y", "S1.Y", "S2.Y", "DoLP.Y", "mask"}) f.channels[c].assign(n, 0.0f);
  float* s0 = f.channel("S0.Y").data();
  float* s1 = f.channel("S1.Y").data();
  float* s2 = f.channel("S2.Y").data();
  float* dl = f.channel("DoLP.Y").data();
  float* m = f.channel("mask").data();
  const std::size_t kk = static_cast<std::size_t>(k) * static_cast<std::size_t>(k);
  tbb::parallel_for(0, h, [&](int y) {
    std::vector<sky::ViewRay> rays(static_cast<std::size_t>(w) * kk);
    std::vector<float> weight(rays.size(), 0.0f);
    std::vector<sky::StokesF> st(rays.size());
    for (int x = 0; x < w; ++x)
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
          const std::size_t q = static_cast<std::size_t>(x) * kk + static_cast<std::size_t>(j * k + i);
          const Eigen::Vector2d p(x - 0.5 + (i + 0.5) / k, y - 0.5 + (j + 0.5) / k);
          if (const auto r = cam.ray(p)) {
            rays[q] = {r->d.cast<float>(), r->e0.cast<float>()};
            weight[q] = 1;
          } else {
            rays[q] = {Eigen::Vector3f::UnitZ(), Eigen::Vector3f::UnitX()};
          }
        }
    sky.stokes(rays, sun, st);
    for (int x = 0; x < w; ++x) {
      double a0 = 0, a1 = 0, a2 = 0, c = 0;
      for (std::size_t q = static_cast<std::size_t>(x) * kk; q < static_cast<std::size_t>(x + 1) * kk; ++q) {
        a0 += D(weight[q] * st[q].s0);
        a1 += D(weight[q] * st[q].s1);
        a2 += D(weight[q] * st[q].s2);
        c += D(weight[q]);
      }
      const std::size_t o = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
      const double inv = 1.0 / static_cast<double>(kk);
      s0[o] = static_cast<float>(a0 * inv);
      s1[o] = static_cast<float>(a1 * inv);
      s2[o] = static_cast<float>(a2 * inv);
      m[o] = static_cast<float>(c * inv);
      dl[o] = stack::dolp_of(s0[o], s1[o], s2[o]);
    }
  });
  return f;
}

}  // namespace

void study_spp(const StudyOptions& o) {
  const int binning = o.small ? 16 : 2;
  const std::vector<int> spps = o.small ? std::vector<int>{1, 4, 16} : std::vector<int>{1, 2, 4, 8, 16, 64};
  const int reference_grid = o.small ? 8 : 16;  // k: k² samples per pixel
  const int default_spp = render::RenderOptions{}.spp;

  auto cam = paper_camera(binning, 0);
  scene::Scene scene;
  scene.site = paper_site();
  const scene::Truth truth = scene::make_truth(scene, *cam, times_over("2022-09-23T10:00:00Z", 0, 1)[0]);

  Table t({"sky", "spp", "width", "height", "setup_ms", "ms_per_frame", "stokes_rms_rel", "stokes_max_rel",
           "dolp_rms", "dolp_max", "edge_pixels", "coverage_rms", "coverage_max", "reference_grid",
           "is_default"});
  for (const bool disc : {false, true}) {
    sky::SkySpec spec;
    spec.sun_disc = disc;
    const auto sky_model = sky::make_sky(spec);
    const stack::Frame ref = reference_frame(*cam, *sky_model, truth.sun, reference_grid);
    for (const int spp : spps) {
      render::RenderOptions ro;
      ro.spp = spp;
      ro.channels = {"S0", "S1", "S2", "DoLP", "mask"};
      std::unique_ptr<render::Renderer> r;
      const double setup_s = best_seconds(1, [&] { r = std::make_unique<render::Renderer>(cam, ro); });
      stack::Frame f;
      const double frame_s = best_seconds(o.small || spp >= 64 ? 1 : 3, [&] { f = r->render(*sky_model, truth.sun); });
      const Errors e = compare(f, ref);
      t.row()
          .set("sky", disc ? "rayleigh+sun_disc" : "rayleigh")
          .set("spp", spp)
          .set("width", cam->width())
          .set("height", cam->height())
          .set("setup_ms", 1e3 * setup_s)
          .set("ms_per_frame", 1e3 * frame_s)
          .set("stokes_rms_rel", e.stokes_rms)
          .set("stokes_max_rel", e.stokes_max)
          .set("dolp_rms", e.dolp_rms)
          .set("dolp_max", e.dolp_max)
          .set("edge_pixels", e.edge_pixels)
          .set("coverage_rms", e.coverage_rms)
          .set("coverage_max", e.coverage_max)
          .set("reference_grid", reference_grid)
          .set("is_default", spp == default_spp);
    }
  }
  t.write((std::filesystem::path(o.out_dir) / "spp.csv").string());
}

}  // namespace skypol::studies::tradeoff
