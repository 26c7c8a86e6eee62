// The first step every estimator shares: check a stack, pick its DoLP channel, work out which
// pixels see sky and in which direction (camera and level frame), and the helpers built on that
// (masked disk filter, sun finding, the north/south decision, turning a pole direction into a
// PoleEstimate). Conventions are in skypole/estimate.h.
#pragma once

#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "camera/lens.h"
#include "stack/frame.h"
#include "skypole/estimate.h"

namespace skypol::skypole {

// One image per frame, borrowed, not copied: a stack's channel, or images a method made and keeps
// (its filtered DoLP). The images must outlive this, as a SkyImages' lens must outlive it. Copies
// of a SkyImages (a jackknife's views, a masked sky) then share the stack's pixels instead of
// holding the frames again, which for a day of full-resolution frames is gigabytes.
class FrameImages {
 public:
  FrameImages() = default;
  // Borrows each of `images`: a function that reads frames takes a stack's or its own.
  FrameImages(const std::vector<std::vector<float>>& images) {  // NOLINT(google-explicit-constructor)
    for (const std::vector<float>& image : images) images_.push_back(&image);
  }
  void push_back(const std::vector<float>& image) { images_.push_back(&image); }
  const std::vector<float>& operator[](std::size_t k) const { return *images_[k]; }
  std::size_t size() const { return images_.size(); }
  bool empty() const { return images_.empty(); }
  // Whether two hold the same pixels (the same values, wherever they live).
  friend bool operator==(const FrameImages& a, const FrameImages& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t k = 0; k < a.size(); ++k)
      if (a[k] != b[k]) return false;
    return true;
  }

 private:
  std::vector<const std::vector<float>*> images_;
};

// A stack reduced to what the estimators use. Images are row-major, index = y·width + x.
// It borrows the stack's lens and DoLP channels: the stack must outlive it.
struct SkyImages {
  int width = 0;
  int height = 0;
  std::string band;
  const camera::Lens* lens = nullptr;          // owned by the stack's camera
  Eigen::Matrix3d level_from_camera = Eigen::Matrix3d::Identity();
  double min_elevation_deg = 0;                // InputOptions::min_elevation_deg: the lowest sky read
  std::vector<std::uint8_t> valid;             // 1 = sky pixel usable in every frame
  std::vector<Eigen::Vector3f> ray_camera;     // unit direction per pixel (zero where !valid)
  // Directions of the sky pixels a sensor masked because its demosaic read a clipped raw value in
  // some frame (the stack's "clipped" channel, render/sensor_stage.h), if not valid otherwise.
  std::vector<Eigen::Vector3f> clipped_rays;
  FrameImages dolp;                            // per frame, the stack's channel (borrowed)
  std::vector<double> times_s;                 // seconds since frame 0
  bool times_known = false;                    // false: all frames carry the same time
  int valid_count = 0;

  std::size_t pixels() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  std::size_t frames() const { return dolp.size(); }
};

// The frames a computation reads, in order: all of a stack's (all_frames), or the ones a frame
// jackknife keeps (kept_frames: those whose keep[i] is 1).
using FrameRefs = std::vector<const stack::Frame*>;
FrameRefs all_frames(const stack::Stack& stack);
FrameRefs kept_frames(const stack::Stack& stack, const std::vector<std::uint8_t>& keep);

// The band the estimators read of a stack with these bands and channels: `options.band`, else B,
// else the first band, else that of the first DoLP channel by name, else Y.
std::string pick_band(const std::vector<std::string>& bands, const std::vector<std::string>& channels,
                      const InputOptions& options);

// Checks `stack` for `method` (which needs at least `min_frames` frames) and prepares it.
// Throws std::invalid_argument with a message naming the method, frame and channel.
// The same as sky_of(read_sky_frames(stack, options, min_frames, method), …, method).
SkyImages prepare_sky_images(const stack::Stack& stack, const InputOptions& options,
                             std::size_t min_frames, std::string_view method);

// prepare_sky_images in two steps, so that a jackknife's sub-run, which reads some of the frames
// or the sky without one sector, costs a count and not a copy of the stack prepared again
// (skypole/stack_sky.h). A pixel is valid in a set of frames when it is usable in each (finite
// DoLP, not masked) and its ray is above the elevation limit, which is geometry: so each frame's
// usability and the rays are read once, and the valid pixels of any set of frames follow.
struct SkyFrames {
  const stack::Stack* stack = nullptr;
  InputOptions options;
  SkyImages geometry;                               // sky_geometry and the band; no frames
  std::vector<std::vector<std::uint8_t>> usable;    // per frame, per pixel: finite DoLP, not masked
  std::vector<std::vector<std::uint8_t>> clipped;   // per frame, per pixel (empty: no "clipped" channel)
  // Per pixel usable in some frame: its unit ray where that is above the elevation limit (else zero).
  std::vector<Eigen::Vector3f> ray;
  std::vector<std::uint8_t> sky;                    // 1: such a ray
};
// Checks `stack` as prepare_sky_images does and reads it (throws as it does).
SkyFrames read_sky_frames(const stack::Stack& stack, const InputOptions& options, std::size_t min_frames,
                          std::string_view method);
// The prepare_sky_images of the frames whose keep[i] is 1 (nullptr: all of them) with the pixels
// whose left_out[i] is 1 masked in every frame (nullptr: none): what prepare_sky_images makes of
// frames_kept or sector_left_out (uncertainty.h), exactly. Throws as that would (too few frames
// for `method`'s min_frames, no sky left).
SkyImages sky_of(const SkyFrames& frames, const std::vector<std::uint8_t>* keep,
                 const std::vector<std::uint8_t>* left_out, std::size_t min_frames, std::string_view method);

// read_sky_frames and sky_of of every frame (no keep, no left_out) for a stack read one frame at a
// time (stack/stack_io.h read_stack_frames), whose frames are never all in memory: each frame is
// checked as it comes and its usable and clipped pixels folded into the whole sky's, so that what
// it keeps is a few images whatever the number of frames. Throws what those would, in their order.
class WholeSkyReader {
 public:
  // `stack`: the stack's shared facts (camera, bands; it must outlive this and the sky), without
  // its frames, of which there are `frames`.
  WholeSkyReader(const stack::Stack& stack, std::size_t frames, const InputOptions& options, std::size_t min_frames,
                 std::string_view method);
  // The next frame (in order).
  void add(const stack::Frame& frame);
  // After every frame: sky_of(read_sky_frames(…), nullptr, nullptr, …) without the frames' DoLP
  // (frames() == 0; times_s and times_known are set).
  SkyImages sky() const;
  std::size_t bytes() const;  // what it keeps between frames

 private:
  const stack::Stack* stack_;
  InputOptions options_;
  std::string method_;
  std::size_t frames_ = 0, read_ = 0;
  SkyImages geometry_;
  stack::Frame previous_;  // the last frame's truth (time order)
  std::vector<std::uint8_t> valid_, any_, clipped_, usable_, clipped_frame_;
  std::vector<double> times_;
};

// The "AoLP.<band>" channel of each frame (not copied: they live in the frames); throws
// std::invalid_argument naming the frame when one lacks it or has the wrong size.
std::vector<const std::vector<float>*> aolp_channels(const FrameRefs& frames, const SkyImages& sky,
                                                     std::string_view method);

// The default disk-filter radius for an image: 0.5 % of the shorter side, at least 1 px
// (≈ 5 px on the paper's 1224×1024 DoLP images, MATLAB's fspecial('disk') default radius).
double default_filter_radius_px(int width, int height);

// Circular averaging filter (a disk of `radius_px` around each pixel) that averages only valid
// pixels; invalid pixels come out 0. radius 0 copies the image. O(radius) per pixel.
std::vector<float> disk_filter(const std::vector<float>& image, const SkyImages& sky,
                               double radius_px);

// disk_filter of every frame's DoLP (frames in parallel).
std::vector<std::vector<float>> filter_all(const SkyImages& sky, double radius_px);

// Value below which `fraction` of the valid pixels of `image` lie (nth_element; 0 if none).
float valid_quantile(const std::vector<float>& image, const SkyImages& sky, double fraction);

// Which of n values (0-based, in sorted order) the q-quantile is. The callers differ on purpose:
// the estimators' robust scales are the medians their calibration is read with, the study reports
// the textbook one.
enum class QuantileRank {
  lower,    // ⌊q·(n − 1)⌋: the lower median at q = 0.5, the extremes at q = 0 and 1
  nearest,  // ⌈q·n⌉ − 1, at least 0 (nearest rank: the least value with at least q·n values ≤ it)
  upper,    // ⌊q·n⌋, at most n − 1: the upper median v[n / 2] at q = 0.5
};

// The q-quantile (0 ≤ q ≤ 1) of v at `rank`; 0 for an empty v.
double quantile(std::vector<double> v, double q, QuantileRank rank = QuantileRank::lower);

// The element of rank k (0-based, k < v.size()) of v: what std::nth_element would put at k, found
// without sorting a copy of v (a radix histogram of the leading bits picks the few elements that
// can be it), since the robust fits take the median of millions of residuals per frame and round.
double nth_smallest(const std::vector<double>& v, std::size_t k);

// Bilinear sample of `image` at continuous pixel (u, v) (pixel centres at integers); nullopt if
// any of the four neighbours is not valid.
std::optional<double> sample_bilinear(const std::vector<float>& image, const SkyImages& sky,
                                      const Eigen::Vector2d& pixel);

// The sun in each frame, found as the lowest DoLP above the horizon (the antisun, the other zero
// of DoLP, is below it in daytime). nullopt for a frame whose lowest DoLP is not sun-like (above
// a quarter of the frame's 99th percentile: the sun is not in view). The direction is the weighted
// centroid of the low-DoLP pixels within 10° of the minimum.
std::vector<std::optional<Eigen::Vector3d>> find_suns(const SkyImages& sky, const FrameImages& dolp);

struct HemisphereDecision {
  bool ok = false;
  bool is_north = true;     // the given axis direction is the NCP (true) or the SCP (false)
  std::string source;       // "sun rotation", "hint", or "sun rotation, overriding the hint: …"
  std::string why;          // when !ok
  bool from_suns = false;   // the suns' rotation decided (without a hint, or against it)
};

// The rate of the sun's hour angle, rad/s: 360° per solar day.
inline constexpr double kHourAngleRate = 2 * std::numbers::pi / 86400.0;

// The sense of the sun's turn from one frame to another `seconds_apart` later, as a sign on the
// sun-rotation vote: s_i × s_j ∝ −sin Δω·NCP, so a pair more than 12 h of hour angle apart (a
// midnight sun) sees the sun turned the short way round, against the sky: −1; otherwise +1.
double rotation_sense(double seconds_apart);

// Is `axis_camera`, the end of the pole axis above the horizon, the NCP (rather than the SCP)?
// From the sun's rotation: Σ (s_i × s_j)·axis < 0 over all pairs of frames i < j with a sun means
// NCP. A north/south hint decides when the rotation cannot; when the rotation contradicts the hint
// decisively, the data win and `source` says so (skypole/README.md, "North or south").
// times_s (seconds, one per sun; empty: unknown): each pair's vote counts with its
// rotation_sense (as great_circle's, great_circle.h step 5).
HemisphereDecision decide_hemisphere(const std::vector<std::optional<Eigen::Vector3d>>& suns,
                                     const Eigen::Vector3d& axis_camera, Hemisphere hint,
                                     const std::vector<double>& times_s = {});

// The stack's sky geometry without its images: the lens, the image size and the level frame (the
// stack's tilt and roll, or options.attitude; estimate.h) — what prepare_sky_images starts from and
// make_estimate reads.
SkyImages sky_geometry(const stack::Stack& stack, const InputOptions& options);
// The same from the camera and the first frame's truth.
SkyImages sky_geometry(const camera::Camera& camera, const scene::Truth& first, const InputOptions& options);

// Why pixel (x, y) is not usable sky, for a decline that has to say what its answer ran into:
// the edge of the field of view (outside the image, beyond the image circle, or looking below
// min_elevation_deg) or sky that the stack masked (cloud, clipped sky, an occluder, the mask
// channel, the per-pixel sky mask or a non-finite value: the lens sees it above the elevation
// limit).
enum class Unusable { field_edge, masked_sky };
Unusable why_unusable(const SkyImages& sky, int x, int y);
// The words for it in a decline: "the edge of the field of view (…)" or "masked sky (…)", and
// the cause it may point to: "the pole may be outside the field of view" or "… behind the mask".
std::string_view unusable_words(Unusable u);
std::string_view pole_beyond_words(Unusable u);

// Sets e's position to the NCP direction `ncp_camera` (camera frame): the pole above the horizon,
// north or south, α_rel, altitude, latitude, heading (or, in e.note, why it is undefined) and the
// pixel (none outside the image). Nothing else of e changes.
void place_pole(PoleEstimate& e, const SkyImages& sky, const Eigen::Vector3d& ncp_camera,
                const InputOptions& options);

// The north celestial pole of an observer at latitude_deg, in the camera frame of `sky`, for a camera
// turned to heading_rad (world = Rz(−heading)·level, estimate.h): where the methods that find the
// heading and take or fit the latitude place their pole.
Eigen::Vector3d ncp_camera_at(const SkyImages& sky, double heading_rad, double latitude_deg);

// A valid PoleEstimate placed at `ncp_camera` (place_pole).
PoleEstimate make_estimate(std::string method, const SkyImages& sky,
                           const Eigen::Vector3d& ncp_camera, const InputOptions& options);

// An invalid estimate with its reason.
PoleEstimate invalid_estimate(std::string method, std::string why);

// Pairs of frame indices (i < j) to difference.
enum class PairMode { consecutive, all, interval };
PairMode parse_pair_mode(std::string_view name);  // "consecutive" | "all" | "interval"
std::string_view pair_mode_name(PairMode m);
std::vector<std::pair<int, int>> make_pairs(int frames, PairMode mode, int interval);

// Unit vector for a float ray.
inline Eigen::Vector3d to_double(const Eigen::Vector3f& v) { return v.cast<double>(); }

}  // namespace skypol::skypole
