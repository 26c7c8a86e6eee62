// From ENU to the table's frame and back: μ = d_z, μ0 = s_z, Δφ the angle from the sun's
// horizontal direction to the view's, counter-clockwise seen from above (ENU is right-handed, so
// this is the solver's sense). The table answers in the meridian basis e0m = e90m × d,
// e90m = ẑ × d/|ẑ × d|; one rotate_reference-style turn takes it to the caller's e0.
#include "sky/vrte/vrte_sky.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <numbers>
#include <stdexcept>

#include "sky/ray_block.h"
#include "sky/vector_clones.h"

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

// The batch paths' per-sun state. ms holds, for every μ node k of the table and every azimuth
// node j, the multiple scattering summed over its Fourier terms: [(k·J + j)·3 + s], s = I, Q, U
// (U at |Δφ|; it is odd in Δφ); factor the single-scattering factor at v = i/kFactorSteps.
struct PlanArrays {
  std::vector<float> ms, factor;
};

constexpr int kHalf = VrteSky::kAzimuthSteps;
constexpr int kAzimuthNodes = 2 * (kHalf + 1);  // J
constexpr int kPhaseNodes = 3601;                // Θ = kπ/(n − 1), the spacing of vrte::AngleTable

// Δφ of azimuth node j: 2 atan(j/N) on the sun's side, π − 2 atan((j − N − 1)/N) on the other.
double azimuth_node(int j) {
  if (j <= kHalf) return 2.0 * std::atan(static_cast<double>(j) / kHalf);
  return std::numbers::pi - 2.0 * std::atan(static_cast<double>(j - kHalf - 1) / kHalf);
}

// asin on [0, 1] in float: Cephes' asinf (its polynomial on [0, ½], asin x = π/2 − 2 asin √((1 − x)/2)
// above; relative error a few 1e-8 before rounding), written so that GCC vectorizes it.
float asin_approx(float x) {
  const bool high = x > 0.5f;
  const float y = high ? std::sqrt(0.5f * (1.0f - x)) : x;
  const float z = y * y;
  float p = 4.2163199048e-2f;
  p = p * z + 2.4181311049e-2f;
  p = p * z + 4.5470025998e-2f;
  p = p * z + 7.4953002686e-2f;
  p = p * z + 1.6666752422e-1f;
  const float a = y + y * z * p;
  return high ? 1.57079632679f - 2.0f * a : a;
}

// max(i, 0) and min(a, b) on indices by masks: GCC 12 turns std::max(0, i) in an index into a
// select of pointers, which it cannot vectorize as a gather, and SSE2 has no integer min. The
// difference wraps (INT_MIN, a NaN's conversion, minus b gives b).
int nonnegative(int i) { return i & ~(i >> 31); }
int min_index(int a, int b) {
  const int d = static_cast<int>(static_cast<unsigned>(a) - static_cast<unsigned>(b));
  return b + (d & (d >> 31));
}

struct Kernel {
  float sx, sy, sz;  // the sun
  float hx, hy;      // its horizontal direction (North at the zenith)
  float ground;      // the ground's radiance
  int grid;          // the table's μ nodes
  // kPhaseNodes and kFactorSteps, passed at run time: with the index range known at compile time
  // GCC 12 widens the indices unsigned and then cannot vectorize the gathers.
  int phase_nodes, factor_steps;
  const float* ms;
  const float* factor;
  const float* phase;
};

// The pixel loop runs in blocks, in three passes:
//  1. (vectorized) the view's Δφ from the sun and its azimuth node (no trig: tan(Δφ/2) or
//     cot(Δφ/2) from ρ·cos and ρ·sin), its v and the table's four-point Lagrange weights in μ,
//     the scattering angle (2 asin |d − s|/2, exact near the sun) and the node of the phase
//     table and of the factor's grid below it;
//  2. (one pixel at a time) every table read: the multiple scattering, eight floats at once (at
//     each of the four μ nodes the plan's I, Q, U at the two azimuth nodes are six consecutive
//     floats, read as one vector and weighted; then the linear step in azimuth), and the linear
//     steps in the phase table (ωF11 and −ωF12/sin²Θ of two neighbouring angles: four
//     consecutive floats) and in the factor (two). Contiguous loads cost a fraction of what the
//     vectorizer's emulated gathers (30 scalar loads a pixel, each with its index moved out of a
//     vector register) do;
//  3. (vectorized) the multiple scattering turned from the meridian basis into the caller's, the
//     single scattering as ωF11 and the polarized part along E = d × s (as in RayleighSky), then
//     VrteSky's rules; what does not depend on the band (the turn, E's components) in a pass
//     of its own, so that a colour scene's bands share it with the first.
// Indices are clamped as integers, so that any input (NaN, whose conversion gives INT_MIN,
// included) reads inside the arrays; a float clamp before the conversion would keep GCC 12 from
// vectorizing the table reads. Plain arithmetic and selects, restrict-qualified arrays.
constexpr std::size_t kBlock = 128;
constexpr int kRow = 3 * kAzimuthNodes;  // floats per μ node of the plan
using Float8 = float __attribute__((vector_size(32)));

struct Stencils {
  alignas(32) int offset[kBlock];  // the first μ node's I at the first azimuth node
  alignas(32) float w0[kBlock], w1[kBlock], w2[kBlock], w3[kBlock], ft[kBlock];
  alignas(32) int phase_node[kBlock], factor_node[kBlock];  // the nodes below Θ and below v
  alignas(32) float fk[kBlock], fg[kBlock];                 // and the steps from them
  alignas(32) float i[kBlock], q[kBlock], u[kBlock];  // multiple scattering, meridian basis, |Δφ|
  alignas(32) float f11[kBlock], h12[kBlock], g[kBlock];  // ωF11, −ωF12/sin²Θ, the factor
  // The view's side of the sun's vertical (ρ sin Δφ), the turn to the caller's basis (cos 2χ,
  // sin 2χ), and E·e0, s·e0 for the single scattering's polarization.
  alignas(32) float sn[kBlock], cr[kBlock], sr[kBlock], a[kBlock], b[kBlock];
};

SKYPOL_VECTOR_CLONES void stencils(const Kernel& p, std::size_t n, const float* __restrict dx_,
                                   const float* __restrict dy_, const float* __restrict dz_, Stencils& st) {
  const float sx = p.sx, sy = p.sy, sz = p.sz, shx = p.hx, shy = p.hy;
  const int grid = p.grid, phase_nodes = p.phase_nodes, factor_steps = p.factor_steps;
  constexpr float kTwoOverPi = static_cast<float>(2.0 / std::numbers::pi);
  const float phase_scale = static_cast<float>(phase_nodes - 1) * static_cast<float>(1.0 / std::numbers::pi);
  int* __restrict offset = st.offset;
  float *__restrict w0 = st.w0, *__restrict w1 = st.w1, *__restrict w2 = st.w2, *__restrict w3 = st.w3;
  float* __restrict ft_ = st.ft;
  int *__restrict phase_node = st.phase_node, *__restrict factor_node = st.factor_node;
  float *__restrict fk_ = st.fk, *__restrict fg_ = st.fg;
  for (std::size_t j = 0; j < n; ++j) {
    const float dx = dx_[j], dy = dy_[j], dz = dz_[j];
    // ρ·(cos Δφ, sin Δφ) from the view's horizontal part (ρ = |d_h|); within 1e-6 of the zenith
    // the view takes the sun's azimuth.
    const float r2 = dx * dx + dy * dy;
    const bool zenith = !(r2 > 1e-12f);
    const float rho = std::sqrt(r2);
    const float c = zenith ? 1.0f : shx * dx + shy * dy, sn = zenith ? 0.0f : shx * dy - shy * dx;
    const float t = std::fabs(sn) / (rho + std::fabs(c));
    const float ut = t * static_cast<float>(kHalf);
    const int jt = nonnegative(min_index(static_cast<int>(ut), kHalf - 1));
    const int ja = c < 0.0f ? jt + kHalf + 1 : jt;
    ft_[j] = ut - static_cast<float>(jt);
    const float mu = std::max(0.0f, std::min(1.0f, dz));
    const float v = std::sqrt(asin_approx(mu) * kTwoOverPi);
    const float u = v * static_cast<float>(grid - 1);
    const int base = nonnegative(min_index(static_cast<int>(u) - 1, grid - 4));
    const float tt = u - static_cast<float>(base + 1);
    w0[j] = -tt * (tt - 1.0f) * (tt - 2.0f) * (1.0f / 6.0f);
    w1[j] = (tt + 1.0f) * (tt - 1.0f) * (tt - 2.0f) * 0.5f;
    w2[j] = -(tt + 1.0f) * tt * (tt - 2.0f) * 0.5f;
    w3[j] = (tt + 1.0f) * tt * (tt - 1.0f) * (1.0f / 6.0f);
    offset[j] = base * kRow + 3 * ja;
    const float qx = dx - sx, qy = dy - sy, qz = dz - sz;
    const float half = std::min(1.0f, 0.5f * std::sqrt(qx * qx + qy * qy + qz * qz));
    const float th = 2.0f * asin_approx(half) * phase_scale;
    const int k = nonnegative(min_index(static_cast<int>(th), phase_nodes - 2));
    phase_node[j] = k;
    fk_[j] = th - static_cast<float>(k);
    const float ug = v * static_cast<float>(factor_steps);
    const int ig = nonnegative(min_index(static_cast<int>(ug), factor_steps - 1));
    factor_node[j] = ig;
    fg_[j] = ug - static_cast<float>(ig);
  }
}

SKYPOL_VECTOR_CLONES void table_reads(const Kernel& p, std::size_t n, Stencils& st) {
  const float* __restrict ms = p.ms;
  const float* __restrict phase = p.phase;
  const float* __restrict factor = p.factor;
  for (std::size_t j = 0; j < n; ++j) {
    const float* r = ms + st.offset[j];
    Float8 a0, a1, a2, a3;
    std::memcpy(&a0, r, sizeof a0);
    std::memcpy(&a1, r + kRow, sizeof a1);
    std::memcpy(&a2, r + 2 * kRow, sizeof a2);
    std::memcpy(&a3, r + 3 * kRow, sizeof a3);
    const Float8 m = a0 * st.w0[j] + a1 * st.w1[j] + a2 * st.w2[j] + a3 * st.w3[j];
    const float f = st.ft[j];
    st.i[j] = m[0] + f * (m[3] - m[0]);
    st.q[j] = m[1] + f * (m[4] - m[1]);
    st.u[j] = m[2] + f * (m[5] - m[2]);
    const float* h = phase + 2 * st.phase_node[j];
    const float fk = st.fk[j];
    st.f11[j] = h[0] + fk * (h[2] - h[0]);
    st.h12[j] = h[1] + fk * (h[3] - h[1]);
    const float* g = factor + st.factor_node[j];
    st.g[j] = g[0] + st.fg[j] * (g[1] - g[0]);
  }
}

// The part of pass 3 that does not depend on the band.
SKYPOL_VECTOR_CLONES void rotations(const Kernel& p, std::size_t n, const float* __restrict dx_,
                                    const float* __restrict dy_, const float* __restrict dz_,
                                    const float* __restrict ux_, const float* __restrict uy_,
                                    const float* __restrict uz_, Stencils& st) {
  const float sx = p.sx, sy = p.sy, sz = p.sz, shx = p.hx, shy = p.hy;
  float *__restrict sn_ = st.sn, *__restrict cr_ = st.cr, *__restrict sr_ = st.sr;
  float *__restrict a_ = st.a, *__restrict b_ = st.b;
  for (std::size_t j = 0; j < n; ++j) {
    const float dx = dx_[j], dy = dy_[j], dz = dz_[j];
    const float ux = ux_[j], uy = uy_[j], uz = uz_[j];
    const float r2 = dx * dx + dy * dy;
    const bool zenith = !(r2 > 1e-12f);
    sn_[j] = zenith ? 0.0f : shx * dy - shy * dx;
    // Meridian basis (e0m = (h dz, −ρ), e90m = ẑ × h with h = d_h/ρ) to the caller's (e0, d × e0):
    // the angle's cos 2χ and sin 2χ from ρ·(e0·e0m) and ρ·(e0·e90m).
    const float A = zenith ? (ux * shx + uy * shy) * dz : (ux * dx + uy * dy) * dz - uz * r2;
    const float B = zenith ? uy * shx - ux * shy : uy * dx - ux * dy;
    const float ab = A * A + B * B;
    const float inv = ab > 0.0f ? 1.0f / ab : 0.0f;
    cr_[j] = (A * A - B * B) * inv, sr_[j] = 2.0f * A * B * inv;
    // Single scattering. E = d × s; a = E·e0, b = E·(d × e0) = s·e0 (d unit, e0 ⟂ d).
    const float ex = dy * sz - dz * sy, ey = dz * sx - dx * sz, ez = dx * sy - dy * sx;
    a_[j] = ex * ux + ey * uy + ez * uz, b_[j] = sx * ux + sy * uy + sz * uz;
  }
}

SKYPOL_VECTOR_CLONES void combine(const Kernel& p, std::size_t n, const float* __restrict dz_, const Stencils& st,
                                  float* __restrict s0, float* __restrict s1, float* __restrict s2,
                                  float* __restrict s3) {
  const float ground = p.ground;
  const float* __restrict mi_ = st.i;
  const float* __restrict mq_ = st.q;
  const float* __restrict mu_ = st.u;
  const float* __restrict f11_ = st.f11;
  const float* __restrict h12_ = st.h12;
  const float* __restrict g_ = st.g;
  const float *__restrict sn_ = st.sn, *__restrict cr_ = st.cr, *__restrict sr_ = st.sr;
  const float *__restrict a_ = st.a, *__restrict b_ = st.b;
  for (std::size_t j = 0; j < n; ++j) {
    const float dz = dz_[j];
    const float mi = mi_[j], mq = mq_[j], mu = sn_[j] < 0.0f ? -mu_[j] : mu_[j];  // U is odd in Δφ
    const float cr = cr_[j], sr = sr_[j], a = a_[j], b = b_[j];
    const float f11 = f11_[j], g = g_[j];
    const float pol = h12_[j] * g;
    const float i = mi + f11 * g;
    const float q = mq * cr + mu * sr + pol * (a * a - b * b);
    const float w = -mq * sr + mu * cr + pol * 2.0f * a * b;
    // No negative radiance, no degree above 1; the ground below the horizon.
    const float p2 = q * q + w * w;
    const float scale = p2 > i * i ? i / std::sqrt(p2) : 1.0f;
    const bool lit = i > 0.0f, below = dz < 0.0f;
    s0[j] = below ? ground : lit ? i : 0.0f;
    s1[j] = below || !lit ? 0.0f : q * scale;
    s2[j] = below || !lit ? 0.0f : w * scale;
    s3[j] = 0.0f;
  }
}

// Bands p[b] into out[b]: their kernels differ only in the tables (the sun and the grid are the
// same), so the first pass and the band-free part of the third run once per block for all of them.
void vrte_float(std::span<const Kernel* const> p, const ViewRaysSoA& rays, std::span<const StokesSoA> out) {
  Stencils st;
  const float *dx = rays.dx, *dy = rays.dy, *dz = rays.dz, *ux = rays.ux, *uy = rays.uy, *uz = rays.uz;
  for (std::size_t first = 0; first < rays.count; first += kBlock) {
    const std::size_t m = std::min(kBlock, rays.count - first);
    stencils(*p[0], m, dx + first, dy + first, dz + first, st);
    rotations(*p[0], m, dx + first, dy + first, dz + first, ux + first, uy + first, uz + first, st);
    for (std::size_t b = 0; b < p.size(); ++b) {
      table_reads(*p[b], m, st);
      const StokesSoA& o = out[b];
      combine(*p[b], m, dz + first, st, o.s0 + first, o.s1 + first, o.s2 + first, o.s3 + first);
    }
  }
}

}  // namespace

struct VrteSky::SunPlan {
  Eigen::Vector3d sun;  // what it was made for
  bool lit = false;     // the sun above the horizon
  Kernel kernel{};
  PlanArrays arrays;
};

VrteSky::VrteSky(std::shared_ptr<const vrte::VrteTable> table) : table_(std::move(table)) {
  if (!table_ || table_->terms() == 0) throw std::invalid_argument("vrte sky: needs a built table");
  // ωF11 and −ωF12/sin²Θ of the untruncated layer: with E = d × s, |E|² = sin²Θ, the single
  // scattering's polarized part is (−ωF12/sin²Θ)·factor·(a² − b², 2ab) in the caller's basis.
  const vrte::ExactLayer& exact = table_->exact();
  phase_.resize(2 * static_cast<std::size_t>(kPhaseNodes));
  for (int k = 0; k < kPhaseNodes; ++k) {
    const double th = std::numbers::pi * k / (kPhaseNodes - 1);
    const vrte::Elements f = exact.omega_f(std::cos(th));
    const double s = std::sin(th);
    phase_[2 * static_cast<std::size_t>(k)] = static_cast<float>(f.f11);
    phase_[2 * static_cast<std::size_t>(k) + 1] = s > 0.0 ? static_cast<float>(-f.f12 / (s * s)) : 0.0f;
  }
  // Forward and backward F12 vanishes with sin²Θ: the ends take their neighbour's ratio.
  phase_[1] = phase_[3];
  phase_[2 * kPhaseNodes - 1] = phase_[2 * kPhaseNodes - 3];
  const auto terms = static_cast<std::size_t>(table_->terms());
  cos_m_.resize(terms * kAzimuthNodes);
  sin_m_.resize(cos_m_.size());
  for (std::size_t m = 0; m < terms; ++m)
    for (int j = 0; j < kAzimuthNodes; ++j) {
      const double a = static_cast<double>(m) * azimuth_node(j);
      cos_m_[m * kAzimuthNodes + static_cast<std::size_t>(j)] = std::cos(a);
      sin_m_[m * kAzimuthNodes + static_cast<std::size_t>(j)] = std::sin(a);
    }
}

std::shared_ptr<const VrteSky::SunPlan> VrteSky::plan(const Sun& sun) const {
  // Under the lock, so that threads rendering the same frame wait for one plan instead of each
  // making its own.
  const std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& kept : plans_)
    if (kept && kept->sun == sun.direction) return kept;
  auto p = std::make_shared<SunPlan>();
  p->sun = sun.direction;
  const Eigen::Vector3d& s = sun.direction;
  p->lit = s.z() > 0.0;
  if (p->lit) {
    const vrte::VrteTable& t = *table_;
    const vrte::VrteTable::SunSlice slice = t.slice(s.z());
    const auto g = static_cast<std::size_t>(t.grid()), terms = static_cast<std::size_t>(t.terms());
    PlanArrays& a = p->arrays;
    a.ms.resize(g * kAzimuthNodes * 3 + 8);  // + 8: pass 2 reads eight floats where it needs six
    std::vector<double> acc(kAzimuthNodes);
    for (std::size_t k = 0; k < g; ++k)
      for (std::size_t c = 0; c < 3; ++c) {
        std::fill(acc.begin(), acc.end(), 0.0);
        for (std::size_t m = 0; m < terms; ++m) {
          const double coefficient = slice.down[(m * g + k) * 3 + c];
          const double* trig = (c < 2 ? cos_m_.data() : sin_m_.data()) + m * kAzimuthNodes;
          for (int j = 0; j < kAzimuthNodes; ++j) acc[static_cast<std::size_t>(j)] += coefficient * trig[j];
        }
        for (std::size_t j = 0; j < kAzimuthNodes; ++j) a.ms[(k * kAzimuthNodes + j) * 3 + c] = static_cast<float>(acc[j]);
      }
    a.factor.resize(kFactorSteps + 1);
    for (int i = 0; i <= kFactorSteps; ++i)
      a.factor[static_cast<std::size_t>(i)] = static_cast<float>(vrte::single_scattering_factor(
          t.exact().tau, vrte::grid_mu(static_cast<double>(i) / kFactorSteps), slice.mu0, false));
    const Horizontal sh = unit_horizontal(s.x(), s.y(), {0.0, 1.0});
    p->kernel = {static_cast<float>(s.x()), static_cast<float>(s.y()), static_cast<float>(s.z()),
                 static_cast<float>(sh.x),  static_cast<float>(sh.y),  static_cast<float>(slice.ground),
                 t.grid(),                  kPhaseNodes,               kFactorSteps,
                 a.ms.data(),               a.factor.data(),           phase_.data()};
  }
  std::shared_ptr<const SunPlan>& slot = plans_[next_plan_];
  next_plan_ = (next_plan_ + 1) % plans_.size();
  slot = std::move(p);
  return slot;
}

Stokes VrteSky::stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const {
  return eval(*table_, table_->slice(sun.direction.z()), d, e0, sun.direction);
}

void VrteSky::stokes(std::span<const ViewRay> rays, const Sun& sun, std::span<StokesF> out) const {
  assert(out.size() == rays.size());
  if (out.size() < rays.size()) rays = rays.first(out.size());
  const std::shared_ptr<const SunPlan> p = plan(sun);
  if (!p->lit) {
    std::fill(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(rays.size()), StokesF{0, 0, 0, 0});
    return;
  }
  detail::for_each_ray_block(rays, [&](const detail::RayBlock& b) {
    alignas(32) float s0[detail::RayBlock::kSize], s1[detail::RayBlock::kSize], s2[detail::RayBlock::kSize],
        s3[detail::RayBlock::kSize];
    const Kernel* k[] = {&p->kernel};
    const StokesSoA planes[] = {{s0, s1, s2, s3}};
    vrte_float(k, {b.count, b.dx, b.dy, b.dz, b.ux, b.uy, b.uz}, planes);
    StokesF* o = out.data() + b.first;
    for (std::size_t j = 0; j < b.count; ++j) o[j] = {s0[j], s1[j], s2[j], s3[j]};
  });
}

void VrteSky::stokes_soa(const ViewRaysSoA& rays, const Sun& sun, const StokesSoA& out) const {
  const std::shared_ptr<const SunPlan> p = plan(sun);
  if (!p->lit) {
    for (float* o : {out.s0, out.s1, out.s2, out.s3}) std::fill(o, o + rays.count, 0.0f);
    return;
  }
  const Kernel* k[] = {&p->kernel};
  vrte_float(k, rays, {&out, 1});
}

bool VrteSky::stokes_soa_bands(std::span<const SkyModel* const> skies, const ViewRaysSoA& rays, const Sun& sun,
                               std::span<const StokesSoA> out) {
  const std::size_t n = skies.size();
  if (n < 2 || n > kMaxBands || out.size() != n) return false;
  std::array<const VrteSky*, kMaxBands> v{};
  for (std::size_t b = 0; b < n; ++b) {
    v[b] = dynamic_cast<const VrteSky*>(skies[b]);
    if (!v[b] || v[b]->table_->grid() != v[0]->table_->grid()) return false;
  }
  std::array<std::shared_ptr<const SunPlan>, kMaxBands> plans;
  std::array<const Kernel*, kMaxBands> kernels{};
  for (std::size_t b = 0; b < n; ++b) {
    plans[b] = v[b]->plan(sun);
    kernels[b] = &plans[b]->kernel;
  }
  if (!plans[0]->lit) {  // the same sun for every band
    for (const StokesSoA& o : out)
      for (float* c : {o.s0, o.s1, o.s2, o.s3}) std::fill(c, c + rays.count, 0.0f);
    return true;
  }
  vrte_float(std::span(kernels).first(n), rays, out);
  return true;
}

}  // namespace skypol::sky
