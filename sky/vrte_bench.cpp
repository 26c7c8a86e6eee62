// The benchmark's atmospheres: a clear molecular sky and the same with a moderately forward
// scattering aerosol (a synthetic matrix with every element non-zero, not a measured one).
#include "sky/vrte_bench.h"

#include <chrono>
#include <cmath>
#include <memory>
#include <random>
#include <thread>
#include <vector>

#include "sky/vrte_sky.h"

namespace skypol::sky::vrte {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double lookup_rate(const std::shared_ptr<const VrteTable>& table, int n) {
  const VrteSky sky(table);
  std::mt19937_64 rng(1);
  std::normal_distribution<float> g;
  std::vector<ViewRay> rays(static_cast<std::size_t>(n));
  for (auto& r : rays) {
    Eigen::Vector3f d(g(rng), g(rng), std::abs(g(rng)));
    d.normalize();
    Eigen::Vector3f e = Eigen::Vector3f::UnitZ() - d.z() * d;
    if (e.norm() < 1e-6f) e = Eigen::Vector3f::UnitX();
    r = {d, e.normalized()};
  }
  std::vector<StokesF> out(rays.size());
  Sun sun;
  sun.direction = Eigen::Vector3d(0.3, 0.5, 0.81).normalized();
  sky.stokes(rays, sun, out);  // warm-up
  const auto t0 = std::chrono::steady_clock::now();
  int reps = 0;
  do {
    sky.stokes(rays, sun, out);
    ++reps;
  } while (seconds_since(t0) < 0.5);
  return static_cast<double>(reps) * n / seconds_since(t0) / 1e6;
}

}  // namespace

BenchFigures bench(int threads, int rays) {
  BenchFigures b;
  b.threads = threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency());
  TableOptions opt;
  opt.threads = b.threads;
  LayerOptics o;
  o.wavelength_nm = 550;
  o.tau_rayleigh = 0.0975;
  o.depolarization = 0.0279;
  auto t0 = std::chrono::steady_clock::now();
  auto ray = std::make_shared<const VrteTable>(VrteTable::build(o, 0.1, opt));
  b.rayleigh_build_s = seconds_since(t0);
  b.rayleigh_terms = ray->terms();
  o.tau_aerosol = 0.2;
  o.aerosol_ssa = 0.95;
  o.aerosol = synthetic_aerosol(0.7, 200, 0.2, 0.05);
  t0 = std::chrono::steady_clock::now();
  auto aer = std::make_shared<const VrteTable>(VrteTable::build(o, 0.1, opt));
  b.aerosol_build_s = seconds_since(t0);
  b.aerosol_terms = aer->terms();
  b.rayleigh_mrays_per_s = lookup_rate(ray, rays);
  b.aerosol_mrays_per_s = lookup_rate(aer, rays);
  return b;
}

}  // namespace skypol::sky::vrte
