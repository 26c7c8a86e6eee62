// The doubling–adding solver's invariants: a thin layer is the closed-form single scattering
// (I, Q and U, reflected and transmitted, in the meridian basis of sky/vrte/vrte_solver.h); a
// conservative layer conserves flux; reflection and transmission obey reciprocity (Hovenier et
// al. 2004, ch. 5); the mirror-image shortcut of the doubling equals the full adding.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <Eigen/Geometry>

#include "sky/units.h"
#include "sky/vrte/vrte_solver.h"

using namespace skypol::sky;
using namespace skypol::sky::vrte;
using skypol::kPi;

namespace {


double sum_i(const FourierSolution& s, bool up, std::size_t i, std::size_t j, double dphi, int k) {
  double r = 0;
  for (int m = 0; m < s.terms; ++m) {
    const double v = up ? s.up_at(m, i, j, k) : s.down_at(m, i, j, k);
    r += v * (k == 2 ? std::sin(m * dphi) : std::cos(m * dphi));
  }
  return r;
}
}  // namespace

TEST_CASE("A thin Rayleigh layer gives the closed-form single scattering, I, Q and U, up and down", "[vrte][solver]") {
  const double tau = 1e-4;
  LayerOptics o;
  o.tau_rayleigh = tau;
  const std::vector<double> mu{0.05, 0.3, 0.6, 0.95};
  const FourierSolution s = solve(scale_layer(o, 8), 0.0, mu, {});
  for (std::size_t i = 0; i < mu.size(); ++i)
    for (std::size_t j = 0; j < mu.size(); ++j)
      for (double dphi : {0.0, 0.7, 1.9, 3.0}) {
        for (bool up : {false, true}) {
          // The sun at azimuth 0 (x), the observer looking at azimuth dphi, up or down.
          const double m = mu[i], m0 = mu[j];
          const Eigen::Vector3d sun(std::sqrt(1 - m0 * m0), 0, m0);
          const double sn = std::sqrt(1 - m * m);
          const Eigen::Vector3d d(sn * std::cos(dphi), sn * std::sin(dphi), up ? -m : m);
          const Eigen::Vector3d e90 = Eigen::Vector3d(-std::sin(dphi), std::cos(dphi), 0);
          const Eigen::Vector3d e0 = e90.cross(d);
          const double c = d.dot(sun);  // cos Θ (light from the sun scattered towards −d)
          const double f = up       ? m0 / (m + m0) * (1 - std::exp(-tau / m - tau / m0))
                           : i == j ? tau / m0 * std::exp(-tau / m0)
                                    : m0 * (std::exp(-tau / m) - std::exp(-tau / m0)) / (m - m0);
          const double I = 0.75 * (1 + c * c) / (4 * kPi) * f;
          const Eigen::Vector3d E = d.cross(sun);  // ⟂ the scattering plane
          const double a = E.dot(e0), b = E.dot(e90), p = 0.75 * (1 - c * c) / (4 * kPi) * f;
          const double n2 = a * a + b * b;
          INFO("mu " << m << " mu0 " << m0 << " dphi " << dphi << (up ? " up" : " down"));
          // multiple scattering is O(τ/μ + τ/μ0) of single
          const double tol = 2 * (tau / m + tau / m0) * I + 1e-12;
          CHECK(sum_i(s, up, i, j, dphi, 0) == Approx(I).margin(tol));
          CHECK(sum_i(s, up, i, j, dphi, 1) == Approx(n2 > 0 ? p * (a * a - b * b) / n2 : 0).margin(tol));
          CHECK(sum_i(s, up, i, j, dphi, 2) == Approx(n2 > 0 ? p * 2 * a * b / n2 : 0).margin(tol));
        }
      }
}

namespace {
// Reflected + diffusely transmitted + direct flux over incident flux, minus 1, for the sun at
// each Gauss node: the largest |·| (a black ground, so nothing comes back from below).
double flux_defect(const LayerOptics& o, SolverOptions opt) {
  opt.keep_gauss_matrices = true;
  const FourierSolution s = solve(scale_layer(o, opt.streams), 0.0, std::vector<double>{}, opt);
  const int ns = s.stokes;
  double worst = 0;
  for (std::size_t j = 0; j < s.gauss_mu.size(); ++j) {
    double flux = s.gauss_mu[j] * std::exp(-s.scaled_tau / s.gauss_mu[j]);  // direct beam
    for (std::size_t i = 0; i < s.gauss_mu.size(); ++i) {
      const auto r = static_cast<Eigen::Index>(i) * ns, c = static_cast<Eigen::Index>(j) * ns;
      flux += s.gauss_w[i] * s.gauss_mu[i] * (s.gauss_reflection[0](r, c) + s.gauss_transmission[0](r, c));
    }
    worst = std::max(worst, std::abs(flux / s.gauss_mu[j] - 1));
  }
  return worst;
}
}  // namespace

TEST_CASE("A conservative layer over a black ground reflects and transmits all the incident flux to 1e-7",
          "[vrte][solver]") {
  // Molecules alone and molecules with a conservative aerosol, thin to thick, at the solver's
  // default options and at 16 streams. The doubling starts from a layer correct to second order:
  // a single-scattering start loses flux ∝ τ·initial_tau (Wiscombe 1976), which the last check
  // shows is what this test would catch.
  double worst = 0, single_start = 0;
  for (bool aerosol : {false, true})
    for (int streams : {8, 16})
      for (double tau : {0.02, 0.25, 0.5, 1.0, 2.0}) {
        LayerOptics o;
        o.tau_rayleigh = aerosol ? tau / 2 : tau;
        o.depolarization = 0.03;
        if (aerosol) {
          o.tau_aerosol = tau / 2;
          o.aerosol_ssa = 1.0;
          o.aerosol = synthetic_aerosol(0.7, 120, 0.3, 0.1);
        }
        SolverOptions opt;
        opt.streams = streams;
        const double d = flux_defect(o, opt);
        INFO("tau " << tau << " streams " << streams << (aerosol ? " with aerosol" : " molecules"));
        CHECK(d < 1e-7);
        worst = std::max(worst, d);
        opt.second_order_start = false;
        single_start = std::max(single_start, flux_defect(o, opt));
      }
  CHECK(single_start > 1e-6);
  std::printf("flux conservation: worst |defect| %.2e (single-scattering start: %.2e)\n", worst, single_start);
}

TEST_CASE("Reciprocity: R(mu, mu0)/mu0 = D R(mu0, mu)^T D / mu, and the same for T with the layer turned over",
          "[vrte][solver]") {
  LayerOptics o;
  o.tau_rayleigh = 0.3;
  o.depolarization = 0.03;
  o.tau_aerosol = 0.2;
  o.aerosol_ssa = 0.9;
  o.aerosol = synthetic_aerosol(0.6, 120, 0.3, 0.1);
  SolverOptions opt;
  opt.keep_gauss_matrices = true;
  for (double albedo : {0.0, 0.4}) {
    const FourierSolution s = solve(scale_layer(o, opt.streams), albedo, std::vector<double>{}, opt);
    const int ns = s.stokes;
    REQUIRE(ns == 4);
    // D: Hovenier's diag(1, 1, −1, 1) for the transposition; M = diag(1, 1, −1, −1) turns the
    // layer over (light from below is the mirror image of light from above).
    const Eigen::Vector4d D(1, 1, -1, 1), M(1, 1, -1, -1);
    for (int m = 0; m < s.terms; m += 3)
      for (std::size_t i = 0; i < s.gauss_mu.size(); i += 2)
        for (std::size_t j = 0; j < s.gauss_mu.size(); j += 3) {
          const auto bi = static_cast<Eigen::Index>(i) * ns, bj = static_cast<Eigen::Index>(j) * ns;
          const auto& R = s.gauss_reflection[static_cast<std::size_t>(m)];
          const auto& T = s.gauss_transmission[static_cast<std::size_t>(m)];
          const Eigen::Matrix4d rij = R.block(bi, bj, 4, 4) / s.gauss_mu[j];
          const Eigen::Matrix4d rji =
              D.asDiagonal() * R.block(bj, bi, 4, 4).transpose() * D.asDiagonal() / s.gauss_mu[i];
          CHECK((rij - rji).cwiseAbs().maxCoeff() < 1e-7 * (1 + rij.cwiseAbs().maxCoeff()));
          if (albedo == 0.0) {  // with a ground, T is not a layer's own transmission
            const Eigen::Matrix4d tij = T.block(bi, bj, 4, 4) / s.gauss_mu[j];
            const Eigen::Matrix4d tji = (D.cwiseProduct(M)).asDiagonal() * T.block(bj, bi, 4, 4).transpose() *
                                        (D.cwiseProduct(M)).asDiagonal() / s.gauss_mu[i];
            CHECK((tij - tji).cwiseAbs().maxCoeff() < 1e-7 * (1 + tij.cwiseAbs().maxCoeff()));
          }
        }
  }
}

TEST_CASE("The mirror-image doubling equals the full adding equations", "[vrte][solver]") {
  LayerOptics o;
  o.tau_rayleigh = 0.2;
  o.tau_aerosol = 0.4;
  o.aerosol_ssa = 0.93;
  o.aerosol = synthetic_aerosol(0.75, 120, 0.3, 0.1);
  const std::vector<double> mu{0.0, 0.1, 0.5, 1.0};
  SolverOptions a, b;
  b.symmetric_doubling = false;
  const ScaledLayer layer = scale_layer(o, a.streams);
  const FourierSolution sa = solve(layer, 0.2, mu, a), sb = solve(layer, 0.2, mu, b);
  REQUIRE(sa.down.size() == sb.down.size());
  for (std::size_t k = 0; k < sa.down.size(); ++k) {
    CHECK(sa.down[k] == Approx(sb.down[k]).margin(1e-12));
    CHECK(sa.up[k] == Approx(sb.up[k]).margin(1e-12));
  }
}

TEST_CASE("Zero-weight nodes at the horizon and the zenith give finite values and the right limits", "[vrte][solver]") {
  LayerOptics o;
  o.tau_rayleigh = 0.3;
  const std::vector<double> mu{0.0, 1.0, 0.5};
  const FourierSolution s = solve(scale_layer(o, 8), 0.5, mu, {});
  for (double v : s.down) CHECK(std::isfinite(v));
  for (double v : s.up) CHECK(std::isfinite(v));
  for (int m = 0; m < s.terms; ++m)
    for (std::size_t i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        CHECK(s.down_at(m, i, 0, k) == 0.0);                        // a sun at the horizon lights nothing
        if (m > 0) CHECK(std::abs(s.down_at(m, i, 1, k)) < 1e-12);  // a sun at the zenith: no azimuth
        // A view at the zenith: only the m = 2 Q and U survive (the meridian basis turns with Δφ).
        if (m > 0 && !(m == 2 && k > 0)) CHECK(std::abs(s.down_at(m, 1, i, k)) < 1e-12);
      }
  CHECK(s.down_at(0, 0, 2, 0) > 0.0);  // the horizon sky is lit
  CHECK_THROWS(solve(scale_layer(o, 8), 1.5, mu, {}));
  CHECK_THROWS(solve(scale_layer(o, 8), 0.5, std::vector<double>{-0.1}, {}));
}
