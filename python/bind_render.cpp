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

// What render/pipeline.cpp's render_scene does before it writes, minus previews: camera, sky,
// renderer options (the sensor's inputs added), the channels the file would keep.
struct Setup {
  const scene::Scene& sc;
  std::shared_ptr<const camera::Camera> cam;
  std::unique_ptr<sky::SkyModel> sky;
  std::vector<std::string> kept;
  bool keep_raw = false;
  std::vector<std::uint8_t> sky_region;  // the meter's sky (auto exposure only)
  std::unique_ptr<render::Renderer> renderer;

  Setup(const scene::Scene& s, const std::optional<std::vector<std::string>>& channels) : sc(s) {
    const std::vector<std::string> legal{"S0", "S1", "S2", "S3", "DoLP", "AoLP", "mask", "raw"};
    if (channels) {
      for (const std::string& c : *channels) {
        if (!contains(legal, c)) {
          throw std::invalid_argument("render: unknown channel '" + c + "' (expected S0, S1, S2, S3, DoLP, AoLP, mask, raw)");
        }
        if (c == "raw" && !sc.sensor) throw std::invalid_argument("render: 'raw' is the sensor's mosaic: it needs a [sensor] section");
      }
    }
    cam = scene::build_camera(sc.camera);
    sky = scene::build_sky(sc.sky);
    render::RenderOptions ro;
    ro.spp = sc.render.spp;
    ro.seed = sc.render.seed;
    ro.bands = sc.render.bands;
    ro.channels = channels ? *channels : sc.output.channels;
    kept = render::kept_channels(render::channel_names(ro), ro.channels, sc.sensor.has_value());
    keep_raw = contains(kept, "raw");
    if (sc.sensor) {
      for (const char* c : {"S0", "S1", "S2", "mask"}) {
        if (!contains(ro.channels, c)) ro.channels.emplace_back(c);
      }
    }
    renderer = std::make_unique<render::Renderer>(cam, ro, render::make_occluders(sc.occluders));
    if (sc.sensor && sc.sensor->auto_exposure) sky_region = render::sky_pixels(*cam);
  }

  void describe(PyStack& out) const {
    out.stack.camera = cam;
    out.stack.bands = sc.render.bands;
    out.stack.camera_description = sc.camera.description;
    out.stack.scene_text = sc.text;
    out.sky_model = sky->name();
  }

  // Frame `index` of the series (the sensor's noise key) at instant t, into f.
  void render(sky::Instant t, std::uint64_t index, stack::Frame& f) const {
    f.truth = scene::make_truth(sc, *cam, t);
    renderer->render(*sky, f.truth.sun, f);
    if (sc.sensor) render::apply_sensor(*sc.sensor, sc.render.bands, index, f, keep_raw, sky_region);
    std::erase_if(f.channels, [&](const auto& c) { return !contains(kept, c.first); });
  }
};

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
  auto out = std::make_shared<PyStack>();
  py::gil_scoped_release release;
  const Setup setup(sc, channels);
  stack::Stack& st = out->stack;
  setup.describe(*out);
  st.frames.reserve(todo.size());
  for (const auto& [t, index] : todo) {
    // A new frame each time: its vectors become the NumPy arrays' memory.
    stack::Frame f = setup.renderer->new_frame();
    setup.render(t, index, f);
    st.frames.push_back(std::move(f));
  }
  return out;
}

// The scene's frames one at a time for skypol.iter_frames: the renderer is built once, and without
// a sensor every frame is rendered into the same memory, as `skypol render` does (the arrays of
// one frame are overwritten by the next). The sensor stage replaces its channels' vectors, so with
// a sensor each frame gets new memory (earlier arrays stay valid).
class FrameStream {
 public:
  FrameStream(std::shared_ptr<scene::Scene> sc, const std::optional<std::vector<std::string>>& channels)
      : scene_(std::move(sc)), setup_(*scene_, channels) {}

  std::shared_ptr<PyStack> render(long index) {
    const auto n = static_cast<long>(scene_->times.size());
    if (index < 0 || index >= n) throw py::index_error("frame " + std::to_string(index) + " of " + std::to_string(n));
    py::gil_scoped_release release;
    if (!current_ || scene_->sensor) {
      current_ = std::make_shared<PyStack>();
      setup_.describe(*current_);
      current_->stack.frames.push_back(setup_.renderer->new_frame());
    }
    setup_.render(scene_->times[static_cast<std::size_t>(index)], static_cast<std::uint64_t>(index),
                  current_->stack.frames.front());
    return current_;
  }

 private:
  std::shared_ptr<scene::Scene> scene_;
  Setup setup_;
  std::shared_ptr<PyStack> current_;
};

}  // namespace

void bind_render(py::module_& m) {
  py::class_<FrameStream>(m, "FrameStream", "Frames of a scene one at a time; use skypol.iter_frames")
      .def(py::init<std::shared_ptr<scene::Scene>, const std::optional<std::vector<std::string>>&>(), py::arg("scene"),
           py::arg("channels") = py::none())
      .def("render", &FrameStream::render, py::arg("index"));
  m.def("render", &render_frames, py::arg("scene"), py::arg("frames") = py::none(), py::arg("times") = py::none(),
        py::arg("channels") = py::none(),
        "Render frames of a scene into a StackHandle (GIL released); see skypol.render_stack");
}

}  // namespace skypol::python
