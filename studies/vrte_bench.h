// What the VRTE sky costs, for `skypol bench`: each band's table solved from scratch (the cold
// cost, once per band and atmosphere), read back from the cache (warm), and the scene rendered
// with warm tables beside the same scene under single scattering. Figures, never a test.
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"

namespace skypol::studies {

struct VrteBenchFigures {
  std::vector<std::string> bands;
  std::vector<double> wavelengths_nm;
  std::string aerosol;
  double tau_550 = 0;
  int streams = 0, grid = 0;
  int solver_threads = 0;               // the solver's threads (all cores)
  std::vector<double> cold_build_s;     // per band: optics (Mie) + solve + write to the cache
  std::vector<double> warm_read_s;      // per band: read back and checked
  int frames = 0;
  double single_render_ms = 0, single_render_best_ms = 0;  // sky render per frame (rayleigh, same bands)
  double vrte_render_ms = 0, vrte_render_best_ms = 0;      // the same with the warm VRTE tables
  // The same renders in the process's CPU time per frame (every thread's): what the machine's other
  // work inflates far less than the wall time.
  double single_render_cpu_ms = 0, vrte_render_cpu_ms = 0;
  double single_end_to_end_ms = 0, vrte_end_to_end_ms = 0;  // render + write per frame (render_scene)
  // The accuracy knob: the first band's table solved (not cached) at each asked-for streams value.
  std::vector<int> sweep_streams;
  std::vector<double> sweep_build_s;
};

// `scene` as given if its sky is vrte, else the same scene with a default vrte sky (continental_clean,
// τ(550) = 0.1, 12 streams); the single-scattering run is the same scene with model = "rayleigh".
// Tables go to a cache folder inside scratch_dir (removed afterwards), never the user's cache.
// streams_sweep: streams values to time the first band's table at (empty: none).
VrteBenchFigures bench_vrte(const scene::Scene& scene, int frames, const std::string& scratch_dir,
                            const std::vector<int>& streams_sweep = {});

}  // namespace skypol::studies
