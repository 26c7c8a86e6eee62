#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "render/polarization_math.h"

namespace skypol::render {
namespace {

bool wants(const RenderOptions& o, const char* name) {
  return std::find(o.channels.begin(), o.channels.end(), name) != o.channels.end();
}

bool is_rgb(const RenderOptions& o) { return o.bands == std::vector<std::string>{"R", "G", "B"}; }

// A counter-based hash (SplitMix64 finaliser): the random numbers of a sample depend only on
// (seed, pixel, sample), never on which thread drew them.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}
double uniform01(std::uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

// Output pointers of the first band; other bands are copies (the sky models are grey).
struct Outputs {
  float* s0 = nullptr;
  float* s1 = nullptr;
  float* s2 = nullptr;
  float* s3 = nullptr;
  float* dolp = nullptr;
  float* aolp = nullptr;
  float* mask = nullptr;
};

}  // namespace

std::vector<std::string> channel_names(const RenderOptions& o) {
  std::vector<std::string> names;
  for (const char* c : {"S0", "S1", "S2", "S3", "DoLP", "AoLP"}) {
    if (!wants(o, c)) continue;
    for (const std::string& b : o.bands) names.push_back(std::string(c) + "." + b);
  }
  if (is_rgb(o) && wants(o, "S0")) names.insert(names.end(), {"R", "G", "B"});
  if (wants(o, "mask")) names.push_back("mask");
  return names;
}

Renderer::Renderer(std::shared_ptr<const camera::Camera> camera, RenderOptions options,
                   std::shared_ptr<const Occluders> occluders)
    : camera_(std::move(camera)), options_(std::move(options)), occluders_(std::move(occluders)) {
  if (options_.spp == 1) {
    const int h = camera_->height();
    const std::size_t w = static_cast<std::size_t>(camera_->width());
    cached_rays_.resize(w * static_cast<std::size_t>(h));
    cached_weight_.resize(cached_rays_.size());
    const int tile = options_.tile_rows;
    tbb::parallel_for(0, (h + tile - 1) / tile, [&](int t) {
      const int y0 = t * tile, y1 = std::min(h, y0 + tile);
      const std::size_t first = static_cast<std::size_t>(y0) * w, count = static_cast<std::size_t>(y1 - y0) * w;
      trace_tile(y0, y1, std::span(cached_rays_).subspan(first, count), std::span(cached_weight_).subspan(first, count));
    });
  }
}

void Renderer::trace_tile(int y0, int y1, std::span<sky::ViewRay> rays, std::span<float> weight) const {
  const int w = camera_->width();
  const int spp = options_.spp;
  std::vector<int> perm(static_cast<std::size_t>(spp));
  std::size_t k = 0;
  for (int y = y0; y < y1; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::uint64_t pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(w) + static_cast<std::uint64_t>(x);
      // N-rooks stratification: sample s takes column stratum s and row stratum perm(s), both
      // jittered; perm is a seeded shuffle per pixel. At spp = 1 the sample is the pixel centre.
      const std::uint64_t base = mix(options_.seed ^ mix(pixel));
      if (spp > 1) {
        std::iota(perm.begin(), perm.end(), 0);
        for (int s = spp - 1; s > 0; --s) {
          const auto j = static_cast<int>(mix(base + static_cast<std::uint64_t>(s)) % static_cast<std::uint64_t>(s + 1));
          std::swap(perm[static_cast<std::size_t>(s)], perm[static_cast<std::size_t>(j)]);
        }
      }
      for (int s = 0; s < spp; ++s, ++k) {
        Eigen::Vector2d p(x, y);
        if (spp > 1) {
          const std::uint64_t h = mix(base ^ (0x5851f42d4c957f2dull * static_cast<std::uint64_t>(s + 1)));
          p.x() += (s + uniform01(h)) / spp - 0.5;
          p.y() += (perm[static_cast<std::size_t>(s)] + uniform01(mix(h))) / spp - 0.5;
        }
        if (std::optional<camera::CameraRay> r = camera_->ray(p)) {
          rays[k].d = r->d.cast<float>();
          rays[k].e0 = r->e0.cast<float>();
          weight[k] = 1;
        } else {
          rays[k].d = Eigen::Vector3f::UnitZ();  // any valid ray: its Stokes vector is weighted by 0
          rays[k].e0 = Eigen::Vector3f::UnitX();
          weight[k] = 0;
        }
      }
    }
  }
  if (occluders_) {
    std::vector<Eigen::Vector3f> dirs(k);
    std::vector<std::uint8_t> hit(k);
    for (std::size_t i = 0; i < k; ++i) dirs[i] = rays[i].d;
    occluders_->occluded(dirs, hit);
    for (std::size_t i = 0; i < k; ++i) {
      if (hit[i]) weight[i] = 0;
    }
  }
}

Frame Renderer::render(const sky::SkyModel& sky, const sky::Sun& sun) const {
  const int w = camera_->width(), h = camera_->height();
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  const std::size_t spp = static_cast<std::size_t>(options_.spp);
  const bool projected = camera_->transport() == camera::Transport::projected;
  const auto& o = options_;

  Frame frame;
  frame.width = w;
  frame.height = h;
  const std::string& b0 = o.bands.front();
  auto make = [&](const char* what, bool wanted) -> float* {
    if (!wanted) return nullptr;
    std::vector<float>& v = frame.channels[what == std::string("mask") ? std::string("mask") : what + ("." + b0)];
    v.resize(n);
    return v.data();
  };
  Outputs out;
  out.s0 = make("S0", wants(o, "S0"));
  out.s1 = make("S1", wants(o, "S1"));
  out.s2 = make("S2", wants(o, "S2"));
  out.s3 = make("S3", wants(o, "S3"));
  out.dolp = make("DoLP", wants(o, "DoLP"));
  out.aolp = make("AoLP", wants(o, "AoLP"));
  out.mask = make("mask", wants(o, "mask"));

  struct Scratch {
    std::vector<sky::ViewRay> rays;
    std::vector<float> weight;
    std::vector<sky::StokesF> stokes;
    std::vector<float> acc;
  };
  tbb::enumerable_thread_specific<Scratch> scratch;
  const int tile = o.tile_rows;
  tbb::parallel_for(0, (h + tile - 1) / tile, [&](int t) {
    Scratch& sc = scratch.local();
    const int y0 = t * tile, y1 = std::min(h, y0 + tile);
    const std::size_t first = static_cast<std::size_t>(y0) * static_cast<std::size_t>(w);
    const std::size_t pixels = static_cast<std::size_t>(y1 - y0) * static_cast<std::size_t>(w);
    std::span<const sky::ViewRay> rays;
    std::span<const float> weight;
    if (!cached_rays_.empty()) {
      rays = std::span<const sky::ViewRay>(cached_rays_).subspan(first, pixels);
      weight = std::span<const float>(cached_weight_).subspan(first, pixels);
    } else {
      sc.rays.resize(pixels * spp);
      sc.weight.resize(pixels * spp);
      trace_tile(y0, y1, sc.rays, sc.weight);
      rays = sc.rays;
      weight = sc.weight;
    }
    sc.stokes.resize(rays.size());
    sky.stokes(rays, sun, sc.stokes);
    if (projected) {
      for (std::size_t i = 0; i < rays.size(); ++i) {
        if (weight[i] > 0) sc.stokes[i] = to_projected(*camera_, rays[i], sc.stokes[i]);
      }
    }

    // Per pixel: mean over its samples (occluded/outside samples count as black), then the
    // derived quantities, into tile buffers by plain float loops that the compiler vectorizes;
    // then copied to the channels the scene asked for.
    sc.acc.resize(7 * pixels);
    float* a0 = sc.acc.data();
    float* a1 = a0 + pixels;
    float* a2 = a1 + pixels;
    float* a3 = a2 + pixels;
    float* cover = a3 + pixels;
    float* dl = cover + pixels;
    float* al = dl + pixels;
    const sky::StokesF* st = sc.stokes.data();
    const float* wt = weight.data();
    if (spp == 1) {
      for (std::size_t p = 0; p < pixels; ++p) {
        a0[p] = wt[p] * st[p].s0;
        a1[p] = wt[p] * st[p].s1;
        a2[p] = wt[p] * st[p].s2;
        a3[p] = wt[p] * st[p].s3;
        cover[p] = wt[p];
      }
    } else {
      const float inv_spp = 1.0f / static_cast<float>(spp);
      for (std::size_t p = 0; p < pixels; ++p) {
        float s0 = 0, s1 = 0, s2 = 0, s3 = 0, c = 0;
        for (std::size_t i = p * spp; i < (p + 1) * spp; ++i) {
          s0 += wt[i] * st[i].s0;
          s1 += wt[i] * st[i].s1;
          s2 += wt[i] * st[i].s2;
          s3 += wt[i] * st[i].s3;
          c += wt[i];
        }
        a0[p] = s0 * inv_spp, a1[p] = s1 * inv_spp, a2[p] = s2 * inv_spp, a3[p] = s3 * inv_spp;
        cover[p] = c * inv_spp;
      }
    }
    if (out.dolp) {
      for (std::size_t p = 0; p < pixels; ++p) dl[p] = dolp_of(a0[p], a1[p], a2[p]);
    }
    if (out.aolp) {
      for (std::size_t p = 0; p < pixels; ++p) al[p] = aolp_of(a1[p], a2[p]);
    }
    const std::size_t bytes = pixels * sizeof(float);
    for (auto [dst, src] : {std::pair{out.s0, a0}, {out.s1, a1}, {out.s2, a2}, {out.s3, a3}, {out.dolp, dl},
                            {out.aolp, al}, {out.mask, cover}}) {
      if (dst) std::memcpy(dst + first, src, bytes);
    }
  });

  // The sky models are grey: every further band carries the first band's values.
  for (std::size_t i = 1; i < o.bands.size(); ++i) {
    for (const char* c : {"S0", "S1", "S2", "S3", "DoLP", "AoLP"}) {
      if (wants(o, c)) frame.channels[std::string(c) + "." + o.bands[i]] = frame.channels[std::string(c) + "." + b0];
    }
  }
  if (is_rgb(o) && wants(o, "S0")) {
    for (const char* c : {"R", "G", "B"}) frame.channels[c] = frame.channels["S0." + b0];
  }
  return frame;
}

}  // namespace skypol::render
