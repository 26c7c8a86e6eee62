// skypol_vrte_bench: prints what a VRTE table costs per band and what a pixel lookup costs.
// Usage: skypol_vrte_bench [threads]   (not run by ctest: figures, not pass/fail)
#include <cstdio>
#include <cstdlib>

#include "sky/vrte_bench.h"

int main(int argc, char** argv) {
  const int threads = argc > 1 ? std::atoi(argv[1]) : 0;
  const auto b = skypol::sky::vrte::bench(threads);
  std::printf("vrte table build, %d thread(s), default options (12 streams, grid 25):\n", b.threads);
  std::printf("  molecules only:        %.3f s  (%d Fourier terms)\n", b.rayleigh_build_s, b.rayleigh_terms);
  std::printf("  molecules + aerosol:   %.3f s  (%d Fourier terms)\n", b.aerosol_build_s, b.aerosol_terms);
  std::printf("vrte per-pixel lookup (batch path, one thread):\n");
  std::printf("  molecules only:        %.2f Mrays/s\n", b.rayleigh_mrays_per_s);
  std::printf("  molecules + aerosol:   %.2f Mrays/s\n", b.aerosol_mrays_per_s);
  std::printf("the renderer's path (stokes_soa, chunks of 256 rays of a fisheye, one thread):\n");
  std::printf("  molecules + aerosol:   %.2f Mrays/s\n", b.aerosol_soa_mrays_per_s);
  std::printf("  single scattering:     %.2f Mrays/s  (vrte costs %.2fx)\n", b.single_soa_mrays_per_s,
              b.single_soa_mrays_per_s / b.aerosol_soa_mrays_per_s);
  std::printf("  per-sun plan:          %.3f ms  (once per frame and band)\n", b.aerosol_plan_ms);
  return 0;
}
