#include "sky/vrte/quadrature.h"

#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "sky/units.h"

namespace skypol::sky {
namespace {

// Pₙ(z) and Pₙ'(z) by the three-term recurrence, |z| < 1.
std::pair<double, double> legendre_derivative(int n, double z) {
  double p0 = 1.0, p1 = z;
  for (int k = 2; k <= n; ++k) {
    const double fk = static_cast<double>(k);
    const double p2 = ((2.0 * fk - 1.0) * z * p1 - (fk - 1.0) * p0) / fk;
    p0 = p1;
    p1 = p2;
  }
  if (n == 1) p0 = 1.0;
  return {p1, static_cast<double>(n) * (z * p1 - p0) / (z * z - 1.0)};
}

}  // namespace

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
    for (int it = 0; it < 100; ++it) {
      const auto [p, d] = legendre_derivative(n, z);
      const double dz = p / d;
      z -= dz;
      if (std::abs(dz) < 1e-16) break;
    }
    const double dp = legendre_derivative(n, z).second;  // at the converged root, for the weight
    const double wgt = 2.0 / ((1.0 - z * z) * dp * dp);
    const std::size_t hi = nn - 1 - static_cast<std::size_t>(i), lo = static_cast<std::size_t>(i);
    nodes[hi] = z;
    nodes[lo] = -z;
    weights[hi] = wgt;
    weights[lo] = wgt;
  }
  if (n % 2 == 1) nodes[nn / 2] = 0.0;
}

void gauss_legendre01(int n, std::vector<double>& x, std::vector<double>& w) {
  gauss_legendre(n, x, w);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = 0.5 * (1.0 + x[i]);
    w[i] *= 0.5;
  }
}

}  // namespace skypol::sky
