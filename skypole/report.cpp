// Estimates printed beside the truth in a stack's headers: the table and JSON of `skypol estimate`
// and `skypol run`.
#include "skypole/report.h"

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <stdexcept>

#include <sys/resource.h>

#include "scene/json_text.h"
#include "stack/oiio_module.h"
#include "stack/stack_io.h"
#include "stack/temp_files.h"
#include "skypole/classic.h"
#include "skypole/classic_stream.h"
#include "skypole/estimate_plot.h"
#include "skypole/evaluate.h"
#include "skypole/sky_images.h"

namespace skypol::skypole {
namespace {

// A number with `decimals` decimals (and a sign if `sign`), or "null" where it is undefined.
std::string number_or_null(const std::optional<double>& v, int decimals, bool sign = false) {
  if (!v) return "null";
  char buf[64];
  std::snprintf(buf, sizeof buf, sign ? "%+.*f" : "%.*f", decimals, *v);
  return buf;
}

std::string heading_or_null(const std::optional<double>& v, int decimals) {
  return v ? format_heading(*v, decimals) : "null";
}

using scene::json_quoted;

// The classic estimator's step images (the paper's Fig. 1D and Fig. 2) as one multi-channel EXR:
// filtered.NN, difference.II-JJ, binary.II-JJ, sum, maximum. Written to a temporary name first.
// Errors name the stack the images come from and the file, with the writer's own reason (OIIO
// keeps an ImageOutput's errors on the object, not in OIIO::geterror()).
void write_intermediates(const ClassicImages& im, const std::string& path, const std::string& stack_path) {
  std::vector<std::string> names;
  std::vector<const float*> planes;
  std::vector<std::vector<float>> converted;  // uint8 images as float
  converted.reserve(im.binaries.size() + 1);
  char buf[64];
  for (std::size_t i = 0; i < im.filtered.size(); ++i) {
    std::snprintf(buf, sizeof buf, "filtered.%02zu", i);
    names.emplace_back(buf);
    planes.push_back(im.filtered[i].data());
  }
  for (std::size_t k = 0; k < im.pairs.size(); ++k) {
    std::snprintf(buf, sizeof buf, "%02d-%02d", im.pairs[k].first, im.pairs[k].second);
    names.push_back(std::string("difference.") + buf);
    planes.push_back(im.differences[k].data());
    converted.emplace_back(im.binaries[k].begin(), im.binaries[k].end());
    names.push_back(std::string("binary.") + buf);
    planes.push_back(converted.back().data());
  }
  names.emplace_back("sum");
  planes.push_back(im.sum.data());
  converted.emplace_back(im.maximum.begin(), im.maximum.end());
  names.emplace_back("maximum");
  planes.push_back(converted.back().data());

  const auto n = static_cast<std::size_t>(im.width) * static_cast<std::size_t>(im.height);
  std::vector<float> pixels(n * names.size());
  for (std::size_t c = 0; c < names.size(); ++c) {
    for (std::size_t i = 0; i < n; ++i) pixels[i * names.size() + c] = planes[c][i];
  }
  std::string thresholds;
  for (float t : im.thresholds) thresholds += (thresholds.empty() ? "" : " ") + std::to_string(t);
  const std::string what = stack_path + ": cannot write the classic intermediates to " + path + ": ";
  const std::string tmp = stack::temp_name(path);
  const std::string error = stack::oiio::write_float_image(
      path, tmp, im.width, im.height, names, pixels.data(),
      {{"compression", "zip"}, {"skypol:classic_thresholds", thresholds}});
  if (!error.empty()) {
    std::remove(tmp.c_str());
    throw std::invalid_argument(what + error);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp.c_str());
    throw std::invalid_argument(what + why);
  }
}

// One object per method, the same keys whether the method answered or declined (then every
// number is null and why_invalid says why).
void print_json(const std::string& path, const stack::Stack& stack, const PoleEstimate& e,
                const std::optional<Score>& s) {
  const scene::Truth& t = stack.frames.at(0).truth;
  const auto v = [&](double x) { return e.valid ? std::optional<double>(x) : std::nullopt; };
  // An imported capture has no truth to print (its latitude is known only with its site).
  const std::optional<double> true_latitude =
      stack.site_known ? std::optional<double>(t.site.latitude_deg) : std::nullopt;
  const std::optional<double> true_heading = stack.truth_known ? std::optional<double>(t.heading_deg) : std::nullopt;
  std::printf("{\"stack\": %s, \"method\": \"%s\", \"valid\": %s, \"why_invalid\": %s, \"frames\": %zu, "
              "\"seconds\": %.4f,\n",
              json_quoted(path).c_str(), e.method.c_str(), e.valid ? "true" : "false",
              e.valid ? "null" : json_quoted(e.why_invalid).c_str(), stack.frames.size(), e.seconds);
  std::printf(" \"truth_known\": %s, \"latitude_deg\": %s, \"true_latitude_deg\": %s, \"latitude_error_deg\": %s,\n",
              stack.truth_known ? "true" : "false", number_or_null(v(e.latitude_deg), 6).c_str(),
              number_or_null(true_latitude, 6).c_str(),
              number_or_null(s ? std::optional<double>(s->latitude_error_deg) : std::nullopt, 6).c_str());
  std::printf(" \"heading_deg\": %s, \"true_heading_deg\": %s, \"bearing_error_deg\": %s,\n",
              heading_or_null(e.valid ? e.heading_deg : std::nullopt, 6).c_str(), number_or_null(true_heading, 6).c_str(),
              number_or_null(s ? s->bearing_error_deg : std::nullopt, 6).c_str());
  std::printf(" \"sigma_bearing_deg\": %s, \"sigma_latitude_deg\": %s, \"cone95_deg\": %s,\n",
              number_or_null(v(e.sigma_bearing_deg), 6).c_str(), number_or_null(v(e.sigma_latitude_deg), 6).c_str(),
              number_or_null(v(e.cone95_deg), 6).c_str());
  std::printf(" \"angular_error_deg\": %s, \"pole\": %s, \"residual_deg\": %s,\n",
              number_or_null(s ? std::optional<double>(s->angular_error_deg) : std::nullopt, 6).c_str(),
              e.valid ? (e.is_north ? "\"north\"" : "\"south\"") : "null",
              number_or_null(v(e.residual_deg), 6).c_str());
  std::printf(" \"note\": %s}", json_quoted(e.note).c_str());
}

void print_table(const stack::Stack& stack, const PoleEstimate& e, const Score& s) {
  const scene::Truth& t = stack.frames.at(0).truth;
  std::printf("method   %s (%.3f s)%s%s\n", e.method.c_str(), e.seconds, e.note.empty() ? "" : "; ", e.note.c_str());
  std::printf("%-24s %12s %12s %12s %12s\n", "", "estimate", "truth", "error", "1-sigma");
  std::printf("%-24s %12.3f %12.3f %+12.3f %12.3f\n", "latitude (deg)", e.latitude_deg, t.site.latitude_deg,
              s.latitude_error_deg, e.sigma_latitude_deg);
  std::printf("%-24s %12s %12.3f %12s %12.3f\n", "north bearing (deg)", heading_or_null(e.heading_deg, 3).c_str(),
              t.heading_deg, number_or_null(s.bearing_error_deg, 3, true).c_str(), e.sigma_bearing_deg);
  std::printf("%-24s %12s %12s %12.3f %12s\n", "pole on the sphere (deg)", e.is_north ? "north" : "south",
              t.pole_is_north ? "north" : "south", s.angular_error_deg, "");
  std::printf("%-24s %12.3f\n", "95% cone (deg)", e.cone95_deg);
}

// An imported capture: the estimate alone (no truth, no error columns).
void print_unscored(const PoleEstimate& e) {
  std::printf("method   %s (%.3f s)%s%s\n", e.method.c_str(), e.seconds, e.note.empty() ? "" : "; ", e.note.c_str());
  std::printf("%-24s %12s %12s\n", "", "estimate", "1-sigma");
  std::printf("%-24s %12.3f %12.3f\n", "latitude (deg)", e.latitude_deg, e.sigma_latitude_deg);
  std::printf("%-24s %12s %12.3f\n", "north bearing (deg)", heading_or_null(e.heading_deg, 3).c_str(),
              e.sigma_bearing_deg);
  std::printf("%-24s %12s\n", "pole on the sphere", e.is_north ? "north" : "south");
  std::printf("%-24s %12.3f\n", "95% cone (deg)", e.cone95_deg);
}

// The estimate plot of `estimates` (the stack holds its clipped channel, estimator_channels).
void write_plots(const EstimateRequest& r, const stack::Stack& stack, const std::vector<PoleEstimate>& estimates) {
  const PlotOptions options;
  for (const std::string& path : write_estimate_plots(stack, estimates, r.input, r.plot, options)) {
    if (!r.json) std::printf("plot     %s\n", path.c_str());
  }
  std::fflush(stdout);
}

}  // namespace

ProcessUsage process_usage() {
  ProcessUsage u;
  u.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  rusage r{};
  getrusage(RUSAGE_SELF, &r);
  const auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  u.user_s = seconds(r.ru_utime);
  u.system_s = seconds(r.ru_stime);
  u.max_rss_mib = static_cast<double>(r.ru_maxrss) / 1024.0;  // KiB on Linux
  return u;
}

std::string profile_line(const std::string& stage, const ProcessUsage& from, const ProcessUsage& to) {
  const double user = to.user_s - from.user_s, sys = to.system_s - from.system_s;
  char buf[256];
  std::snprintf(buf, sizeof buf, "profile %s wall_s=%.3f cpu_s=%.3f user_s=%.3f sys_s=%.3f max_rss_mib=%.1f",
                stage.c_str(), to.wall_s - from.wall_s, user + sys, user, sys, to.max_rss_mib);
  return buf;
}

std::vector<std::string> estimator_channels(const std::string& path, const InputOptions& input) {
  const stack::StackSummary s = stack::peek_stack(path);
  const auto has = [&](const std::string& c) { return std::find(s.channels.begin(), s.channels.end(), c) != s.channels.end(); };
  const std::string band = pick_band(s.bands, s.channels, input);
  if (!has("DoLP." + band)) {
    // No such band: every DoLP and AoLP, so that the estimators name what the stack holds.
    std::vector<std::string> want;
    for (const std::string& c : s.channels)
      if (c == "mask" || c.rfind("DoLP.", 0) == 0 || c.rfind("AoLP.", 0) == 0) want.push_back(c);
    return want;
  }
  std::vector<std::string> want;
  for (const std::string& c : {"DoLP." + band, "AoLP." + band, "S0." + band, std::string("mask"), std::string("clipped")})
    if (has(c)) want.push_back(c);
  return want;
}

std::vector<std::string> expand_methods(const std::vector<std::string>& names) {
  const std::vector<std::string>& legal = method_names();
  if (names.size() == 1 && names[0] == "all") return legal;
  for (const std::string& m : names) {
    if (std::find(legal.begin(), legal.end(), m) == legal.end()) {
      throw std::invalid_argument("unknown method '" + m + "' (expected one of " + method_names_list() + ", or all)");
    }
  }
  if (names.empty()) throw std::invalid_argument("no method given");
  return names;
}

void print_estimate(const EstimateRequest& r) {
  const std::vector<std::string> methods = expand_methods(r.methods);
  if (!r.intermediates.empty() && methods != std::vector<std::string>{"classic"}) {
    throw std::invalid_argument("--intermediates: only the classic method has intermediate images");
  }
  const ProcessUsage start = process_usage();
  // classic alone, without its images or a plot, reads the stack part by part (classic_stream.h): a
  // day of full-resolution frames does not fit in memory as floats. Profiled, its "read" line is a
  // pass that only decodes the channels the estimators read, one part at a time, so that the
  // method's line is what it costs beside that decode.
  const bool streamed = methods == std::vector<std::string>{"classic"} && r.intermediates.empty() && r.plot.empty();
  std::optional<PoleEstimate> streamed_estimate;
  stack::Stack stack;
  if (!streamed) stack = stack::read_stack(r.path, estimator_channels(r.path, r.input));
  else if (r.profile) (void)stack::read_stack_frames(r.path, estimator_channels(r.path, r.input), [](std::size_t, stack::Frame&&) {});
  ProcessUsage last = process_usage();
  if (r.profile) std::fprintf(stderr, "%s\n", profile_line("read", start, last).c_str());
  if (streamed) {
    try {
      StreamedEstimate s = run_classic_streamed(r.path, r.input);
      stack = std::move(s.stack);
      streamed_estimate = std::move(s.estimate);
    } catch (const std::invalid_argument& err) {
      // Declined: the frames' truths and sizes for the report, from their headers and one channel.
      const std::vector<std::string> channels = stack::peek_stack(r.path).channels;
      std::vector<stack::Frame> frames;
      stack = stack::read_stack_frames(r.path, {channels.begin(), channels.begin() + (channels.empty() ? 0 : 1)},
                                       [&](std::size_t, stack::Frame&& f) {
        f.channels.clear();
        frames.push_back(std::move(f));
      });
      stack.frames = std::move(frames);
      streamed_estimate = invalid_estimate("classic", err.what());
    }
  }
  if (stack.frames.empty()) throw std::invalid_argument(r.path + ": the stack has no frames");
  if (!r.json) {
    std::printf("stack    %s (%zu frames, %dx%d)%s\n", r.path.c_str(), stack.frames.size(), stack.frames[0].width,
                stack.frames[0].height, stack.truth_known ? "" : ", a capture: truth unknown, nothing to score");
  }
  if (r.json) std::printf("[");
  std::size_t declined = 0;
  std::vector<PoleEstimate> done;  // for auto, which combines the answers already computed
  for (std::size_t i = 0; i < methods.size(); ++i) {
    if (r.progress) r.progress(i, methods.size());
    PoleEstimate e;
    if (streamed_estimate) {
      e = *streamed_estimate;
    } else if (!r.intermediates.empty()) {
      // One run gives the images and the answer, with the same uncertainty and bound as every
      // other route (run_method).
      ClassicImages images;
      e = run_method(stack, "classic", r.input, &images);
      write_intermediates(images, r.intermediates, r.path);
    } else {
      try {
        e = run_or_combine(stack, methods[i], r.input, done);
      } catch (const std::invalid_argument& err) {
        e = PoleEstimate{};
        e.method = methods[i];
        e.valid = false;
        e.why_invalid = err.what();
      }
    }
    done.push_back(e);
    if (r.profile) {
      const ProcessUsage now = process_usage();
      std::fprintf(stderr, "%s\n", profile_line(methods[i], last, now).c_str());
      last = now;
    }
    if (r.progress && i + 1 == methods.size()) r.progress(methods.size(), methods.size());
    if (r.before_output) r.before_output();
    std::optional<Score> s;
    if (e.valid) {
      if (stack.truth_known) s = score(e, stack.frames[0].truth);
    } else {
      ++declined;
    }
    if (r.json) {
      if (i) std::printf(",\n");
      print_json(r.path, stack, e, s);
    } else if (e.valid && !s) {
      print_unscored(e);
    } else if (e.valid) {
      print_table(stack, e, *s);
    } else {
      // A declined method says why, in the text as in the JSON (never a silent blank).
      std::printf("method   %s: declined: %s\n", methods[i].c_str(), e.why_invalid.c_str());
    }
  }
  if (r.json) std::printf("]\n");
  std::fflush(stdout);
  if (r.profile) std::fprintf(stderr, "%s\n", profile_line("total", start, process_usage()).c_str());
  if (!r.plot.empty()) write_plots(r, stack, done);
  if (declined == methods.size()) {
    throw std::invalid_argument(r.path + ": " +
                                (methods.size() == 1 ? methods[0] + " found no pole: " + done[0].why_invalid
                                                     : std::string("no method found a pole")));
  }
}

}  // namespace skypol::skypole
