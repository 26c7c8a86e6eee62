// A scene's frames rendered into memory (render/renderer.h), frame for frame what `skypol render`
// writes (render/pipeline.h: same options, same sensor stage with the same frame index, same
// channels kept), with each frame's channel vectors handed to Python without a copy. The GIL is
// released while rendering.
#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "python/bindings.h"
#include "python/convert.h"
#include "python/py_stack.h"
#include "render/occluders_embree.h"
#include "render/renderer.h"
#include "render/sensor_stage.h"
#include "scene/scene.h"
#include "scene/truth.h"

namespace skypol::python {
namespace {

bool contains(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }

// frames: indices into scene.times (negative from the end); times: instants instead of the scene's
// (the sensor's noise is then keyed by their position). Neither: every time of the scene.
std::shared_ptr<PyStack> render_frames(const scene::Scene& sc, const std::optional<std::vector<long>>& frames,
                                const std::optional<std::vector<double>>& times,
                                const std::optional<std::vector<std::string>>& channels) {
  if (frames && times) throw std::invalid_argument("render: give frames or times, not both");
  // (instant, sensor frame index) of every frame to render, in order.
  std::vector<std::pair<sky::Instant, std::uint64_t>> todo;
  if (times) {
    for (std::size_t i = 0; i < times->size(); ++i) todo.emplace_back(instant_of((*times)[i]), i);
  } else if (frames) {
    const auto n = static_cast<long>(sc.times.size());
    for (long i : *frames) {
      const long k = i < 0 ? i + n : i;
      if (k < 0 || k >= n) {
        throw std::invalid_argument("render: frame " + std::to_string(i) + " of a scene with " + std::to_string(n) +
                                    " time(s)");
      }
      todo.emplace_back(sc.times[static_cast<std::size_t>(k)], static_cast<std::uint64_t>(k));
    }
  } else {
    for (std::size_t i = 0; i < sc.times.size(); ++i) todo.emplace_back(sc.times[i], i);
  }
  const std::vector<std::string> legal{"S0", "S1", "S2", "S3", "DoLP", "AoLP", "mask", "raw"};
  if (channels) {
    for (const std::string& c : *channels) {
      if (!contains(legal, c)) {
        throw std::invalid_argument("render: unknown channel '" + c + "' (expected S0, S1, S2, S3, DoLP, AoLP, mask, raw)");
      }
      if (c == "raw" && !sc.sensor) throw std::invalid_argument("render: 'raw' is the sensor's mosaic: it needs a [sensor] section");
    }
  }

  auto out = std::make_shared<PyStack>();
  py::gil_scoped_release release;
  // What render/pipeline.cpp's render_scene does before it writes, minus previews.
  std::shared_ptr<const camera::Camera> cam = scene::build_camera(sc.camera);
  std::unique_ptr<sky::SkyModel> sky = scene::build_sky(sc.sky);
  render::RenderOptions ro;
  ro.spp = sc.render.spp;
  ro.seed = sc.render.seed;
  ro.bands = sc.render.bands;
  ro.channels = channels ? *channels : sc.output.channels;
  std::vector<std::string> kept = render::channel_names(ro);
  const bool keep_raw = contains(ro.channels, "raw");
  if (keep_raw) kept.emplace_back("raw");
  if (sc.sensor) {
    for (const char* c : {"S0", "S1", "S2", "mask"}) {
      if (!contains(ro.channels, c)) ro.channels.emplace_back(c);
    }
  }
  const render::Renderer renderer(cam, ro, render::make_occluders(sc.occluders));

  stack::Stack& st = out->stack;
  st.camera = cam;
  st.bands = sc.render.bands;
  st.camera_description = sc.camera.description;
  st.scene_text = sc.text;
  out->sky_model = sky->name();
  st.frames.reserve(todo.size());
  for (const auto& [t, index] : todo) {
    // A new frame each time: its vectors become the NumPy arrays' memory.
    stack::Frame f = renderer.new_frame();
    f.truth = scene::make_truth(sc, *cam, t);
    renderer.render(*sky, f.truth.sun, f);
    if (sc.sensor) render::apply_sensor(*sc.sensor, sc.render.bands, index, f, keep_raw);
    std::erase_if(f.channels, [&](const auto& c) { return !contains(kept, c.first); });
    st.frames.push_back(std::move(f));
  }
  return out;
}

}  // namespace

void bind_render(py::module_& m) {
  m.def("render", &render_frames, py::arg("scene"), py::arg("frames") = py::none(), py::arg("times") = py::none(),
        py::arg("channels") = py::none(),
        "Render frames of a scene into a StackHandle (GIL released); see skypol.render_stack");
}

}  // namespace skypol::python
