// The benchmark's atmospheres: a clear molecular sky and the same with a moderately forward
// scattering aerosol (a synthetic matrix with every element non-zero, not a measured one).
#include "sky/vrte/vrte_bench.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <ctime>
#include <memory>
#include <numbers>
#include <random>
#include <span>
#include <thread>
#include <vector>

#include "sky/rayleigh.h"
#include "sky/vrte/vrte_sky.h"

namespace skypol::sky::vrte {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Random directions over the sky with e0 towards the zenith.
std::vector<ViewRay> sky_rays(int n) {
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
  return rays;
}

Sun bench_sun() {
  Sun sun;
  sun.direction = Eigen::Vector3d(0.3, 0.5, 0.81).normalized();
  return sun;
}

// Calls f() until half a second of CPU time has passed; calls per CPU second. The process's CPU
// time is the calling thread's here (the lookups run alone), and unlike wall time it does not grow
// when other work shares the cores.
template <class F>
double rate(F&& f) {
  f();  // warm-up
  const std::clock_t t0 = std::clock();
  const auto cpu_seconds = [t0] { return static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC; };
  int reps = 0;
  do {
    f();
    ++reps;
  } while (cpu_seconds() < 0.5);
  return reps / cpu_seconds();
}

double lookup_rate(const std::shared_ptr<const VrteTable>& table, int n) {
  const VrteSky sky(table);
  const std::vector<ViewRay> rays = sky_rays(n);
  std::vector<StokesF> out(rays.size());
  const Sun sun = bench_sun();
  return rate([&] { sky.stokes(rays, sun, out); }) * n / 1e6;
}

// The upper hemisphere as an equidistant fisheye at the zenith sees it, row by row (neighbouring
// rays close together, as the renderer's are), about n rays.
std::vector<ViewRay> fisheye_rays(int n) {
  const int side = static_cast<int>(std::sqrt(4.0 * n / std::numbers::pi));
  std::vector<ViewRay> rays;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const double u = (x + 0.5) / side * 2 - 1, v = (y + 0.5) / side * 2 - 1, r = std::hypot(u, v);
      if (r >= 1) continue;
      const double th = r * std::numbers::pi / 2, ph = std::atan2(v, u);
      const Eigen::Vector3d d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      const Eigen::Vector3d e(std::cos(th) * std::cos(ph), std::cos(th) * std::sin(ph), -std::sin(th));  // ∂d/∂θ
      rays.push_back({d.cast<float>(), e.cast<float>()});
    }
  return rays;
}

// The renderer's calls: stokes_soa on chunks of 256 rays, or for several bands
// VrteSky::stokes_soa_bands as the renderer calls it. Rays (each in every band) per second.
double soa_rate(std::span<const SkyModel* const> skies, int n) {
  const std::vector<ViewRay> rays = fisheye_rays(n);
  const std::size_t m = rays.size(), bands = skies.size();
  std::vector<float> in(6 * m), out(4 * bands * m);
  for (std::size_t j = 0; j < m; ++j)
    for (int c = 0; c < 3; ++c) {
      in[static_cast<std::size_t>(c) * m + j] = rays[j].d[c];
      in[static_cast<std::size_t>(3 + c) * m + j] = rays[j].e0[c];
    }
  const Sun sun = bench_sun();
  constexpr std::size_t kChunk = 256;
  return rate([&] {
           for (std::size_t x = 0; x < m; x += kChunk) {
             const std::size_t k = std::min(kChunk, m - x);
             const ViewRaysSoA r{k, &in[x], &in[m + x], &in[2 * m + x], &in[3 * m + x], &in[4 * m + x], &in[5 * m + x]};
             std::array<StokesSoA, VrteSky::kMaxBands> o;
             for (std::size_t b = 0; b < bands; ++b) {
               float* base = &out[4 * b * m + x];
               o[b] = {base, base + m, base + 2 * m, base + 3 * m};
             }
             if (bands == 1) {
               skies[0]->stokes_soa(r, sun, o[0]);
             } else if (!VrteSky::stokes_soa_bands(skies, r, sun, std::span(o).first(bands))) {
               for (std::size_t b = 0; b < bands; ++b) skies[b]->stokes_soa(r, sun, o[b]);
             }
           }
         }) *
         static_cast<double>(m) / 1e6;
}

// One ray under a new sun each call: what the per-sun plan costs.
double plan_ms(const std::shared_ptr<const VrteTable>& table) {
  const VrteSky sky(table);
  const float d[3] = {0.0f, 0.0f, 1.0f}, e[3] = {1.0f, 0.0f, 0.0f};
  float o[4];
  const ViewRaysSoA r{1, &d[0], &d[1], &d[2], &e[0], &e[1], &e[2]};
  int k = 0;
  return 1e3 / rate([&] {
           Sun sun;
           sun.direction = Eigen::Vector3d(0.3, 0.5, 0.5 + 0.001 * (++k)).normalized();
           sky.stokes_soa(r, sun, {&o[0], &o[1], &o[2], &o[3]});
         });
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
  const VrteSky red(aer), green(aer), blue(aer);
  const RayleighSky single;
  const SkyModel* one[] = {&red};
  const SkyModel* three[] = {&red, &green, &blue};
  const SkyModel* grey[] = {&single};
  b.aerosol_soa_mrays_per_s = soa_rate(one, rays);
  b.aerosol_bands_soa_mrays_per_s = soa_rate(three, rays);
  b.single_soa_mrays_per_s = soa_rate(grey, rays);
  b.aerosol_plan_ms = plan_ms(aer);
  return b;
}

}  // namespace skypol::sky::vrte
