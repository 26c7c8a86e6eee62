// The E-vectors of a frame's sky: what the sky mask's judgments and the AoLP sun fits read
// (sky_mask.h, sun_vector.h), computed once per frame of a stack rather than once per fit. An
// estimate with its jackknives fits each frame's sun some twenty times, on subsets of the same
// pixels (frames kept, a sector left out, the mask of each), and the E-vector of a pixel is its
// ray (geometry) turned by its AoLP (the frame's): it does not depend on which pixels a fit reads.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "camera/camera.h"
#include "skypole/sky_images.h"

namespace skypol::skypole {

// The unit E-vector (camera frame) of a pixel looking along unit d_cam whose sensor AoLP is
// `aolp` (radians), through the camera's transport; nullopt where it is undefined (projected
// transport with d ⟂ the optical axis).
std::optional<Eigen::Vector3d> e_vector(const Eigen::Vector3d& d_cam, double aolp, camera::Transport t);

// A pixel's sensor AoLP and how its E-vector turns with it, from the unit E-vector `e` (e_vector's)
// of a pixel looking along unit d_cam: (cos a, sin a) of the sensor angle a (mod π) that gives e,
// and `turn` = ∂e/∂a (⟂ e and d_cam; for meridional transport d_cam × e). A sensor whose
// polarizers are off their nominal angles reads each AoLP off by an amount that depends on the
// AoLP itself (sun_vector.h), which the AoLP sun fit models with these.
struct EVectorTurn {
  double cos_a = 1, sin_a = 0;
  Eigen::Vector3d turn = Eigen::Vector3d::Zero();
};
EVectorTurn e_vector_turn(const Eigen::Vector3d& d_cam, const Eigen::Vector3d& e, camera::Transport t);

// One frame's e_vector at each valid pixel of a sky whose DoLP is at least min_dolp, in pixel
// order. A fit on a sky whose valid pixels are among these (the same sky with pixels masked) reads
// its own by skipping the others.
struct FrameEVectors {
  enum : std::uint8_t { kDefined = 1, kFiniteAolp = 2 };
  double min_dolp = 0;
  // Whether the AoLP sun fits on these model the sensor's polarizer angle errors (sun_vector.h;
  // polarizer_fit, estimate.h).
  PolarizerFit polarizer = PolarizerFit::plain;
  std::vector<std::uint32_t> pixel;  // ascending
  std::vector<Eigen::Vector3d> e;    // e_vector there (zero where undefined)
  std::vector<std::uint8_t> flags;   // kDefined: e_vector gave one; kFiniteAolp: the AoLP is finite
  // With the polarizer model, per entry: ∂e/∂a and (cos 2a, sin 2a) of its sensor AoLP a
  // (e_vector_turn; zero where e is undefined), in floats as the AoLP's own precision is. Made
  // here, once, because every sun fit on the frame reads them; empty for the plain fit.
  struct Turn {
    Eigen::Vector3f turn = Eigen::Vector3f::Zero();
    float cos2 = 0, sin2 = 0;
  };
  std::vector<Turn> turns;
};
FrameEVectors frame_e_vectors(const SkyImages& sky, const std::vector<float>& dolp, const std::vector<float>& aolp,
                              camera::Transport transport, double min_dolp, PolarizerFit polarizer);

}  // namespace skypol::skypole
