// Named aerosol types and the assembly of one layer's optics (atmosphere_optics.h) at one
// wavelength: Rayleigh from optical_depth.h, the aerosol from Mie theory (mie.h).
// The types are OPAC's (Hess, Koepke & Schult 1998, Bull. Amer. Meteor. Soc. 79, 831–844):
// external mixtures of log-normal components, number densities from their Table 4, size
// parameters and radius ranges from their Table 1 (dry, RH = 0 %), refractive indices at 550 nm.
// Simplifications (sky/README.md): no hygroscopic growth (the dry components), and each
// component's refractive index held at its 550 nm value at every wavelength.
#pragma once

#include <complex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sky/vrte/atmosphere_optics.h"
#include "sky/vrte/mie.h"

namespace skypol::sky {

// One named type: its components (number densities in cm⁻³, OPAC's) and where they come from.
struct AerosolType {
  std::string name;
  std::vector<MieComponent> components;
  std::vector<std::string> component_names;  // OPAC's: "WASO", "INSO", "SOOT", "SSAM", …
};

// The legal names: continental_clean, continental_average, continental_polluted, urban,
// maritime_clean, maritime_polluted, desert.
std::vector<std::string> aerosol_type_names();
// Throws std::invalid_argument("sky.aerosol.type: …") listing the legal names.
const AerosolType& aerosol_type(std::string_view name);

// What a scene says about its aerosol. Field names are the TOML keys under [sky.aerosol].
struct AerosolSpec {
  std::string type = "continental_clean";  // a name above, "custom", or "none" (molecules only)
  // custom: one log-normal mode, dN/d ln r with median radius r_g and σ_g, m = n + ik
  double median_radius_um = 0.1;
  double geometric_std = 2.0;
  double refractive_real = 1.5;
  double refractive_imag = 0.0;
  double tau_550 = 0.1;               // aerosol extinction optical depth at 550 nm, ≥ 0
  std::optional<double> angstrom;     // default: the type's, from Mie extinction at 440 and 870 nm
  std::optional<double> ssa;          // default: Mie's single-scattering albedo; override ∈ [0, 1]
  int angle_nodes = MieQuadrature{}.angle_nodes;  // Gauss–Legendre nodes of the table, ≥ 16
};

// Throws std::invalid_argument whose message starts with the field ("sky.aerosol.angstrom: …").
void validate(const AerosolSpec& spec);

// The mixture a spec describes (empty for "none").
std::vector<MieComponent> aerosol_components(const AerosolSpec& spec);

// The type's Ångström exponent between 440 and 870 nm from its Mie extinction (AERONET's pair).
double mie_angstrom_exponent(const std::vector<MieComponent>& mixture);

// The Ångström exponent a spec uses: its own, else its mixture's Mie value.
double effective_angstrom(const AerosolSpec& spec);

// One layer's optics at one wavelength: τ_R and ρₙ from Bodhaine et al. (pressure in hPa at the
// site, altitude in m, latitude in degrees), τ_a = tau_550·(λ/550)^−α, ω from Mie (or the
// override), the aerosol's scattering matrix table on spec.angle_nodes nodes. With type "none"
// or tau_550 = 0 the aerosol table is left empty. Throws std::invalid_argument naming the field.
LayerOptics layer_optics(double wavelength_nm, double pressure_hpa, double altitude_m, double latitude_deg,
                         const AerosolSpec& spec);

// The same at each of a list of wavelengths (e.g. band_wavelength_nm of "R", "G", "B"), in order.
std::vector<LayerOptics> layer_optics(std::span<const double> wavelengths_nm, double pressure_hpa,
                                      double altitude_m, double latitude_deg, const AerosolSpec& spec);

}  // namespace skypol::sky
