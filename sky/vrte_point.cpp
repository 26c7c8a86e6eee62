// One solve with the asked-for mu and mu0 as zero-weight nodes, then the Fourier sum at Δφ and the
// map from skypol's meridian basis to the tables' (docs/conventions.md, "VRTE").
#include "sky/vrte_point.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "sky/vrte_solver.h"

namespace skypol::sky::vrte {

PointResult coulson_point(const LayerOptics& optics, double albedo, double mu0, double mu, double dphi_deg,
                          int streams) {
  if (!std::isfinite(dphi_deg)) throw std::invalid_argument("vrte: dphi must be finite");
  const ScaledLayer layer = scale_layer(optics, streams);
  SolverOptions opt;
  opt.streams = streams;
  const std::vector<double> nodes{mu, mu0};
  const FourierSolution s = solve(layer, albedo, nodes, opt);
  const double a = dphi_deg * std::numbers::pi / 180.0;
  PointResult r;
  for (int m = 0; m < s.terms; ++m) {
    const double c = std::cos(m * a), n = std::sin(m * a);
    r.top_up.i += s.up_at(m, 0, 1, 0) * c;
    r.top_up.q += s.up_at(m, 0, 1, 1) * c;
    r.top_up.u += s.up_at(m, 0, 1, 2) * n;
    r.ground_down.i += s.down_at(m, 0, 1, 0) * c;
    r.ground_down.q += s.down_at(m, 0, 1, 1) * c;
    r.ground_down.u += s.down_at(m, 0, 1, 2) * n;
  }
  // π: the tables' flux; −1 on Q and U: their basis is skypol's meridian basis turned by 90°.
  const double k = std::numbers::pi;
  r.top_up = {k * r.top_up.i, -k * r.top_up.q, -k * r.top_up.u};
  r.ground_down = {k * r.ground_down.i, -k * r.ground_down.q, -k * r.ground_down.u};
  return r;
}

PointResult coulson_point(double tau, double albedo, double depolarization, double mu0, double mu, double dphi_deg,
                          int streams) {
  LayerOptics o;
  o.tau_rayleigh = tau;
  o.depolarization = depolarization;
  return coulson_point(o, albedo, mu0, mu, dphi_deg, streams);
}

}  // namespace skypol::sky::vrte
