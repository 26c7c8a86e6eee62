// Presets: the numbers the papers' set-ups imply, checked from the cited figures.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "camera/intrinsics.h"
#include "camera/presets.h"
#include "sky/units.h"

using namespace skypol::camera;
using skypol::rad_from_deg;

TEST_CASE("SkyPole's Fujinon 1.8 mm on the IMX250: f = 521.739 px, 185° circle of r = 842.3 px fits", "[presets]") {
  const auto spec = lens_spec(lens_preset("fujinon_fe185c057ha1"), sensor_preset("lucid_phx050s_qc"));
  const auto lens = make_lens(spec);
  CHECK(lens->intrinsics().fx == Approx(1.8 / 3.45e-3));
  CHECK(lens->intrinsics().fx == Approx(521.739).margin(1e-3));
  const ImageCircle c = image_circle(*lens);
  CHECK(c.radius_px == Approx(rad_from_deg(1.8 / 3.45e-3 * 92.5)).epsilon(1e-9));
  CHECK(c.fits_on_sensor);
  CHECK(c.full_circle_fov_deg == Approx(185));
}

TEST_CASE("Sigma 8 mm F3.5 circular fisheye: equisolid (lensfun), 9.177 mm image height at 70 deg", "[presets]") {
  const auto& p = lens_preset("sigma_8mm_f3.5");
  CHECK(p.model == "equisolid");  // lensfun data/db/slr-sigma.xml: <type>equisolid</type>
  CHECK(p.focal_mm == 8.0);
  CHECK(p.fov_deg == 180);
  // Image height at 70° off-axis, r = 2f sin(θ/2) = 16 mm · sin 35° = 9.1772 mm; an equidistant
  // model would give f·θ = 9.7738 mm there, 0.6 mm (173 px of 3.45 µm) further out.
  const SensorPreset& sensor = sensor_preset("sony_imx250mzr");
  const auto lens = make_lens(lens_spec(p, sensor));
  const double theta = rad_from_deg(70);
  const auto px = lens->project({std::sin(theta), 0.0, std::cos(theta)});
  REQUIRE(px.has_value());
  const double r_mm = (px->x() - lens->intrinsics().cx) * sensor.pitch_um * 1e-3;
  CHECK(r_mm == Approx(9.1772).margin(1e-4));
  CHECK(lens->max_field_angle() == Approx(rad_from_deg(90)));
}

TEST_CASE("Sun et al. 2019's model of that lens keeps its own name: equidistant, 140 deg", "[presets]") {
  const auto& p = lens_preset("sun2019_sigma_8mm_equidistant_140");
  CHECK(p.fov_deg == 140);
  CHECK(p.model == "equidistant");
  CHECK(p.focal_mm == 8.0);
  CHECK(make_lens(lens_spec(p, sensor_preset("sony_imx250mzr")))->max_field_angle() ==
        Approx(rad_from_deg(70)));
}

TEST_CASE("IMX250MZR sensor preset: geometry, layout, 12-bit full scale at full well", "[presets]") {
  const auto& s = sensor_preset("sony_imx250mzr");
  CHECK(s.width == 2448);
  CHECK(s.height == 2048);
  CHECK(s.pitch_um == 3.45);
  CHECK(s.dofp.width == 2448);
  CHECK(s.dofp.mosaic_deg == std::array<double, 4>{90, 45, 135, 0});
  CHECK(s.dofp.adc_bits == 12);
  CHECK(s.dofp.gain_dn_per_e * s.dofp.full_well_e == Approx(4095));
  CHECK_NOTHROW(validate(s.dofp));
  CHECK_THROWS_WITH(sensor_preset("imx999"), Catch::Contains("sony_imx250mzr") && Catch::Contains("imx999"));
  CHECK_THROWS_WITH(lens_preset("nikkor"), Catch::Contains("fujinon_fe185c057ha1"));
}

TEST_CASE("SkyPole's PHX050S-QC is the colour IMX250MYR: RGGB over the polarizer blocks", "[presets]") {
  const auto& s = sensor_preset("lucid_phx050s_qc");
  CHECK(s.dofp.color_filter == ColorFilter::rggb_blocks);
  CHECK(sensor_preset("sony_imx250mzr").dofp.color_filter == ColorFilter::none);
  CHECK(band_of_pixel(s.dofp, 3, 3) == 2);  // blue block: the band the SkyPole paper used
}
