// Preset values and their sources (see presets.h). Sources are cited per entry.
#include "camera/presets.h"

#include <array>
#include <stdexcept>
#include <string>

namespace skypol::camera {
namespace {

const std::array<LensPreset, 3> kLenses = {{
    {"fujinon_fe185c057ha1", "equidistant", 1.8, 185.0,
     "Fujifilm FUJINON FE185C057HA-1 datasheet: focal length 1.8 mm, angle of view 185°. The "
     "projection is taken as equidistant (nominal: the datasheet's real image height table, if "
     "you have it, belongs in a `tabulated` lens). Used by SkyPole (PNAS 2023, SI: "
     "\"FE185C57HA-1\", f/2.8)."},
    // The lens itself. lensfun's database (github.com/lensfun/lensfun, data/db/slr-sigma.xml,
    // entries "Sigma 8mm f/3.5 EX DG Circular", checked at commit 1c8b8f0, 2026-08) gives it as
    // <type>equisolid</type> with focal 8 mm in all three calibrations (Nikon D5100, Canon 7D,
    // Canon 5D Mark III; the last one's panorama fit has real-focal 7.15 mm). The field is the
    // maker's 180° for a circular fisheye: image height r = 2f·sin(θ/2), 9.177 mm at 70° off-axis,
    // 11.31 mm (a 22.6 mm circle) at 90°.
    {"sigma_8mm_f3.5", "equisolid", 8.0, 180.0,
     "Sigma 8 mm F3.5 EX DG Circular Fisheye: equisolid projection, 8 mm (lensfun database, "
     "data/db/slr-sigma.xml, \"Sigma 8mm f/3.5 EX DG Circular\", <type>equisolid</type>); "
     "180° field (maker's figure for the circular image). Used by Sun et al. 2019 (Sensors "
     "19:4844), who model it differently: see sun2019_sigma_8mm_equidistant_140."},
    // What Sun et al. 2019 model, named for it: not the lens's own projection (see above).
    {"sun2019_sigma_8mm_equidistant_140", "equidistant", 8.0, 140.0,
     "Sun et al. 2019 (Sensors 19:4844, §2.1 and §4) model their Sigma 8 mm F3.5 in equidistant "
     "imaging mode with an effective field of view of about 140°: this preset is that model, for "
     "reproducing the paper. The lens itself is equisolid (sigma_8mm_f3.5)."},
}};

DofpSensor imx250_dofp() {
  DofpSensor s;
  s.width = 2448;
  s.height = 2048;
  s.mosaic_deg = {90, 45, 135, 0};
  s.full_well_e = 11000;
  s.adc_bits = 12;
  s.gain_dn_per_e = 4095.0 / 11000;  // full well = ADC full scale at unity analog gain
  s.read_noise_e = 2.3;              // nominal
  s.dark_current_e_s = 3;            // nominal
  s.extinction_ratio = 100;          // nominal placeholder, see source
  return s;
}

DofpSensor imx250myr_dofp() {
  DofpSensor s = imx250_dofp();
  s.color_filter = ColorFilter::rggb_blocks;  // band_response {1, 1, 1}: nominal
  return s;
}

const std::array<SensorPreset, 2> kSensors = {{
    {"sony_imx250mzr", 2448, 2048, 3.45, imx250_dofp(),
     "Sony IMX250MZR (mono polarization, e.g. Lucid PHX050S-P): 2448 × 2048 effective pixels of "
     "3.45 µm and the 90°/45° over 135°/0° polarizer layout (Sony IMX250MZR/MYR flyer); 12-bit "
     "ADC; full well 11 ke- (Teledyne DALSA Genie Nano M2450-Polarized specification, \"11ke "
     "(max)\"). Nominal, not from a datasheet: read noise 2.3 e-, dark current 3 e-/s, "
     "extinction ratio 100 (wire-grid micro-polarizers vary with wavelength and incidence angle; "
     "calibrate, e.g. Hagen et al., Opt. Eng. 58(8) 082408, 2019)."},
    {"lucid_phx050s_qc", 2448, 2048, 3.45, imx250myr_dofp(),
     "Lucid PHX050S-QC, the camera of SkyPole (PNAS 2023, SI), whose sensor is the colour "
     "IMX250MYR: same geometry and polarizer layout as the IMX250MZR, with an RGGB Bayer filter "
     "over the 2×2 polarizer blocks (color_filter rggb_blocks; equal band responses, nominal); "
     "noise figures as sony_imx250mzr (nominal)."},
}};

template <class T>
const T& find(std::span<const T> all, std::string_view name, const char* what) {
  for (const auto& p : all)
    if (p.name == name) return p;
  std::string legal;
  for (const auto& p : all) legal += (legal.empty() ? "" : ", ") + std::string(p.name);
  throw std::invalid_argument(std::string("unknown ") + what + " preset \"" + std::string(name) +
                              "\" (expected one of " + legal + ")");
}

}  // namespace

std::span<const LensPreset> lens_presets() { return kLenses; }
std::span<const SensorPreset> sensor_presets() { return kSensors; }

const LensPreset& lens_preset(std::string_view name) { return find(lens_presets(), name, "lens"); }
const SensorPreset& sensor_preset(std::string_view name) {
  return find(sensor_presets(), name, "sensor");
}

LensSpec lens_spec(const LensPreset& lens, const SensorPreset& sensor) {
  LensSpec s;
  s.model = std::string(lens.model);
  s.width = sensor.width;
  s.height = sensor.height;
  s.focal_mm = lens.focal_mm;
  s.pitch_um = sensor.pitch_um;
  s.fov_deg = lens.fov_deg;
  return s;
}

}  // namespace skypol::camera
