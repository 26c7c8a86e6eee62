// One sky model per band: the renderer writes each band from its own model (the VRTE sky's S0–S2
// differ by band), a grey model still fills every band with the same values, and the pipeline pays
// for VRTE tables only when a scene asks for the VRTE sky. Renders of the hard scenes under the
// VRTE sky hold no NaN or Inf. Small tables (4 streams, grid 8) and binned cameras: seconds.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <string>

#include <unistd.h>

#include "camera/orientation.h"
#include "camera/radial_lens.h"
#include "render/pipeline.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "sky/rayleigh.h"
#include "sky/units.h"
#include "stack/stack_io.h"
#include "sky/sky_test_util.h"

using namespace skypol;
using skypol::testing::sun_at;
namespace fs = std::filesystem;

namespace {

std::shared_ptr<const camera::Camera> small_fisheye(int w = 48, int h = 40) {
  camera::Intrinsics k;
  k.width = w;
  k.height = h;
  k.fx = k.fy = 0.95 * (h / 2.0) / rad_from_deg(92.5);
  k.cx = (w - 1) / 2.0;
  k.cy = (h - 1) / 2.0;
  auto lens = std::make_shared<camera::RadialLens>(camera::Mapping::equidistant, k, rad_from_deg(92.5));
  return std::make_shared<camera::Camera>(lens, camera::world_from_heading_tilt_roll(20, 0, 0));
}

sky::SkySpec small_vrte() {
  sky::SkySpec s;
  s.model = "vrte";
  s.streams = 4;
  s.grid = 8;
  s.aerosol.tau_550 = 0.15;
  s.aerosol.angle_nodes = 64;
  return s;
}

// A temporary SKYPOL_CACHE_DIR for the pipeline, restored afterwards.
struct CacheEnv {
  fs::path path;
  std::string saved;
  bool had = false;
  explicit CacheEnv(const std::string& name)
      : path(fs::temp_directory_path() / ("skypol-band-render-" + std::to_string(::getpid()) + "-" + name)) {
    fs::remove_all(path);
    if (const char* v = std::getenv("SKYPOL_CACHE_DIR")) had = true, saved = v;
    ::setenv("SKYPOL_CACHE_DIR", path.c_str(), 1);
  }
  ~CacheEnv() {
    if (had) {
      ::setenv("SKYPOL_CACHE_DIR", saved.c_str(), 1);
    } else {
      ::unsetenv("SKYPOL_CACHE_DIR");
    }
    fs::remove_all(path);
  }
  std::size_t files() const {
    if (!fs::exists(path)) return 0;
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(path)) ++n;
    return n;
  }
};

bool all_finite(const stack::Frame& f) {
  for (const auto& [name, data] : f.channels) {
    for (float v : data) {
      if (!std::isfinite(v)) return false;
    }
  }
  return true;
}

const fs::path kScenes = fs::path(SKYPOL_SOURCE_DIR) / "scenes";

}  // namespace

TEST_CASE("a sky with one model per band renders each band from its own model", "[renderer][bands]") {
  const auto cam = small_fisheye();
  render::RenderOptions o;
  o.bands = {"R", "G", "B"};
  const std::vector<std::string> bands = o.bands;
  const sky::BandSkies skies = sky::make_band_skies(small_vrte(), bands, sky::SiteAtmosphere{}, {});
  std::vector<const sky::SkyModel*> models;
  for (const auto& m : skies.skies) models.push_back(m.get());
  const sky::Sun sun = sun_at(140, 35);
  for (const int spp : {1, 4}) {
    o.spp = spp;
    const render::Renderer r(cam, o);
    const stack::Frame f = r.render(models, sun);
    CHECK(all_finite(f));
    for (std::size_t b = 0; b < 3; ++b) {
      // Each band alone through the one-model path gives the same bytes.
      render::RenderOptions one = o;
      one.bands = {bands[b]};
      const stack::Frame g = render::Renderer(cam, one).render(*models[b], sun);
      for (const char* c : {"S0", "S1", "S2", "DoLP", "AoLP"}) {
        INFO(c << "." << bands[b] << " spp " << spp);
        CHECK(f.channel(std::string(c) + "." + bands[b]) == g.channel(std::string(c) + "." + bands[b]));
      }
    }
    CHECK(f.channel("R") == f.channel("S0.R"));
    CHECK(f.channel("B") == f.channel("S0.B"));
    for (const char* c : {"S0", "S1", "S2", "DoLP"}) {
      INFO(c);
      CHECK(f.channel(std::string(c) + ".R") != f.channel(std::string(c) + ".G"));
      CHECK(f.channel(std::string(c) + ".G") != f.channel(std::string(c) + ".B"));
    }
  }
  // A count that is neither one nor one per band is refused.
  const std::vector<const sky::SkyModel*> two{models[0], models[1]};
  CHECK_THROWS_AS(render::Renderer(cam, o).render(two, sun), std::invalid_argument);
}

TEST_CASE("a grey sky gives every band the same values", "[renderer][bands]") {
  const auto cam = small_fisheye();
  render::RenderOptions o;
  o.bands = {"R", "G", "B"};
  const sky::RayleighSky grey(sky::RayleighParams{0.8});
  const stack::Frame f = render::Renderer(cam, o).render(grey, sun_at(10, 50));
  for (const char* c : {"S0", "S1", "S2", "DoLP", "AoLP"}) {
    CHECK(f.channel(std::string(c) + ".R") == f.channel(std::string(c) + ".G"));
    CHECK(f.channel(std::string(c) + ".G") == f.channel(std::string(c) + ".B"));
  }
}

TEST_CASE("a grey scene builds no VRTE table; a vrte scene builds its tables once", "[pipeline][bands]") {
  CacheEnv cache("pay");
  const fs::path out = cache.path.parent_path() / ("skypol-band-render-" + std::to_string(::getpid()) + ".exr");
  const std::vector<scene::Override> small{{"camera.binning", "32"}, {"time.step_min", "600"}};
  const scene::Scene grey = scene::load_scene((kScenes / "skypole-marseille.toml").string(), small);
  const render::RenderReport g = render::render_scene(grey, out.string());
  CHECK(g.tables_built == 0);
  CHECK(g.tables_read == 0);
  CHECK(cache.files() == 0);
  CHECK(!fs::exists(cache.path));

  std::vector<scene::Override> vrte = small;
  vrte.insert(vrte.end(), {{"sky.streams", "4"}, {"sky.grid", "8"}, {"sky.aerosol.angle_nodes", "64"}});
  const scene::Scene v = scene::load_scene((kScenes / "skypole-marseille-vrte.toml").string(), vrte);
  const render::RenderReport cold = render::render_scene(v, out.string());
  CHECK(cold.tables_built == 3);
  CHECK(cache.files() == 3);
  const render::RenderReport warm = render::render_scene(v, out.string());
  CHECK(warm.tables_built == 0);
  CHECK(warm.tables_read == 3);
  const stack::Stack st = stack::read_stack(out.string());
  REQUIRE(!st.frames.empty());
  for (const stack::Frame& f : st.frames) CHECK(all_finite(f));
  CHECK(st.frames.front().channel("S0.R") != st.frames.front().channel("S0.B"));
  fs::remove(out);
}

TEST_CASE("vrte renders of the hard scenes hold no NaN or Inf", "[pipeline][bands][hard]") {
  CacheEnv cache("hard");
  const fs::path out = cache.path.parent_path() / ("skypol-band-hard-" + std::to_string(::getpid()) + ".exr");
  // (hard-tilted-camera includes skypole-marseille.toml, whose [sky] sets the grey model's max_dolp: it
  // cannot become vrte by --set.)
  for (const char* name : {"hard-sun-zenith.toml", "hard-sun-horizon.toml", "hard-polar-day.toml",
                           "hard-equator.toml", "hard-southern.toml"}) {
    INFO(name);
    const std::vector<scene::Override> o{{"sky.model", "\"vrte\""}, {"sky.streams", "4"}, {"sky.grid", "8"},
                                         {"sky.aerosol.angle_nodes", "64"}, {"camera.binning", "16"}};
    const scene::Scene s = scene::load_scene((kScenes / name).string(), o);
    (void)render::render_scene(s, out.string());
    const stack::Stack st = stack::read_stack(out.string());
    for (const stack::Frame& f : st.frames) CHECK(all_finite(f));
  }
  fs::remove(out);
}
