// Presets: the numbers the papers' set-ups imply, checked from the cited figures.
#include <catch2/catch.hpp>

#include <numbers>

#include "camera/intrinsics.h"
#include "camera/presets.h"

using namespace skypol::camera;

TEST_CASE("SkyPole's Fujinon 1.8 mm on the IMX250: f = 521.739 px, 185° circle of r = 842.3 px fits", "[presets]") {
  const auto spec = lens_spec(lens_preset("fujinon_fe185c057ha1"), sensor_preset("lucid_phx050s_qc"));
  const auto lens = make_lens(spec);
  CHECK(lens->intrinsics().fx == Approx(1.8 / 3.45e-3));
  CHECK(lens->intrinsics().fx == Approx(521.739).margin(1e-3));
  const ImageCircle c = image_circle(*lens);
  CHECK(c.radius_px == Approx(1.8 / 3.45e-3 * 92.5 * std::numbers::pi / 180).epsilon(1e-9));
  CHECK(c.fits_on_sensor);
  CHECK(c.full_circle_fov_deg == Approx(185));
}

TEST_CASE("Sun et al.'s Sigma 8 mm: 140° effective, equidistant", "[presets]") {
  const auto& p = lens_preset("sigma_8mm_f3.5");
  CHECK(p.fov_deg == 140);
  CHECK(p.model == "equidistant");
  CHECK(make_lens(lens_spec(p, sensor_preset("sony_imx250mzr")))->max_field_angle() ==
        Approx(70 * std::numbers::pi / 180));
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
