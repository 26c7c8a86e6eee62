#include "render/renderer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "render/occlusion_pass.h"
#include "stack/polarization_math.h"
#include "sky/vector_clones.h"
#include "sky/vrte/vrte_sky.h"

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

// Pixels evaluated together: the model's results for a chunk stay in L1 while the derived
// quantities are computed from them.
constexpr std::size_t kChunk = 256;

// Where one band's channels live (null: not asked for).
struct BandOutputs {
  float* s0 = nullptr;
  float* s1 = nullptr;
  float* s2 = nullptr;
  float* s3 = nullptr;
  float* dolp = nullptr;
  float* aolp = nullptr;
};

// Where the evaluated bands' channels live, and the further channels that carry copies of them.
// A grey sky (one model) is evaluated for the first band only: the other bands, and R, G, B, are
// copies of it. A sky with one model per band is evaluated into every band; R, G, B copy S0.R/G/B.
struct Outputs {
  std::vector<BandOutputs> bands;  // one per model
  float* mask = nullptr;
  std::vector<std::pair<float*, const float*>> copies;  // (destination, source), whole frames

  // Rows [y0, y1) of every copy, done while the tile is still in cache.
  void copy_rows(std::size_t first, std::size_t count) const {
    for (const auto& [dst, src] : copies) std::memcpy(dst + first, src + first, count * sizeof(float));
  }
};

// Gives `frame` exactly the channels these options name, each of n floats (storage reused where it
// fits), and returns where to write for `models` sky models (1, or one per band).
Outputs prepare(stack::Frame& frame, const RenderOptions& o, int w, int h, std::size_t models = 1) {
  frame.width = w;
  frame.height = h;
  const std::vector<std::string> names = channel_names(o);
  std::erase_if(frame.channels,
                [&](const auto& c) { return std::find(names.begin(), names.end(), c.first) == names.end(); });
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  for (const std::string& name : names) stack::size_channel(frame.channels[name], n);

  Outputs out;
  auto at = [&](const std::string& name) { return frame.channels.at(name).data(); };
  auto band = [&](const std::string& b, const char* c) { return wants(o, c) ? at(std::string(c) + "." + b) : nullptr; };
  const std::size_t evaluated = models == 1 ? 1 : o.bands.size();
  for (std::size_t i = 0; i < evaluated; ++i) {
    const std::string& b = o.bands[i];
    out.bands.push_back({band(b, "S0"), band(b, "S1"), band(b, "S2"), band(b, "S3"), band(b, "DoLP"), band(b, "AoLP")});
  }
  out.mask = wants(o, "mask") ? at("mask") : nullptr;
  for (std::size_t i = evaluated; i < o.bands.size(); ++i) {
    for (const char* c : {"S0", "S1", "S2", "S3", "DoLP", "AoLP"}) {
      if (wants(o, c)) out.copies.emplace_back(band(o.bands[i], c), band(o.bands.front(), c));
    }
  }
  if (is_rgb(o) && wants(o, "S0")) {
    const char* rgb[] = {"R", "G", "B"};
    for (std::size_t i = 0; i < 3; ++i) out.copies.emplace_back(at(rgb[i]), out.bands[evaluated == 1 ? 0 : i].s0);
  }
  return out;
}

// DoLP and AoLP of n pixels (each output may be null). Separate plain loops over restrict-
// qualified arrays: each vectorizes (fast_atan2 has no library call), eight wide on AVX2.
SKYPOL_VECTOR_CLONES void derive(std::size_t n, const float* __restrict s0, const float* __restrict s1, const float* __restrict s2,
            float* __restrict dolp, float* __restrict aolp) {
  if (dolp) {
    for (std::size_t j = 0; j < n; ++j) dolp[j] = stack::dolp_of(s0[j], s1[j], s2[j]);
  }
  if (aolp) {
    for (std::size_t j = 0; j < n; ++j) aolp[j] = stack::aolp_of(s1[j], s2[j]);
  }
}

// Zeros where no sample sees the sky (+0, whatever the sign of the model's value there). One plane
// per loop: GCC turns four selects on one condition into a branch, and one select into a blend.
void clear_unseen(std::size_t n, const float* __restrict weight, float* __restrict s) {
  for (std::size_t j = 0; j < n; ++j) {
    const float v = s[j];  // loaded unconditionally, so the select if-converts
    s[j] = weight[j] > 0 ? v : 0.0f;
  }
}

void clear_unseen(std::size_t n, const float* weight, const sky::StokesSoA& s) {
  for (float* plane : {s.s0, s.s1, s.s2, s.s3}) clear_unseen(n, weight, plane);
}

// Shaded occluders: their unpolarized light on top of what the sky gives (scene/occluder_spec.h).
void add_surface(std::size_t n, const float* __restrict surface, float* __restrict s0) {
  for (std::size_t j = 0; j < n; ++j) s0[j] += surface[j];
}

void fill_zero(float* p, std::size_t first, std::size_t count) {
  if (p && count > 0) std::memset(p + first, 0, count * sizeof(float));
}

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
                   std::shared_ptr<const Occluders> occluders, std::shared_ptr<const RayPlanes> planes)
    : camera_(std::move(camera)), options_(std::move(options)), occluders_(std::move(occluders)) {
  static std::atomic<std::uint64_t> tokens{0};
  token_ = ++tokens;
  const std::size_t n = static_cast<std::size_t>(camera_->width()) * static_cast<std::size_t>(camera_->height());
  if (occluders_ && occluders_->shaded()) surface_s0_.resize(n);
  if (options_.spp != 1) {
    if (!surface_s0_.empty()) shade_sampled();
    return;
  }
  if (planes && !occluders_) {
    if (planes->width() != camera_->width() || planes->height() != camera_->height() ||
        planes->tile_rows() != options_.tile_rows)
      throw std::invalid_argument("renderer: the ray planes offered were made for another camera or tiling");
    planes_ = std::move(planes);
    return;
  }
  if (!options_.keep_rays && !occluders_) {  // traced per tile in each render (render_cached)
    traced_spans_ = std::make_unique<std::atomic<std::int64_t>[]>(static_cast<std::size_t>(camera_->height()));
    for (int y = 0; y < camera_->height(); ++y) traced_spans_[static_cast<std::size_t>(y)].store(-1, std::memory_order_relaxed);
    return;
  }
  planes_ = std::make_shared<const RayPlanes>(*camera_, options_.tile_rows, occluders_.get(),
                                              surface_s0_.empty() ? nullptr : &surface_s0_);
}

void Renderer::shade_sampled() {
  // The occluder surfaces do not change over a stack: their per-pixel mean S0 once, here.
  const int h = camera_->height(), tile = options_.tile_rows;
  const std::size_t w = static_cast<std::size_t>(camera_->width()), spp = static_cast<std::size_t>(options_.spp);
  tbb::parallel_for(0, (h + tile - 1) / tile, [&](int t) {
    const int y0 = t * tile, y1 = std::min(h, y0 + tile);
    const std::size_t first = static_cast<std::size_t>(y0) * w, count = static_cast<std::size_t>(y1 - y0) * w;
    std::vector<sky::ViewRay> rays(count * spp);
    std::vector<float> weight(count * spp), s0(count * spp);
    trace_tile(y0, y1, rays, weight, s0);
    for (std::size_t p = 0; p < count; ++p) {
      float sum = 0;
      for (std::size_t i = p * spp; i < (p + 1) * spp; ++i) sum += s0[i];
      surface_s0_[first + p] = sum / static_cast<float>(spp);
    }
  });
}

void Renderer::trace_tile(int y0, int y1, std::span<sky::ViewRay> rays, std::span<float> weight,
                          std::span<float> surface_s0) const {
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
  if (occluders_) apply_occluders(*occluders_, rays.first(k), weight.first(k), surface_s0);
}

stack::Frame Renderer::render(const sky::SkyModel& sky, const sky::Sun& sun) const {
  stack::Frame frame;
  render(sky, sun, frame);
  return frame;
}

stack::Frame Renderer::render(std::span<const sky::SkyModel* const> skies, const sky::Sun& sun) const {
  stack::Frame frame;
  render(skies, sun, frame);
  return frame;
}

void Renderer::render(const sky::SkyModel& sky, const sky::Sun& sun, stack::Frame& frame) const {
  const sky::SkyModel* one[] = {&sky};
  render(one, sun, frame);
}

void Renderer::check_skies(std::span<const sky::SkyModel* const> skies) const {
  if (skies.size() != 1 && skies.size() != options_.bands.size()) {
    throw std::invalid_argument("renderer: " + std::to_string(skies.size()) + " sky models for " +
                                std::to_string(options_.bands.size()) + " bands (give one, or one per band)");
  }
}

void Renderer::render(std::span<const sky::SkyModel* const> skies, const sky::Sun& sun, stack::Frame& frame) const {
  check_skies(skies);
  if (options_.spp == 1) {
    render_cached(skies, sun, frame, 0, camera_->height());
  } else {
    render_sampled(skies, sun, frame);
  }
}

stack::Frame Renderer::new_frame() const {
  stack::Frame frame;
  prepare(frame, options_, camera_->width(), camera_->height());
  return frame;
}

// One sample per pixel from the cached planes: per row, the model over the span of sky-seeing
// pixels in chunks, written straight into the frame's channels (scratch for the Stokes components
// the scene does not keep); zeros outside the span. Rows [first, last) of the camera, into a frame
// of last − first rows (the whole frame, or a band: render_rows).
void Renderer::render_cached(std::span<const sky::SkyModel* const> skies, const sky::Sun& sun, stack::Frame& frame,
                             int first, int last) const {
  const int w = camera_->width(), h = last - first;
  // The token names the rows too. A frame this renderer left holds zeros outside the spans of
  // rows [prev, prev + h): with the planes, those spans are known for any rows, and only what
  // was inside them and is outside now needs clearing (a band frame reused for other rows);
  // traced per tile, only for the same rows. Same size, so prepare() keeps every channel's storage.
  const std::uint64_t key = token_ << 32 | static_cast<std::uint32_t>(first);
  int prev = -1;
  if (options_.reuse_cleared && frame.zero_outside >> 32 == token_ && frame.width == w && frame.height == h) {
    const int p = static_cast<int>(frame.zero_outside & 0xffffffffu);
    if (p == first || planes_ || traced_spans_) prev = p;
  }
  frame.zero_outside = 0;  // until every tile is done
  const Outputs out = prepare(frame, options_, w, h, skies.size());
  const bool projected = camera_->transport() == camera::Transport::projected;
  const std::size_t width = static_cast<std::size_t>(w);
  const std::size_t camera_offset = static_cast<std::size_t>(first) * width;  // frame index + it = camera pixel
  const int tile = options_.tile_rows;
  tbb::enumerable_thread_specific<TileRays> tile_rays;  // used only without planes_
  tbb::parallel_for(0, (h + tile - 1) / tile, [&](int t) {
    // Where a band's Stokes planes go when the frame has no channel for them; one set per band, as
    // a colour vrte sky writes its bands together.
    alignas(64) float scratch[sky::VrteSky::kMaxBands][4][kChunk];
    const int y0 = first + t * tile, y1 = std::min(last, y0 + tile);
    TileRays* traced = nullptr;
    if (!planes_) {
      traced = &tile_rays.local();
      traced->trace(*camera_, y0, y1, nullptr);
    }
    for (int y = y0; y < y1; ++y) {
      const std::size_t row = static_cast<std::size_t>(y - first) * width;  // in the frame
      const RayRow span = planes_ ? planes_->row(y) : traced->row(y);
      const std::size_t x0 = static_cast<std::size_t>(span.x0), x1 = static_cast<std::size_t>(span.x1);
      if (traced_spans_)
        traced_spans_[static_cast<std::size_t>(y)].store(std::int64_t{span.x0} | std::int64_t{span.x1} << 32,
                                                         std::memory_order_relaxed);
      // Zeros go to [c0, c1) and [d0, d1): all outside the span, or, where the frame's previous
      // span [a, b) of this row is known (zeros outside it), [a, b) minus the new span.
      std::size_t c0 = 0, c1 = x0, d0 = x1, d1 = width;
      // The old row's span: this row's, the planes', or as an earlier render traced it (-1 if
      // none did: then all the outside is cleared).
      std::int64_t old = -1;
      if (prev == first) {
        old = std::int64_t{span.x0} | std::int64_t{span.x1} << 32;
      } else if (prev >= 0) {
        const int y_old = prev + (y - first);
        if (planes_) {
          const RayRow r = planes_->row(y_old);
          old = std::int64_t{r.x0} | std::int64_t{r.x1} << 32;
        } else {
          old = traced_spans_[static_cast<std::size_t>(y_old)].load(std::memory_order_relaxed);
        }
      }
      if (old >= 0) {
        const std::size_t a = static_cast<std::size_t>(old & 0xffffffff), b = static_cast<std::size_t>(old >> 32);
        c0 = a, c1 = std::max(a, std::min(b, x0));
        d0 = std::min(b, std::max(a, x1)), d1 = b;
      }
      for (const BandOutputs& b : out.bands) {
        for (float* p : {b.s0, b.s1, b.s2, b.s3, b.dolp, b.aolp}) {
          fill_zero(p, row + c0, c1 - c0);
          fill_zero(p, row + d0, d1 - d0);
        }
      }
      fill_zero(out.mask, row + c0, c1 - c0);
      fill_zero(out.mask, row + d0, d1 - d0);
      for (std::size_t x = x0; x < x1; x += kChunk) {
        const std::size_t n = std::min(kChunk, x1 - x), i = row + x, q = x - x0;
        const float *dx = span.dx + q, *dy = span.dy + q, *dz = span.dz + q;
        const float *ux = span.ux + q, *uy = span.uy + q, *uz = span.uz + q;
        const sky::ViewRaysSoA rays{n, dx, dy, dz, ux, uy, uz};
        const float* weight = span.weight + q;
        auto planes_of = [&](std::size_t k) {
          const BandOutputs& b = out.bands[k];
          float(&sc)[4][kChunk] = scratch[k % sky::VrteSky::kMaxBands];
          return sky::StokesSoA{b.s0 ? b.s0 + i : sc[0], b.s1 ? b.s1 + i : sc[1], b.s2 ? b.s2 + i : sc[2],
                                b.s3 ? b.s3 + i : sc[3]};
        };
        // A colour vrte sky evaluates its bands together (the per-pixel geometry once); any other
        // sky band by band.
        std::array<sky::StokesSoA, sky::VrteSky::kMaxBands> planes;
        const std::size_t together_bands = std::min(out.bands.size(), planes.size());
        for (std::size_t k = 0; k < together_bands; ++k) planes[k] = planes_of(k);
        const bool together = sky::VrteSky::stokes_soa_bands(skies, rays, sun, std::span(planes).first(together_bands));
        for (std::size_t k = 0; k < out.bands.size(); ++k) {
          const BandOutputs& b = out.bands[k];
          const sky::StokesSoA s = k < planes.size() ? planes[k] : planes_of(k);
          if (!together) skies[k]->stokes_soa(rays, sun, s);
          if (projected) {
            for (std::size_t j = 0; j < n; ++j) {
              if (weight[j] == 0) continue;
              const sky::ViewRay r{{dx[j], dy[j], dz[j]}, {ux[j], uy[j], uz[j]}};
              const sky::StokesF p = stack::to_projected(*camera_, r, {s.s0[j], s.s1[j], s.s2[j], s.s3[j]});
              s.s0[j] = p.s0, s.s1[j] = p.s1, s.s2[j] = p.s2, s.s3[j] = p.s3;
            }
          }
          clear_unseen(n, weight, s);
          if (!surface_s0_.empty()) add_surface(n, surface_s0_.data() + camera_offset + i, s.s0);
          derive(n, s.s0, s.s1, s.s2, b.dolp ? b.dolp + i : nullptr, b.aolp ? b.aolp + i : nullptr);
        }
        if (out.mask) std::memcpy(out.mask + i, weight, n * sizeof(float));
      }
    }
    out.copy_rows(static_cast<std::size_t>(y0 - first) * width, static_cast<std::size_t>(y1 - y0) * width);
  });
  frame.zero_outside = key;
}

void Renderer::render_rows(std::span<const sky::SkyModel* const> skies, const sky::Sun& sun, int y0, int y1,
                           stack::Frame& band) const {
  if (options_.spp != 1) throw std::logic_error("renderer: rows are rendered at 1 sample per pixel only");
  check_skies(skies);
  if (!(0 <= y0 && y0 < y1 && y1 <= camera_->height()))
    throw std::invalid_argument("renderer: rows [" + std::to_string(y0) + ", " + std::to_string(y1) +
                                ") outside the camera's " + std::to_string(camera_->height()));
  render_cached(skies, sun, band, y0, y1);
}

// N samples per pixel: rays traced per tile and frame, Stokes averaged per pixel (samples that do
// not see the sky count as black), the mask is the covered fraction.
void Renderer::render_sampled(std::span<const sky::SkyModel* const> skies, const sky::Sun& sun,
                              stack::Frame& frame) const {
  const int w = camera_->width(), h = camera_->height();
  frame.zero_outside = 0;
  const Outputs out = prepare(frame, options_, w, h, skies.size());
  const bool projected = camera_->transport() == camera::Transport::projected;
  const std::size_t spp = static_cast<std::size_t>(options_.spp);
  struct Scratch {
    std::vector<sky::ViewRay> rays;
    std::vector<float> weight;
    std::vector<sky::StokesF> stokes;
    std::vector<float> acc;
  };
  tbb::enumerable_thread_specific<Scratch> scratch;
  const int tile = options_.tile_rows;
  tbb::parallel_for(0, (h + tile - 1) / tile, [&](int t) {
    Scratch& sc = scratch.local();
    const int y0 = t * tile, y1 = std::min(h, y0 + tile);
    const std::size_t first = static_cast<std::size_t>(y0) * static_cast<std::size_t>(w);
    const std::size_t pixels = static_cast<std::size_t>(y1 - y0) * static_cast<std::size_t>(w);
    sc.rays.resize(pixels * spp);
    sc.weight.resize(pixels * spp);
    trace_tile(y0, y1, sc.rays, sc.weight);
    sc.stokes.resize(sc.rays.size());
    for (std::size_t k = 0; k < out.bands.size(); ++k) {
      const BandOutputs& b = out.bands[k];
      skies[k]->stokes(sc.rays, sun, sc.stokes);
      if (projected) {
        for (std::size_t i = 0; i < sc.rays.size(); ++i) {
          if (sc.weight[i] > 0) sc.stokes[i] = stack::to_projected(*camera_, sc.rays[i], sc.stokes[i]);
        }
      }
      sc.acc.resize(5 * pixels);
      float* a0 = sc.acc.data();
      float* a1 = a0 + pixels;
      float* a2 = a1 + pixels;
      float* a3 = a2 + pixels;
      float* cover = a3 + pixels;
      const sky::StokesF* st = sc.stokes.data();
      const float* wt = sc.weight.data();
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
      clear_unseen(pixels, cover, sky::StokesSoA{a0, a1, a2, a3});
      if (!surface_s0_.empty()) add_surface(pixels, surface_s0_.data() + first, a0);
      derive(pixels, a0, a1, a2, b.dolp ? b.dolp + first : nullptr, b.aolp ? b.aolp + first : nullptr);
      for (auto [dst, src] : {std::pair{b.s0, a0}, {b.s1, a1}, {b.s2, a2}, {b.s3, a3}}) {
        if (dst) std::memcpy(dst + first, src, pixels * sizeof(float));
      }
      if (k == 0 && out.mask) std::memcpy(out.mask + first, cover, pixels * sizeof(float));
    }
    out.copy_rows(first, pixels);
  });
}

}  // namespace skypol::render
