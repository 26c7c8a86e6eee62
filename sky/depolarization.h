// The maximum degree of linear polarization Pmax of a real sky, from its turbidity.
// Real skies never reach Rayleigh's DoLP = 1 at 90° from the sun: aerosols and multiple
// scattering depolarize (clear days ≈ 0.6–0.8). Pmax(T) = exp(−(T − 0.6)/4) is the form used in
// the sky model of Gkanias, Risse, Mangan & Webb (PLoS Comput. Biol. 15(7) e1007123, 2019), which
// builds on Wilkie et al. 2004 ("An analytical model for skylight polarisation", EGSR). The
// constants 0.6 and 4 come from that model; we have not re-derived them from measurements, so
// treat this as a plausible trend, not a calibrated law. T = 2 → 0.70, T = 3 → 0.55, T = 6 → 0.26.
#pragma once

namespace skypol::sky {

// Turbidity T ≥ 1 (1 = pure molecular air); throws std::invalid_argument otherwise.
double max_dolp_from_turbidity(double turbidity);

}  // namespace skypol::sky
