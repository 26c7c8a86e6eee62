// The estimators (skypole/evaluate.h) on a stack in memory, with the GIL released: the estimate as
// a dict (python/convert.h: every field of PoleEstimate) plus its score against the stack's truth.
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "python/bindings.h"
#include "python/convert.h"
#include "python/py_stack.h"
#include "skypole/estimate_plot.h"
#include "skypole/evaluate.h"

namespace skypol::python {
namespace {

py::dict estimate(const PyStack& s, const std::string& method, const std::string& band, const std::string& hemisphere,
                  double min_elevation_deg, double heading_undefined_within_deg,
                  const std::optional<std::pair<double, double>>& attitude, const std::string& site,
                  const std::string& polarizer_model) {
  skypole::InputOptions in;
  in.use_site = skypole::parse_site_use(site);
  in.polarizer_model = skypole::parse_polarizer_model(polarizer_model);
  in.band = band;
  in.hemisphere = skypole::parse_hemisphere(hemisphere);
  in.min_elevation_deg = min_elevation_deg;
  in.heading_undefined_within_deg = heading_undefined_within_deg;
  if (attitude) in.attitude = skypole::Attitude{attitude->first, attitude->second};
  skypole::PoleEstimate e;
  std::optional<skypole::Score> score;
  {
    py::gil_scoped_release release;
    e = skypole::run_method(s.stack, method, in);
    // A capture (skypol import) has no truth to score against: its frames' heading is a placeholder.
    if (e.valid && s.stack.truth_known && !s.stack.frames.empty()) {
      score = skypole::score(e, s.stack.frames.front().truth);
    }
  }
  py::dict d = estimate_to_dict(e);
  d["score"] = score ? py::object(score_to_dict(*score)) : py::object(py::none());
  return d;
}

// skypole/estimate_plot.h on a stack in memory: the estimates as estimate()'s dicts.
std::vector<std::string> plot_estimate(const PyStack& s, const py::list& estimates, const std::string& path,
                                       const std::string& band, double min_elevation_deg,
                                       const std::optional<std::size_t>& frame) {
  std::vector<skypole::PoleEstimate> es;
  for (const py::handle& item : estimates) es.push_back(estimate_from_dict(item.cast<py::dict>()));
  skypole::InputOptions in;
  in.band = band;
  in.min_elevation_deg = min_elevation_deg;
  skypole::PlotOptions options;
  options.frame = frame;
  py::gil_scoped_release release;
  return skypole::write_estimate_plots(s.stack, es, in, path, options);
}

}  // namespace

// python/bind_calibration.cpp: the calibration model on the calibration study's rows.
void bind_calibration(py::module_& m);

void bind_skypole(py::module_& m) {
  bind_calibration(m);
  m.def("method_names", &skypole::method_names, "The estimators run_method knows (the registry's and auto)");
  m.def("methods_json", &skypole::methods_json,
        "The estimators' registry as JSON: name, description, traits, calibration (`skypol methods --json`)");
  m.def("estimate", &estimate, py::arg("stack"), py::arg("method"), py::arg("band") = "",
        py::arg("hemisphere") = "automatic", py::arg("min_elevation_deg") = 0.0,
        py::arg("heading_undefined_within_deg") = 0.5, py::arg("attitude") = py::none(), py::arg("site") = "stack",
        py::arg("polarizer_model") = "stack",
        "Run one estimator on a StackHandle: dict of every PoleEstimate field plus 'score' (None if invalid)");
  m.def("plot_estimate", &plot_estimate, py::arg("stack"), py::arg("estimates"), py::arg("path"), py::arg("band") = "",
        py::arg("min_elevation_deg") = 0.0, py::arg("frame") = py::none(),
        "The picture of estimates (dicts of estimate()) on a StackHandle: a PNG, or one per method in a folder");
  m.def(
      "estimate_fields",
      [] {
        py::list names;
        for (const auto& item : estimate_to_dict(skypole::PoleEstimate{})) names.append(item.first);
        names.append("score");
        return names;
      },
      "The keys of estimate()'s dict, in order (skypol.Estimate's fields)");
}

}  // namespace skypol::python
