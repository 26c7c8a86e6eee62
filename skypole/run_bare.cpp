// A method by its name, alone (run_bare.h).
#include "skypole/run_bare.h"

#include <stdexcept>
#include <string>

#include "skypole/classic.h"
#include "skypole/evaluate.h"
#include "skypole/great_circle.h"
#include "skypole/invariance.h"
#include "skypole/sun_azimuth.h"
#include "skypole/sun_vector.h"

namespace skypol::skypole {

PoleEstimate run_bare(const SkyView& view, std::string_view method) {
  const InputOptions& input = view.input();
  if (method == "classic") {
    // classic reads a stack (its jackknife re-pairs the frames it filtered once: classic.h).
    ClassicParams p;
    p.input = input;
    if (view.is_whole()) return estimate_classic(view.stack(), p).estimate;
    return estimate_classic(view.copy(), p).estimate;
  }
  if (method == "great_circle") {
    GreatCircleParams p;
    p.input = input;
    return great_circle_pole(great_circle_pairs(view, p), p).estimate;
  }
  if (method == "invariance") {
    InvarianceParams p;
    p.input = input;
    return estimate_invariance(view, p).estimate;
  }
  if (method == "sun_vector" || method == "sun_vector_ephemeris" || method == "sun_dolp") {
    if (method == "sun_vector_ephemeris" && !view.stack().site_known) {
      // An imported capture without [site]: the ephemeris has nothing to be computed for.
      throw std::invalid_argument("sun_vector_ephemeris needs the site, and this capture's is unknown "
                                  "(give [site] when importing)");
    }
    SunVectorParams p;
    p.input = input;
    p.mode = method == "sun_vector_ephemeris" ? PoleFromSun::ephemeris : PoleFromSun::circle;
    p.source = method == "sun_dolp" ? SunSource::dolp : SunSource::aolp;
    // A jackknife's sub-run reads only the pole: the misfit is measured on the whole stack.
    p.model_misfit = view.is_whole();
    PoleEstimate e = estimate_sun_vector(view, p).estimate;
    e.method = std::string(method);
    return e;
  }
  if (method == "sun_azimuth") {
    SunAzimuthParams p;
    p.input = input;
    return estimate_sun_azimuth(view, p);
  }
  std::string legal;
  for (const auto& n : method_names()) legal += (legal.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown estimator \"" + std::string(method) +
                              "\" (expected one of " + legal + ")");
}

}  // namespace skypol::skypole
