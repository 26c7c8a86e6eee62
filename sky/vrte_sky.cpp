// From ENU to the table's frame and back: μ = d_z, μ0 = s_z, Δφ the angle from the sun's
// horizontal direction to the view's, counter-clockwise seen from above (ENU is right-handed, so
// this is the solver's sense). The table answers in the meridian basis e0m = e90m × d,
// e90m = ẑ × d/|ẑ × d|; one rotate_reference-style turn takes it to the caller's e0.
#include "sky/vrte_sky.h"

#include <cassert>
#include <cmath>
#include <stdexcept>

namespace skypol::sky {

namespace {

struct Horizontal {
  double x, y;
};

// A unit horizontal direction, or `fallback` when the vector is (nearly) vertical.
Horizontal unit_horizontal(double x, double y, Horizontal fallback) {
  const double r = std::sqrt(x * x + y * y);
  if (r < 1e-12) return fallback;
  return {x / r, y / r};
}

Stokes eval(const vrte::VrteTable& t, const vrte::VrteTable::SunSlice& slice, const Eigen::Vector3d& d,
            const Eigen::Vector3d& e0, const Eigen::Vector3d& s) {
  if (!(s.z() > 0.0)) return {};
  if (d.z() < 0.0) return {slice.ground, 0.0, 0.0, 0.0};
  const Horizontal sh = unit_horizontal(s.x(), s.y(), {0.0, 1.0});  // sun at the zenith: North
  const Horizontal dh = unit_horizontal(d.x(), d.y(), sh);          // view at the zenith: the sun's azimuth
  const double c = sh.x * dh.x + sh.y * dh.y;
  const double n = sh.x * dh.y - sh.y * dh.x;
  vrte::StokesIQU r = t.down(slice, d.z(), c, n);
  // Interpolation in μ0 can undershoot where the sky fades to nothing (a sun within a few tenths of
  // a degree of the horizon): no negative radiance, no degree above 1.
  if (!(r.i > 0.0)) return {};
  if (const double p2 = r.q * r.q + r.u * r.u; p2 > r.i * r.i) {
    const double k = r.i / std::sqrt(p2);
    r.q *= k, r.u *= k;
  }
  const Eigen::Vector3d e90m(-dh.y, dh.x, 0.0);
  const Eigen::Vector3d e0m = e90m.cross(d);
  const double a = e0.dot(e0m), b = e0.dot(e90m);
  const double r2 = a * a + b * b;
  if (!(r2 > 0.0)) return {r.i, 0.0, 0.0, 0.0};  // e0 not ⟂ d: no basis to speak of
  const double c2 = (a * a - b * b) / r2, s2 = 2.0 * a * b / r2;
  return {r.i, r.q * c2 + r.u * s2, -r.q * s2 + r.u * c2, 0.0};
}

}  // namespace

VrteSky::VrteSky(std::shared_ptr<const vrte::VrteTable> table) : table_(std::move(table)) {
  if (!table_ || table_->terms() == 0) throw std::invalid_argument("vrte sky: needs a built table");
}

Stokes VrteSky::stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const {
  return eval(*table_, table_->slice(sun.direction.z()), d, e0, sun.direction);
}

void VrteSky::stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const {
  assert(out.size() == rays.size());
  const std::size_t n = rays.size() < out.size() ? rays.size() : out.size();
  const vrte::VrteTable::SunSlice slice = table_->slice(sun.direction.z());
  for (std::size_t i = 0; i < n; ++i) {
    const Stokes s = eval(*table_, slice, rays[i].d.cast<double>(), rays[i].e0.cast<double>(), sun.direction);
    out[i] = {static_cast<float>(s.s0), static_cast<float>(s.s1), static_cast<float>(s.s2), 0.0f};
  }
}

void VrteSky::stokes_soa(const ViewRaysSoA& rays, const Sun& sun, const StokesSoA& out) const {
  const vrte::VrteTable::SunSlice slice = table_->slice(sun.direction.z());
  for (std::size_t i = 0; i < rays.count; ++i) {
    const Eigen::Vector3d d(rays.dx[i], rays.dy[i], rays.dz[i]), e0(rays.ux[i], rays.uy[i], rays.uz[i]);
    const Stokes s = eval(*table_, slice, d, e0, sun.direction);
    out.s0[i] = static_cast<float>(s.s0);
    out.s1[i] = static_cast<float>(s.s1);
    out.s2[i] = static_cast<float>(s.s2);
    out.s3[i] = 0.0f;
  }
}

}  // namespace skypol::sky
