#include "sky/mie.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

namespace skypol::sky {
namespace {

constexpr double kPi = std::numbers::pi;
using cplx = std::complex<double>;

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
  for (int n = nmx; n >= 1; --n) {
    const cplx en = static_cast<double>(n) / mx;
    d[static_cast<std::size_t>(n) - 1] = en - 1.0 / (d[static_cast<std::size_t>(n)] + en);
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
    const cplx da = dn / m + fn / x;
    const cplx db = dn * m + fn / x;
    a[static_cast<std::size_t>(n) - 1] = (da * psi - psi1) / (da * xi - xi1);
    b[static_cast<std::size_t>(n) - 1] = (db * psi - psi1) / (db * xi - xi1);
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

// S1, S2 on a set of μ ≥ 0 and on their mirrors −μ at once, using πₙ(−μ) = (−1)ⁿ⁻¹πₙ(μ) and
// τₙ(−μ) = (−1)ⁿτₙ(μ): the series is summed separately over odd and even n (B&H eqs. 4.74, 4.47).
// Structure of arrays, so the loop over angles vectorizes.
class MirrorAmplitudes {
 public:
  explicit MirrorAmplitudes(std::span<const double> mu_nonneg) : mu_(mu_nonneg.begin(), mu_nonneg.end()) {
    const std::size_t p = mu_.size();
    for (auto* v : {&pi_, &pim1_}) v->assign(p, 0.0);
    for (auto& v : acc_) v.assign(p, 0.0);
  }

  // Accumulate the series for coefficients a, b (n = 1..nstop).
  void sum(const std::vector<cplx>& a, const std::vector<cplx>& b, int nstop) {
    const std::size_t p = mu_.size();
    std::fill(pi_.begin(), pi_.end(), 1.0);
    std::fill(pim1_.begin(), pim1_.end(), 0.0);
    for (auto& v : acc_) std::fill(v.begin(), v.end(), 0.0);
    for (int n = 1; n <= nstop; ++n) {
      const double fn = static_cast<double>(n);
      const double c = (2.0 * fn + 1.0) / (fn * (fn + 1.0));
      const cplx ca = c * a[static_cast<std::size_t>(n) - 1];
      const cplx cb = c * b[static_cast<std::size_t>(n) - 1];
      const double ar = ca.real(), ai = ca.imag(), br = cb.real(), bi = cb.imag();
      const int off = (n % 2 == 1) ? 0 : 8;  // odd n: accumulators 0..7, even n: 8..15
      double* __restrict api_r = acc_[static_cast<std::size_t>(off) + 0].data();  // Σ c a π
      double* __restrict api_i = acc_[static_cast<std::size_t>(off) + 1].data();
      double* __restrict btau_r = acc_[static_cast<std::size_t>(off) + 2].data();  // Σ c b τ
      double* __restrict btau_i = acc_[static_cast<std::size_t>(off) + 3].data();
      double* __restrict atau_r = acc_[static_cast<std::size_t>(off) + 4].data();  // Σ c a τ
      double* __restrict atau_i = acc_[static_cast<std::size_t>(off) + 5].data();
      double* __restrict bpi_r = acc_[static_cast<std::size_t>(off) + 6].data();  // Σ c b π
      double* __restrict bpi_i = acc_[static_cast<std::size_t>(off) + 7].data();
      double* __restrict pi = pi_.data();
      double* __restrict pim1 = pim1_.data();
      const double* __restrict mu = mu_.data();
      for (std::size_t j = 0; j < p; ++j) {
        const double pn = pi[j];
        const double tn = fn * mu[j] * pn - (fn + 1.0) * pim1[j];
        api_r[j] += ar * pn;
        api_i[j] += ai * pn;
        btau_r[j] += br * tn;
        btau_i[j] += bi * tn;
        atau_r[j] += ar * tn;
        atau_i[j] += ai * tn;
        bpi_r[j] += br * pn;
        bpi_i[j] += bi * pn;
        const double next = ((2.0 * fn + 1.0) * mu[j] * pn - (fn + 1.0) * pim1[j]) / fn;
        pim1[j] = pn;
        pi[j] = next;
      }
    }
  }

  std::size_t size() const { return mu_.size(); }

  // Amplitudes at +μⱼ and at −μⱼ.
  void at(std::size_t j, cplx& s1p, cplx& s2p, cplx& s1m, cplx& s2m) const {
    auto g = [&](int k) { return cplx(acc_[static_cast<std::size_t>(k)][j], acc_[static_cast<std::size_t>(k) + 1][j]); };
    const cplx api_o = g(0), btau_o = g(2), atau_o = g(4), bpi_o = g(6);
    const cplx api_e = g(8), btau_e = g(10), atau_e = g(12), bpi_e = g(14);
    s1p = api_o + api_e + btau_o + btau_e;
    s2p = atau_o + atau_e + bpi_o + bpi_e;
    // Odd n: π keeps its sign at −μ, τ flips; even n: π flips, τ keeps.
    s1m = (api_o - btau_o) - (api_e - btau_e);
    s2m = (-atau_o + bpi_o) + (atau_e - bpi_e);
  }

 private:
  std::vector<double> mu_, pi_, pim1_;
  std::vector<double> acc_[16];
};

double lognormal_density(double y, double yg, double s) {
  const double t = (y - yg) / s;
  return std::exp(-0.5 * t * t);
}

void check_component(const MieComponent& c, std::size_t i) {
  const std::string who = "mie component " + std::to_string(i);
  check_m(c.m, who);
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

// The radius grid of one component, uniform in ln r where particles are small, no coarser than
// size_step in x where they are large (coarser again far out in the tail), and trapezoid weights
// times the number density in ln r.
void radius_grid(const LogNormal& size, double k_per_um, const MieQuadrature& q, std::vector<double>& r,
                 std::vector<double>& w) {
  const LogNormal s = with_default_range(size);
  const double ymin = std::log(s.r_min_um), ymax = std::log(s.r_max_um);
  const double yg = std::log(s.median_radius_um), sg = std::log(s.geometric_std);
  const double yarea = yg + 2.0 * sg * sg;  // peak of the area-weighted distribution
  std::vector<double> y;
  double yy = ymin;
  while (yy < ymax) {
    y.push_back(yy);
    const double x = k_per_um * std::exp(yy);
    const double t = (yy - yarea) / sg;
    const double rel = std::exp(-0.5 * t * t);
    const double stretch = rel >= q.tail_fraction ? 1.0 : std::min(8.0, std::sqrt(q.tail_fraction / rel));
    const double h = std::min(q.ln_r_step, stretch * q.size_step / x);
    yy += h;
  }
  if (y.empty() || ymax - y.back() < 1e-9) {
    if (!y.empty()) y.pop_back();
  }
  y.push_back(ymax);
  if (y.size() < 2) y.insert(y.begin(), ymin);
  r.resize(y.size());
  w.resize(y.size());
  for (std::size_t i = 0; i < y.size(); ++i) {
    r[i] = std::exp(y[i]);
    const double left = i > 0 ? y[i] - y[i - 1] : 0.0;
    const double right = i + 1 < y.size() ? y[i + 1] - y[i] : 0.0;
    w[i] = 0.5 * (left + right) * lognormal_density(y[i], yg, sg);
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
    double wsum = 0.0;
    for (double wi : w) wsum += wi;
    const double scale = comp.number_density / total_density / wsum;  // number fraction / ∫n dy
    for (std::size_t i = 0; i < r.size(); ++i) {
      const double x = k * r[i];
      const int nstop = mie_coefficients(comp.m, x, a, b, d);
      const Sums s = series_sums(a, b, nstop);
      const double wi = w[i] * scale;
      // Cross sections: C = (2π/k²) Σ…  (B&H eqs. 4.61, 4.62); g·C_sca = (4π/k²) Σ… (eq. 4.80).
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
  const double cfac = 2.0 * kPi / (k * k);
  out.c_ext_um2 = cfac * c_ext;
  out.c_sca_um2 = cfac * c_sca;
  out.ssa = c_ext > 0.0 ? std::min(1.0, c_sca / c_ext) : 1.0;
  out.g = c_sca > 0.0 ? gc_sca / c_sca : 0.0;
  if (angles) {
    // F = 4π ⟨½|S|²…⟩ / (k² ⟨C_sca⟩) = 2 ⟨½|S|²…⟩ / Σ(2n+1)(|a|²+|b|²)-sum: ½∫F11 dμ = 1 exactly
    // in the continuum (B&H eq. 4.77 integrated).
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

void gauss_legendre(int n, std::vector<double>& nodes, std::vector<double>& weights) {
  if (n < 1) throw std::invalid_argument("gauss_legendre: " + std::to_string(n) + " nodes (need ≥ 1)");
  const std::size_t nn = static_cast<std::size_t>(n);
  nodes.assign(nn, 0.0);
  weights.assign(nn, 0.0);
  const double fn = static_cast<double>(n);
  for (int i = 0; i < (n + 1) / 2; ++i) {
    // Tricomi's initial guess for the i-th largest root, then Newton on Pₙ.
    const double th = kPi * (static_cast<double>(i) + 0.75) / (fn + 0.5);
    double z = std::cos(th) * (1.0 - (fn - 1.0) / (8.0 * fn * fn * fn));
    double dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double fk = static_cast<double>(k);
        const double p2 = ((2.0 * fk - 1.0) * z * p1 - (fk - 1.0) * p0) / fk;
        p0 = p1;
        p1 = p2;
      }
      if (n == 1) p0 = 1.0;
      dp = fn * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16) break;
    }
    // Recompute the derivative at the converged root for the weight.
    {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double fk = static_cast<double>(k);
        const double p2 = ((2.0 * fk - 1.0) * z * p1 - (fk - 1.0) * p0) / fk;
        p0 = p1;
        p1 = p2;
      }
      if (n == 1) p0 = 1.0;
      dp = fn * (z * p1 - p0) / (z * z - 1.0);
    }
    const double wgt = 2.0 / ((1.0 - z * z) * dp * dp);
    const std::size_t hi = nn - 1 - static_cast<std::size_t>(i), lo = static_cast<std::size_t>(i);
    nodes[hi] = z;
    nodes[lo] = -z;
    weights[hi] = wgt;
    weights[lo] = wgt;
  }
  if (n % 2 == 1) nodes[nn / 2] = 0.0;
}

double quadrature_norm(const ScatteringMatrixTable& t) {
  double s = 0.0;
  for (std::size_t i = 0; i < t.f11.size() && i < t.weight.size(); ++i) s += t.weight[i] * t.f11[i];
  return 0.5 * s;
}

}  // namespace skypol::sky
