// Scenes from Python (scene/scene.h): a file or TOML text, with overrides exactly as `--set` takes
// them (python/skypol/__init__.py turns a dict into "key=value" text), checked by the same loader
// as the CLI, so a bad value raises skypol.SceneError with the CLI's message and location.
#include <memory>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "python/convert.h"
#include "python/sun_table.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "scene/scene_source.h"
#include "scene/truth.h"

namespace skypol::python {
namespace {

std::vector<scene::Override> overrides_of(const std::vector<std::string>& assignments) {
  std::vector<scene::Override> out;
  for (const std::string& a : assignments) out.push_back(scene::parse_override(a));
  return out;
}

std::shared_ptr<camera::Camera> camera_of(const scene::Scene& s) {
  return std::const_pointer_cast<camera::Camera>(scene::build_camera(s.camera));
}

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<scene::Scene, std::shared_ptr<scene::Scene>>(m, "Scene", "A checked scene (scene/scene.h)")
      .def_readonly("file", &scene::Scene::file)
      .def_readonly("text", &scene::Scene::text)
      .def_property_readonly("times",
                             [](const scene::Scene& s) {
                               py::array_t<double> t(static_cast<py::ssize_t>(s.times.size()));
                               for (std::size_t i = 0; i < s.times.size(); ++i) {
                                 t.mutable_at(static_cast<py::ssize_t>(i)) = s.times[i].unix_seconds;
                               }
                               return t;
                             })
      .def_property_readonly("site",
                             [](const scene::Scene& s) {
                               py::dict d;
                               d["latitude_deg"] = s.site.latitude_deg;
                               d["longitude_deg"] = s.site.longitude_deg;
                               d["height_m"] = s.site.height_m;
                               return d;
                             })
      .def_property_readonly("sun_options", [](const scene::Scene& s) { return sun_options_to_dict(s.sun_options); })
      .def_property_readonly("orientation",
                             [](const scene::Scene& s) {
                               py::dict d;
                               d["heading_deg"] = s.camera.heading_deg;
                               d["tilt_deg"] = s.camera.tilt_deg;
                               d["roll_deg"] = s.camera.roll_deg;
                               return d;
                             })
      .def_property_readonly("camera_description", [](const scene::Scene& s) { return s.camera.description; })
      .def_property_readonly("sky_model", [](const scene::Scene& s) { return s.sky.model; })
      .def_property_readonly("bands", [](const scene::Scene& s) { return s.render.bands; })
      .def_property_readonly("spp", [](const scene::Scene& s) { return s.render.spp; })
      .def_property_readonly("has_sensor", [](const scene::Scene& s) { return s.sensor.has_value(); })
      .def_property_readonly("has_occluders", [](const scene::Scene& s) { return !s.occluders.empty(); })
      .def_property_readonly("output_path", [](const scene::Scene& s) { return s.output.path; })
      .def_property_readonly("output_channels", [](const scene::Scene& s) { return s.output.channels; })
      .def_property_readonly("output_half", [](const scene::Scene& s) { return s.output.half; })
      .def_property_readonly("output_compression", [](const scene::Scene& s) { return s.output.compression; })
      .def_property_readonly("channel_names",
                             [](const scene::Scene& s) {
                               render::RenderOptions ro;
                               ro.bands = s.render.bands;
                               ro.channels = s.output.channels;
                               return render::channel_names(ro);
                             })
      .def("camera", &camera_of, "The scene's camera (built from its [camera] section)")
      .def(
          "truth",
          [](const scene::Scene& s, const camera::Camera& cam, double unix_seconds) {
            return truth_to_dict(scene::make_truth(s, cam, instant_of(unix_seconds)));
          },
          py::arg("camera"), py::arg("unix_seconds"))
      .def(
          "sun_positions",
          [](const scene::Scene& s, const Seconds& t) {
            return sun_table(s.site, s.sun_options, t);
          },
          py::arg("unix_seconds"));

  m.def(
      "load_scene",
      [](const std::string& path, const std::vector<std::string>& overrides) {
        return std::make_shared<scene::Scene>(scene::load_scene(path, overrides_of(overrides)));
      },
      py::arg("path"), py::arg("overrides") = std::vector<std::string>{},
      "A scene file with `--set`-style overrides (\"key=value\" text); raises SceneError");
  m.def(
      "parse_scene",
      [](const std::string& text, const std::string& file_name, const std::vector<std::string>& overrides) {
        return std::make_shared<scene::Scene>(
            scene::scene_from_source(scene::parse_scene_source(text, file_name, overrides_of(overrides))));
      },
      py::arg("text"), py::arg("file_name"), py::arg("overrides") = std::vector<std::string>{},
      "A scene from TOML text; includes resolve against the folder of file_name; raises SceneError");
  m.def("toml_quoted", &scene::toml_quoted, py::arg("text"),
        "`text` as a TOML basic string, quoted as the scene language writes one (scene/scene_source.h)");
}

}  // namespace skypol::python
