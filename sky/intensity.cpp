// Radiance models. Preetham's luminance coefficients (Appendix A.2 of Preetham et al. 1999),
// each linear in the turbidity T:
//   A = 0.1787 T − 1.4630   B = −0.3554 T + 0.4275   C = −0.0227 T + 5.3251
//   D = 0.1206 T − 2.5771   E = −0.0670 T + 0.3703
// Turbidity range: the zenith factor 1 + A e^B turns negative just below T ≈ 1.65 and B turns
// positive (a horizon term that diverges) below T ≈ 1.2, so the fit is unusable for very clear
// air; above T ≈ 10 the sky is haze. We accept [2, 10].
#include "sky/intensity.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "sky/ray_block.h"
#include "sky/units.h"

namespace skypol::sky {
namespace {

struct Perez {
  double a, b, c, d, e;
};

Perez preetham_luminance(double t) {
  return {0.1787 * t - 1.4630, -0.3554 * t + 0.4275, -0.0227 * t + 5.3251, 0.1206 * t - 2.5771,
          -0.0670 * t + 0.3703};
}

// Perez F for the cosine of the view zenith angle (clamped to the horizon) and the scattering angle.
double perez(const Perez& p, double cos_theta, double gamma) {
  const double ct = std::max(cos_theta, 1e-4);  // e^{B/cos θ} → 0 at the horizon since B < 0
  const double cg = std::cos(gamma);
  return (1.0 + p.a * std::exp(p.b / ct)) * (1.0 + p.c * std::exp(p.d * gamma) + p.e * cg * cg);
}

// Float approximations that GCC vectorizes (the libm calls do not vectorize without -ffast-math);
// the scalar double path uses libm and is the reference the batch path is tested against.

// acos on [−1, 1]: Abramowitz & Stegun 4.4.46 on |x| (|error| ≤ 2e-8 rad), reflected for x < 0.
float acos_approx(float x) {
  const float ax = std::fabs(x);
  float p = -0.0012624911f;
  p = p * ax + 0.0066700901f;
  p = p * ax - 0.0170881256f;
  p = p * ax + 0.0308918810f;
  p = p * ax - 0.0501743046f;
  p = p * ax + 0.0889789874f;
  p = p * ax - 0.2145988016f;
  p = p * ax + 1.5707963050f;
  const float r = std::sqrt(1.0f - ax) * p;
  return x < 0.0f ? std::numbers::pi_v<float> - r : r;
}

// e^x = 2^n · 2^f with n = round(x·log2 e) (by the 1.5·2²³ trick) and 2^f, |f| ≤ ½, from its
// degree-6 Taylor polynomial (relative error ≤ 2e-7); x clamped to [−87, 88] (normal floats).
float exp_approx(float x) {
  const float y = std::clamp(x, -87.0f, 88.0f) * 1.44269504f;
  const float n = (y + 12582912.0f) - 12582912.0f;
  const float f = (y - n) * 0.69314718f;
  float p = 1.0f / 720.0f;
  p = p * f + 1.0f / 120.0f;
  p = p * f + 1.0f / 24.0f;
  p = p * f + 1.0f / 6.0f;
  p = p * f + 0.5f;
  p = p * f + 1.0f;
  p = p * f + 1.0f;
  return p * std::bit_cast<float>((static_cast<std::int32_t>(n) + 127) << 23);
}

double sun_zenith_angle(const Sun& sun) { return std::acos(std::clamp(sun.direction.z(), -1.0, 1.0)); }

}  // namespace

IntensityModel intensity_model_from_name(const std::string& name) {
  if (name == "uniform") return IntensityModel::uniform;
  if (name == "rayleigh") return IntensityModel::rayleigh;
  if (name == "preetham") return IntensityModel::preetham;
  throw std::invalid_argument("intensity model \"" + name + "\" is unknown (expected uniform, rayleigh or preetham)");
}

std::string to_string(IntensityModel model) {
  switch (model) {
    case IntensityModel::uniform: return "uniform";
    case IntensityModel::rayleigh: return "rayleigh";
    case IntensityModel::preetham: return "preetham";
  }
  return "unknown";
}

void validate(const IntensityParams& p) {
  if (p.model == IntensityModel::preetham && !(p.turbidity >= 2.0 && p.turbidity <= 10.0)) {
    throw std::invalid_argument("turbidity " + std::to_string(p.turbidity) +
                                " is outside [2, 10], the range where Preetham's luminance fit is usable");
  }
}

double sky_radiance(const IntensityParams& params, const Eigen::Vector3d& d, const Sun& sun) {
  const double c = std::clamp(d.dot(sun.direction), -1.0, 1.0);
  double radiance = 1.0;
  switch (params.model) {
    case IntensityModel::uniform: break;
    case IntensityModel::rayleigh: radiance = 1.0 + c * c; break;
    case IntensityModel::preetham: {
      const Perez p = preetham_luminance(params.turbidity);
      const double gamma = 2.0 * std::asin(std::min(0.5 * (d - sun.direction).norm(), 1.0));  // exact near the sun
      radiance = perez(p, d.z(), gamma) / perez(p, 1.0, sun_zenith_angle(sun));
      break;
    }
  }
  return radiance;
}

IntensitySky::IntensitySky(std::unique_ptr<SkyModel> inner, IntensityParams params)
    : inner_(std::move(inner)), params_(params) {
  if (!inner_) throw std::invalid_argument("IntensitySky needs an inner model");
  validate(params_);
}

Stokes IntensitySky::stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const {
  const Stokes s = inner_->stokes(d, e0, sun);
  const double radiance = sky_radiance(params_, d, sun);
  const double k = s.s0 > 0 ? radiance / s.s0 : 0.0;
  return {radiance, k * s.s1, k * s.s2, k * s.s3};
}

void IntensitySky::stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const {
  assert(out.size() == rays.size());
  if (out.size() < rays.size()) rays = rays.first(out.size());
  inner_->stokes(rays, sun, out.first(rays.size()));
  const float sx = static_cast<float>(sun.direction.x());
  const float sy = static_cast<float>(sun.direction.y());
  const float sz = static_cast<float>(sun.direction.z());
  const Perez pd = preetham_luminance(params_.turbidity);
  const float pa = static_cast<float>(pd.a), pb = static_cast<float>(pd.b), pc = static_cast<float>(pd.c),
              pdd = static_cast<float>(pd.d), pe = static_cast<float>(pd.e);
  const float norm = static_cast<float>(1.0 / perez(pd, 1.0, sun_zenith_angle(sun)));
  const IntensityModel model = params_.model;
  detail::for_each_ray_block(rays, [&](const detail::RayBlock& b) {
    float radiance[detail::RayBlock::kSize];
    // One branch-free loop per model, so that each vectorizes.
    if (model == IntensityModel::uniform) {
      for (std::size_t j = 0; j < b.count; ++j) radiance[j] = 1.0f;
    } else if (model == IntensityModel::rayleigh) {
      for (std::size_t j = 0; j < b.count; ++j) {
        const float c = b.dx[j] * sx + b.dy[j] * sy + b.dz[j] * sz;
        radiance[j] = 1.0f + c * c;
      }
    } else {
      for (std::size_t j = 0; j < b.count; ++j) {
        const float c = b.dx[j] * sx + b.dy[j] * sy + b.dz[j] * sz;
        // γ = 2 asin(|d − s|/2): acos(c) loses all precision near the sun in float (slope ∞ at 1),
        // where Perez's circumsolar term e^{Dγ} is steepest.
        const float ex = b.dx[j] - sx, ey = b.dy[j] - sy, ez = b.dz[j] - sz;
        const float half_chord = std::min(0.5f * std::sqrt(ex * ex + ey * ey + ez * ez), 1.0f);
        const float gamma = std::numbers::pi_v<float> - 2.0f * acos_approx(half_chord);
        const float ct = std::max(b.dz[j], 1e-4f);
        radiance[j] = norm * (1.0f + pa * exp_approx(pb / ct)) * (1.0f + pc * exp_approx(pdd * gamma) + pe * c * c);
      }
    }
    StokesF* __restrict o = out.data() + b.first;
    for (std::size_t j = 0; j < b.count; ++j) {
      const float k = o[j].s0 > 0.0f ? radiance[j] / o[j].s0 : 0.0f;
      o[j].s0 = radiance[j];
      o[j].s1 *= k;
      o[j].s2 *= k;
      o[j].s3 *= k;
    }
  });
}

}  // namespace skypol::sky
