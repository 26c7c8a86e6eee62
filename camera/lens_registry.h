// The lens models as one registry: each model is one entry (its name, a line saying what it is,
// the optional LensSpec fields it reads, its traits and its factory), and everything that lists,
// checks or builds lenses asks it: make_lens and lens_model_names (lens_factory.h), the scene
// language's [camera] section (which defaults and required keys a model has).
//
// Adding a lens model: write its files (e.g. camera/foo.h, foo.cpp: the Lens) and, in its .cpp, a
// function `LensModel foo_lens_model()` returning its entry (camera/detail/lens_checks.h has the
// shared field checks); then add the one line `SKYPOL_LENS(foo)` to camera/lens_list.h (and the
// .cpp to camera/CMakeLists.txt). A test or a program may also add an entry at run time with
// register_lens_model (tests/scene/registry_test.cpp).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "camera/lens.h"
#include "camera/lens_factory.h"

namespace skypol::camera {

// The LensSpec fields that only some models read; a model given one it does not take is an error
// naming the field ("coefficients: not used by model equidistant").
enum class LensField { coefficients, skew, table, ocamcalib_path, clamp_fov_to_monotone };

struct LensModel {
  std::string name;
  std::string description;            // one line
  std::vector<LensField> fields;      // the optional fields it reads
  // Traits the scene language reads:
  bool radial = false;                // an ideal mapping r(θ) of one focal length (RadialLens)
  bool hemisphere_default = false;    // fov_deg defaults to 180° when a scene gives none
  bool size_from_file = false;        // width and height come from its calibration file (ocam)
  bool pitch_converts_mm = false;     // pitch_um converts its own millimetres to pixels, so fx
                                      // does not replace it (tabulated)
  // Checks the spec (its fields named in the messages) and builds the lens, before binning.
  std::function<std::shared_ptr<const Lens>(const LensSpec&)> make;
};

// The entries in registration order (lens_list.h, then register_lens_model's).
const std::vector<LensModel>& lens_models();
const LensModel* find_lens_model(std::string_view name);

// Adds an entry; throws std::invalid_argument for an empty or taken name or one without make.
bool register_lens_model(LensModel entry);

// The entry functions named in lens_list.h.
#define SKYPOL_LENS(name) LensModel name##_lens_model();
#include "camera/lens_list.h"
#undef SKYPOL_LENS

}  // namespace skypol::camera
