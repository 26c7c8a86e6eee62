// Internal pieces of the batched pixel → ray inverses (Lens::ray_row) of the models without a
// closed-form inverse: θ(r) tabulated once per lens and interpolated, one Newton step on the
// forward model, and sin/cos from a table. Plain arithmetic and table loads only, so that a loop
// over pixels vectorises (libm's sin and cos do not, without -ffast-math). Not part of the
// camera interface.
#pragma once

#include <algorithm>
#include <cmath>
#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include <Eigen/Core>

#include "camera/lens.h"
#include "sky/units.h"

namespace skypol::camera::detail {

// Rows are handled in blocks of this many pixels (buffers on the stack).
inline constexpr std::size_t kRowBlock = 256;

// min and max by value: std::min's reference to a local can leave a branch in the loop.
inline double vmin(double a, double b) { return b < a ? b : a; }
inline double vmax(double a, double b) { return a < b ? b : a; }

// x clamped to [lo, hi], a NaN to lo: for table indices, which must stay in bounds whatever the
// pixel (a non-finite row computes its lanes before they are discarded).
inline double index_clamp(double x, double lo, double hi) {
  const double a = x >= lo ? x : lo;
  return a <= hi ? a : hi;
}

// The column x0 + i. Through int: SSE2 converts int32, not size_t, to double in vector code (the
// same value for any row a sensor has).
inline double column(double x0, std::size_t i) { return x0 + static_cast<double>(static_cast<int>(i)); }

// The second pass of the loops below: pixels flagged 2 take exact(pixel) (the model's ray()),
// a non-finite row none, and the flags (kept as doubles: GCC 12 does not vectorise a loop that
// stores both doubles and bytes) become valid[].
template <class Exact>
void settle_flags(const double* flag, bool finite, Exact exact, double y, double x0, std::size_t n, double* dx,
                  double* dy, double* dz, unsigned char* valid) {
  for (std::size_t i = 0; i < n; ++i) {
    valid[i] = static_cast<unsigned char>(flag[i]);
    if (!finite) valid[i] = 0, dx[i] = 0, dy[i] = 0, dz[i] = 1;
    if (valid[i] != 2) continue;
    const auto d = exact(Eigen::Vector2d(column(x0, i), y));
    valid[i] = d ? 1 : 0;
    const Eigen::Vector3d v = d ? *d : Eigen::Vector3d::UnitZ();
    dx[i] = v.x(), dy[i] = v.y(), dz[i] = v.z();
  }
}

// sin and cos at the 257 nodes θi = iπ/256 (libm's values) and the nodes themselves.
struct SinCosTable {
  static constexpr int kNodes = 256;
  double theta[kNodes + 1], s[kNodes + 1], c[kNodes + 1];
};
const SinCosTable& sincos_table();

// sin θ and cos θ for θ in [0, π] (a little past either end is fine), within 2 ulp of libm: the
// nearest node θi, then the angle-addition formula with the Taylor series of Δ = θ − θi
// (|Δ| ≤ π/512, so the terms kept leave < 1e-25). Δ is exact (Sterbenz).
inline void sincos_0_pi(const SinCosTable& t, double theta, double& s, double& c) {
  const double q = index_clamp(theta * (SinCosTable::kNodes / kPi) + 0.5, 0.0,
                               static_cast<double>(SinCosTable::kNodes));
  const int i = static_cast<int>(q);
  const double* nodes = t.theta;
  const double* sines = t.s;
  const double* cosines = t.c;
  const double d = theta - nodes[i], d2 = d * d;
  const double sd = d * (1 - d2 / 6 * (1 - d2 / 20 * (1 - d2 / 42)));
  const double cm1 = -d2 / 2 * (1 - d2 / 12 * (1 - d2 / 30 * (1 - d2 / 56)));  // cos Δ − 1
  const double si = sines[i], ci = cosines[i];
  s = si + (si * cm1 + ci * sd);
  c = ci + (ci * cm1 - si * sd);
}

// θ(r) of a radially symmetric lens on a uniform grid of normalized radii r in [0, r_max], with
// the slopes dθ/dr = 1/r'(θ) from the forward model: a cubic Hermite interpolant whose error is
// O(h⁴) (about 1e-13 rad at 1024 segments for the lenses in camera/), which one Newton step on the
// forward model then squares away.
struct RadialTable {
  static constexpr int kSegments = 1024;
  double r_max = 0, inv_h = 0;
  std::vector<double> theta, slope_h;  // θ and h·dθ/dr at the kSegments + 1 nodes

  // fwd(θ, r, dr): the forward model r(θ) and r'(θ), rising on [0, θmax]; exact(r): θ(r) solved
  // to full precision (the model's own inverse).
  template <class Fwd, class Exact>
  RadialTable(double theta_max, double radius_max, Fwd fwd, Exact exact) : r_max(radius_max) {
    const double h = r_max / kSegments;
    inv_h = kSegments / r_max;
    theta.resize(kSegments + 1);
    slope_h.resize(kSegments + 1);
    for (int j = 0; j <= kSegments; ++j) {
      theta[j] = j == 0 ? 0.0 : j == kSegments ? theta_max : std::clamp(exact(j * h), 0.0, theta_max);
      double r, dr;
      fwd(theta[j], r, dr);
      // Where r'(θ) vanishes (a field of view cut at a turning point) the slope is the secant's:
      // the pixels there fail the Newton check below and take the exact inverse.
      slope_h[j] = dr > 1e-6 ? h / dr : j > 0 ? theta[j] - theta[j - 1] : 0.0;
    }
  }

  // The interpolated θ at r (clamped to [0, r_max]).
  double operator()(double r) const {
    const double u = index_clamp(r, 0.0, r_max) * inv_h;
    const int iu = static_cast<int>(u);
    const int i = iu < kSegments - 1 ? iu : kSegments - 1;
    const double t = u - i, s = 1 - t;
    const double* th = theta.data();
    const double* m = slope_h.data();
    return s * s * ((1 + 2 * t) * th[i] + t * m[i]) + t * t * ((3 - 2 * t) * th[i + 1] - s * m[i + 1]);
  }
};

// The table of r(θ) = θ·(1 + k1θ² + k2θ⁴ + k3θ⁶ + k4θ⁸) on [0, θmax] (Kannala–Brandt's θd, and
// the radial parts of thin prism and Mei), or nullptr where r'(θ) stops being positive inside.
std::unique_ptr<const RadialTable> odd_polynomial_table(const std::array<double, 4>& k, double theta_max);

// A table built on first use, once, by whichever thread asks first: lenses are built far more
// often than they answer rows (fit_fov_to_sensor bisects on make_lens), and ray() needs none.
// build() holds values, not the lens, so lens copies may share it.
class LazyRadialTable {
 public:
  explicit LazyRadialTable(std::function<std::unique_ptr<const RadialTable>()> build) : build_(std::move(build)) {}
  const RadialTable* get() const {
    std::call_once(once_, [this] { table_ = build_(); });
    return table_.get();
  }

 private:
  std::function<std::unique_ptr<const RadialTable>()> build_;
  mutable std::once_flag once_;
  mutable std::unique_ptr<const RadialTable> table_;
};

// Lens::ray_row for a radially symmetric lens with normalized image height r(θ) rising on
// [0, θmax] (fwd as in RadialTable) and image circle r ≤ r_max: per pixel the table's θ, one
// Newton step, sin and cos from the table, all without branches. The pixels it cannot vouch for
// take exact(pixel), the model's ray(): those within 1e-9 of the circle's edge (so validity is
// ray()'s to the last bit) and those whose Newton step is > 1e-9 rad or whose r'(θ) < 1e-3 (near
// a turning point, where one step is not enough).
template <class Fwd, class Exact>
void tabulated_ray_row(const Intrinsics& k, const RadialTable& tab, double theta_max, Fwd fwd, Exact exact,
                       double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
                       unsigned char* valid) {
  const double my = (y - k.cy) / k.fy;
  const bool finite = std::isfinite(y) && std::isfinite(x0) && std::isfinite(x0 + static_cast<double>(n));
  const double r_max = tab.r_max, inner = r_max * (1 - 1e-9), outer = r_max * (1 + 1e-9);
  const SinCosTable& sc = sincos_table();
  // Short loops over a block, each simple enough for GCC to vectorise (one loop with the table
  // loads, the Newton step and the outputs together stays scalar).
  double flag[kRowBlock], mxs[kRowBlock], rs[kRowBlock], t0[kRowBlock], th[kRowBlock], ss[kRowBlock],
      cs[kRowBlock];
  for (std::size_t b = 0; b < n; b += kRowBlock) {
    const std::size_t m = std::min(kRowBlock, n - b);
    for (std::size_t i = 0; i < m; ++i) {
      const double mx = (column(x0, b + i) - k.cx) / k.fx;
      mxs[i] = mx;
      rs[i] = std::sqrt(mx * mx + my * my);
    }
    for (std::size_t i = 0; i < m; ++i) t0[i] = tab(vmin(rs[i], r_max));
    for (std::size_t i = 0; i < m; ++i) {
      const double r = rs[i], rc = vmin(r, r_max);
      double f, d;
      fwd(t0[i], f, d);
      const double step = (f - rc) / d;
      th[i] = vmin(vmax(t0[i] - step, 0.0), theta_max);
      const bool in = r <= inner;
      // Bitwise & and | (no short circuit): no branch.
      const bool check = ((r > inner) & (r <= outer)) | (in & !((std::abs(step) <= 1e-9) & (d >= 1e-3)));
      const double f_in = in ? 1.0 : 0.0;
      flag[i] = check ? 2.0 : f_in;
    }
    for (std::size_t i = 0; i < m; ++i) {
      double si, ci;
      sincos_0_pi(sc, th[i], si, ci);
      ss[i] = si, cs[i] = ci;
    }
    double* ox = dx + b;
    double* oy = dy + b;
    double* oz = dz + b;
    for (std::size_t i = 0; i < m; ++i) {
      const double s_r = ss[i] / vmax(rs[i], 1e-300);  // r = 0: s = 0
      const bool in = flag[i] == 1.0;
      ox[i] = in ? s_r * mxs[i] : 0.0;
      oy[i] = in ? s_r * my : 0.0;
      oz[i] = in ? cs[i] : 1.0;
    }
    settle_flags(flag, finite, exact, y, column(x0, b), m, ox, oy, oz, valid + b);
  }
}

}  // namespace skypol::camera::detail

namespace skypol::camera::detail {

// Lens::ray_row of a model whose ray() is a closed form written once as kernel(u, v, x, y, z) →
// inside?, used by ray() too, so that both give the same bits. The kernel computes every lane
// (its square roots guarded), so the loop has no branch; a pixel outside gets (0, 0, 1).
template <class Kernel>
void closed_form_ray_row(Kernel kernel, double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
                         unsigned char* valid) {
  const bool finite = std::isfinite(y) && std::isfinite(x0) && std::isfinite(x0 + static_cast<double>(n));
  // The validity goes through a double buffer, as in settle_flags.
  double flag[kRowBlock];
  for (std::size_t b = 0; b < n; b += kRowBlock) {
    const std::size_t m = std::min(kRowBlock, n - b);
    for (std::size_t i = 0; i < m; ++i) {
      double a, bb, c;
      const bool ok = finite & kernel(column(x0, b + i), y, a, bb, c);
      flag[i] = ok ? 1.0 : 0.0;
      dx[b + i] = ok ? a : 0.0;
      dy[b + i] = ok ? bb : 0.0;
      dz[b + i] = ok ? c : 1.0;
    }
    for (std::size_t i = 0; i < m; ++i) valid[b + i] = static_cast<unsigned char>(flag[i]);
  }
}

}  // namespace skypol::camera::detail

namespace skypol::camera::detail {

// Lens::ray_row of a model whose normalized image point m is a 2-D distortion q(p) of a point p
// (radial plus tangential / thin-prism terms) that ray() inverts by damped Newton. Per pixel,
// without branches: norm(u, v, mx, my) the normalized point; p starts on m's azimuth at the
// radius the table of the radial part alone gives; three undamped Newton steps on the full
// q(p) (dist(px, py, qx, qy, j) with j the Jacobian row by row); lift(px, py, |p|, x, y, z) the
// unit direction. The pixels it cannot vouch for take exact(pixel), the model's ray(): |p|
// within 1e-9 of p_max (the edge of the field, so validity is ray()'s), those whose last step is
// > 1e-9 (the start was too far, e.g. strong tangential terms) and those lift() refuses inside.
template <class Norm, class Dist, class Lift, class Exact>
void undistort_ray_row(const RadialTable& tab, double p_max, Norm norm, Dist dist, Lift lift, Exact exact, double y,
                       double x0, std::size_t n, double* dx, double* dy, double* dz, unsigned char* valid) {
  const bool finite = std::isfinite(y) && std::isfinite(x0) && std::isfinite(x0 + static_cast<double>(n));
  const double inner = p_max * (1 - 1e-9), outer = p_max * (1 + 1e-9), far = p_max * (1 + 1e-3);
  // Short loops over a block, so that GCC vectorises the ones without table loads (see
  // tabulated_ray_row).
  double flag[kRowBlock], mxs[kRowBlock], mys[kRowBlock], st[kRowBlock], pxs[kRowBlock], pys[kRowBlock],
      steps[kRowBlock], prs[kRowBlock], ax[kRowBlock], ay[kRowBlock], az[kRowBlock], oks[kRowBlock];
  for (std::size_t b = 0; b < n; b += kRowBlock) {
    const std::size_t m = std::min(kRowBlock, n - b);
    for (std::size_t i = 0; i < m; ++i) {
      double mx, my;
      norm(column(x0, b + i), y, mx, my);
      mxs[i] = mx, mys[i] = my;
      st[i] = std::sqrt(mx * mx + my * my);
    }
    for (std::size_t i = 0; i < m; ++i) st[i] = tab(st[i]) / vmax(st[i], 1e-300);  // |p|/|m|, radial part alone
    for (std::size_t i = 0; i < m; ++i) {
      const double mx = mxs[i], my = mys[i];
      double px = mx * st[i], py = my * st[i], step = 0;
      for (int it = 0; it < 3; ++it) {
        double qx, qy, j[4];
        dist(px, py, qx, qy, j);
        const double det = j[0] * j[3] - j[1] * j[2];
        const double ex = mx - qx, ey = my - qy;
        const double sx = (j[3] * ex - j[1] * ey) / det, sy = (j[0] * ey - j[2] * ex) / det;
        px += sx, py += sy;
        step = std::abs(sx) + std::abs(sy);
      }
      pxs[i] = px, pys[i] = py, steps[i] = step;
      prs[i] = std::sqrt(px * px + py * py);
    }
    for (std::size_t i = 0; i < m; ++i) {
      double a, bb, c;
      oks[i] = lift(pxs[i], pys[i], prs[i], a, bb, c) ? 1.0 : 0.0;
      ax[i] = a, ay[i] = bb, az[i] = c;
    }
    double* ox = dx + b;
    double* oy = dy + b;
    double* oz = dz + b;
    for (std::size_t i = 0; i < m; ++i) {
      const double pr = prs[i];
      // Converged and inside: the ray; converged past the edge, or (a pixel far outside the
      // image circle, where three steps from the table's clamped start are not enough) still far
      // past it: none; otherwise (at the edge, not converged, a NaN) ray() decides.
      const bool converged = steps[i] <= 1e-9;
      const bool in = converged & (oks[i] == 1.0) & (pr <= inner);
      const bool out = (converged & (pr > outer)) | (pr > far);
      const double f_out = out ? 0.0 : 2.0;
      flag[i] = in ? 1.0 : f_out;
      ox[i] = in ? ax[i] : 0.0;
      oy[i] = in ? ay[i] : 0.0;
      oz[i] = in ? az[i] : 1.0;
    }
    settle_flags(flag, finite, exact, y, column(x0, b), m, ox, oy, oz, valid + b);
  }
}

}  // namespace skypol::camera::detail
