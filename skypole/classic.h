// The SkyPole algorithm as the paper runs it (Kronland-Martinet et al., PNAS 2023, Fig. 1D and
// Materials and Methods), every step a parameter with the paper's choice as its default:
//   1. circular averaging filter on each DoLP image (masked pixels excluded from the average);
//   2. absolute DoLP differences between pairs of frames (consecutive by default, as Fig. 1D);
//   3. threshold, binarize: low difference (≤ threshold) = 1;
//   4. sum of the binary images;
//   5. maximum of the sum: the pole, where every difference is low (the radial invariance circles
//      of all pairs meet only there, SI "The NCP is the only point ...");
//   6. pixel → direction through the lens → level frame → α_rel, altitude → heading, latitude
//      (conventions in skypole/estimate.h); north/south from the sun's rotation.
// Ties (step 5): the pixels that reach the maximum form one or more 8-connected blobs; the pole is
// the largest blob (most pixels; on equal size the one with the smallest first pixel index), at the
// normalised mean of its pixels' unit directions (its centroid on the sphere).
// The paper gives no threshold; the default is relative: 5 % of each difference image's 99th
// percentile, so it behaves the same for Pmax = 1 or 0.7 and for any frame interval, but never
// below 3σ of the difference image's noise (else noise decides the binary images: on the paper's
// day with 1 % sensor noise the plain 5 % threshold misses by 6.6°, with the floor by 0.19°).
// An absolute threshold (e.g. 0.01 DoLP, 0.07° noise-free) is ThresholdMode::absolute.
// Validity: the maximal blob must not touch the edge of the usable image (image circle, mask,
// horizon); if it does, the estimate is invalid and says what the blob ran into and why: diffuse
// (not localised: a short or noisy window), or compact at masked sky or at the edge of the field
// of view, where the pole may lie beyond (classic.cpp). residual_deg = RMS angular radius of the
// blob. Uncertainty: skypole/uncertainty.h.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "stack/frame.h"
#include "skypole/estimate.h"
#include "skypole/sky_images.h"

namespace skypol::skypole {

enum class ThresholdMode { absolute, relative };
ThresholdMode parse_threshold_mode(std::string_view name);  // "absolute" | "relative"
std::string_view threshold_mode_name(ThresholdMode m);

struct ClassicParams {
  InputOptions input;
  // Disk radius of the averaging filter in pixels; nullopt → default_filter_radius_px (0.5 % of the
  // shorter image side, ≥ 1). 0 disables the filter.
  std::optional<double> filter_radius_px;
  PairMode pairs = PairMode::consecutive;
  int interval = 1;  // frames between the two of a pair, for PairMode::interval
  ThresholdMode threshold_mode = ThresholdMode::relative;
  double threshold = 0.05;  // absolute: DoLP units; relative: fraction of each |ΔDoLP|'s p99
  // relative mode only: the threshold is at least noise_floor × the difference image's noise σ
  // (robust estimate, classic.cpp); 0 turns the floor off (the paper's plain threshold).
  double noise_floor = 3.0;
  bool keep_intermediates = false;
};

// The images of each step, for inspection (all width×height, row-major; invalid pixels 0).
struct ClassicImages {
  int width = 0;
  int height = 0;
  std::vector<std::pair<int, int>> pairs;         // frame indices of each difference
  std::vector<std::vector<float>> filtered;       // per frame
  std::vector<std::vector<float>> differences;    // |filtered_i − filtered_j| per pair
  std::vector<float> thresholds;                  // the threshold applied to each difference
  std::vector<std::vector<std::uint8_t>> binaries;  // 1 = difference ≤ threshold
  std::vector<float> sum;                         // sum of the binaries
  std::vector<std::uint8_t> maximum;              // 1 = pixel of the chosen maximal blob
};

struct ClassicResult {
  PoleEstimate estimate;
  ClassicImages images;  // empty unless keep_intermediates
};

// Needs at least 3 frames (2 differences; PairMode::interval: interval + 2 frames).
// Throws std::invalid_argument for unusable input (estimate.h, "Failures").
// The same as classic_from(prepare_classic(stack, params), params).
ClassicResult estimate_classic(const stack::Stack& stack, const ClassicParams& params = {});

// The method in two parts, so that a jackknife over frames refilters nothing: step 1 (the filter,
// with reading the sky images most of the cost) once per frame, steps 2–6 on the frames kept.
struct ClassicPrepared {
  SkyImages sky;
  double radius_px = 0;
  std::vector<std::vector<float>> filtered;  // step 1, per frame
  double seconds = 0;
};
ClassicPrepared prepare_classic(const stack::Stack& stack, const ClassicParams& params);
// The same on a sky already prepared for classic's frames (StackSky::sky(classic_min_frames(params),
// "classic")), which borrows the stack's DoLP: the stack must outlive the result.
ClassicPrepared prepare_classic(SkyImages sky, const ClassicParams& params);
// The frames classic needs: 3 (2 differences), or interval + 2 for PairMode::interval.
std::size_t classic_min_frames(const ClassicParams& params);
// Steps 2–6 on the frames `keep_frame` keeps (nullptr or empty: all), paired among themselves as
// a stack of only those frames would be: the answer a sub-stack gives, without its re-reading.
ClassicResult classic_from(const ClassicPrepared& prepared, const ClassicParams& params,
                           const std::vector<std::uint8_t>* keep_frame = nullptr);

// Steps 2–6 of several runs at once (the whole stack and a frame jackknife's subsets), fed one
// filtered frame at a time, so that a stack read part by part need not hold its frames: a filtered
// frame is kept only until the last pair that reads it (two frames back for consecutive pairs,
// `interval` for PairMode::interval, every frame for PairMode::all), each distinct pair is
// differenced once, and each run keeps its count of low differences per pixel. Each answer is
// classic_from(prepare_classic(…), params, &keep) of the run's keep, bit for bit.
class ClassicRuns {
 public:
  // `sky`: the whole stack's prepared sky (it must outlive this; its frames are not read);
  // `frames`: how many will be added; keeps: one run each (empty: every frame). Throws as
  // prepare_classic and classic_from would (parameters, too few frames for a run).
  ClassicRuns(const SkyImages& sky, const ClassicParams& params, std::size_t frames,
              const std::vector<std::vector<std::uint8_t>>& keeps);
  // The next frame's DoLP, disk-filtered on `sky` with radius_px() (step 1).
  void add(std::vector<float> filtered);
  double radius_px() const { return radius_; }
  // find_suns of frame f's filtered DoLP, once it is added.
  const std::optional<Eigen::Vector3d>& sun(std::size_t f) const { return suns_[f]; }
  // Run r's answer, once every frame is added.
  PoleEstimate answer(std::size_t r) const;
  std::size_t bytes() const;  // what it keeps between frames

 private:
  struct Pair {
    int a = 0, b = 0;                // frames, a < b
    std::vector<std::size_t> runs;  // the runs that read it
  };
  struct Run {
    std::vector<int> frames;
    std::size_t pairs = 0;
    // Per pixel, how many of its pairs differ little there: in 16 bits while it has fewer than
    // 65536 pairs (the other vector stays empty).
    std::vector<std::uint16_t> count16;
    std::vector<std::uint32_t> count;
  };
  const SkyImages* sky_;
  ClassicParams params_;
  double radius_;
  std::size_t frames_, added_ = 0, next_pair_ = 0;
  std::vector<Run> runs_;
  std::vector<Pair> pairs_;                  // by their later frame
  std::vector<int> last_use_;                // per frame, the last frame whose pairs read it
  std::vector<std::vector<float>> filtered_;  // per frame, while a pair will read it
  std::vector<std::optional<Eigen::Vector3d>> suns_;  // per frame, find_suns of its filtered DoLP
};

}  // namespace skypol::skypole
