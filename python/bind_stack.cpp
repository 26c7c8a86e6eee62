// Stacks in memory (stack/frame.h) and on disk (stack/stack_io.h): zero-copy views of every
// channel, the truth of every frame, read and write, and stacks built from a user's arrays.
#include <algorithm>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "camera/dofp_sensor.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/py_stack.h"
#include "scene/scene.h"
#include "scene/scene_error.h"
#include "scene/truth.h"
#include "sky/sky_model.h"
#include "stack/polarization_math.h"
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
  header.polarizer_angles = st.frames.front().polarizer_angles;  // one sensor per stack
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

using Attributes = std::vector<std::pair<std::string, std::string>>;

// A stack written part by part from Python: the truth of every part is the scene's at its time
// (scene/truth.h), the pixels of part i are produce(i), a dict of height×width float32 arrays
// holding exactly `channels`, copied into one frame reused for every part, so a stack of any
// length costs one frame of memory. attributes / part_attributes: StackHeader's.
void write_stream(const scene::Scene& sc, const std::string& path, const std::vector<double>& times,
                  const std::vector<std::string>& channels, const py::function& produce, const std::string& sky_model,
                  const Attributes& attributes, const std::vector<Attributes>& part_attributes, bool half,
                  const std::string& compression) {
  const std::shared_ptr<const camera::Camera> cam = scene::build_camera(sc.camera);
  const int w = cam->width(), h = cam->height();
  std::vector<scene::Truth> truths;
  for (double t : times) truths.push_back(scene::make_truth(sc, *cam, instant_of(t)));
  stack::StackHeader header;
  header.bands = sc.render.bands;
  header.camera_description = sc.camera.description;
  header.scene_text = sc.text;
  header.sky_model = sky_model;
  header.attributes = attributes;
  header.part_attributes = part_attributes;
  stack::WriteOptions wo;
  wo.half = half;
  wo.compression = compression;
  stack::Frame frame;
  frame.width = w;
  frame.height = h;
  std::optional<py::error_already_set> failure;  // produce's own exception, raised as it is
  const auto n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  try {
    stack::write_stack_reusing(path, truths, channels, w, h, header, wo, [&](std::size_t i) -> const stack::Frame& {
      try {
        const py::dict d = produce(i);
        frame.truth = truths[i];
        for (const std::string& c : channels) {
          if (!d.contains(c)) throw std::invalid_argument("write_stream: part " + std::to_string(i) + " has no channel '" + c + "'");
          const auto a = d[c.c_str()].cast<py::array_t<float, py::array::c_style | py::array::forcecast>>();
          if (a.ndim() != 2 || a.shape(0) != h || a.shape(1) != w) {
            throw std::invalid_argument("write_stream: channel '" + c + "' of part " + std::to_string(i) +
                                        " is not " + std::to_string(h) + "×" + std::to_string(w));
          }
          std::vector<float>& v = frame.channels[c];
          v.resize(n);
          std::memcpy(v.data(), a.data(), n * sizeof(float));
        }
        return frame;
      } catch (py::error_already_set& e) {
        failure.emplace(std::move(e));
        throw std::runtime_error("stopped by the Python producer");
      }
    });
  } catch (const std::exception&) {
    if (failure) throw *failure;
    throw;
  }
}

// `mask` (height × width) eroded by the demosaic's reach of the scene's [sensor] (camera::erode_mask,
// demosaic_reach: 1 pixel on a mono sensor, 3 on a colour one), as the sensor stage and `skypol
// import` erode theirs.
py::array_t<float> erode_for_demosaic(const scene::Scene& sc, const py::array_t<float, py::array::c_style | py::array::forcecast>& mask) {
  if (!sc.sensor) throw std::invalid_argument("erode_for_demosaic: the scene has no [sensor]");
  if (mask.ndim() != 2) throw std::invalid_argument("erode_for_demosaic: the mask must be 2-D");
  const auto h = static_cast<int>(mask.shape(0)), w = static_cast<int>(mask.shape(1));
  std::vector<float> m(mask.data(), mask.data() + static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  camera::erode_mask(m, w, h, camera::demosaic_reach(sc.sensor->dofp));
  py::array_t<float> out({h, w});
  std::copy(m.begin(), m.end(), out.mutable_data());
  return out;
}

// One raw mosaic (DN) through the demosaic and the masks of `skypol import` (stack/capture_import.h):
// the scene's [sensor] at the given exposure, Stokes per band zeroed outside `mask` (the lens'
// image circle eroded by the demosaic's reach, erode_for_demosaic), DoLP and AoLP
// (stack/polarization_math.h), R/G/B copies of S0 for a colour sensor, and the clipped pixels masked (camera::mask_clipped) with channel "clipped".
py::dict demosaic_frame(const scene::Scene& sc, const py::array_t<std::uint16_t, py::array::c_style | py::array::forcecast>& raw,
                        const py::array_t<float, py::array::c_style | py::array::forcecast>& mask, double exposure_us) {
  if (!sc.sensor) throw std::invalid_argument("demosaic_frame: the scene has no [sensor]");
  camera::DofpSensor d = sc.sensor->dofp;
  d.exposure_us = exposure_us;
  camera::validate(d);
  if (raw.ndim() != 2 || raw.shape(0) != d.height || raw.shape(1) != d.width || mask.ndim() != 2 ||
      mask.shape(0) != d.height || mask.shape(1) != d.width) {
    throw std::invalid_argument("demosaic_frame: raw and mask must be " + std::to_string(d.height) + "×" +
                                std::to_string(d.width) + " (the sensor's height × width)");
  }
  const std::size_t n = static_cast<std::size_t>(d.width) * static_cast<std::size_t>(d.height);
  const std::span<const std::uint16_t> dn(raw.data(), n);
  std::vector<float> m(mask.data(), mask.data() + n);
  const bool colour = d.color_filter != camera::ColorFilter::none;
  std::vector<std::pair<std::string, camera::StokesPlanes>> planes;
  if (colour) {
    std::array<camera::StokesPlanes, 3> rgb = camera::demosaic_color_bilinear(d, dn, sc.sensor->demosaic);
    for (std::size_t b = 0; b < 3; ++b) planes.emplace_back(sc.render.bands.at(b), std::move(rgb[b]));
  } else {
    planes.emplace_back(sc.render.bands.at(0), camera::demosaic_bilinear(d, dn, sc.sensor->demosaic));
  }
  py::dict out;
  const auto array_of = [&](const std::vector<float>& v) {
    py::array_t<float> a({static_cast<py::ssize_t>(d.height), static_cast<py::ssize_t>(d.width)});
    std::memcpy(a.mutable_data(), v.data(), n * sizeof(float));
    return a;
  };
  for (auto& [band, p] : planes) {
    std::vector<float> dolp(n), aolp(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (m[i] == 0.0f) p.s0[i] = p.s1[i] = p.s2[i] = 0.0f;
      dolp[i] = stack::dolp_of(p.s0[i], p.s1[i], p.s2[i]);
      aolp[i] = stack::aolp_of(p.s1[i], p.s2[i]);
    }
    if (colour) out[band.c_str()] = array_of(p.s0);
    out[("S0." + band).c_str()] = array_of(p.s0);
    out[("S1." + band).c_str()] = array_of(p.s1);
    out[("S2." + band).c_str()] = array_of(p.s2);
    out[("DoLP." + band).c_str()] = array_of(dolp);
    out[("AoLP." + band).c_str()] = array_of(aolp);
  }
  std::vector<float> clipped_sky;
  camera::mask_clipped(camera::clipped_pixels(d, dn), m, clipped_sky);
  out["mask"] = array_of(m);
  out["clipped"] = array_of(clipped_sky);
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
  m.def("write_stream", &write_stream, py::arg("scene"), py::arg("path"), py::arg("unix_seconds"), py::arg("channels"),
        py::arg("produce"), py::arg("sky_model"), py::arg("attributes") = Attributes{},
        py::arg("part_attributes") = std::vector<Attributes>{}, py::arg("half") = false, py::arg("compression") = "zip",
        "A stack file written part by part: produce(i) gives part i's channels; the truth is the scene's");
  m.def("erode_for_demosaic", &erode_for_demosaic, py::arg("scene"), py::arg("mask"),
        "The mask eroded by the reach of the scene's sensor's demosaic (1 pixel mono, 3 colour)");
  m.def("demosaic_frame", &demosaic_frame, py::arg("scene"), py::arg("raw"), py::arg("mask"), py::arg("exposure_us"),
        "A raw mosaic (DN) through the scene's [sensor] as `skypol import` converts it: the channels of a capture frame");
}

}  // namespace skypol::python
