// skypol_vrte_bench: prints what a VRTE table costs per band and what a pixel lookup costs, and
// with --natraj what each streams value costs and how close it comes to Natraj et al. 2009's
// tables (the 504-entry sample tests/sky/vrte_coulson_test.cpp holds).
// Usage: skypol_vrte_bench [threads] [--natraj streams...]   (not run by ctest: figures, not pass/fail)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

#include "sky/vrte/vrte_bench.h"
#include "sky/vrte/vrte_point.h"

namespace {

struct Row {
  double tau, albedo;
  int up;
  double mu0, mu, phi, i, q, u;
};
const Row kRows[] = {
#include "natraj2009_tables.inc"
};

std::size_t index_of(const std::vector<double>& v, double x) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (std::abs(v[k] - x) < 1e-9) return k;
  std::fprintf(stderr, "skypol_vrte_bench: %g is not in the sample's grid\n", x);
  std::exit(1);
}

// One coulson_table solve per (τ, albedo) of the sample; the worst |difference| in I, Q, U for
// views near the horizon (μ = 0.02) and above (μ ≥ 0.2), and the solves' time.
void natraj(int streams) {
  const std::vector<double> mu0{0.1, 0.4, 0.92}, mu{0.02, 0.2, 0.64, 1.0}, phi{0, 90, 150};
  double low = 0, high = 0, seconds = 0;
  for (double tau : {0.02, 0.25, 1.0})
    for (double albedo : {0.0, 0.25, 0.8}) {
      skypol::sky::LayerOptics o;
      o.tau_rayleigh = tau;
      const auto t0 = std::chrono::steady_clock::now();
      const auto t = skypol::sky::vrte::coulson_table(o, albedo, mu0, mu, phi, streams);
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      for (const Row& r : kRows) {
        if (r.tau != tau || r.albedo != albedo) continue;
        const auto& cell = t.at(index_of(mu0, r.mu0), index_of(mu, r.mu), index_of(phi, r.phi));
        const auto& v = r.up ? cell.top_up : cell.ground_down;
        const double d = std::max({std::abs(v.i - r.i), std::abs(v.q - r.q), std::abs(v.u - r.u)});
        double& worst = r.mu < 0.1 ? low : high;
        worst = std::max(worst, d);
      }
    }
  std::printf("  %2d streams:  %.3f s   worst |diff| %.1e at mu 0.02, %.1e at mu >= 0.2\n", streams, seconds, low,
              high);
}

}  // namespace

int main(int argc, char** argv) {
  int threads = 0;
  std::vector<int> sweep;
  for (int a = 1; a < argc; ++a) {
    if (std::strcmp(argv[a], "--natraj") == 0) {
      for (++a; a < argc; ++a) sweep.push_back(std::atoi(argv[a]));
    } else {
      threads = std::atoi(argv[a]);
    }
  }
  if (!sweep.empty()) {
    std::printf(
        "Natraj et al. 2009's sample (%zu entries, 9 layers: tau 0.02, 0.25, 1 x albedo 0, 0.25, 0.8), "
        "one solve per layer on %u thread(s):\n",
        sizeof kRows / sizeof kRows[0], std::thread::hardware_concurrency());
    for (int s : sweep) natraj(s);
    return 0;
  }
  const auto b = skypol::sky::vrte::bench(threads);
  std::printf("vrte table build, %d thread(s), default options (12 streams, grid 25):\n", b.threads);
  std::printf("  molecules only:        %.3f s  (%d Fourier terms)\n", b.rayleigh_build_s, b.rayleigh_terms);
  std::printf("  molecules + aerosol:   %.3f s  (%d Fourier terms)\n", b.aerosol_build_s, b.aerosol_terms);
  std::printf("vrte per-pixel lookup (batch path, one thread, per CPU second):\n");
  std::printf("  molecules only:        %.2f Mrays/s\n", b.rayleigh_mrays_per_s);
  std::printf("  molecules + aerosol:   %.2f Mrays/s\n", b.aerosol_mrays_per_s);
  std::printf("the renderer's path (stokes_soa, chunks of 256 rays of a fisheye, one thread, per CPU second):\n");
  std::printf("  molecules + aerosol:   %.2f Mrays/s\n", b.aerosol_soa_mrays_per_s);
  std::printf("  three such bands:      %.2f Mrays/s  (together, each ray in all three: %.2fx one band's time)\n",
              b.aerosol_bands_soa_mrays_per_s, b.aerosol_soa_mrays_per_s / b.aerosol_bands_soa_mrays_per_s);
  std::printf(
      "  single scattering:     %.2f Mrays/s  (the kernel alone: vrte costs %.2fx; the renderer's sky\n"
      "                         stage adds per-pixel work both share, skypol bench)\n",
      b.single_soa_mrays_per_s, b.single_soa_mrays_per_s / b.aerosol_soa_mrays_per_s);
  std::printf("  per-sun plan:          %.3f ms  (once per frame and band)\n", b.aerosol_plan_ms);
  return 0;
}
