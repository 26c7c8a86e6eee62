// One solve with the asked-for mu and mu0 as zero-weight nodes, then the Fourier sum at Δφ and the
// map from skypol's meridian basis to the tables' (docs/conventions.md, "VRTE").
#include "sky/vrte/vrte_point.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "sky/units.h"
#include "sky/vrte/vrte_solver.h"

namespace skypol::sky::vrte {

CoulsonTable coulson_table(const LayerOptics& optics, double albedo, std::span<const double> mu0,
                           std::span<const double> mu, std::span<const double> dphi_deg, int streams) {
  for (double a : dphi_deg)
    if (!std::isfinite(a)) throw std::invalid_argument("vrte: dphi must be finite");
  const ScaledLayer layer = scale_layer(optics, streams);
  SolverOptions opt;
  opt.streams = streams;
  // Views first, then suns: each angle a zero-weight node of the one solve.
  std::vector<double> nodes(mu.begin(), mu.end());
  nodes.insert(nodes.end(), mu0.begin(), mu0.end());
  const FourierSolution s = solve(layer, albedo, nodes, opt);
  CoulsonTable t;
  t.mu0.assign(mu0.begin(), mu0.end());
  t.mu.assign(mu.begin(), mu.end());
  t.dphi_deg.assign(dphi_deg.begin(), dphi_deg.end());
  t.values.resize(mu0.size() * mu.size() * dphi_deg.size());
  // π: the tables' flux; −1 on Q and U: their basis is skypol's meridian basis turned by 90°.
  const double k = std::numbers::pi;
  for (std::size_t j = 0; j < mu0.size(); ++j)
    for (std::size_t i = 0; i < mu.size(); ++i)
      for (std::size_t a = 0; a < dphi_deg.size(); ++a) {
        const double phi = rad_from_deg(dphi_deg[a]);
        PointResult r;
        for (int m = 0; m < s.terms; ++m) {
          const double c = std::cos(m * phi), n = std::sin(m * phi);
          const std::size_t js = mu.size() + j;
          r.top_up.i += s.up_at(m, i, js, 0) * c;
          r.top_up.q += s.up_at(m, i, js, 1) * c;
          r.top_up.u += s.up_at(m, i, js, 2) * n;
          r.ground_down.i += s.down_at(m, i, js, 0) * c;
          r.ground_down.q += s.down_at(m, i, js, 1) * c;
          r.ground_down.u += s.down_at(m, i, js, 2) * n;
        }
        r.top_up = {k * r.top_up.i, -k * r.top_up.q, -k * r.top_up.u};
        r.ground_down = {k * r.ground_down.i, -k * r.ground_down.q, -k * r.ground_down.u};
        t.values[(j * mu.size() + i) * dphi_deg.size() + a] = r;
      }
  return t;
}

PointResult coulson_point(const LayerOptics& optics, double albedo, double mu0, double mu, double dphi_deg,
                          int streams) {
  const double a[] = {mu0}, b[] = {mu}, c[] = {dphi_deg};
  return coulson_table(optics, albedo, a, b, c, streams).values[0];
}

PointResult coulson_point(double tau, double albedo, double depolarization, double mu0, double mu, double dphi_deg,
                          int streams) {
  LayerOptics o;
  o.tau_rayleigh = tau;
  o.depolarization = depolarization;
  return coulson_point(o, albedo, mu0, mu, dphi_deg, streams);
}

}  // namespace skypol::sky::vrte
