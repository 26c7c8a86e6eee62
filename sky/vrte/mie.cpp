#include "sky/vrte/mie.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "sky/units.h"
#include "sky/vector_clones.h"

namespace skypol::sky {
namespace {

using cplx = std::complex<double>;

// a/b without libgcc's __divdc3 (which guards against overflow at ~10× the cost): the values
// divided here stay far from the limits of double (|ξₙ| ≤ ~10⁵⁰ for n ≤ N at any x ≥ 10⁻⁴).
inline cplx quot(cplx a, cplx b) {
  const double inv = 1.0 / std::norm(b);
  return cplx((a.real() * b.real() + a.imag() * b.imag()) * inv, (a.imag() * b.real() - a.real() * b.imag()) * inv);
}

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void check_m(cplx m, const std::string& who) {
  if (!(std::isfinite(m.real()) && std::isfinite(m.imag()) && m.real() > 0.0 && m.imag() >= 0.0 &&
        std::abs(m) <= 20.0)) {
    throw std::invalid_argument(who + ": refractive index " + num(m.real()) + " + " + num(m.imag()) +
                                "i must have n > 0, k ≥ 0 and |m| ≤ 20");
  }
}

// Partial-wave coefficients aₙ, bₙ (n = 1..N, stored at [n−1]) of B&H eq. 4.88, with
// Dₙ(mx) = ψₙ'(mx)/ψₙ(mx) by downward recurrence (B&H eq. 4.89), and ψₙ, χₙ of the real
// argument x by upward recurrence (stable for n ≤ N ≈ x + 4x^⅓). ξₙ = ψₙ − iχₙ (B&H's
// χₙ = −x yₙ(x)). The recurrence for D starts from D = 0 at n₀ = max(N, |mx|) + 8|mx|^⅓ + 16.
// Below |mx| the recurrence neither damps nor amplifies an error in its start (for real m), so
// the start must be far enough above the turning point n ≈ |mx| for the error to have died
// there: it shrinks like exp(−(4/3)√(2/|mx|)·L^{3/2}) over the L orders beyond |mx|, which the
// 8|mx|^⅓ term makes < 10⁻¹⁷. B&H's own margin (+16) leaves relative errors of 10⁻⁵ in Qext at
// m = 1.33, x = 100 and 3·10⁻⁴ at m = 1.5, x = 1000 (Wiscombe 1980 discusses the same issue).
int mie_coefficients(cplx m, double x, std::vector<cplx>& a, std::vector<cplx>& b, std::vector<cplx>& d) {
  const int nstop = mie_term_count(x);
  const cplx mx = m * x;
  const double amx = std::abs(mx);
  const int nmx = std::max(nstop, static_cast<int>(std::ceil(amx))) + static_cast<int>(8.0 * std::cbrt(amx)) + 16;
  d.assign(static_cast<std::size_t>(nmx) + 1, cplx(0.0, 0.0));
  const cplx inv_mx = quot(1.0, mx), inv_m = quot(1.0, m);
  for (int n = nmx; n >= 1; --n) {
    const cplx en = static_cast<double>(n) * inv_mx;
    d[static_cast<std::size_t>(n) - 1] = en - quot(1.0, d[static_cast<std::size_t>(n)] + en);
  }
  a.resize(static_cast<std::size_t>(nstop));
  b.resize(static_cast<std::size_t>(nstop));
  double psi0 = std::cos(x), psi1 = std::sin(x);  // ψ₋₁, ψ₀
  double chi0 = -std::sin(x), chi1 = std::cos(x);  // χ₋₁, χ₀
  cplx xi1(psi1, -chi1);
  for (int n = 1; n <= nstop; ++n) {
    const double fn = static_cast<double>(n);
    const double psi = (2.0 * fn - 1.0) * psi1 / x - psi0;
    const double chi = (2.0 * fn - 1.0) * chi1 / x - chi0;
    const cplx xi(psi, -chi);
    const cplx dn = d[static_cast<std::size_t>(n)];
    const cplx da = dn * inv_m + fn / x;
    const cplx db = dn * m + fn / x;
    a[static_cast<std::size_t>(n) - 1] = quot(da * psi - psi1, da * xi - xi1);
    b[static_cast<std::size_t>(n) - 1] = quot(db * psi - psi1, db * xi - xi1);
    psi0 = psi1;
    psi1 = psi;
    chi0 = chi1;
    chi1 = chi;
    xi1 = xi;
  }
  return nstop;
}

struct Sums {
  double ext = 0.0;    // Σ(2n+1) Re(aₙ + bₙ)
  double sca = 0.0;    // Σ(2n+1)(|aₙ|² + |bₙ|²)
  double asym = 0.0;   // Σ n(n+2)/(n+1) Re(aₙa*ₙ₊₁ + bₙb*ₙ₊₁) + (2n+1)/(n(n+1)) Re(aₙb*ₙ)
  cplx back{0.0, 0.0}; // Σ(2n+1)(−1)ⁿ(aₙ − bₙ)
};

Sums series_sums(const std::vector<cplx>& a, const std::vector<cplx>& b, int nstop) {
  Sums s;
  for (int n = 1; n <= nstop; ++n) {
    const std::size_t i = static_cast<std::size_t>(n) - 1;
    const double fn = static_cast<double>(n);
    const double c = 2.0 * fn + 1.0;
    s.ext += c * (a[i].real() + b[i].real());
    s.sca += c * (std::norm(a[i]) + std::norm(b[i]));
    s.asym += c / (fn * (fn + 1.0)) * (a[i] * std::conj(b[i])).real();
    if (n < nstop) {
      s.asym += fn * (fn + 2.0) / (fn + 1.0) * (a[i] * std::conj(a[i + 1]) + b[i] * std::conj(b[i + 1])).real();
    }
    s.back += (n % 2 == 0 ? c : -c) * (a[i] - b[i]);
  }
  return s;
}

// Per order n of the amplitude series: c·aₙ and c·bₙ (c = (2n+1)/(n(n+1))) and the recurrence
// constants, τₙ = n·μπₙ − (n+1)πₙ₋₁ and πₙ₊₁ = ((2n+1)/n)·μπₙ − ((n+1)/n)·πₙ₋₁.
struct Order {
  double ar, ai, br, bi;
  double n, n1, g2, g1;
};

constexpr std::size_t kLanes = 4;  // angles per vector
using Lanes = double __attribute__((vector_size(kLanes * sizeof(double))));

// The whole series for kLanes angles at a time, the eight sums in registers: one pass over the
// orders per block of angles (the orders' constants are shared by all angles). GCC's vector
// extension: 4 doubles, one AVX2 register in the AVX2 clone, two SSE2 registers otherwise.
SKYPOL_VECTOR_CLONES void amplitude_series(std::size_t padded, const Order* order, int nstop,
                                           const double* __restrict mu, double* __restrict p1r,
                                           double* __restrict p1i, double* __restrict q1r, double* __restrict q1i,
                                           double* __restrict p2r, double* __restrict p2i, double* __restrict q2r,
                                           double* __restrict q2i) {
  for (std::size_t j = 0; j < padded; j += kLanes) {
    Lanes m, pn, pm;
    for (std::size_t l = 0; l < kLanes; ++l) {
      m[l] = mu[j + l];
      pn[l] = 1.0;
      pm[l] = 0.0;
    }
    Lanes P1r = pm, P1i = pm, Q1r = pm, Q1i = pm, P2r = pm, P2i = pm, Q2r = pm, Q2i = pm;
    // Two orders per step (odd n, then even n + 1): the π recurrence is the critical path.
    int n = 1;
    for (; n + 1 <= nstop; n += 2) {
      const Order& o = order[n - 1];
      const Order& e = order[n];
      const Lanes mp = m * pn;
      const Lanes tn = o.n * mp - o.n1 * pm;
      const Lanes pe = o.g2 * mp - o.g1 * pm;  // π of order n + 1
      const Lanes mpe = m * pe;
      const Lanes te = e.n * mpe - e.n1 * pn;
      P1r += o.ar * pn + e.br * te;
      P1i += o.ai * pn + e.bi * te;
      Q1r += o.br * tn + e.ar * pe;
      Q1i += o.bi * tn + e.ai * pe;
      P2r += o.br * pn + e.ar * te;
      P2i += o.bi * pn + e.ai * te;
      Q2r += o.ar * tn + e.br * pe;
      Q2i += o.ai * tn + e.bi * pe;
      const Lanes next = e.g2 * mpe - e.g1 * pn;
      pm = pe;
      pn = next;
    }
    if (n == nstop) {  // a last odd order
      const Order& o = order[n - 1];
      const Lanes mp = m * pn;
      const Lanes tn = o.n * mp - o.n1 * pm;
      P1r += o.ar * pn;
      P1i += o.ai * pn;
      Q1r += o.br * tn;
      Q1i += o.bi * tn;
      P2r += o.br * pn;
      P2i += o.bi * pn;
      Q2r += o.ar * tn;
      Q2i += o.ai * tn;
    }
    for (std::size_t l = 0; l < kLanes; ++l) {
      p1r[j + l] = P1r[l];
      p1i[j + l] = P1i[l];
      q1r[j + l] = Q1r[l];
      q1i[j + l] = Q1i[l];
      p2r[j + l] = P2r[l];
      p2i[j + l] = P2i[l];
      q2r[j + l] = Q2r[l];
      q2i[j + l] = Q2i[l];
    }
  }
}

// The amplitude series on a set of μ ≥ 0 and on their mirrors −μ at once, using
// πₙ(−μ) = (−1)ⁿ⁻¹πₙ(μ) and τₙ(−μ) = (−1)ⁿτₙ(μ) (B&H eqs. 4.46–4.47, 4.74). With Aₚ = Σ c aₙπₙ,
// Bₚ = Σ c bₙτₙ, Cₚ = Σ c aₙτₙ, Dₚ = Σ c bₙπₙ summed over odd (o) or even (e) n:
//   S1(±μ) = P1 ± Q1 with P1 = A_o + B_e, Q1 = B_o + A_e,
//   S2(±μ) = P2 ± Q2 with P2 = D_o + C_e, Q2 = C_o + D_e,
// so four complex sums per angle serve both directions.
class MirrorAmplitudes {
 public:
  explicit MirrorAmplitudes(std::span<const double> mu_nonneg) : count_(mu_nonneg.size()) {
    const std::size_t padded = (count_ + kLanes - 1) / kLanes * kLanes;
    mu_.assign(padded, 0.0);
    std::copy(mu_nonneg.begin(), mu_nonneg.end(), mu_.begin());
    for (auto& v : acc_) v.assign(padded, 0.0);
  }

  // Sum the series for coefficients a, b (n = 1..nstop).
  void sum(const std::vector<cplx>& a, const std::vector<cplx>& b, int nstop) {
    order_.resize(static_cast<std::size_t>(nstop));
    for (int n = 1; n <= nstop; ++n) {
      const double fn = static_cast<double>(n);
      const double c = (2.0 * fn + 1.0) / (fn * (fn + 1.0));
      const cplx ca = c * a[static_cast<std::size_t>(n) - 1], cb = c * b[static_cast<std::size_t>(n) - 1];
      order_[static_cast<std::size_t>(n) - 1] = {ca.real(), ca.imag(), cb.real(), cb.imag(),
                                                 fn,        fn + 1.0,  (2.0 * fn + 1.0) / fn, (fn + 1.0) / fn};
    }
    amplitude_series(mu_.size(), order_.data(), nstop, mu_.data(), acc_[0].data(), acc_[1].data(), acc_[2].data(),
                     acc_[3].data(), acc_[4].data(), acc_[5].data(), acc_[6].data(), acc_[7].data());
  }

  std::size_t size() const { return count_; }

  // Amplitudes at +μⱼ and at −μⱼ.
  void at(std::size_t j, cplx& s1p, cplx& s2p, cplx& s1m, cplx& s2m) const {
    const cplx p1(acc_[0][j], acc_[1][j]), q1(acc_[2][j], acc_[3][j]);
    const cplx p2(acc_[4][j], acc_[5][j]), q2(acc_[6][j], acc_[7][j]);
    s1p = p1 + q1;
    s1m = p1 - q1;
    s2p = p2 + q2;
    s2m = p2 - q2;
  }

 private:
  std::size_t count_;
  std::vector<double> mu_;
  std::vector<Order> order_;
  std::vector<double> acc_[8];
};

double lognormal_density(double y, double yg, double s) {
  const double t = (y - yg) / s;
  return std::exp(-0.5 * t * t);
}

void check_component(const MieComponent& c, std::size_t i) {
  const std::string who = "mie component " + std::to_string(i);
  check_m(c.m, who);
  if (c.m == cplx(1.0, 0.0)) {
    throw std::invalid_argument(who + ": refractive index 1 + 0i is the medium itself (scatters nothing)");
  }
  const LogNormal& s = c.size;
  if (!(std::isfinite(s.median_radius_um) && s.median_radius_um > 0.0)) {
    throw std::invalid_argument(who + ": median radius " + num(s.median_radius_um) + " µm must be > 0");
  }
  if (!(std::isfinite(s.geometric_std) && s.geometric_std > 1.0 && s.geometric_std <= 5.0)) {
    throw std::invalid_argument(who + ": geometric standard deviation " + num(s.geometric_std) +
                                " must be in (1, 5]");
  }
  const bool default_range = s.r_min_um == 0.0 && s.r_max_um == 0.0;
  if (!default_range && !(std::isfinite(s.r_min_um) && std::isfinite(s.r_max_um) && s.r_min_um > 0.0 &&
                          s.r_max_um > s.r_min_um)) {
    throw std::invalid_argument(who + ": radius range [" + num(s.r_min_um) + ", " + num(s.r_max_um) +
                                "] µm must satisfy 0 < r_min < r_max (or both 0 for the default)");
  }
  if (!(std::isfinite(c.number_density) && c.number_density >= 0.0)) {
    throw std::invalid_argument(who + ": number density " + num(c.number_density) + " must be ≥ 0");
  }
}

// The radius nodes of one component and their weights (quadrature weight in ln r times the
// number density dN/d ln r): composite 8-point Gauss–Legendre panels in ln r. A panel is 8 steps
// wide, a step being ln_r_step where particles are small and size_step/x where they are large, so
// oscillations of Q(x) and S(Θ; x) are sampled; far in the tail of the area-weighted distribution
// (weight < tail_fraction of its peak) the size step grows as 1/√weight, up to 8×. Panels make
// the rule high order whatever the step does, so a varying step costs no accuracy where the
// integrand is smooth (a trapezoid rule on a non-uniform grid would fall to second order).
void radius_grid(const LogNormal& size, double k_per_um, const MieQuadrature& q, std::vector<double>& r,
                 std::vector<double>& w) {
  constexpr int kPanel = 8;
  static const auto gl = [] {
    std::pair<std::vector<double>, std::vector<double>> p;
    gauss_legendre(kPanel, p.first, p.second);
    return p;
  }();
  const LogNormal s = with_default_range(size);
  const double ymin = std::log(s.r_min_um), ymax = std::log(s.r_max_um);
  const double yg = std::log(s.median_radius_um), sg = std::log(s.geometric_std);
  const double yarea = yg + 2.0 * sg * sg;  // peak of the area-weighted distribution
  r.clear();
  w.clear();
  double y0 = ymin;
  while (y0 < ymax) {
    const double x = k_per_um * std::exp(y0);
    const double t = (y0 - yarea) / sg;
    const double rel = std::exp(-0.5 * t * t);
    const double stretch = rel >= q.tail_fraction ? 1.0 : std::min(8.0, std::sqrt(q.tail_fraction / rel));
    // A panel spans at most 2 ln σ_g, so narrow distributions get their own resolution.
    const double step = std::min({q.ln_r_step, stretch * q.size_step / x, 0.25 * sg});
    double y1 = y0 + kPanel * step;
    if (y1 > ymax || ymax - y1 < 0.25 * kPanel * step) y1 = ymax;  // no sliver of a last panel
    const double half = 0.5 * (y1 - y0), mid = 0.5 * (y1 + y0);
    for (int i = 0; i < kPanel; ++i) {
      const double y = mid + half * gl.first[static_cast<std::size_t>(i)];
      r.push_back(std::exp(y));
      w.push_back(half * gl.second[static_cast<std::size_t>(i)] * lognormal_density(y, yg, sg));
    }
    y0 = y1;
  }
}

MieEnsemble ensemble(std::span<const MieComponent> mixture, double wavelength_nm, const MieQuadrature& q,
                     bool angles) {
  if (mixture.empty()) throw std::invalid_argument("mie: the mixture is empty");
  if (!(std::isfinite(wavelength_nm) && wavelength_nm > 0.0)) {
    throw std::invalid_argument("mie: wavelength " + num(wavelength_nm) + " nm must be > 0");
  }
  if (angles && q.angle_nodes < 2) {
    throw std::invalid_argument("mie: " + std::to_string(q.angle_nodes) + " angle nodes (need ≥ 2)");
  }
  if (!(q.ln_r_step > 0.0 && q.size_step > 0.0 && q.tail_fraction >= 0.0)) {
    throw std::invalid_argument("mie: quadrature steps must be > 0");
  }
  double total_density = 0.0;
  for (std::size_t i = 0; i < mixture.size(); ++i) {
    check_component(mixture[i], i);
    total_density += mixture[i].number_density;
  }
  if (!(total_density > 0.0)) throw std::invalid_argument("mie: every component has number density 0");

  const double lambda_um = wavelength_nm * 1e-3;
  const double k = 2.0 * kPi / lambda_um;  // µm⁻¹

  MieEnsemble out;
  std::vector<double> mu_all, wt_all, mu_half;
  if (angles) {
    gauss_legendre(q.angle_nodes, mu_all, wt_all);
    // The non-negative half, ascending: node N−1−j mirrors node j.
    const std::size_t n = mu_all.size();
    for (std::size_t j = n / 2; j < n; ++j) mu_half.push_back(mu_all[j] < 0 ? 0.0 : mu_all[j]);
  }
  const std::size_t nang = mu_all.size();
  std::vector<double> f11(nang, 0.0), f12(nang, 0.0), f33(nang, 0.0), f34(nang, 0.0);
  MirrorAmplitudes amp(mu_half);

  double c_ext = 0.0, c_sca = 0.0, gc_sca = 0.0;  // density-weighted sums over all components
  std::vector<cplx> a, b, d;
  std::vector<double> r, w;
  for (const MieComponent& comp : mixture) {
    if (comp.number_density == 0.0) continue;
    radius_grid(comp.size, k, q, r, w);
    // Number fraction over the integral of the whole (untruncated) log-normal, √(2π) ln σ_g:
    // particles outside [r_min, r_max] count but are not integrated, as in OPAC.
    const double scale = comp.number_density / total_density / (std::sqrt(2.0 * kPi) * std::log(comp.size.geometric_std));
    for (std::size_t i = 0; i < r.size(); ++i) {
      const double x = k * r[i];
      const int nstop = mie_coefficients(comp.m, x, a, b, d);
      const Sums s = series_sums(a, b, nstop);
      const double wi = w[i] * scale;
      // Cross sections: C = (2π/k²) Σ…  (B&H eqs. 4.61, 4.62); g·C_sca = (4π/k²) Σ… (B&H sect. 4.5).
      c_ext += wi * s.ext;
      c_sca += wi * s.sca;
      gc_sca += wi * 2.0 * s.asym;
      ++out.radius_nodes;
      if (!angles) continue;
      amp.sum(a, b, nstop);
      const std::size_t half = amp.size();
      for (std::size_t j = 0; j < half; ++j) {
        cplx s1p, s2p, s1m, s2m;
        amp.at(j, s1p, s2p, s1m, s2m);
        const std::size_t up = nang - half + j;  // index of +μⱼ in the ascending table
        const std::size_t dn = half - 1 - j;     // index of −μⱼ
        auto add = [&](std::size_t idx, cplx s1, cplx s2) {
          const double n1 = std::norm(s1), n2 = std::norm(s2);
          const cplx c21 = s2 * std::conj(s1);
          f11[idx] += wi * 0.5 * (n2 + n1);
          f12[idx] += wi * 0.5 * (n2 - n1);
          f33[idx] += wi * c21.real();
          f34[idx] += wi * c21.imag();
        };
        add(up, s1p, s2p);
        if (dn != up) add(dn, s1m, s2m);  // with N odd the middle node μ = 0 is its own mirror
      }
    }
  }
  if (!(c_sca > 0.0)) {
    // m = 1 + 0i (or particles far below the range of double): nothing to normalise a phase
    // function by. Refuse rather than hand the solver NaNs.
    throw std::invalid_argument("mie: the mixture scatters no light (refractive index 1 + 0i?)");
  }
  const double cfac = 2.0 * kPi / (k * k);
  out.c_ext_um2 = cfac * c_ext;
  out.c_sca_um2 = cfac * c_sca;
  out.ssa = c_ext > 0.0 ? std::min(1.0, c_sca / c_ext) : 1.0;
  out.g = c_sca > 0.0 ? gc_sca / c_sca : 0.0;
  if (angles) {
    // F = 4π ⟨½|S|²…⟩ / (k² ⟨C_sca⟩) = 2 ⟨½|S|²…⟩ / Σ(2n+1)(|a|²+|b|²)-sum: ½∫F11 dμ = 1 exactly
    // in the continuum.
    const double norm = 2.0 / c_sca;
    ScatteringMatrixTable& t = out.table;
    t.cos_theta = mu_all;
    t.weight = wt_all;
    t.f11.resize(nang);
    t.f12.resize(nang);
    t.f33.resize(nang);
    t.f34.resize(nang);
    for (std::size_t j = 0; j < nang; ++j) {
      t.f11[j] = norm * f11[j];
      t.f12[j] = norm * f12[j];
      t.f33[j] = norm * f33[j];
      t.f34[j] = norm * f34[j];
    }
    t.f22 = t.f11;  // spheres
    t.f44 = t.f33;
  }
  return out;
}

}  // namespace

int mie_term_count(double x) {
  const double c = std::cbrt(x);
  double n;
  if (x <= 8.0) {
    n = x + 4.0 * c + 1.0;
  } else if (x < 4200.0) {
    n = x + 4.05 * c + 2.0;
  } else {
    n = x + 4.0 * c + 2.0;
  }
  return std::max(2, static_cast<int>(n));
}

MieSphere mie_sphere(cplx m, double x, std::span<const double> cos_theta) {
  check_m(m, "mie");
  if (!(std::isfinite(x) && x > 0.0 && x <= 2.0e4)) {
    throw std::invalid_argument("mie: size parameter " + num(x) + " must be in (0, 20000]");
  }
  for (double mu : cos_theta) {
    if (!(mu >= -1.0 && mu <= 1.0)) throw std::invalid_argument("mie: cos Θ = " + num(mu) + " is outside [−1, 1]");
  }
  std::vector<cplx> a, b, d;
  const int nstop = mie_coefficients(m, x, a, b, d);
  const Sums s = series_sums(a, b, nstop);
  MieSphere out;
  const double x2 = x * x;
  out.qext = 2.0 / x2 * s.ext;
  out.qsca = 2.0 / x2 * s.sca;
  out.qback = std::norm(s.back) / x2;
  out.g = s.sca > 0.0 ? 2.0 * s.asym / s.sca : 0.0;
  out.s1.resize(cos_theta.size());
  out.s2.resize(cos_theta.size());
  for (std::size_t j = 0; j < cos_theta.size(); ++j) {
    const double mu = cos_theta[j];
    double pim1 = 0.0, pn = 1.0;
    cplx s1(0.0, 0.0), s2(0.0, 0.0);
    for (int n = 1; n <= nstop; ++n) {
      const double fn = static_cast<double>(n);
      const double tn = fn * mu * pn - (fn + 1.0) * pim1;
      const double c = (2.0 * fn + 1.0) / (fn * (fn + 1.0));
      const cplx an = a[static_cast<std::size_t>(n) - 1], bn = b[static_cast<std::size_t>(n) - 1];
      s1 += c * (an * pn + bn * tn);
      s2 += c * (an * tn + bn * pn);
      const double next = ((2.0 * fn + 1.0) * mu * pn - (fn + 1.0) * pim1) / fn;
      pim1 = pn;
      pn = next;
    }
    out.s1[j] = s1;
    out.s2[j] = s2;
  }
  return out;
}

LogNormal with_default_range(const LogNormal& size) {
  LogNormal s = size;
  if (s.r_min_um == 0.0 && s.r_max_um == 0.0) {
    const double sg = std::log(s.geometric_std);
    s.r_min_um = s.median_radius_um * std::exp(-4.0 * sg);
    s.r_max_um = s.median_radius_um * std::exp(4.0 * sg + 2.0 * sg * sg);
  }
  return s;
}

MieEnsemble mie_ensemble(std::span<const MieComponent> mixture, double wavelength_nm, const MieQuadrature& q) {
  return ensemble(mixture, wavelength_nm, q, true);
}

MieEnsemble mie_ensemble_cross_sections(std::span<const MieComponent> mixture, double wavelength_nm,
                                        const MieQuadrature& q) {
  return ensemble(mixture, wavelength_nm, q, false);
}

double quadrature_norm(const ScatteringMatrixTable& t) {
  double s = 0.0;
  for (std::size_t i = 0; i < t.f11.size() && i < t.weight.size(); ++i) s += t.weight[i] * t.f11[i];
  return 0.5 * s;
}

}  // namespace skypol::sky
