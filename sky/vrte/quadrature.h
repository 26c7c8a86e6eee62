// Gauss–Legendre quadrature: the one rule the Mie averages, the scattering-matrix tables and the
// VRTE solver's streams share.
#pragma once

#include <vector>

namespace skypol::sky {

// n ≥ 1 nodes on [−1, 1], ascending, with weights summing to 2 (exact for polynomials of degree
// ≤ 2n − 1). Throws std::invalid_argument for n < 1.
void gauss_legendre(int n, std::vector<double>& nodes, std::vector<double>& weights);

// The same rule mapped to (0, 1): x = (1 + z)/2, w = w_z/2 (weights sum to 1), ascending.
void gauss_legendre01(int n, std::vector<double>& x, std::vector<double>& w);

}  // namespace skypol::sky
