// Stack checking and the shared image helpers of the estimators (interfaces in sky_images.h).
#include "skypole/sky_images.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <Eigen/Geometry>

#include <tbb/parallel_for.h>

#include "camera/orientation.h"
#include "sky/sun.h"
#include "sky/time.h"
#include "sky/units.h"

namespace skypol::skypole {
namespace {

// North or south (skypole/README.md): a pole estimated within this of the horizon is the equator's
// and reported north; a hint loses to a sun-rotation vote at least this one-sided (|Σ| ≥ k·Σ|·|).
constexpr double kEquatorBandDeg = 0.1;
constexpr double kDecisiveVote = 0.6;

std::string channel_list(const stack::Frame& f) {
  std::string s;
  for (const auto& [name, data] : f.channels) s += (s.empty() ? "" : ", ") + name;
  return s.empty() ? std::string("none") : s;
}

std::string frame_label(const stack::Frame& f, std::size_t index) {
  std::ostringstream os;
  os << "frame " << index;
  if (f.truth.time.unix_seconds != 0) os << " (" << sky::format_iso8601(f.truth.time) << ")";
  return os.str();
}

const std::vector<float>* find_channel(const stack::Frame& f, const std::string& name) {
  const auto it = f.channels.find(name);
  return it == f.channels.end() ? nullptr : &it->second;
}

}  // namespace

std::string pick_band(const std::vector<std::string>& bands, const std::vector<std::string>& channels,
                      const InputOptions& options) {
  if (!options.band.empty()) return options.band;
  for (const auto& b : bands)
    if (b == "B") return b;
  if (!bands.empty()) return bands.front();
  const std::string* first = nullptr;  // the first DoLP channel by name
  for (const std::string& name : channels)
    if (name.rfind("DoLP.", 0) == 0 && (!first || name < *first)) first = &name;
  return first ? first->substr(5) : "Y";
}

FrameRefs all_frames(const stack::Stack& stack) {
  FrameRefs out;
  for (const stack::Frame& f : stack.frames) out.push_back(&f);
  return out;
}

FrameRefs kept_frames(const stack::Stack& stack, const std::vector<std::uint8_t>& keep) {
  FrameRefs out;
  for (std::size_t i = 0; i < keep.size() && i < stack.frames.size(); ++i)
    if (keep[i]) out.push_back(&stack.frames[i]);
  return out;
}

SkyImages prepare_sky_images(const stack::Stack& stack, const InputOptions& options,
                             std::size_t min_frames, std::string_view method) {
  return sky_of(read_sky_frames(stack, options, min_frames, method), nullptr, nullptr, min_frames, method);
}

namespace {

void check_min_frames(std::size_t frames, std::size_t min_frames, const std::string& m) {
  if (frames < min_frames)
    throw std::invalid_argument(m + ": needs at least " + std::to_string(min_frames) +
                                " frames, the stack has " + std::to_string(frames));
}

}  // namespace

namespace {

// The checks of the stack as a whole, before any frame is read (prepare_sky_images' order).
void check_stack(const stack::Stack& stack, std::size_t frames, std::size_t min_frames, const InputOptions& options,
                 const std::string& m) {
  if (!stack.camera)
    throw std::invalid_argument(m + ": the stack has no camera (the lens model is needed to turn "
                                    "pixels into directions)");
  check_min_frames(frames, min_frames, m);
  if (!(options.min_elevation_deg > -90 && options.min_elevation_deg < 90))
    throw std::invalid_argument(m + ": min_elevation_deg must be in (−90, 90), got " +
                                std::to_string(options.min_elevation_deg));
}

// The sky's geometry and band, from the stack's camera and its first frame.
SkyImages geometry_and_band(const stack::Stack& stack, const stack::Frame& first, const InputOptions& options,
                            const std::string& m) {
  SkyImages sky = sky_geometry(*stack.camera, first.truth, options);
  if (sky.width <= 0 || sky.height <= 0)
    throw std::invalid_argument(m + ": the camera has an empty image (" + std::to_string(sky.width) +
                                "×" + std::to_string(sky.height) + ")");
  std::vector<std::string> channels;
  for (const auto& [name, data] : first.channels) channels.push_back(name);
  sky.band = pick_band(stack.bands, channels, options);
  return sky;
}

// Frame k checked (size, DoLP and mask channels, time order after `previous`, if any) and its
// usable pixels (finite DoLP, not masked) and clipped ones (left empty without a "clipped" channel).
void read_frame(const stack::Frame& f, std::size_t k, const stack::Frame* previous, const SkyImages& sky,
                const std::string& m, std::vector<std::uint8_t>& usable, std::vector<std::uint8_t>& clipped) {
  const std::string dolp_name = "DoLP." + sky.band;
  const std::size_t n = sky.pixels();
  if (f.width != sky.width || f.height != sky.height)
    throw std::invalid_argument(m + ": " + frame_label(f, k) + " is " + std::to_string(f.width) +
                                "×" + std::to_string(f.height) + ", the camera is " +
                                std::to_string(sky.width) + "×" + std::to_string(sky.height));
  const std::vector<float>* d = find_channel(f, dolp_name);
  if (!d)
    throw std::invalid_argument(m + ": " + frame_label(f, k) + " has no \"" + dolp_name +
                                "\" channel (channels: " + channel_list(f) + ")");
  if (d->size() != n)
    throw std::invalid_argument(m + ": " + frame_label(f, k) + " channel \"" + dolp_name +
                                "\" has " + std::to_string(d->size()) + " values, expected " +
                                std::to_string(n));
  const std::vector<float>* mask = find_channel(f, "mask");
  if (mask && mask->size() != n)
    throw std::invalid_argument(m + ": " + frame_label(f, k) + " channel \"mask\" has " +
                                std::to_string(mask->size()) + " values, expected " +
                                std::to_string(n));
  usable.assign(n, 1);
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite((*d)[i])) usable[i] = 0;
    if (mask && !((*mask)[i] > 0.5f)) usable[i] = 0;
  }
  clipped.clear();
  if (const std::vector<float>* c = find_channel(f, "clipped"); c && c->size() == n) {
    clipped.resize(n, 0);
    for (std::size_t i = 0; i < n; ++i)
      if ((*c)[i] > 0.5f) clipped[i] = 1;
  }
  if (previous && f.truth.time < previous->truth.time)
    throw std::invalid_argument(m + ": frames must be in time order; " + frame_label(f, k) +
                                " is earlier than frame " + std::to_string(k - 1));
}

// The unit ray of each pixel usable in some frame (any[i]) where it is above the elevation limit
// (else zero), and 1 in `sky_out` there.
void usable_rays(const std::vector<std::uint8_t>& any, const SkyImages& sky, const InputOptions& options,
                 std::vector<Eigen::Vector3f>& ray, std::vector<std::uint8_t>& sky_out) {
  const std::size_t n = sky.pixels();
  const double min_z = std::sin(options.min_elevation_deg * kRadPerDeg);
  ray.assign(n, Eigen::Vector3f::Zero());
  sky_out.assign(n, 0);
  tbb::parallel_for(0, sky.height, [&](int y) {
    for (int x = 0; x < sky.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(sky.width) +
                            static_cast<std::size_t>(x);
      if (!any[i]) continue;
      const auto r = sky.lens->ray(Eigen::Vector2d(x, y));
      if (!r || (sky.level_from_camera * *r).z() < min_z) continue;
      ray[i] = r->normalized().cast<float>();
      sky_out[i] = 1;
    }
  });
}

// sky_of's last step: `sky` holds its valid pixels (usable in every frame kept, not left out) and
// its frames' times; its rays, valid count and clipped rays follow from the stack's rays
// (usable_rays) and the pixels clipped in some frame kept (empty: none). Throws when no sky is left.
void finish_sky(SkyImages& sky, const std::vector<std::uint8_t>& clipped, const std::vector<Eigen::Vector3f>& ray,
                const std::vector<std::uint8_t>& sky_flag, const InputOptions& options, const std::string& m) {
  const std::size_t n = sky.pixels();
  sky.ray_camera.assign(n, Eigen::Vector3f::Zero());
  for (std::size_t i = 0; i < n; ++i) {
    if (!sky.valid[i]) continue;
    if (!sky_flag[i]) {
      sky.valid[i] = 0;
      continue;
    }
    sky.ray_camera[i] = ray[i];
    ++sky.valid_count;
  }
  // The clipped sky, in pixel order, above the same elevation: no method reads it (it is not
  // valid), but the cloud gate counts it as sky it could not read (cloud_share.h).
  const double min_z = std::sin(options.min_elevation_deg * kRadPerDeg);
  for (std::size_t i = 0; i < clipped.size(); ++i) {
    if (!clipped[i] || sky.valid[i]) continue;
    const int x = static_cast<int>(i % static_cast<std::size_t>(sky.width));
    const int y = static_cast<int>(i / static_cast<std::size_t>(sky.width));
    const auto r = sky.lens->ray(Eigen::Vector2d(x, y));
    if (r && (sky.level_from_camera * *r).z() >= min_z) sky.clipped_rays.push_back(r->normalized().cast<float>());
  }
  if (sky.valid_count == 0 && !sky.clipped_rays.empty())
    throw std::invalid_argument(m + ": the sensor clipped the sky: no sky pixel above " +
                                std::to_string(options.min_elevation_deg) +
                                "° elevation escapes clipping in every frame (channel \"clipped\"); a shorter "
                                "exposure or a lower gain reads it");
  if (sky.valid_count == 0)
    throw std::invalid_argument(m + ": no pixel sees sky above " + std::to_string(options.min_elevation_deg) +
                                "° elevation (check the mask channel, the lens and the tilt)");
}

// Frames' times as sky_of sets them: seconds since the first, and whether they differ.
void set_times(SkyImages& sky, const std::vector<double>& unix_seconds) {
  const double t0 = unix_seconds.front();
  sky.times_known = unix_seconds.back() != t0;
  for (const double t : unix_seconds) sky.times_s.push_back(t - t0);
}

}  // namespace

SkyFrames read_sky_frames(const stack::Stack& stack, const InputOptions& options, std::size_t min_frames,
                          std::string_view method) {
  const std::string m(method);
  check_stack(stack, stack.frames.size(), min_frames, options, m);
  SkyFrames out;
  out.stack = &stack;
  out.options = options;
  out.geometry = geometry_and_band(stack, stack.frames.front(), options, m);
  const SkyImages& sky = out.geometry;
  std::vector<std::uint8_t> any(sky.pixels(), 0);  // usable in some frame
  for (std::size_t k = 0; k < stack.frames.size(); ++k) {
    std::vector<std::uint8_t>& usable = out.usable.emplace_back();
    read_frame(stack.frames[k], k, k > 0 ? &stack.frames[k - 1] : nullptr, sky, m, usable,
               out.clipped.emplace_back());
    for (std::size_t i = 0; i < usable.size(); ++i) any[i] |= usable[i];
  }
  usable_rays(any, sky, options, out.ray, out.sky);
  return out;
}

SkyImages sky_of(const SkyFrames& frames, const std::vector<std::uint8_t>* keep,
                 const std::vector<std::uint8_t>* left_out, std::size_t min_frames, std::string_view method) {
  const std::string m(method);
  const stack::Stack& stack = *frames.stack;
  std::vector<std::size_t> kept;
  for (std::size_t k = 0; k < stack.frames.size(); ++k)
    if (!keep || (*keep)[k]) kept.push_back(k);
  check_min_frames(kept.size(), min_frames, m);

  SkyImages sky = frames.geometry;
  const std::size_t n = sky.pixels();
  sky.valid.assign(n, 1);
  std::vector<std::uint8_t> clipped;  // 1: a sky pixel the sensor masked for clipping, in some frame
  std::vector<double> times;
  for (const std::size_t k : kept) {
    const std::vector<std::uint8_t>& usable = frames.usable[k];
    for (std::size_t i = 0; i < n; ++i) sky.valid[i] &= usable[i];
    if (const std::vector<std::uint8_t>& c = frames.clipped[k]; !c.empty()) {
      clipped.resize(n, 0);
      for (std::size_t i = 0; i < n; ++i) clipped[i] |= c[i];
    }
    sky.dolp.push_back(stack.frames[k].channels.at("DoLP." + sky.band));  // borrowed
    times.push_back(stack.frames[k].truth.time.unix_seconds);
  }
  if (left_out)
    for (std::size_t i = 0; i < n; ++i)
      if ((*left_out)[i]) sky.valid[i] = 0;
  set_times(sky, times);
  finish_sky(sky, clipped, frames.ray, frames.sky, frames.options, m);
  return sky;
}

WholeSkyReader::WholeSkyReader(const stack::Stack& stack, std::size_t frames, const InputOptions& options,
                               std::size_t min_frames, std::string_view method)
    : stack_(&stack), options_(options), method_(method), frames_(frames) {
  check_stack(stack, frames, min_frames, options, method_);
}

void WholeSkyReader::add(const stack::Frame& frame) {
  const std::size_t k = read_;
  if (k == 0) {
    geometry_ = geometry_and_band(*stack_, frame, options_, method_);
    valid_.assign(geometry_.pixels(), 1);
    any_.assign(geometry_.pixels(), 0);
  }
  read_frame(frame, k, k > 0 ? &previous_ : nullptr, geometry_, method_, usable_, clipped_frame_);
  for (std::size_t i = 0; i < usable_.size(); ++i) {
    valid_[i] &= usable_[i];
    any_[i] |= usable_[i];
  }
  if (!clipped_frame_.empty()) {
    clipped_.resize(clipped_frame_.size(), 0);
    for (std::size_t i = 0; i < clipped_frame_.size(); ++i) clipped_[i] |= clipped_frame_[i];
  }
  previous_.truth = frame.truth;
  times_.push_back(frame.truth.time.unix_seconds);
  ++read_;
}

std::size_t WholeSkyReader::bytes() const {
  return valid_.capacity() + any_.capacity() + clipped_.capacity() + usable_.capacity() + clipped_frame_.capacity() +
         times_.capacity() * sizeof(double);
}

SkyImages WholeSkyReader::sky() const {
  if (read_ != frames_)
    throw std::logic_error("WholeSkyReader: " + std::to_string(read_) + " of " + std::to_string(frames_) +
                           " frames read");
  SkyImages sky = geometry_;
  sky.valid = valid_;
  set_times(sky, times_);
  std::vector<Eigen::Vector3f> ray;
  std::vector<std::uint8_t> sky_flag;
  usable_rays(any_, sky, options_, ray, sky_flag);
  finish_sky(sky, clipped_, ray, sky_flag, options_, method_);
  return sky;
}

std::vector<const std::vector<float>*> aolp_channels(const FrameRefs& frames, const SkyImages& sky,
                                                     std::string_view method) {
  const std::string name = "AoLP." + sky.band;
  std::vector<const std::vector<float>*> out;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const stack::Frame& f = *frames[k];
    const std::vector<float>* a = find_channel(f, name);
    if (!a)
      throw std::invalid_argument(std::string(method) + ": " + frame_label(f, k) + " has no \"" +
                                  name + "\" channel (channels: " + channel_list(f) + ")");
    if (a->size() != sky.pixels())
      throw std::invalid_argument(std::string(method) + ": " + frame_label(f, k) + " channel \"" +
                                  name + "\" has the wrong size");
    out.push_back(a);
  }
  return out;
}

double default_filter_radius_px(int width, int height) {
  return std::max(1.0, std::round(0.005 * std::min(width, height)));
}

std::vector<float> disk_filter(const std::vector<float>& image, const SkyImages& sky,
                               double radius_px) {
  const int w = sky.width, h = sky.height;
  const std::size_t W = static_cast<std::size_t>(w);
  std::vector<float> out(image.size(), 0.0f);
  if (!(radius_px >= 0) || !std::isfinite(radius_px))
    throw std::invalid_argument("disk filter radius must be ≥ 0, got " + std::to_string(radius_px));
  const int r = static_cast<int>(std::floor(radius_px));
  if (r < 1) {
    for (std::size_t i = 0; i < image.size(); ++i) out[i] = sky.valid[i] ? image[i] : 0.0f;
    return out;
  }
  // Row prefix sums of value·valid and valid; row y occupies (W + 1) entries.
  std::vector<double> pv((W + 1) * static_cast<std::size_t>(h), 0.0);
  std::vector<double> pm(pv.size(), 0.0);
  for (int y = 0; y < h; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * (W + 1);
    const std::size_t src = static_cast<std::size_t>(y) * W;
    for (std::size_t x = 0; x < W; ++x) {
      const bool v = sky.valid[src + x] != 0;
      pv[row + x + 1] = pv[row + x] + (v ? static_cast<double>(image[src + x]) : 0.0);
      pm[row + x + 1] = pm[row + x] + (v ? 1.0 : 0.0);
    }
  }
  std::vector<int> half(static_cast<std::size_t>(2 * r + 1));
  for (int dy = -r; dy <= r; ++dy)
    half[static_cast<std::size_t>(dy + r)] =
        static_cast<int>(std::floor(std::sqrt(radius_px * radius_px - dy * dy) + 1e-9));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * W + static_cast<std::size_t>(x);
      if (!sky.valid[i]) continue;
      double s = 0, c = 0;
      for (int dy = -r; dy <= r; ++dy) {
        const int yy = y + dy;
        if (yy < 0 || yy >= h) continue;
        const int hw = half[static_cast<std::size_t>(dy + r)];
        const std::size_t row = static_cast<std::size_t>(yy) * (W + 1);
        const std::size_t x0 = static_cast<std::size_t>(std::max(0, x - hw));
        const std::size_t x1 = static_cast<std::size_t>(std::min(w - 1, x + hw)) + 1;
        s += pv[row + x1] - pv[row + x0];
        c += pm[row + x1] - pm[row + x0];
      }
      out[i] = c > 0 ? static_cast<float>(s / c) : 0.0f;
    }
  return out;
}

std::vector<std::vector<float>> filter_all(const SkyImages& sky, double radius_px) {
  std::vector<std::vector<float>> out(sky.frames());
  tbb::parallel_for(std::size_t{0}, sky.frames(),
                    [&](std::size_t t) { out[t] = disk_filter(sky.dolp[t], sky, radius_px); });
  return out;
}

float valid_quantile(const std::vector<float>& image, const SkyImages& sky, double fraction) {
  std::vector<float> v;
  v.reserve(static_cast<std::size_t>(sky.valid_count));
  for (std::size_t i = 0; i < image.size(); ++i)
    if (sky.valid[i]) v.push_back(image[i]);
  if (v.empty()) return 0.0f;
  const double f = std::clamp(fraction, 0.0, 1.0);
  const auto k = static_cast<std::size_t>(std::floor(f * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

double quantile(std::vector<double> v, double q, QuantileRank rank) {
  if (v.empty()) return 0.0;
  const std::size_t n = v.size();
  switch (rank) {
    case QuantileRank::lower: return nth_smallest(v, static_cast<std::size_t>(q * static_cast<double>(n - 1)));
    case QuantileRank::nearest: {
      const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(n)));
      return nth_smallest(v, std::clamp<std::size_t>(k, 1, n) - 1);
    }
    case QuantileRank::upper:
      return nth_smallest(v, std::min(static_cast<std::size_t>(q * static_cast<double>(n)), n - 1));
  }
  return 0.0;
}

double nth_smallest(const std::vector<double>& v, std::size_t k) {
  const auto by_sorting = [&] {
    std::vector<double> w = v;
    std::nth_element(w.begin(), w.begin() + static_cast<std::ptrdiff_t>(k), w.end());
    return w[k];
  };
  if (v.size() < 4096) return by_sorting();
  // A double's bits as an unsigned key in the order of its value (negatives reversed).
  const auto key = [](double x) {
    const auto b = std::bit_cast<std::uint64_t>(x);
    return (b >> 63) ? ~b : b | (std::uint64_t{1} << 63);
  };
  constexpr int kShift = 48;  // buckets by sign, exponent and 4 bits of mantissa
  std::vector<std::uint32_t> count(std::size_t{1} << (64 - kShift), 0);
  for (const double x : v) {
    if (std::isnan(x)) return by_sorting();  // where nth_element's answer is its own
    ++count[key(x) >> kShift];
  }
  std::size_t bucket = 0, below = 0;
  while (below + count[bucket] <= k) below += count[bucket++];
  std::vector<double> in;
  in.reserve(count[bucket]);
  for (const double x : v)
    if ((key(x) >> kShift) == bucket) in.push_back(x);
  const auto at = in.begin() + static_cast<std::ptrdiff_t>(k - below);
  std::nth_element(in.begin(), at, in.end());
  // −0 and +0 are equal to nth_element, which may return either; the key orders them.
  return *at == 0 ? by_sorting() : *at;
}

std::optional<double> sample_bilinear(const std::vector<float>& image, const SkyImages& sky,
                                      const Eigen::Vector2d& pixel) {
  const double fx = std::floor(pixel.x()), fy = std::floor(pixel.y());
  if (!(fx >= 0 && fy >= 0 && fx + 1 < sky.width && fy + 1 < sky.height)) {
    // Exactly on the last row/column: allow it when the point is a pixel centre.
    return std::nullopt;
  }
  const std::size_t x = static_cast<std::size_t>(fx), y = static_cast<std::size_t>(fy);
  const std::size_t W = static_cast<std::size_t>(sky.width);
  const std::size_t i00 = y * W + x, i10 = i00 + 1, i01 = i00 + W, i11 = i01 + 1;
  if (!sky.valid[i00] || !sky.valid[i10] || !sky.valid[i01] || !sky.valid[i11]) return std::nullopt;
  const double ax = pixel.x() - fx, ay = pixel.y() - fy;
  const auto at = [&](std::size_t i) { return static_cast<double>(image[i]); };
  return (1 - ay) * ((1 - ax) * at(i00) + ax * at(i10)) + ay * ((1 - ax) * at(i01) + ax * at(i11));
}

std::vector<std::optional<Eigen::Vector3d>> find_suns(const SkyImages& sky, const FrameImages& dolp) {
  std::vector<std::optional<Eigen::Vector3d>> suns;
  for (std::size_t t = 0; t < dolp.size(); ++t) {
    const std::vector<float>& img = dolp[t];
    std::size_t best = 0;
    float best_v = std::numeric_limits<float>::infinity();
    for (std::size_t i = 0; i < img.size(); ++i)
      if (sky.valid[i] && img[i] < best_v) {
        best_v = img[i];
        best = i;
      }
    const float p99 = valid_quantile(img, sky, 0.99);
    if (!(best_v < 0.25f * p99)) {
      suns.emplace_back(std::nullopt);
      continue;
    }
    // Refine: centroid of the directions within 10° of the minimum, weighted by how far below
    // 10 % of the p99 their DoLP lies (the sun's neighbourhood is flat, DoLP ∝ γ²: one pixel is noisy).
    const Eigen::Vector3d s0 = to_double(sky.ray_camera[best]);
    const double cut = 0.1 * static_cast<double>(p99);
    const double cos10 = std::cos(10 * kRadPerDeg);
    Eigen::Vector3d acc = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < img.size(); ++i) {
      const double v = img[i];
      if (!sky.valid[i] || !(v < cut)) continue;
      const Eigen::Vector3d d = to_double(sky.ray_camera[i]);
      if (d.dot(s0) < cos10) continue;
      acc += (cut - v) * d;
    }
    suns.emplace_back(acc.norm() > 0 ? Eigen::Vector3d(acc.normalized()) : s0);
  }
  return suns;
}

namespace {

// The sun-rotation vote over all pairs of frames with a sun (i earlier than j): long baselines
// dominate, so noise in the individual sun positions averages out. vote < 0: the axis is the NCP.
struct RotationVote {
  double vote = 0, total = 0;
  int used = 0;
};

RotationVote rotation_vote(const std::vector<std::optional<Eigen::Vector3d>>& suns,
                           const Eigen::Vector3d& axis_camera, const std::vector<double>& times_s) {
  const bool timed = times_s.size() == suns.size();
  RotationVote v;
  for (std::size_t i = 0; i < suns.size(); ++i)
    for (std::size_t j = i + 1; j < suns.size(); ++j) {
      if (!suns[i] || !suns[j]) continue;
      const Eigen::Vector3d c = suns[i]->cross(*suns[j]);
      v.vote += (timed ? rotation_sense(times_s[j] - times_s[i]) : 1.0) * c.dot(axis_camera);
      v.total += c.norm();
      ++v.used;
    }
  return v;
}

std::string hint_against_data(bool hint_north, bool data_north) {
  return std::string("sun rotation, overriding the hint: hemisphere = ") +
         (hint_north ? "north" : "south") + " was given, but the sun's rotation is decisive and says " +
         (data_north ? "north" : "south");
}

}  // namespace

double rotation_sense(double seconds_apart) {
  return std::sin(kHourAngleRate * seconds_apart) < 0 ? -1.0 : 1.0;
}

HemisphereDecision decide_hemisphere(const std::vector<std::optional<Eigen::Vector3d>>& suns,
                                     const Eigen::Vector3d& axis_camera, Hemisphere hint,
                                     const std::vector<double>& times_s) {
  HemisphereDecision d;
  const RotationVote v = rotation_vote(suns, axis_camera, times_s);
  const bool seen = v.used > 0 && v.total >= std::sin(0.5 * kRadPerDeg);
  if (hint != Hemisphere::automatic) {
    // The axis is the end above the horizon (see the header): the NCP for a northern observer.
    // A hint decides unless the data contradict it decisively (skypole/README.md, "North or
    // south"): then the data win and the source says so.
    d.ok = true;
    d.is_north = hint == Hemisphere::north;
    d.source = "hint";
    if (seen && std::abs(v.vote) >= kDecisiveVote * v.total && (v.vote < 0) != d.is_north) {
      d.source = hint_against_data(d.is_north, v.vote < 0);
      d.is_north = v.vote < 0;
      d.from_suns = true;
    }
    return d;
  }
  d.source = "sun rotation";
  if (v.used == 0) {
    d.why = "cannot tell north from south: the sun (lowest DoLP above the horizon) is in view in "
            "fewer than two frames; pass hemisphere = north or south";
    return d;
  }
  if (!seen) {
    d.why = "cannot tell north from south: the sun's motion between the frames is too small to give "
            "the sense of rotation; pass hemisphere = north or south";
    return d;
  }
  if (std::abs(v.vote) < 0.3 * v.total) {
    // The sun moved enough, but the suns found in the frames do not turn one way: they are
    // misplaced (noise, a low sun, cloud over the sun's side of the sky), not too close.
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "cannot tell north from south: the suns found in the frames turn both ways about the "
                  "axis (net %.0f %% of their motion one way, 30 %% needed); the sun positions are "
                  "unreliable (noise, a low sun or cloud); pass hemisphere = north or south",
                  v.total > 0 ? 100 * std::abs(v.vote) / v.total : 0.0);
    d.why = buf;
    return d;
  }
  d.ok = true;
  d.is_north = v.vote < 0;
  d.from_suns = true;
  return d;
}

SkyImages sky_geometry(const stack::Stack& stack, const InputOptions& options) {
  return sky_geometry(*stack.camera, stack.frames.front().truth, options);
}

SkyImages sky_geometry(const camera::Camera& camera, const scene::Truth& first, const InputOptions& options) {
  SkyImages sky;
  sky.lens = &camera.lens();
  sky.width = camera.width();
  sky.height = camera.height();
  const Attitude att = options.attitude.value_or(Attitude{first.tilt_deg, first.roll_deg});
  sky.level_from_camera = camera::world_from_heading_tilt_roll(0.0, att.tilt_deg, att.roll_deg);
  sky.min_elevation_deg = options.min_elevation_deg;
  return sky;
}

Unusable why_unusable(const SkyImages& sky, int x, int y) {
  if (x < 0 || y < 0 || x >= sky.width || y >= sky.height) return Unusable::field_edge;
  const auto r = sky.lens->ray(Eigen::Vector2d(x, y));
  if (!r || (sky.level_from_camera * r->normalized()).z() < std::sin(sky.min_elevation_deg * kRadPerDeg))
    return Unusable::field_edge;
  return Unusable::masked_sky;
}

std::string_view unusable_words(Unusable u) {
  return u == Unusable::field_edge
             ? "the edge of the field of view (image circle, image border or elevation limit)"
             : "masked sky (cloud, clipped or unpolarized sky, an occluder or the mask channel)";
}

std::string_view pole_beyond_words(Unusable u) {
  return u == Unusable::field_edge ? "the pole may be outside the field of view" : "the pole may be behind the mask";
}

void place_pole(PoleEstimate& e, const SkyImages& sky, const Eigen::Vector3d& ncp_camera,
                const InputOptions& options) {
  const Eigen::Vector3d ncp = ncp_camera.normalized();
  const Eigen::Vector3d ncp_level = sky.level_from_camera * ncp;
  // The equator rule (docs/conventions.md): north unless the estimate puts the NCP more than
  // kEquatorBandDeg below the horizon. An estimator cannot tell latitude 0 from ±0.001°, so an
  // observer on the equator is reported north (the NCP, possibly a hair below the horizon, with
  // its latitude as measured) rather than flipping to south on the estimate's noise.
  e.is_north = ncp_level.z() >= -std::sin(kEquatorBandDeg * kRadPerDeg);
  e.pole_camera = e.is_north ? ncp : Eigen::Vector3d(-ncp);
  e.pole_level = sky.level_from_camera * e.pole_camera;
  const Eigen::Vector3d& p = e.pole_level;
  const double horiz = std::hypot(p.x(), p.y());
  e.altitude_deg = std::atan2(p.z(), horiz) / kRadPerDeg;
  e.azimuth_rel_deg = horiz > 0 ? wrap360(std::atan2(p.x(), p.y()) / kRadPerDeg) : 0.0;
  e.latitude_deg = e.is_north ? e.altitude_deg : -e.altitude_deg;
  if (90.0 - e.altitude_deg < options.heading_undefined_within_deg) {
    e.heading_deg = std::nullopt;
    e.note = "bearing undefined: the celestial pole is within " +
             std::to_string(options.heading_undefined_within_deg) +
             "° of the zenith (observer at a geographic pole)";
  } else {
    e.heading_deg = wrap360((e.is_north ? 0.0 : 180.0) - e.azimuth_rel_deg);
  }
  e.pixel = std::nullopt;
  const auto px = sky.lens->project(e.pole_camera);
  if (px && px->x() >= -0.5 && px->y() >= -0.5 && px->x() <= sky.width - 0.5 &&
      px->y() <= sky.height - 0.5)
    e.pixel = *px;
}

Eigen::Vector3d ncp_camera_at(const SkyImages& sky, double heading_rad, double latitude_deg) {
  const Eigen::Matrix3d world_from_level =
      Eigen::AngleAxisd(-heading_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return sky.level_from_camera.transpose() * world_from_level.transpose() * sky::north_celestial_pole(latitude_deg);
}

PoleEstimate make_estimate(std::string method, const SkyImages& sky,
                           const Eigen::Vector3d& ncp_camera, const InputOptions& options) {
  PoleEstimate e;
  e.method = std::move(method);
  e.valid = true;
  place_pole(e, sky, ncp_camera, options);
  return e;
}

PoleEstimate invalid_estimate(std::string method, std::string why) {
  PoleEstimate e;
  e.method = std::move(method);
  e.valid = false;
  e.why_invalid = std::move(why);
  return e;
}

PairMode parse_pair_mode(std::string_view name) {
  if (name == "consecutive") return PairMode::consecutive;
  if (name == "all") return PairMode::all;
  if (name == "interval") return PairMode::interval;
  throw std::invalid_argument("unknown pair mode \"" + std::string(name) +
                              "\" (expected one of consecutive, all, interval)");
}

std::string_view pair_mode_name(PairMode m) {
  switch (m) {
    case PairMode::consecutive: return "consecutive";
    case PairMode::all: return "all";
    case PairMode::interval: return "interval";
  }
  return "?";
}

std::vector<std::pair<int, int>> make_pairs(int frames, PairMode mode, int interval) {
  std::vector<std::pair<int, int>> pairs;
  switch (mode) {
    case PairMode::consecutive:
      for (int i = 0; i + 1 < frames; ++i) pairs.emplace_back(i, i + 1);
      break;
    case PairMode::all:
      for (int i = 0; i < frames; ++i)
        for (int j = i + 1; j < frames; ++j) pairs.emplace_back(i, j);
      break;
    case PairMode::interval:
      if (interval < 1)
        throw std::invalid_argument("pair interval must be ≥ 1 frame, got " + std::to_string(interval));
      for (int i = 0; i + interval < frames; ++i) pairs.emplace_back(i, i + interval);
      break;
  }
  return pairs;
}

}  // namespace skypol::skypole
