#include "render/sweep_run.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>

#include <tbb/global_control.h>

#include "render/pipeline.h"
#include "scene/scene_error.h"
#include "stack/temp_files.h"

namespace skypol::render {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using scene::FileLoc;
using scene::SceneError;

std::string seconds_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

void write_atomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = stack::temp_name(path.string());
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw scene::SceneError(scene::FileLoc{path.string(), 0, 0}, "cannot write the manifest");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw scene::SceneError(scene::FileLoc{path.string(), 0, 0}, "cannot write the manifest: " + ec.message());
  }
}

void remove_all(const std::vector<fs::path>& paths) {
  std::error_code ec;
  for (const fs::path& p : paths) fs::remove(p, ec);
}

}  // namespace

SweepReport run_sweep(const scene::Sweep& sweep, const SweepOptions& options) {
  SweepReport report;
  report.variants = sweep.size();
  const auto t_check = Clock::now();
  // Every variant is loaded and checked before anything is written: a sweep either starts whole
  // or fails with the first bad entry. Only the manifest and the file names are kept (a scene per
  // variant would hold ~3 kB); this shard's variants are made again when rendered.
  std::string manifest;
  std::vector<std::string> files;
  files.reserve(report.variants);
  for (std::size_t i = 0; i < report.variants; ++i) {
    const scene::Variant v = scene::make_variant(sweep, i, options.overrides);
    manifest += scene::manifest_line(v) + "\n";
    files.push_back(v.file);
  }
  const fs::path dir(options.out_dir);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    throw scene::SceneError(scene::FileLoc{options.out_dir, 0, 0}, "cannot create the output folder" + (ec ? ": " + ec.message() : ""));
  }
  // Leftovers of runs killed mid-write (NAME.tmp-HOST-PID of this host's dead processes,
  // stack/temp_files.h): one scan of the folder maps each NAME to its leftovers.
  std::map<std::string, std::vector<fs::path>> stale = stack::stale_temporaries(dir);
  remove_all(stale["manifest.jsonl"]);
  write_atomically(dir / "manifest.jsonl", manifest);
  report.check_seconds = since(t_check);

  std::optional<tbb::global_control> threads;
  if (options.threads > 0) {
    threads.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(options.threads));
  }
  const auto t_render = Clock::now();
  for (std::size_t i = 0; i < report.variants; ++i) {
    if (!options.shard.has(i)) continue;
    ++report.in_shard;
    const fs::path out = dir / files[i];
    if (fs::exists(out)) {
      ++report.skipped;
      continue;
    }
    if (options.dry_run) continue;
    if (auto it = stale.find(files[i]); it != stale.end()) remove_all(it->second);
    const auto t0 = Clock::now();
    try {
      const scene::Variant v = scene::make_variant(sweep, i, options.overrides);
      const RenderReport r = render_scene(v.scene, out.string());
      ++report.rendered;
      if (options.log) {
        options.log("variant " + std::to_string(i + 1) + "/" + std::to_string(report.variants) + ": " + out.string() +
                    " (" + std::to_string(r.frames) + " frames " + std::to_string(r.width) + "x" +
                    std::to_string(r.height) + ", " + seconds_text(since(t0)) + " s)");
      }
    } catch (const std::exception& e) {
      report.failures.push_back("variant " + std::to_string(i) + " (" + files[i] + "): " + e.what());
      if (options.log) options.log(report.failures.back());
    }
  }
  report.render_seconds = since(t_render);
  return report;
}


}  // namespace skypol::render
