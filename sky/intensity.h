// Sky radiance (S0) models, separate from the polarization pattern: a pattern fixes DoLP and
// AoLP, an intensity model fixes how bright each direction is. Relative units throughout.
//   uniform   1 everywhere (a pattern-only sky: S0 carries no information)
//   rayleigh  1 + cos²γ, the Rayleigh phase function, 1 at 90° from the sun (what the rayleigh
//             and berry models give by themselves)
//   preetham  Preetham, Shirley & Smits 1999 ("A practical analytic model for daylight",
//             SIGGRAPH), luminance Y: the Perez et al. 1993 all-weather form
//             F(θ, γ) = (1 + A e^{B/cos θ})(1 + C e^{Dγ} + E cos²γ) with A…E linear in the
//             turbidity T (their Appendix A.2), as Y/Y_zenith = F(θ, γ)/F(0, θs): 1 at the zenith.
//             Defined above the horizon; below it the horizon's value is used (no ground model).
// The sun's disc is a separate effect (sun_disc.h), applied after clouds so that cloud hides it.
#pragma once

#include <memory>
#include <string>

#include <Eigen/Core>

#include "sky/sky_model.h"

namespace skypol::sky {

enum class IntensityModel { uniform, rayleigh, preetham };

// "uniform" / "rayleigh" / "preetham"; throws std::invalid_argument listing the legal names.
IntensityModel intensity_model_from_name(const std::string& name);
std::string to_string(IntensityModel model);

struct IntensityParams {
  IntensityModel model = IntensityModel::rayleigh;
  double turbidity = 3.0;  // preetham only; [2, 10] (see intensity.cpp for why)
};

// Throws std::invalid_argument naming the bad field and its legal range.
void validate(const IntensityParams& params);

// Radiance of the sky in the unit ENU direction d.
double sky_radiance(const IntensityParams& params, const Eigen::Vector3d& d, const Sun& sun);

// Gives an inner model's pattern a different radiance: S' = S·I(d)/S0 (DoLP and AoLP kept).
// The factory only wraps when the scene asks for a radiance other than the pattern's own.
class IntensitySky final : public SkyModel {
 public:
  IntensitySky(std::unique_ptr<SkyModel> inner, IntensityParams params);
  std::string name() const override { return inner_->name(); }
  Stokes stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const override;
  void stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const override;
  const IntensityParams& params() const { return params_; }
  const SkyModel& inner() const { return *inner_; }

 private:
  std::unique_ptr<SkyModel> inner_;
  IntensityParams params_;
};

}  // namespace skypol::sky
