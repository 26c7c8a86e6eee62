// The registry entries (method_registry.h) of the three methods that find the sun in each frame
// (sun_vector.h): sun_vector, sun_vector_ephemeris and sun_dolp.
#include <string>

#include "skypole/method_registry.h"
#include "skypole/sun_vector.h"

namespace skypol::skypole {
namespace {

std::function<PoleEstimate(const SkyView&)> sun_bare(std::string name, PoleFromSun mode, SunSource source) {
  return [name, mode, source](const SkyView& view) {
    SunVectorParams p;
    p.input = view.input();
    p.mode = mode;
    p.source = source;
    // A jackknife's sub-run reads only the pole: the misfit is measured on the whole stack.
    p.model_misfit = view.is_whole();
    PoleEstimate e = estimate_sun_vector(view, p).estimate;
    e.method = name;
    return e;
  };
}

}  // namespace

// They fit the whole sky per frame, so a sector masked in every frame is a rerun on a view.
Method sun_vector_method() {
  Method m;
  m.name = "sun_vector";
  m.description = "the sun per frame from AoLP (E ⟂ sun); the pole is the axis of the sun's path (sun_vector.h)";
  m.bare = sun_bare(m.name, PoleFromSun::circle, SunSource::aolp);
  m.traits = {.frame_jackknife_max_groups = 6, .sector_jackknife = true, .misfit_measured = true};
  // A short window and a sky far from Rayleigh's law give errors no jackknife sees (its suns move
  // with the departure, alike in every frame); 1° × the unpolarized share covers cloud.
  m.calibration = {.method = m.name, .inflation = 0.45, .floor_deg = 0.025, .max_residual_deg = 5.0, .min_window_min = 60.0,
                   .max_model_misfit = 0.01, .sector_inflation = 0.25, .unpolarized_deg = 1.0};
  return m;
}

Method sun_vector_ephemeris_method() {
  Method m;
  m.name = "sun_vector_ephemeris";
  m.description = "the sun per frame from AoLP against the ephemeris' sun for the stack's site and times (sun_vector.h)";
  m.bare = sun_bare(m.name, PoleFromSun::ephemeris, SunSource::aolp);
  m.traits = {.frame_jackknife_max_groups = 6, .sector_jackknife = true, .needs_site = true,
              .auto_answers_alone = true};
  // Its median error is some twenty times smaller than any other method's, so auto returns its
  // answer as it stands when it agrees. Its suns' elevation misfit shows an error every frame shares; past 30 % of unreadable sky no
  // factor holds its tails.
  m.calibration = {.method = m.name, .inflation = 0.4, .floor_deg = 0.0003, .max_residual_deg = 5.0, .max_unpolarized_share = 0.3,
                   .sector_inflation = 0.1, .elevation_share = 0.25};
  return m;
}

Method sun_dolp_method() {
  Method m;
  m.name = "sun_dolp";
  m.description = "the sun per frame from a Rayleigh fit of DoLP; the pole is the axis of the sun's path (sun_vector.h)";
  m.bare = sun_bare(m.name, PoleFromSun::circle, SunSource::dolp);
  m.traits = {.frame_jackknife_max_groups = 6, .sector_jackknife = true};
  // Its error lives in parts of the sky, so the sector factor binds; it fits the Rayleigh law, so
  // it declines a sky far from it; 1° × the unpolarized share covers cloud. Its pole is the axis
  // of the sun's path, as sun_vector's: in a window under an hour (an arc under 15°) a small bias
  // of the suns, alike in every frame, moves the axis far, so it declines such windows as
  // sun_vector does.
  m.calibration = {.method = m.name, .inflation = 0.25, .floor_deg = 0.03, .max_residual_deg = 5.0, .min_window_min = 60.0,
                   .max_model_misfit = 0.01, .sector_inflation = 0.5, .unpolarized_deg = 1.0};
  return m;
}

}  // namespace skypol::skypole
