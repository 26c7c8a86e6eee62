// One band's VRTE result for every sun and view zenith angle: Fourier coefficients in azimuth on a
// grid of (μ, μ0), built by one solve (vrte_solver.h), cached on disk, looked up per pixel.
// Cost only when asked: nothing here runs unless a scene asks for the VRTE sky.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "sky/vrte/atmosphere_optics.h"
#include "sky/vrte/vrte_phase.h"
#include "sky/vrte/vrte_solver.h"

namespace skypol::sky::vrte {

// streams: the solver's accuracy knob (Gauss nodes per hemisphere; vrte_solver.h). grid: nodes in
// v ∈ [0, 1] with zenith angle θ = (π/2)(1 − v²), the same for μ0; cubic Lagrange in v between
// them (dense at the horizon, where the sky changes fastest; smooth at the zenith). With the
// defaults the interpolation error against direct solves (tests/sky/vrte_table_test.cpp) is, for
// view and sun above 2.3° (μ, μ0 ≥ 0.04), below 5e-5 in I/F and 0.15 % of I; closer to the horizon
// (multiple scattering has a logarithmic edge at μ → 0) below 4e-4 and 1.5 %. grid = 33 cuts the
// errors about threefold for about a third more build time.
struct TableOptions {
  int streams = 12;
  int grid = 25;
  int threads = 0;  // 0: all cores
};

// The table's grid variable: node k of `grid` sits at v = k/(grid − 1), μ = grid_mu(v) =
// sin(πv²/2); grid_v is its inverse on [0, 1] (μ clamped).
double grid_v(double mu);
double grid_mu(double v);

// What the table answers: radiance per unit extraterrestrial solar irradiance (I/F, sr⁻¹), in the
// meridian basis of the direction the observer looks (FourierSolution's convention), without the
// direct sun. The single scattering of the direct beam is computed exactly per query with the
// untruncated scattering matrix; the table holds the rest (the "TMS" split of Nakajima & Tanaka
// 1988, which also keeps a forward-peaked aerosol's aureole out of the interpolation).
class VrteTable {
 public:
  VrteTable() = default;

  // One solve (about 0.1–1 s, vrte_bench). Throws std::invalid_argument for bad inputs.
  static VrteTable build(const LayerOptics& optics, double albedo, const TableOptions& options = {});

  // The cached table for these inputs in `dir` (created if missing), built and written there when
  // absent or unreadable. `hit` reports which. The file is named by a hash of every input that
  // changes the table (cache_file_name); it is written to a temporary name and renamed.
  static VrteTable cached(const LayerOptics& optics, double albedo, const TableOptions& options,
                          const std::filesystem::path& dir, bool* hit = nullptr);

  // The bytes that identify a table: format version, every optical input (not the wavelength,
  // which the solver never reads), albedo, streams and grid; and the file name derived from them.
  static std::string cache_key(const LayerOptics& optics, double albedo, const TableOptions& options);
  static std::string cache_file_name(const LayerOptics& optics, double albedo, const TableOptions& options);

  // Writes atomically (temporary file, then rename); false on any I/O error (nothing left behind).
  bool write(const std::filesystem::path& file) const;
  // Reads and validates a file (magic, version, key, sizes, checksum); nullopt if anything is off.
  static std::optional<VrteTable> read(const std::filesystem::path& file, const LayerOptics& optics, double albedo,
                                       const TableOptions& options);

  // Sky seen from the ground looking up at zenith cosine mu (0 = horizon), and the top of the
  // layer seen looking down at nadir cosine mu; dphi = view azimuth − sun azimuth, radians,
  // counter-clockwise from above. mu, mu0 outside [0, 1] are clamped; a sun with mu0 = 0 gives 0.
  StokesIQU down(double mu, double mu0, double dphi) const;
  StokesIQU up(double mu, double mu0, double dphi) const;
  // The Lambertian ground's radiance (unpolarized) for a sun at mu0.
  double ground(double mu0) const;

  // Per frame: the coefficients interpolated to one sun, so that a pixel costs one interpolation
  // in μ and the Fourier sum.
  struct SunSlice {
    double mu0 = 0;
    std::vector<double> down;  // [(m·grid + k)·3 + s]
    double ground = 0;
  };
  SunSlice slice(double mu0) const;
  // down() through a slice; cos/sin of dphi given (the sky has them from vectors, without trig).
  StokesIQU down(const SunSlice& slice, double mu, double cos_dphi, double sin_dphi) const;

  int terms() const { return terms_; }
  int grid() const { return grid_; }
  const ExactLayer& exact() const { return exact_; }

 private:
  int terms_ = 0, grid_ = 0;
  std::vector<double> down_, up_, ground_;  // multiple scattering: [((m·G + i)·G + j)·3 + s]
  ExactLayer exact_;
  std::string key_;

  StokesIQU table(const std::vector<double>& data, double mu, double mu0, double dphi) const;
  // down or up: the table `multiple` (down_ or up_) plus the exact single scattering that way.
  StokesIQU radiance(const std::vector<double>& multiple, bool up, double mu, double mu0, double dphi) const;
};

}  // namespace skypol::sky::vrte
