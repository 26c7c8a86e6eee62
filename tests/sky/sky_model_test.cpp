// The default many-directions paths of SkyModel loop over the scalar one.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "sky/sky_model.h"

using namespace skypol::sky;

namespace {
// A model with only a scalar path: radiance = 1 + d.z, S1 = e0.x, S2 = sun.z, S3 = d.x.
class Probe final : public SkyModel {
 public:
  std::string name() const override { return "probe"; }
  Stokes stokes(const Eigen::Vector3d& d, const Eigen::Vector3d& e0, const Sun& sun) const override {
    return {1 + d.z(), e0.x(), sun.direction.z(), d.x()};
  }
  using SkyModel::stokes;
};
}  // namespace

TEST_CASE("the default batch path calls the scalar path for every ray", "[sky_model]") {
  const Probe probe;
  Sun sun;
  sun.direction = Eigen::Vector3d(0, 0.6, 0.8);
  std::vector<ViewRay> rays = {{{0, 0, 1}, {1, 0, 0}}, {{1, 0, 0}, {0, 1, 0}}, {{0, 0.6f, 0.8f}, {0.5f, 0, 0}}};
  std::vector<StokesF> out(rays.size());
  const SkyModel& model = probe;
  model.stokes(rays, sun, out);
  CHECK(out[0].s0 == 2.0f);
  CHECK(out[1].s3 == 1.0f);
  CHECK(out[2].s1 == 0.5f);
  CHECK(out[2].s2 == 0.8f);
  CHECK(out[2].s0 == Approx(1.8f));
}

TEST_CASE("the default structure-of-arrays path calls the scalar path for every ray", "[sky_model]") {
  const Probe probe;
  Sun sun;
  sun.direction = Eigen::Vector3d(0, 0.6, 0.8);
  // 300 rays: more than one of the default path's blocks.
  const std::size_t n = 300;
  std::vector<float> dx(n), dy(n, 0.0f), dz(n), ux(n), uy(n, 1.0f), uz(n, 0.0f);
  for (std::size_t i = 0; i < n; ++i) {
    dz[i] = static_cast<float>(i) / static_cast<float>(n);
    dx[i] = std::sqrt(1 - dz[i] * dz[i]);
    ux[i] = static_cast<float>(i % 7);
  }
  std::vector<float> s0(n), s1(n), s2(n), s3(n);
  const SkyModel& model = probe;
  model.stokes_soa({n, dx.data(), dy.data(), dz.data(), ux.data(), uy.data(), uz.data()}, sun,
                   {s0.data(), s1.data(), s2.data(), s3.data()});
  for (std::size_t i = 0; i < n; ++i) {
    CHECK(s0[i] == Approx(1 + dz[i]));
    CHECK(s1[i] == static_cast<float>(i % 7));
    CHECK(s2[i] == 0.8f);
    CHECK(s3[i] == dx[i]);
  }
}
