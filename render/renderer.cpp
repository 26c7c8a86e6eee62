#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "render/polarization_math.h"

namespace skypol::render {
namespace {

bool wants(const RenderOptions& o, const char* name) {
  return std::find(o.channels.begin(), o.channels.end(), name) != o.channels.end();
}

// A counter-based hash (SplitMix64 finaliser): the random numbers of a sample depend only on
// (seed, pixel, sample), never on which thread drew them.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}
double uniform01(std::uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

}  // namespace

std::vector<std::string> channel_names(const RenderOptions& o) {
  std::vector<std::string> names;
  const bool rgb = o.bands == std::vector<std::string>{"R", "G", "B"};
  for (const char* c : {"S0", "S1", "S2", "S3", "DoLP", "AoLP"}) {
    if (!wants(o, c)) continue;
    for (const std::string& b : o.bands) names.push_back(std::string(c) + "." + b);
  }
  if (rgb && wants(o, "S0")) names.insert(names.end(), {"R", "G", "B"});
  if (wants(o, "mask")) names.push_back("mask");
  return names;
}

Renderer::Renderer(std::shared_ptr<const camera::Camera> camera, RenderOptions options,
                   std::shared_ptr<const Occluders> occluders)
    : camera_(std::move(camera)), options_(std::move(options)), occluders_(std::move(occluders)) {
  if (options_.spp == 1) {
    const int h = camera_->height();
    const std::size_t w = static_cast<std::size_t>(camera_->width());
    cached_.resize(w * static_cast<std::size_t>(h));
    const int tile = options_.tile_rows;
    tbb::parallel_for(0, (h + tile - 1) / tile, [&](int t) {
      const int y0 = t * tile, y1 = std::min(h, y0 + tile);
      std::vector<Sample> samples;
      trace_tile(y0, y1, samples);
      std::copy(samples.begin(), samples.end(), cached_.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y0) * w));
    });
  }
}

void Renderer::trace_tile(int y0, int y1, std::vector<Sample>& out) const {
  const int w = camera_->width();
  const int spp = options_.spp;
  out.resize(static_cast<std::size_t>((y1 - y0) * w * spp));
  std::size_t k = 0;
  for (int y = y0; y < y1; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::uint64_t pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(w) + static_cast<std::uint64_t>(x);
      // N-rooks stratification: sample s takes column stratum s and row stratum perm(s), both
      // jittered; perm is a seeded shuffle per pixel. At spp = 1 the sample is the pixel centre.
      std::vector<int> perm(static_cast<std::size_t>(spp));
      std::iota(perm.begin(), perm.end(), 0);
      const std::uint64_t base = mix(options_.seed ^ mix(pixel));
      for (int s = spp - 1; s > 0; --s) {
        const auto j = static_cast<int>(mix(base + static_cast<std::uint64_t>(s)) % static_cast<std::uint64_t>(s + 1));
        std::swap(perm[static_cast<std::size_t>(s)], perm[static_cast<std::size_t>(j)]);
      }
      for (int s = 0; s < spp; ++s, ++k) {
        Eigen::Vector2d p(x, y);
        if (spp > 1) {
          const std::uint64_t h = mix(base ^ (0x5851f42d4c957f2dull * static_cast<std::uint64_t>(s + 1)));
          p.x() += (s + uniform01(h)) / spp - 0.5;
          p.y() += (perm[static_cast<std::size_t>(s)] + uniform01(mix(h))) / spp - 0.5;
        }
        Sample& out_s = out[k];
        if (std::optional<camera::CameraRay> r = camera_->ray(p)) {
          out_s.ray.d = r->d.cast<float>();
          out_s.ray.e0 = r->e0.cast<float>();
          out_s.weight = 1;
        } else {
          out_s.ray.d = Eigen::Vector3f::UnitZ();
          out_s.ray.e0 = Eigen::Vector3f::UnitX();
          out_s.weight = 0;
        }
      }
    }
  }
  if (occluders_) {
    std::vector<Eigen::Vector3f> dirs(out.size());
    std::vector<std::uint8_t> hit(out.size());
    for (std::size_t i = 0; i < out.size(); ++i) dirs[i] = out[i].ray.d;
    occluders_->occluded(dirs, hit);
    for (std::size_t i = 0; i < out.size(); ++i) {
      if (hit[i]) out[i].weight = 0;
    }
  }
}

Frame Renderer::render(const sky::SkyModel& sky, const sky::Sun& sun) const {
  const int w = camera_->width(), h = camera_->height();
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  const int spp = options_.spp;
  const bool projected = camera_->transport() == camera::Transport::projected;

  // Per-pixel accumulators, then the requested channels.
  std::vector<float> s0(n), s1(n), s2(n), s3(n), mask(n);
  struct Scratch {
    std::vector<Sample> samples;
    std::vector<sky::ViewRay> rays;
    std::vector<sky::StokesF> stokes;
  };
  tbb::enumerable_thread_specific<Scratch> scratch;
  const int tile = options_.tile_rows;
  tbb::parallel_for(0, (h + tile - 1) / tile, [&](int t) {
    Scratch& sc = scratch.local();
    const int y0 = t * tile, y1 = std::min(h, y0 + tile);
    const std::size_t first = static_cast<std::size_t>(y0) * static_cast<std::size_t>(w);
    const std::size_t count = static_cast<std::size_t>(y1 - y0) * static_cast<std::size_t>(w) * static_cast<std::size_t>(spp);
    std::span<const Sample> samples;
    if (!cached_.empty()) {
      samples = std::span<const Sample>(cached_).subspan(first, count);
    } else {
      trace_tile(y0, y1, sc.samples);
      samples = sc.samples;
    }
    sc.rays.resize(count);
    sc.stokes.resize(count);
    for (std::size_t i = 0; i < count; ++i) sc.rays[i] = samples[i].ray;
    sky.stokes(sc.rays, sun, sc.stokes);

    const float inv_spp = 1.0f / static_cast<float>(spp);
    for (std::size_t p = 0; p < count / static_cast<std::size_t>(spp); ++p) {
      float a0 = 0, a1 = 0, a2 = 0, a3 = 0, cover = 0;
      for (int s = 0; s < spp; ++s) {
        const std::size_t i = p * static_cast<std::size_t>(spp) + static_cast<std::size_t>(s);
        const float wgt = samples[i].weight;
        sky::StokesF st = sc.stokes[i];
        if (projected && wgt > 0) st = to_projected(*camera_, samples[i].ray, st);
        a0 += wgt * st.s0;
        a1 += wgt * st.s1;
        a2 += wgt * st.s2;
        a3 += wgt * st.s3;
        cover += wgt;
      }
      const std::size_t o = first + p;
      s0[o] = a0 * inv_spp;
      s1[o] = a1 * inv_spp;
      s2[o] = a2 * inv_spp;
      s3[o] = a3 * inv_spp;
      mask[o] = cover * inv_spp;
    }
  });

  Frame frame;
  frame.width = w;
  frame.height = h;
  const auto& o = options_;
  for (const std::string& b : o.bands) {
    // The sky models are grey: every band carries the same Stokes vector (docs/conventions.md).
    if (wants(o, "S0")) frame.channels["S0." + b] = s0;
    if (wants(o, "S1")) frame.channels["S1." + b] = s1;
    if (wants(o, "S2")) frame.channels["S2." + b] = s2;
    if (wants(o, "S3")) frame.channels["S3." + b] = s3;
    if (wants(o, "DoLP")) frame.channels["DoLP." + b] = dolp_image(s0, s1, s2);
    if (wants(o, "AoLP")) frame.channels["AoLP." + b] = aolp_image(s1, s2);
  }
  if (o.bands == std::vector<std::string>{"R", "G", "B"} && wants(o, "S0")) {
    for (const char* c : {"R", "G", "B"}) frame.channels[c] = s0;
  }
  if (wants(o, "mask")) frame.channels["mask"] = std::move(mask);
  return frame;
}

}  // namespace skypol::render
