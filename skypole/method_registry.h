// The estimators as one registry: each method is one entry (its name, a line saying what it does,
// how it runs, its traits and its calibration), and everything that lists or dispatches methods
// reads it — run_method and auto (evaluate.h), run_bare, the studies, the CLI's help and
// `skypol methods`, the Python module and through them the scripts.
//
// Adding an estimator: write its files (e.g. skypole/foo.h, foo.cpp) and, in a file of its own
// (e.g. skypole/foo_method.cpp), a function `Method foo_method()` returning its entry; then add
// the one line `SKYPOL_METHOD(foo)` to skypole/method_list.h (and the .cpp files to
// skypole/CMakeLists.txt). A test or a program may also add an entry at run time with
// register_method (tests/skypole/method_registry_test.cpp).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "skypole/estimate.h"
#include "skypole/stack_sky.h"
#include "skypole/uncertainty.h"

namespace skypol::skypole {

struct ClassicImages;

// What run_method does around a method's answer (evaluate.h, uncertainty.h).
struct MethodTraits {
  // The most frame groups its frame jackknife deals its frames into (uncertainty.h frame_jackknife).
  // A jackknife's variance is itself estimated from K − 1 degrees of freedom, so few groups state a
  // σ that is often far too small: even when right on average, an error beyond 5 stated σ (a lie)
  // is then a tail of F(2, K − 1) — 0.27 % of answers at K = 6, 0.018 % at K = 18 (uncertainty.h,
  // "Few groups"). A method whose refit is cheap deletes one frame at a time, up to more groups;
  // one that reruns whole per group keeps 6.
  int frame_jackknife_max_groups = 6;
  // Whether it runs the sector jackknife (uncertainty.h).
  bool sector_jackknife = false;
  // Whether auto (combine_estimates) weighs its answer.
  bool used_by_auto = true;
  // Whether it reads the stack's site and times (the ephemeris): it cannot run on a stack whose site
  // is unknown or withheld (site_usable), and auto then leaves it out.
  bool needs_site = false;
  // Whether run_method measures the sky's Rayleigh-law misfit for it (rayleigh_law_misfit,
  // PoleEstimate::model_misfit), which its calibration's gate and σ term read.
  bool misfit_measured = false;
  // Whether auto, when this method's answer agrees with the group, returns it as it stands rather
  // than the group's mean (an answer so much sharper than the others that averaging pulls it
  // towards worse ones: sun_vector_ephemeris).
  bool auto_answers_alone = false;
};

// The sector jackknife's sectors (uncertainty.h): six, each a sixth of the image about the
// principal point.
inline constexpr int kSkySectors = 6;

// A method's answer on the whole stack with what its jackknives refit from its own work. An empty
// refit means: the method's bare run (Method::bare) on the view (SkyView::kept, SkyView::without_sector).
struct MethodRun {
  PoleEstimate estimate;
  // The answer from the frames whose keep[i] is 1.
  std::function<PoleEstimate(const std::vector<std::uint8_t>& keep)> without_frames;
  // The answer without sector g of kSkySectors.
  std::function<PoleEstimate(int g)> without_sector;
  // false: this run has no sector jackknife although the method has one (invariance's per-frame
  // refinement, for frames without times).
  bool sectors = true;
};

struct Method {
  std::string name;
  std::string description;  // one line, for help texts and `skypol methods`
  // The method alone on a view: its answer without uncertainty, gates or calibration (run_bare.h).
  // Throws std::invalid_argument for unusable input. The jackknives call it on their views in
  // parallel, as they call the refits of MethodRun.
  std::function<PoleEstimate(const SkyView& view)> bare;
  // Its run on the whole stack for run_method, keeping what its jackknives can refit from;
  // classic_images, when not null, receives classic's step images. Empty: `bare` on the whole stack.
  std::function<MethodRun(const StackSky& whole, ClassicImages* classic_images)> run;
  MethodTraits traits;
  MethodCalibration calibration;  // uncertainty.h; its .method is set to `name` on registration
};

// The entry functions of the methods of skypole/method_list.h (each defined in its own file).
#define SKYPOL_METHOD(name) Method name##_method();
#include "skypole/method_list.h"
#undef SKYPOL_METHOD

// Every registered method, in the order `-m all` runs them and auto weighs them: those of
// skypole/method_list.h, then any added by register_method.
const std::vector<Method>& methods();
// The entry of `name`, or nullptr ("auto" has none: it is the combination, auto.h).
const Method* find_method(std::string_view name);
// The entry of `name`; throws std::invalid_argument naming the legal ones.
const Method& method_entry(std::string_view name);
// Adds `m` after the registered ones (for tests and programs that bring their own method); returns
// true, so that a file can register at static initialisation (`const bool r = register_method(…);`).
// Throws std::invalid_argument for an empty or taken name or an entry without a bare run. Not
// thread-safe: register before any method runs (a registration moves the entries, so the references
// methods() and find_method gave before it no longer hold).
bool register_method(Method m);

// The methods' names and "auto", in registry order: what run_method accepts.
const std::vector<std::string>& method_names();
// "classic, great_circle, …, auto": the legal names for messages and help texts.
std::string method_names_list();

// Whether the methods may read the stack's site and times: the stack knows them (an imported
// capture without [site] does not) and the input does not withhold them (InputOptions::use_site).
bool site_usable(const stack::Stack& stack, const InputOptions& input);
// InputOptions::use_site from the command line's `--site` value: "stack" (use the stack's site, if
// it knows it) or "unknown" (do not). Throws std::invalid_argument naming the legal values.
bool parse_site_use(std::string_view value);
// The help text of `--site`, shared by the commands that take it.
inline constexpr const char* kSiteOptionHelp =
    "stack (default: the stack's site and times, if it knows them) or unknown: estimate as if the site "
    "were unknown, so that methods needing it (the ephemeris) decline and auto is site-free";

// The registry as JSON, for scripts (`skypol methods --json`): an array of
// {"name", "description", "frame_jackknife_max_groups", "sector_jackknife", "used_by_auto",
// "needs_site", "misfit_measured", "auto_answers_alone",
//  "calibration": {every MethodCalibration field but method; infinity: null}}.
std::string methods_json();

}  // namespace skypol::skypole
