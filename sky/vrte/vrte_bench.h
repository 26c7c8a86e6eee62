// Timings of the VRTE sky for `skypol bench` and for sky/vrte/vrte_bench_main.cpp: what a band's table
// costs to build and what a pixel costs to look up. A program that prints figures, never a test.
#pragma once

namespace skypol::sky::vrte {

struct BenchFigures {
  double rayleigh_build_s = 0;  // molecules only (τ = 0.0975, 550 nm), default TableOptions
  double aerosol_build_s = 0;   // molecules + aerosol (τ_a = 0.2, Henyey–Greenstein g = 0.7 matrix)
  int rayleigh_terms = 0, aerosol_terms = 0;
  double rayleigh_mrays_per_s = 0;  // VrteSky batch path, one thread (CPU time), rays over the whole sky
  double aerosol_mrays_per_s = 0;
  // The renderer's path (stokes_soa in chunks of 256 rays, one thread, the rays of a zenith fisheye
  // row by row) for the aerosol table and for single scattering (RayleighSky) on the same rays, and the per-sun plan
  // VrteSky makes once per frame (a new sun every call).
  double aerosol_soa_mrays_per_s = 0, single_soa_mrays_per_s = 0;
  double aerosol_bands_soa_mrays_per_s = 0;  // three bands together (a colour scene), each ray in all three
  double aerosol_plan_ms = 0;
  int threads = 0;
};

// threads: for the builds (0: all cores); the lookups run on the calling thread.
BenchFigures bench(int threads = 0, int rays = 1 << 16);

}  // namespace skypol::sky::vrte
