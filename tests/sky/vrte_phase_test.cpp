// The VRTE solver's scattering matrices: Wigner d-functions against their closed forms, the Greek
// expansion of a tabulated matrix (Rayleigh, whose expansion ends at l = 2, is reproduced exactly),
// delta-M truncation's bookkeeping, and the depolarized Rayleigh matrix's normalisation.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "sky/vrte/vrte_phase.h"
#include "sky/vrte/vrte_solver.h"

using namespace skypol::sky;
using namespace skypol::sky::vrte;

namespace {
// A Rayleigh matrix (depolarization rho) tabulated on Gauss nodes of [-1, 1], as Mie code would.
ScatteringMatrixTable rayleigh_table(double rho, int n) {
  std::vector<double> x, w;
  gauss_legendre01(n, x, w);
  ScatteringMatrixTable t;
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    t.cos_theta.push_back(2.0 * x[k] - 1.0);
    t.weight.push_back(2.0 * w[k]);
    const Elements e = rayleigh_elements(2.0 * x[k] - 1.0, rho);
    t.f11.push_back(e.f11);
    t.f12.push_back(e.f12);
    t.f22.push_back(e.f22);
    t.f33.push_back(e.f33);
    t.f34.push_back(0.1 * (1 - (2 * x[k] - 1) * (2 * x[k] - 1)));  // any smooth F34 (degree 2)
    t.f44.push_back(e.f44);
  }
  return t;
}
}  // namespace

TEST_CASE("Wigner d-functions match their closed forms", "[vrte][phase]") {
  for (double x : {-1.0, -0.7, 0.0, 0.3, 0.99, 1.0}) {
    const WignerRows w = wigner_rows(x, 4);
    CHECK(w.d00[2] == Approx(0.5 * (3 * x * x - 1)).margin(1e-14));
    CHECK(w.d00[3] == Approx(0.5 * (5 * x * x * x - 3 * x)).margin(1e-14));
    // d^l_{02} = sqrt((l−2)!/(l+2)!) P_l^2: P_3^2 = 15 x (1 − x²), P_4^2 = 7.5 (7x² − 1)(1 − x²)
    CHECK(w.d02[3] == Approx(15 * x * (1 - x * x) / std::sqrt(120.0)).margin(1e-14));
    CHECK(w.d02[4] == Approx(7.5 * (7 * x * x - 1) * (1 - x * x) / std::sqrt(360.0)).margin(1e-14));
    // d^3_{22} = (1+x)²(3x − 2)/4, d^3_{2,−2} = (1−x)²(3x + 2)/4 (tables of Wigner d-functions)
    CHECK(w.d22[3] == Approx(0.25 * (1 + x) * (1 + x) * (3 * x - 2)).margin(1e-14));
    CHECK(w.d2m2[3] == Approx(0.25 * (1 - x) * (1 - x) * (3 * x + 2)).margin(1e-14));
  }
}

TEST_CASE("Depolarized Rayleigh matrix: phase function averages to 1, forward F22 = F33", "[vrte][phase]") {
  for (double rho : {0.0, 0.0279, 0.1}) {
    std::vector<double> x, w;
    gauss_legendre01(8, x, w);
    double sum = 0;
    for (std::size_t i = 0; i < x.size(); ++i) sum += w[i] * rayleigh_elements(2 * x[i] - 1, rho).f11;
    CHECK(sum == Approx(1.0).margin(1e-14));  // ½∫F11 dμ with ∫₀¹ weights on [−1,1] halved
    const Elements f = rayleigh_elements(1.0, rho);
    CHECK(f.f22 == Approx(f.f33));
    // degree of polarization at 90°: (1 − ρ)/(1 + ρ) (Hansen & Travis 1974)
    const Elements r = rayleigh_elements(0.0, rho);
    CHECK(-r.f12 / r.f11 == Approx((1 - rho) / (1 + rho)).margin(1e-14));
  }
}

TEST_CASE("Greek expansion of a tabulated Rayleigh matrix ends at l = 2 and reconstructs it", "[vrte][phase]") {
  const ScatteringMatrixTable t = rayleigh_table(0.03, 16);
  const GreekCoefficients g = expand(t, 10);
  CHECK(g.a1[0] == Approx(1.0).margin(1e-14));
  for (std::size_t l = 3; l <= 10; ++l) {
    CHECK(std::abs(g.a1[l]) < 1e-13);
    CHECK(std::abs(g.p[l]) < 1e-13);
    CHECK(std::abs(g.b1[l]) < 1e-13);
  }
  for (double x : {-1.0, -0.5, 0.1, 0.8, 1.0}) {
    const Elements a = g.evaluate(x), b = rayleigh_elements(x, 0.03);
    CHECK(a.f11 == Approx(b.f11).margin(1e-13));
    CHECK(a.f12 == Approx(b.f12).margin(1e-13));
    CHECK(a.f22 == Approx(b.f22).margin(1e-13));
    CHECK(a.f33 == Approx(b.f33).margin(1e-13));
    CHECK(a.f44 == Approx(b.f44).margin(1e-13));
    CHECK(a.f34 == Approx(0.1 * (1 - x * x)).margin(1e-13));
    // evaluate()'s fused recurrences agree with the stored rows
    const WignerRows w = wigner_rows(x, 10);
    double f12 = 0;
    for (std::size_t l = 0; l <= 10; ++l) f12 += g.b1[l] * w.d02[l];
    CHECK(a.f12 == Approx(f12).margin(1e-14));
  }
}

TEST_CASE("Delta-M keeps the phase function's normalisation and moves the peak into f", "[vrte][phase]") {
  // Henyey–Greenstein moments a1_l = (2l+1) g^l (Wiscombe 1977's example), no polarization.
  GreekCoefficients full;
  const double gg = 0.8;
  for (int l = 0; l <= 40; ++l) {
    full.a1.push_back((2 * l + 1) * std::pow(gg, l));
    full.a4.push_back(0);
    full.p.push_back(2 * (2 * l + 1) * std::pow(gg, l));
    full.q.push_back(0);
    full.b1.push_back(0);
    full.b2.push_back(0);
  }
  const Truncated t = delta_m(full, 15);
  CHECK(t.f == Approx(std::pow(gg, 16)).margin(1e-14));
  CHECK(t.coefficients.lmax() == 15);
  CHECK(t.coefficients.a1[0] == Approx(1.0).margin(1e-14));
  // asymmetry factor of the truncated function: (g − f)/(1 − f) (Wiscombe 1977)
  CHECK(t.coefficients.a1[1] / 3 == Approx((gg - t.f) / (1 - t.f)).margin(1e-14));
}

TEST_CASE("Bad layer optics are refused with a message", "[vrte][phase]") {
  LayerOptics o;
  o.tau_rayleigh = -1;
  CHECK_THROWS_WITH(scale_layer(o, 8), Catch::Contains("tau_rayleigh"));
  o.tau_rayleigh = 0.1;
  o.tau_aerosol = 0.1;  // no table
  CHECK_THROWS_WITH(scale_layer(o, 8), Catch::Contains("aerosol"));
  o.tau_aerosol = 0;
  o.depolarization = 0.6;
  CHECK_THROWS_WITH(scale_layer(o, 8), Catch::Contains("depolarization"));
}
