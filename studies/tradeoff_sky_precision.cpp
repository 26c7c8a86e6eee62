// Study 5b: float vs double sky evaluation. Every pixel's ray of the paper's camera (2×2 binned)
// evaluated by a sky model two ways on one thread: the renderer's path (float rays, the models'
// vectorized float loops, SkyModel::stokes over a span) and the reference path (double rays from
// Camera::ray, SkyModel::stokes per direction in double). Errors of the float path against the
// double one: |ΔS|/S0, |ΔDoLP|, |ΔAoLP| (where DoLP > 1 %, AoLP being undefined at DoLP = 0).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "sky/units.h"
#include "studies/tradeoff_setup.h"
#include "studies/tradeoff_studies.h"
#include "studies/tradeoff_table.h"
#include "scene/scene.h"
#include "scene/truth.h"

namespace skypol::studies::tradeoff {

void study_sky_precision(const StudyOptions& o) {
  const int b = o.small ? 16 : 2;
  auto cam = paper_camera(b, 0);
  std::vector<camera::CameraRay> rays_d;
  std::vector<sky::ViewRay> rays_f;
  for (int y = 0; y < cam->height(); ++y)
    for (int x = 0; x < cam->width(); ++x)
      if (auto r = cam->ray(Eigen::Vector2d(x, y))) {
        rays_d.push_back(*r);
        rays_f.push_back({r->d.cast<float>(), r->e0.cast<float>()});
      }
  scene::Scene scene;
  scene.site = paper_site();
  const sky::Sun sun = scene::make_truth(scene, *cam, times_over("2022-09-23T10:00:00Z", 0, 1)[0]).sun;
  const double n = static_cast<double>(rays_d.size());

  struct Variant {
    const char* name;
    sky::SkySpec spec;
  };
  std::vector<Variant> variants(3);
  variants[0].name = "rayleigh";
  variants[1].name = "berry";
  variants[1].spec.model = "berry";
  variants[2].name = "rayleigh+preetham";
  variants[2].spec.intensity = "preetham";

  Table t({"sky", "precision", "ns_per_ray", "mrays_per_s_one_thread", "stokes_max_rel", "stokes_rms_rel",
           "dolp_max", "aolp_max_deg", "rays", "is_default"});
  for (const Variant& v : variants) {
    const auto model = sky::make_sky(v.spec);
    std::vector<sky::Stokes> ref(rays_d.size());
    std::vector<sky::StokesF> out(rays_f.size());
    const double sd = best_seconds(3, [&] {
      for (std::size_t i = 0; i < rays_d.size(); ++i) ref[i] = model->stokes(rays_d[i].d, rays_d[i].e0, sun);
    });
    const double sf = best_seconds(3, [&] { model->stokes(rays_f, sun, out); });
    double smax = 0, ss = 0, dmax = 0, amax = 0;
    for (std::size_t i = 0; i < ref.size(); ++i) {
      const sky::Stokes& r = ref[i];
      const sky::Stokes f{out[i].s0, out[i].s1, out[i].s2, out[i].s3};
      const double e = std::sqrt((f.s0 - r.s0) * (f.s0 - r.s0) + (f.s1 - r.s1) * (f.s1 - r.s1) +
                                 (f.s2 - r.s2) * (f.s2 - r.s2)) /
                       r.s0;
      smax = std::max(smax, e);
      ss += e * e;
      dmax = std::max(dmax, std::abs(f.dolp() - r.dolp()));
      if (r.dolp() > 0.01) {
        double da = std::abs(f.aolp() - r.aolp());
        da = std::min(da, std::numbers::pi - da);  // AoLP is defined mod 180°
        amax = std::max(amax, deg_from_rad(da));
      }
    }
    t.row().set("sky", v.name).set("precision", "double").set("ns_per_ray", 1e9 * sd / n)
        .set("mrays_per_s_one_thread", n / sd / 1e6).set("stokes_max_rel", 0.0).set("stokes_rms_rel", 0.0)
        .set("dolp_max", 0.0).set("aolp_max_deg", 0.0).set("rays", static_cast<int>(n)).set("is_default", false);
    t.row().set("sky", v.name).set("precision", "float").set("ns_per_ray", 1e9 * sf / n)
        .set("mrays_per_s_one_thread", n / sf / 1e6).set("stokes_max_rel", smax)
        .set("stokes_rms_rel", std::sqrt(ss / n)).set("dolp_max", dmax).set("aolp_max_deg", amax)
        .set("rays", static_cast<int>(n)).set("is_default", true);
  }
  t.write((std::filesystem::path(o.out_dir) / "sky_precision.csv").string());
}

}  // namespace skypol::studies::tradeoff
