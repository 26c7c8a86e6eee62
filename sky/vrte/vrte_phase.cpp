// Scattering matrices for the VRTE solver: Rayleigh in closed form, the aerosol through its
// expansion in Wigner d-functions (generalized spherical functions without the phase factors; the
// same functions expand and reconstruct, so the signs of Hovenier's P^l_{mn} do not enter).
#include "sky/vrte/vrte_phase.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "sky/vrte/quadrature.h"

namespace skypol::sky::vrte {

Elements rayleigh_elements(double x, double rho) {
  const double delta = (1.0 - rho) / (1.0 + rho / 2.0);
  const double delta_p = (1.0 - 2.0 * rho) / (1.0 - rho);
  const double a = 0.75 * (1.0 + x * x);
  Elements e;
  e.f11 = delta * a + (1.0 - delta);
  e.f12 = -delta * 0.75 * (1.0 - x * x);
  e.f22 = delta * a;
  e.f33 = delta * 1.5 * x;
  e.f34 = 0.0;
  e.f44 = delta * delta_p * 1.5 * x;
  return e;
}

namespace {

// d^l_{mn} for l = lmin..lmax by the three-term recurrence, starting from d^{lmin}.
void recur(std::vector<double>& d, double x, int m, int n, int lmin, double start) {
  if (static_cast<int>(d.size()) <= lmin) return;
  d[static_cast<std::size_t>(lmin)] = start;
  double prev = 0.0;
  for (int l = lmin; l + 1 < static_cast<int>(d.size()); ++l) {
    const double cur = d[static_cast<std::size_t>(l)];
    const double lf = l;
    const double a = (2.0 * lf + 1.0) * (lf * (lf + 1.0) * x - m * n);
    const double b = (lf + 1.0) * std::sqrt(lf * lf - m * m) * std::sqrt(lf * lf - n * n);
    const double c = lf * std::sqrt((lf + 1.0) * (lf + 1.0) - m * m) * std::sqrt((lf + 1.0) * (lf + 1.0) - n * n);
    const double next = (a * cur - b * prev) / c;
    d[static_cast<std::size_t>(l) + 1] = next;
    prev = cur;
  }
}

}  // namespace

WignerRows wigner_rows(double x, int lmax) {
  const auto n = static_cast<std::size_t>(std::max(lmax, 0) + 1);
  WignerRows w{std::vector<double>(n, 0.0), std::vector<double>(n, 0.0), std::vector<double>(n, 0.0),
               std::vector<double>(n, 0.0)};
  // Legendre (the general recurrence divides by l at l = 0).
  w.d00[0] = 1.0;
  if (n > 1) w.d00[1] = x;
  for (std::size_t l = 1; l + 1 < n; ++l) {
    const double lf = static_cast<double>(l);
    w.d00[l + 1] = ((2.0 * lf + 1.0) * x * w.d00[l] - lf * w.d00[l - 1]) / (lf + 1.0);
  }
  const double s2 = 1.0 - x * x;
  recur(w.d02, x, 0, 2, 2, std::sqrt(3.0 / 8.0) * s2);
  recur(w.d22, x, 2, 2, 2, 0.25 * (1.0 + x) * (1.0 + x));
  recur(w.d2m2, x, 2, -2, 2, 0.25 * (1.0 - x) * (1.0 - x));
  return w;
}

Elements GreekCoefficients::evaluate(double x) const {
  // The four recurrences of wigner_rows run in step here, without storing the rows: this is the
  // solver's inner loop (every node pair at every azimuth).
  const int L = lmax();
  if (L < 0) return {};
  double f11 = a1[0], f44 = a4[0], sp = 0, sq = 0, f12 = 0, f34 = 0;
  double p0 = 1.0, p1 = x;  // Legendre
  if (L >= 1) {
    f11 += a1[1] * x;
    f44 += a4[1] * x;
  }
  for (int l = 1; l + 1 <= L; ++l) {
    const double lf = l;
    const double p2 = ((2.0 * lf + 1.0) * x * p1 - lf * p0) / (lf + 1.0);
    p0 = p1;
    p1 = p2;
    f11 += a1[static_cast<std::size_t>(l + 1)] * p2;
    f44 += a4[static_cast<std::size_t>(l + 1)] * p2;
  }
  if (L >= 2) {
    double e0 = 0.0, e1 = std::sqrt(3.0 / 8.0) * (1.0 - x * x);  // d02
    double g0 = 0.0, g1 = 0.25 * (1.0 + x) * (1.0 + x);          // d22
    double h0 = 0.0, h1 = 0.25 * (1.0 - x) * (1.0 - x);          // d2,-2
    for (int l = 2;; ++l) {
      const auto li = static_cast<std::size_t>(l);
      f12 += b1[li] * e1;
      f34 += b2[li] * e1;
      sp += p[li] * g1;
      sq += q[li] * h1;
      if (l == L) break;
      const double lf = l, l1 = lf + 1.0;
      const double r0 = std::sqrt(l1 * l1 - 4.0), rl = std::sqrt(lf * lf - 4.0);
      const double base = (2.0 * lf + 1.0) * lf * l1 * x;
      // (m, n) = (0, 2): mn = 0; (2, 2): mn = 4; (2, −2): mn = −4.
      const double e2 = (base * e1 - l1 * lf * rl * e0) / (lf * l1 * r0);
      const double g2 = ((base - (2.0 * lf + 1.0) * 4.0) * g1 - l1 * rl * rl * g0) / (lf * r0 * r0);
      const double h2 = ((base + (2.0 * lf + 1.0) * 4.0) * h1 - l1 * rl * rl * h0) / (lf * r0 * r0);
      e0 = e1, e1 = e2, g0 = g1, g1 = g2, h0 = h1, h1 = h2;
    }
  }
  return {f11, f12, 0.5 * (sp + sq), 0.5 * (sp - sq), f34, f44};
}

namespace {

void check_table(const ScatteringMatrixTable& t) {
  const std::size_t n = t.cos_theta.size();
  auto bad = [](const std::string& what) { throw std::invalid_argument("aerosol scattering matrix table: " + what); };
  if (n < 2) bad("needs at least 2 nodes");
  for (const auto* v : {&t.f11, &t.f12, &t.f22, &t.f33, &t.f34, &t.f44})
    if (v->size() != n) bad("every element needs one value per node (" + std::to_string(n) + ")");
  if (!t.weight.empty() && t.weight.size() != n) bad("weights must be empty or one per node");
  for (std::size_t i = 0; i < n; ++i) {
    if (!(t.cos_theta[i] >= -1.0 && t.cos_theta[i] <= 1.0)) bad("cos_theta outside [-1, 1]");
    if (i > 0 && !(t.cos_theta[i] > t.cos_theta[i - 1])) bad("cos_theta must be strictly ascending");
    if (!std::isfinite(t.f11[i]) || !std::isfinite(t.f12[i]) || !std::isfinite(t.f22[i]) || !std::isfinite(t.f33[i]) ||
        !std::isfinite(t.f34[i]) || !std::isfinite(t.f44[i]))
      bad("non-finite element");
  }
}

}  // namespace

// Linear interpolation of a table in cos Θ, clamped at its ends.
double lerp_table(const std::vector<double>& x, const std::vector<double>& v, double at) {
  const auto it = std::lower_bound(x.begin(), x.end(), at);
  if (it == x.begin()) return v.front();
  if (it == x.end()) return v.back();
  const auto hi = static_cast<std::size_t>(it - x.begin()), lo = hi - 1;
  const double a = (at - x[lo]) / (x[hi] - x[lo]);
  return (1.0 - a) * v[lo] + a * v[hi];
}

GreekCoefficients expand(const ScatteringMatrixTable& table, int lmax) {
  check_table(table);
  // Without weights the table is read as piecewise linear in cos Θ and resampled on Gauss nodes
  // fine enough for every l asked for. (Projecting with the trapezoid rule on the table's own
  // nodes would alias high orders into spurious coefficients and a spurious delta-M fraction.)
  ScatteringMatrixTable resampled;
  const ScatteringMatrixTable* tp = &table;
  if (table.weight.empty()) {
    const int n = std::max({4 * (lmax + 1), 2 * static_cast<int>(table.cos_theta.size()), 256});
    std::vector<double> gx, gw;
    gauss_legendre01(n, gx, gw);
    for (std::size_t i = 0; i < gx.size(); ++i) {
      const double x = 2.0 * gx[i] - 1.0;
      resampled.cos_theta.push_back(x);
      resampled.weight.push_back(2.0 * gw[i]);
      resampled.f11.push_back(lerp_table(table.cos_theta, table.f11, x));
      resampled.f12.push_back(lerp_table(table.cos_theta, table.f12, x));
      resampled.f22.push_back(lerp_table(table.cos_theta, table.f22, x));
      resampled.f33.push_back(lerp_table(table.cos_theta, table.f33, x));
      resampled.f34.push_back(lerp_table(table.cos_theta, table.f34, x));
      resampled.f44.push_back(lerp_table(table.cos_theta, table.f44, x));
    }
    tp = &resampled;
  }
  const ScatteringMatrixTable& t = *tp;
  const std::size_t n = t.cos_theta.size();
  const std::vector<double>& w = t.weight;
  const auto nl = static_cast<std::size_t>(lmax + 1);
  GreekCoefficients g{std::vector<double>(nl, 0.0), std::vector<double>(nl, 0.0), std::vector<double>(nl, 0.0),
                      std::vector<double>(nl, 0.0), std::vector<double>(nl, 0.0), std::vector<double>(nl, 0.0)};
  // An n-node quadrature resolves orders up to about n − 1 (Gauss: f·d^l of degree ≤ 2n − 1);
  // higher ones would be aliases, so they are left at 0.
  const int lres = std::min(lmax, static_cast<int>(n) - 1);
  for (std::size_t i = 0; i < n; ++i) {
    const WignerRows r = wigner_rows(t.cos_theta[i], lres);
    const double p = t.f22[i] + t.f33[i], q = t.f22[i] - t.f33[i];
    for (std::size_t l = 0; l <= static_cast<std::size_t>(lres); ++l) {
      const double c = 0.5 * (2.0 * static_cast<double>(l) + 1.0) * w[i];
      g.a1[l] += c * t.f11[i] * r.d00[l];
      g.a4[l] += c * t.f44[i] * r.d00[l];
      g.p[l] += c * p * r.d22[l];
      g.q[l] += c * q * r.d2m2[l];
      g.b1[l] += c * t.f12[i] * r.d02[l];
      g.b2[l] += c * t.f34[i] * r.d02[l];
    }
  }
  // The contract normalises ½∫F11 = 1; a table's own quadrature gets it only to its accuracy.
  // Renormalising keeps the solver conservative (ω alone sets the absorption).
  if (!(g.a1[0] > 0.0)) throw std::invalid_argument("aerosol scattering matrix table: F11 integrates to ≤ 0");
  const double s = 1.0 / g.a1[0];
  for (auto* v : {&g.a1, &g.a4, &g.p, &g.q, &g.b1, &g.b2})
    for (double& c : *v) c *= s;
  return g;
}

Truncated delta_m(const GreekCoefficients& full, int L) {
  Truncated t;
  const int lk = std::min(L, full.lmax());
  if (L + 1 <= full.lmax()) {
    t.f = full.a1[static_cast<std::size_t>(L + 1)] / (2.0 * L + 3.0);
    t.f = std::clamp(t.f, 0.0, 1.0 - 1e-9);
  }
  const double s = 1.0 / (1.0 - t.f);
  const auto nl = static_cast<std::size_t>(lk + 1);
  auto& c = t.coefficients;
  for (auto* v : {&c.a1, &c.a4, &c.p, &c.q, &c.b1, &c.b2}) v->assign(nl, 0.0);
  for (std::size_t l = 0; l < nl; ++l) {
    const double peak = t.f * (2.0 * static_cast<double>(l) + 1.0);
    c.a1[l] = (full.a1[l] - peak) * s;
    c.a4[l] = (full.a4[l] - peak) * s;
    c.p[l] = (full.p[l] - 2.0 * peak) * s;
    c.q[l] = full.q[l] * s;
    c.b1[l] = full.b1[l] * s;
    c.b2[l] = full.b2[l] * s;
  }
  return t;
}

AngleTable::AngleTable(const ScatteringMatrixTable& t, int samples) {
  check_table(t);
  const std::size_t n = t.cos_theta.size();
  rows_.resize(static_cast<std::size_t>(std::max(samples, 2)));
  for (std::size_t k = 0; k < rows_.size(); ++k) {
    const double th = std::numbers::pi * static_cast<double>(k) / static_cast<double>(rows_.size() - 1);
    const double x = std::cos(th);
    // First node ≥ x; clamp outside the table's range.
    const auto it = std::lower_bound(t.cos_theta.begin(), t.cos_theta.end(), x);
    std::size_t hi = static_cast<std::size_t>(it - t.cos_theta.begin());
    double a = 0.0;
    std::size_t lo = hi;
    if (hi == 0) {
      lo = hi = 0;
    } else if (hi >= n) {
      lo = hi = n - 1;
    } else {
      lo = hi - 1;
      a = (x - t.cos_theta[lo]) / (t.cos_theta[hi] - t.cos_theta[lo]);
    }
    auto mix = [&](const std::vector<double>& v) { return (1.0 - a) * v[lo] + a * v[hi]; };
    rows_[k] = {mix(t.f11), mix(t.f12), mix(t.f22), mix(t.f33), mix(t.f34), mix(t.f44)};
  }
  // Same normalisation as expand(): ½∫F11 dμ = 1, here by the trapezoid rule in Θ.
  double sum = 0.0;
  const double h = std::numbers::pi / static_cast<double>(rows_.size() - 1);
  for (std::size_t k = 0; k < rows_.size(); ++k) {
    const double wk = (k == 0 || k + 1 == rows_.size()) ? 0.5 : 1.0;
    sum += wk * rows_[k].f11 * std::sin(h * static_cast<double>(k)) * h;
  }
  if (sum > 0) {
    const double s = 2.0 / sum;
    for (Elements& e : rows_) e = {e.f11 * s, e.f12 * s, e.f22 * s, e.f33 * s, e.f34 * s, e.f44 * s};
  }
}

Elements AngleTable::at(double x) const {
  if (rows_.empty()) return {};
  const double th = std::acos(std::clamp(x, -1.0, 1.0));
  const double u = th / std::numbers::pi * static_cast<double>(rows_.size() - 1);
  const std::size_t k = std::min(static_cast<std::size_t>(u), rows_.size() - 2);
  const double a = u - static_cast<double>(k);
  const Elements& p = rows_[k];
  const Elements& q = rows_[k + 1];
  return {p.f11 + a * (q.f11 - p.f11), p.f12 + a * (q.f12 - p.f12), p.f22 + a * (q.f22 - p.f22),
          p.f33 + a * (q.f33 - p.f33), p.f34 + a * (q.f34 - p.f34), p.f44 + a * (q.f44 - p.f44)};
}

namespace {

Elements mix(const Elements& r, double wr, const Elements& a, double wa) {
  return {wr * r.f11 + wa * a.f11, wr * r.f12 + wa * a.f12, wr * r.f22 + wa * a.f22,
          wr * r.f33 + wa * a.f33, wr * r.f34 + wa * a.f34, wr * r.f44 + wa * a.f44};
}

void check_optics(const LayerOptics& o) {
  auto bad = [](const std::string& what) { throw std::invalid_argument("atmosphere optics: " + what); };
  if (!(o.tau_rayleigh >= 0.0) || !std::isfinite(o.tau_rayleigh)) bad("tau_rayleigh must be finite and >= 0");
  if (!(o.tau_aerosol >= 0.0) || !std::isfinite(o.tau_aerosol)) bad("tau_aerosol must be finite and >= 0");
  if (!(o.depolarization >= 0.0 && o.depolarization < 0.5)) bad("depolarization must be in [0, 0.5)");
  if (!(o.aerosol_ssa >= 0.0 && o.aerosol_ssa <= 1.0)) bad("aerosol_ssa must be in [0, 1]");
  if (o.tau_aerosol > 0.0 && o.aerosol.cos_theta.empty()) bad("tau_aerosol > 0 needs an aerosol scattering matrix");
}

}  // namespace

Elements ScaledLayer::omega_f(double x) const {
  const Elements r = rayleigh_elements(x, depolarization);
  if (!has_aerosol) return mix(r, rayleigh_weight, r, 0.0);
  return mix(r, rayleigh_weight, aerosol.evaluate(x), aerosol_weight);
}

ScaledLayer scale_layer(const LayerOptics& o, int streams_per_hemisphere) {
  check_optics(o);
  ScaledLayer s;
  s.depolarization = o.depolarization;
  const int L = 2 * streams_per_hemisphere - 1;
  double f = 0.0;
  s.has_aerosol = o.tau_aerosol > 0.0 && o.aerosol_ssa > 0.0;
  if (s.has_aerosol) {
    const Truncated t = delta_m(expand(o.aerosol, L + 1), L);
    f = t.f;
    s.aerosol = t.coefficients;
    s.lmax = std::max(2, s.aerosol.lmax());
  }
  s.tau = o.tau_rayleigh + o.tau_aerosol * (1.0 - o.aerosol_ssa * f);
  if (s.tau > 0.0) {
    s.rayleigh_weight = o.tau_rayleigh / s.tau;
    s.aerosol_weight = s.has_aerosol ? o.aerosol_ssa * o.tau_aerosol * (1.0 - f) / s.tau : 0.0;
  }
  return s;
}

Elements ExactLayer::omega_f(double x) const {
  const Elements r = rayleigh_elements(x, depolarization);
  if (aerosol.empty()) return mix(r, rayleigh_weight, r, 0.0);
  return mix(r, rayleigh_weight, aerosol.at(x), aerosol_weight);
}

ExactLayer exact_layer(const LayerOptics& o) {
  check_optics(o);
  ExactLayer e;
  e.depolarization = o.depolarization;
  e.tau = o.tau_rayleigh + o.tau_aerosol;
  if (o.tau_aerosol > 0.0 && o.aerosol_ssa > 0.0) e.aerosol = AngleTable(o.aerosol);
  if (e.tau > 0.0) {
    e.rayleigh_weight = o.tau_rayleigh / e.tau;
    e.aerosol_weight = e.aerosol.empty() ? 0.0 : o.aerosol_ssa * o.tau_aerosol / e.tau;
  }
  return e;
}

ScatteringMatrixTable synthetic_aerosol(double g, int nodes, double f12, double f34) {
  std::vector<double> x, w;
  gauss_legendre01(nodes, x, w);
  ScatteringMatrixTable t;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double c = 2 * x[i] - 1;
    const double f = (1 - g * g) / std::pow(1 + g * g - 2 * g * c, 1.5);
    t.cos_theta.push_back(c);
    t.weight.push_back(2 * w[i]);
    t.f11.push_back(f);
    t.f12.push_back(-f12 * f * (1 - c * c) / (1 + c * c));
    t.f22.push_back(0.95 * f);
    t.f33.push_back(0.9 * f * c);
    t.f34.push_back(f34 * f * (1 - c * c));
    t.f44.push_back(0.85 * f * c);
  }
  return t;
}

}  // namespace skypol::sky::vrte
