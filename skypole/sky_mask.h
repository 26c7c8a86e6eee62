// The per-pixel sky mask the fitting methods share (great_circle, invariance, sun_vector,
// sun_dolp; classic never uses it, to stay the paper's algorithm): the pixels a clear
// single-scattering sky cannot explain are left out, rather than the whole sky declined
// (the cloud gate, cloud_share.h).
//
// Per frame, the sun s is fitted robustly (from the AoLP when the stack has it, E ⟂ s; else from a
// Rayleigh fit of the DoLP), then each sky pixel d is judged against that frame's clear sky:
//  - low DoLP: where the Rayleigh shape g = (1 − c²)/(1 + c²), c = s·d, is at least `min_shape`
//    (≈ 43° or more from the sun and antisun, away from the neutral points), DoLP/g below
//    `low_ratio` of the frame's 90th percentile of DoLP/g. A cloud of opacity α scales DoLP by
//    1 − α (sky/clouds.h), so α > ½ is caught whatever the sky's Pmax;
//  - wrong AoLP: E more than max(`aolp_min_deg`, 4 robust σ) out of the plane ⟂ s (DoLP ≥ 0.05);
//  - saturated (S0 ≥ `saturated` × the frame's largest S0) or dark (S0 ≤ `dark` × its median),
//    when the stack has "S0.<band>": the DoLP and AoLP of clipped or noise-floor pixels are wrong.
// A pixel is masked when it was bad in at least `bad_share` of the frames that could judge it:
// clouds stand still while the sky's pattern turns with the sun, so a pixel that is bad in a
// quarter of its frames is inconsistent over time, and every method here fits all frames at once.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "camera/camera.h"
#include "stack/frame.h"
#include "skypole/e_vectors.h"
#include "skypole/sky_images.h"

namespace skypol::skypole {

struct SkyMaskParams {
  double min_shape = 0.3;
  double low_ratio = 0.5;
  double aolp_min_deg = 10.0;
  double saturated = 0.98;
  double dark = 0.05;
  double bad_share = 0.25;
};

struct SkyMask {
  std::vector<std::uint8_t> masked;  // 1 = left out (only ever a valid sky pixel)
  int masked_count = 0;
  int low_dolp = 0, wrong_aolp = 0, saturated = 0, dark = 0;  // pixels bad at least once, per cause
  std::vector<std::optional<Eigen::Vector3d>> suns;            // per frame, the suns it judged by
};

// What compute_sky_mask learns of each frame on its own: the sun it judges the frame by, and per
// pixel whether the frame could judge it and why it was bad. A frame's judgments depend on that
// frame and on which pixels are valid, not on the other frames, so that the mask of any subset of
// the frames of one sky follows from them alone (mask_from_judgments): a frame jackknife's mask
// costs a count, not a refit.
struct SkyJudgments {
  enum : std::uint8_t { kLow = 1, kAolp = 2, kSat = 4, kDark = 8, kJudged = 16 };
  bool have_aolp = false, have_s0 = false;            // every frame judged had the channel
  std::vector<std::optional<Eigen::Vector3d>> suns;  // per frame, the sun it judged by
  std::vector<std::vector<std::uint8_t>> marks;      // per frame, per pixel: kJudged and the causes
};
// `frames` are the frames of `sky` (sky.dolp[f] is frames[f]'s). e_vectors (optional, one per
// frame, nullptr: computed here): each frame's E-vectors (e_vectors.h) of a sky whose valid pixels
// include sky's, at a min_dolp of at most 0.05. aolp_suns (optional, when the frames have AoLP):
// each frame's sun_from_aolp on `sky` at DoLP ≥ 0.05, already fitted (stack_sky.h).
SkyJudgments judge_sky(const SkyImages& sky, const FrameRefs& frames, const camera::Camera& camera,
                       const SkyMaskParams& p = {},
                       const std::vector<const FrameEVectors*>* e_vectors = nullptr,
                       const std::vector<std::optional<Eigen::Vector3d>>* aolp_suns = nullptr);
// The AoLP and DoLP thresholds the judgments fit and read E-vectors at.
inline constexpr double kMaskMinDolp = 0.05;
// Whether `frames` all have the AoLP and the S0 channel of `sky`'s band: what judge_sky reads.
std::pair<bool, bool> aolp_and_s0(const SkyImages& sky, const FrameRefs& frames);

// The mask from the judgments of the frames whose keep[f] is 1 (nullptr: every frame), with their
// suns: a pixel is masked when it was bad in at least bad_share of the kept frames that judged it.
// `sky` is the one judged.
SkyMask mask_from_judgments(const SkyImages& sky, const SkyJudgments& j, const SkyMaskParams& p = {},
                            const std::vector<std::uint8_t>* keep = nullptr);

// mask_from_judgments of every frame of a stack read one frame at a time: each frame's judgments
// (judge_sky of that frame alone on the whole stack's sky: a frame's judgments do not depend on the
// others) are folded, as they come, into per-pixel counts, so that it keeps 5 bytes per pixel
// whatever the number of frames; mask() is then mask_from_judgments of them all.
class JudgmentTally {
 public:
  explicit JudgmentTally(std::size_t pixels);
  void add(const SkyJudgments& one_frame);
  SkyMask mask(const SkyImages& sky, const SkyMaskParams& p = {}) const;
  std::size_t bytes() const;

 private:
  std::vector<std::uint16_t> judged_, bad_;  // per pixel: the frames that judged it, found it bad
  std::vector<std::uint8_t> any_;            // per pixel: the causes seen
  std::vector<std::optional<Eigen::Vector3d>> suns_;
};

// judge_sky of every frame, then mask_from_judgments.
SkyMask compute_sky_mask(const SkyImages& sky, const stack::Stack& stack, const SkyMaskParams& p = {});

// Clears the pixels `m` masks from `sky` (valid, ray_camera, valid_count), unless that would leave
// fewer than 50 pixels.
void apply_mask(SkyImages& sky, const SkyMask& m);

// compute_sky_mask, then apply_mask. Returns the mask.
SkyMask apply_sky_mask(SkyImages& sky, const stack::Stack& stack, const SkyMaskParams& p = {});

}  // namespace skypol::skypole
