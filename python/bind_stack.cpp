// Stacks in memory (stack/frame.h) and on disk (stack/stack_io.h): zero-copy views of every
// channel, the truth of every frame, read and write, and stacks built from a user's arrays.
#include <algorithm>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "python/convert.h"
#include "python/py_stack.h"
#include "scene/scene.h"
#include "scene/scene_error.h"
#include "scene/truth.h"
#include "sky/sky_model.h"
#include "stack/stack_io.h"

namespace skypol::python {
namespace {

const stack::Frame& frame_at(const PyStack& s, py::ssize_t i) {
  const auto n = static_cast<py::ssize_t>(s.stack.frames.size());
  if (i < 0) i += n;
  if (i < 0 || i >= n) throw py::index_error("frame " + std::to_string(i) + " of a stack of " + std::to_string(n));
  return s.stack.frames[static_cast<std::size_t>(i)];
}

// The header attribute the reader does not keep in stack::Stack.
std::string sky_model_of(const std::string& path) {
  try {
    Imf::MultiPartInputFile file(path.c_str());
    if (const auto* a = file.header(0).findTypedAttribute<Imf::StringAttribute>("skypol:skyModel")) return a->value();
  } catch (const std::exception&) {
  }
  return "unknown";
}

void write_file(const PyStack& s, const std::string& path, std::vector<std::string> channels, bool half,
           const std::string& compression) {
  const stack::Stack& st = s.stack;
  if (st.frames.empty()) throw std::invalid_argument("write_stack: the stack has no frames");
  if (channels.empty()) {
    for (const auto& [name, data] : st.frames.front().channels) channels.push_back(name);
  }
  std::vector<scene::Truth> truths;
  for (std::size_t i = 0; i < st.frames.size(); ++i) {
    const stack::Frame& f = st.frames[i];
    if (f.width != st.frames.front().width || f.height != st.frames.front().height) {
      throw std::invalid_argument("write_stack: frame " + std::to_string(i) + " differs in size from frame 0");
    }
    for (const std::string& c : channels) {
      if (!f.has(c)) throw std::invalid_argument("write_stack: frame " + std::to_string(i) + " has no channel '" + c + "'");
    }
    truths.push_back(f.truth);
  }
  stack::StackHeader header;
  header.bands = st.bands;
  header.camera_description = st.camera_description;
  header.scene_text = st.scene_text;
  header.sky_model = s.sky_model;
  header.exposures = std::all_of(st.frames.begin(), st.frames.end(), [](const stack::Frame& f) { return f.exposure_us.has_value(); });
  stack::WriteOptions wo;
  wo.half = half;
  wo.compression = compression;
  py::gil_scoped_release release;
  stack::write_stack_reusing(path, truths, channels, st.frames.front().width, st.frames.front().height, header, wo,
                             [&](std::size_t i) -> const stack::Frame& { return st.frames[i]; });
}

// A stack from arrays (name → T×H×W float32) at the given times, seen by the scene's camera; the
// truth of each frame is the scene's (scene/truth.h). The arrays are copied once into the stack.
std::shared_ptr<PyStack> from_arrays(const scene::Scene& sc, const std::vector<double>& times,
                                     const std::map<std::string, py::array_t<float, py::array::c_style | py::array::forcecast>>& arrays) {
  auto out = std::make_shared<PyStack>();
  stack::Stack& st = out->stack;
  st.camera = scene::build_camera(sc.camera);
  st.bands = sc.render.bands;
  st.camera_description = sc.camera.description;
  st.scene_text = sc.text;
  out->sky_model = sc.sky.model;
  const int w = st.camera->width(), h = st.camera->height();
  if (arrays.empty()) throw std::invalid_argument("stack_from_arrays: no channels");
  for (const auto& [name, a] : arrays) {
    if (a.ndim() != 3 || a.shape(0) != static_cast<py::ssize_t>(times.size()) || a.shape(1) != h || a.shape(2) != w) {
      std::string shape;
      for (py::ssize_t k = 0; k < a.ndim(); ++k) shape += (k ? "×" : "") + std::to_string(a.shape(k));
      throw std::invalid_argument("stack_from_arrays: channel '" + name + "' is " + shape + ", expected " +
                                  std::to_string(times.size()) + "×" + std::to_string(h) + "×" + std::to_string(w) +
                                  " (frames × the camera's height × width)");
    }
  }
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  for (std::size_t i = 0; i < times.size(); ++i) {
    stack::Frame f;
    f.width = w;
    f.height = h;
    f.truth = scene::make_truth(sc, *st.camera, instant_of(times[i]));
    for (const auto& [name, a] : arrays) {
      std::vector<float>& c = f.channels[name];
      c.resize(n);
      std::memcpy(c.data(), a.data() + i * n, n * sizeof(float));
    }
    st.frames.push_back(std::move(f));
  }
  return out;
}

}  // namespace

void bind_stack(py::module_& m) {
  py::class_<PyStack, std::shared_ptr<PyStack>>(m, "StackHandle", "A stack in memory; use skypol.Stack")
      .def("__len__", [](const PyStack& s) { return s.stack.frames.size(); })
      .def_property_readonly("bands", [](const PyStack& s) { return s.stack.bands; })
      .def_property_readonly("camera_description", [](const PyStack& s) { return s.stack.camera_description; })
      .def_property_readonly("scene_text", [](const PyStack& s) { return s.stack.scene_text; })
      .def_readwrite("sky_model", &PyStack::sky_model)
      .def_property_readonly("truth_known", [](const PyStack& s) { return s.stack.truth_known; })
      .def_property_readonly("site_known", [](const PyStack& s) { return s.stack.site_known; })
      .def_property_readonly("camera",
                             [](const PyStack& s) { return std::const_pointer_cast<camera::Camera>(s.stack.camera); })
      .def("size", [](const PyStack& s, py::ssize_t i) {
        const stack::Frame& f = frame_at(s, i);
        return py::make_tuple(f.height, f.width);
      })
      .def("channel_names", [](const PyStack& s, py::ssize_t i) {
        std::vector<std::string> names;
        for (const auto& [name, data] : frame_at(s, i).channels) names.push_back(name);
        return names;
      })
      .def("channel", [](py::object self, py::ssize_t i, const std::string& name) {
        PyStack& s = self.cast<PyStack&>();
        auto& f = const_cast<stack::Frame&>(frame_at(s, i));
        if (!f.has(name)) throw py::key_error(name);
        return channel_view(f.channel(name), f.width, f.height, self);
      })
      .def("truth", [](const PyStack& s, py::ssize_t i) { return truth_to_dict(frame_at(s, i).truth); })
      .def("write", &write_file, py::arg("path"), py::arg("channels") = std::vector<std::string>{}, py::arg("half") = false,
           py::arg("compression") = "zip");

  m.def(
      "read_stack",
      [](const std::string& path, const std::vector<std::string>& channels) {
        auto out = std::make_shared<PyStack>();
        {
          py::gil_scoped_release release;
          out->stack = stack::read_stack(path, channels);
          out->sky_model = sky_model_of(path);
        }
        return out;
      },
      py::arg("path"), py::arg("channels") = std::vector<std::string>{});
  m.def("stack_from_arrays", &from_arrays, py::arg("scene"), py::arg("unix_seconds"), py::arg("channels"));
}

}  // namespace skypol::python
