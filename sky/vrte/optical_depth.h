// Spectral optical depths of a clear atmosphere: Rayleigh scattering by dry air after Bodhaine,
// Wood, Dutton & Slusser (1999, J. Atmos. Oceanic Technol. 16, 1854–1861; "B99" below), the
// aerosol's Ångström law, and the wavelengths skypol renders its bands at. Wavelengths in nm at
// the interface; B99's formulas take µm and cgs inside.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace skypol::sky {

// The CO2 mixing ratio B99 tabulate at (their Table 3 and eq. 29): 360 ppm by volume.
inline constexpr double kBodhaineCo2Ppm = 360.0;

// Refractive index of dry standard air (15 °C, 1013.25 hPa) with `co2_ppm` of CO2: Peck & Reeder
// (1972) for 300 ppm, (n − 1)·10⁸ = 8060.51 + 2480990/(132.274 − λ⁻²) + 17455.7/(39.32957 − λ⁻²)
// (λ in µm), scaled by 1 + 0.54(C − 0.0003), C by volume (B99 section 2).
double air_refractive_index(double wavelength_nm, double co2_ppm = kBodhaineCo2Ppm);

// King correction factor F(air) = (6 + 3ρ)/(6 − 7ρ) of dry air (B99 eqs. 23–27): N2 and O2 from
// Bates (1984) (1.034 + 3.17·10⁻⁴λ⁻², 1.096 + 1.385·10⁻³λ⁻² + 1.448·10⁻⁴λ⁻⁴, λ in µm), Ar 1.00,
// CO2 1.15, weighted by 78.084 : 20.946 : 0.934 : C(CO2) in percent by volume.
double king_factor_air(double wavelength_nm, double co2_ppm = kBodhaineCo2Ppm);

// Depolarization factor ρₙ from a King factor: ρ = 6(F − 1)/(7F + 3) (the inverse of
// F = (6 + 3ρ)/(6 − 7ρ)). Throws std::invalid_argument unless F is finite and ≥ 1.
double depolarization_from_king(double king_factor);

// Rayleigh scattering cross section per molecule of dry air in cm² (B99, with the King
// factor): σ = 24π³(n² − 1)² / (λ⁴ Nₛ² (n² + 2)²) · F(air), Nₛ = 2.546899·10¹⁹ cm⁻³ (288.15 K,
// 1013.25 hPa). The density cancels against n's, so σ holds at any pressure and temperature.
double rayleigh_cross_section_cm2(double wavelength_nm, double co2_ppm = kBodhaineCo2Ppm);

// B99's closed-form fit of σ for 360 ppm (their eq. 29, λ in µm, σ in 10⁻²⁸ cm²), for 0.25–1 µm:
// (1.0455996 − 341.29061λ⁻² − 0.90230850λ²) / (1 + 0.0027059889λ⁻² − 85.968563λ²).
double rayleigh_cross_section_fit_cm2(double wavelength_nm);

// Acceleration of gravity in cm s⁻² at a latitude and an altitude above sea level (B99 section 4,
// after List 1968): g₀(φ) = 980.6160(1 − 0.0026373 cos 2φ + 0.0000059 cos² 2φ), then
// g = g₀ − (3.085462·10⁻⁴ + 2.27·10⁻⁷ cos 2φ)z + (7.254·10⁻¹¹ + 10⁻¹³ cos 2φ)z²
//       − (1.517·10⁻¹⁷ + 6·10⁻²⁰ cos 2φ)z³, z in metres.
double gravity_cm_s2(double latitude_deg, double altitude_m);

// Mean molecular weight of dry air in g/mol with CO2 (B99): 15.0556 C + 28.9595, C by volume.
double air_molar_mass_g(double co2_ppm = kBodhaineCo2Ppm);

// Vertical Rayleigh optical depth of the air column above a site (B99 section 4):
// τ = σ P A / (mₐ g), P the surface pressure, A = 6.0221367·10²³ mol⁻¹, g at the column's
// mass-weighted mean altitude z_c = 0.73737 z + 5517.56 m (B99, for a standard atmosphere). Throws
// std::invalid_argument (starting with the parameter's name) for λ outside [200, 4000] nm,
// pressure outside (0, 1200] hPa, |latitude| > 90°, altitude outside [−500, 10000] m.
double rayleigh_optical_depth(double wavelength_nm, double pressure_hpa, double altitude_m, double latitude_deg,
                              double co2_ppm = kBodhaineCo2Ppm);

// Ångström's law: τ(λ) = τ(λ_ref)·(λ/λ_ref)^−α.
double angstrom_optical_depth(double tau_ref, double reference_nm, double wavelength_nm, double alpha);
// α from two optical depths: −ln(τ₁/τ₂)/ln(λ₁/λ₂).
double angstrom_exponent(double tau1, double wavelength1_nm, double tau2, double wavelength2_nm);

// The wavelength (nm) a named band is rendered at: "R" 610, "G" 530, "B" 465 (round numbers at
// typical colour-filter peaks of a Sony IMX250MYR-type polarization colour sensor — a documented
// choice, see sky/README.md), "Y" 550 (mono). Any other name throws std::invalid_argument.
double band_wavelength_nm(std::string_view band);

// The legal band names, in the order R, G, B, Y.
std::vector<std::string> band_names();

}  // namespace skypol::sky
