// The Berry–Dennis–Lee sky in vector form.
//
// Derivation. BDL describe the pattern by the stereographic image ζ = tan(θ/2)·e^{iφ} of the
// sky and the complex field w(ζ) ∝ −(ζ − ζ_S+)(ζ − ζ_S−)(ζ − ζ_A+)(ζ − ζ_A−), whose phase is twice
// the E-vector angle; the anti-sun points are the sun points' antipodes, ζ_A∓ = −1/ζ*_S±.
// (1) For an antipodal pair ±p, the great circle through ζ, ζ_p and ζ_−p has, at ζ, the direction
//     arg[(ζ − ζ_p)(ζ − ζ_−p)/(ζ_p − ζ_−p)] (the Möbius map (z − ζ_p)/(z − ζ_−p) sends it to a line
//     through 0). So (ζ − ζ_p)(ζ − ζ_−p) is, up to a real positive factor and a constant phase, the
//     tangent τ_p = p·e0 + i p·e90 pointing from d towards p — a quantity needing no projection.
// (2) Hence w ∝ −τ1 τ2 with p1 = Babinet (antipode: the fourth point) and p2 = Brewster (antipode:
//     Arago). The constant phase is fixed by δ = 0, where −τ² is Rayleigh's E-vector (E = d × s
//     has components (−s·e90, s·e0), whose complex square is −τ_s²).
// (3) Degree: with half-chords sin(γk/2) = |ζ − ζ_pk|/√((1+|ζ|²)(1+|ζ_pk|²)) and
//     cos(γk/2) = |1 + ζ ζ*_pk|/√(…), Rayleigh's sin²γ/(1+cos²γ) is 2uv/(u² + v²) with
//     u = sin²(γ/2), v = cos²(γ/2); BDL's split replaces u, v by U = sin(γ1/2)sin(γ2/2),
//     V = cos(γ1/2)cos(γ2/2). Using sin² = (1 − c)/2, cos² = (1 + c)/2 and UV = |τ1||τ2|/4:
//     DoLP = |τ1||τ2|/(1 + c1 c2) ≤ 1, zero exactly at the four points.
// So S1 + i S2 = −S0·Pmax·τ1τ2/(1 + c1c2): no trig, no square root, and 1 + c1c2 > 0 for δ < 90°
// (it vanishes only where d = ±p1 = ∓p2, i.e. if p2 = −p1).
// (4) BDL themselves stop at |w| (their eq. 4.2, normalised to max |w| = 1, is the "intensity of
//     polarization"). UV = |τ1||τ2|/4 = |w|/4 gives OpenSky's degree |w|/(2 − |w|) = 2UV/(1 − 2UV),
//     the other normalisation on offer: S1 + i S2 = −S0·Pmax·τ1τ2/(2 − |τ1||τ2|), one square root;
//     2 − |τ1||τ2| ≥ 1.
#include "sky/berry.h"

#include <cassert>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

#include "sky/ray_block.h"
#include "sky/units.h"

namespace skypol::sky {

BerryNormalisation parse_berry_normalisation(std::string_view name) {
  if (name == "split_rayleigh") return BerryNormalisation::split_rayleigh;
  if (name == "opensky") return BerryNormalisation::opensky;
  throw std::invalid_argument("unknown berry normalisation \"" + std::string(name) +
                              "\" (expected one of split_rayleigh, opensky)");
}

std::string_view berry_normalisation_name(BerryNormalisation n) {
  return n == BerryNormalisation::opensky ? "opensky" : "split_rayleigh";
}

BerrySky::BerrySky(BerryParams params) : params_(params) {
  if (!(params_.max_dolp >= 0.0 && params_.max_dolp <= 1.0)) {
    throw std::invalid_argument("berry: max_dolp (Pmax) " + std::to_string(params_.max_dolp) + " must be in [0, 1]");
  }
  if (!(params_.separation_deg >= 0.0 && params_.separation_deg <= 45.0)) {
    throw std::invalid_argument("berry: separation_deg " + std::to_string(params_.separation_deg) +
                                " must be in [0, 45] (observed neutral points lie 10°–30° from the sun)");
  }
  if (params_.normalisation != BerryNormalisation::split_rayleigh &&
      params_.normalisation != BerryNormalisation::opensky) {
    throw std::invalid_argument("berry: unknown normalisation (expected split_rayleigh or opensky)");
  }
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> BerrySky::neutral_points(const Sun& sun) const {
  const Eigen::Vector3d& s = sun.direction;
  // Unit tangent at the sun along the solar vertical, pointing towards the zenith.
  Eigen::Vector3d horizontal(s.x(), s.y(), 0.0);
  const double hn = horizontal.norm();
  horizontal = hn > 1e-12 ? Eigen::Vector3d(horizontal / hn)
                          : Eigen::Vector3d(std::sin(sun.azimuth), std::cos(sun.azimuth), 0.0);
  const Eigen::Vector3d up_tangent = Eigen::Vector3d::UnitZ() * hn - horizontal * s.z();
  const double delta = rad_from_deg(params_.separation_deg);
  const double c = std::cos(delta), n = std::sin(delta);
  return {(c * s + n * up_tangent).normalized(), (c * s - n * up_tangent).normalized()};
}

Stokes BerrySky::stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const {
  const auto [p1, p2] = neutral_points(sun);
  const Eigen::Vector3d e90 = d.cross(e0);
  const double c = d.dot(sun.direction);
  const double s0 = 1.0 + c * c;
  const double x1 = p1.dot(e0), y1 = p1.dot(e90), x2 = p2.dot(e0), y2 = p2.dot(e90);
  const double norm = params_.normalisation == BerryNormalisation::opensky
                          ? 2.0 - std::sqrt((x1 * x1 + y1 * y1) * (x2 * x2 + y2 * y2))
                          : 1.0 + d.dot(p1) * d.dot(p2);
  const double k = -s0 * params_.max_dolp / norm;
  return {s0, k * (x1 * x2 - y1 * y2), k * (x1 * y2 + x2 * y1), 0.0};
}

void BerrySky::stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const {
  assert(out.size() == rays.size());
  if (out.size() < rays.size()) rays = rays.first(out.size());
  const auto [p1d, p2d] = neutral_points(sun);
  const Eigen::Vector3f s = sun.direction.cast<float>(), p = p1d.cast<float>(), q = p2d.cast<float>();
  const float pm = static_cast<float>(params_.max_dolp);
  const bool opensky = params_.normalisation == BerryNormalisation::opensky;
  detail::for_each_ray_block(rays, [&](const detail::RayBlock& b) {
    StokesF* __restrict o = out.data() + b.first;
    for (std::size_t j = 0; j < b.count; ++j) {
      const float dx = b.dx[j], dy = b.dy[j], dz = b.dz[j];
      const float ux = b.ux[j], uy = b.uy[j], uz = b.uz[j];
      const float vx = dy * uz - dz * uy;  // e90 = d × e0
      const float vy = dz * ux - dx * uz;
      const float vz = dx * uy - dy * ux;
      const float c = dx * s.x() + dy * s.y() + dz * s.z();
      const float c1 = dx * p.x() + dy * p.y() + dz * p.z();
      const float c2 = dx * q.x() + dy * q.y() + dz * q.z();
      const float x1 = p.x() * ux + p.y() * uy + p.z() * uz, y1 = p.x() * vx + p.y() * vy + p.z() * vz;
      const float x2 = q.x() * ux + q.y() * uy + q.z() * uz, y2 = q.x() * vx + q.y() * vy + q.z() * vz;
      const float s0 = 1.0f + c * c;
      const float norm = opensky ? 2.0f - std::sqrt((x1 * x1 + y1 * y1) * (x2 * x2 + y2 * y2))
                                 : 1.0f + c1 * c2;
      const float k = -s0 * pm / norm;
      o[j].s0 = s0;
      o[j].s1 = k * (x1 * x2 - y1 * y2);
      o[j].s2 = k * (x1 * y2 + x2 * y1);
      o[j].s3 = 0.0f;
    }
  });
}

}  // namespace skypol::sky
