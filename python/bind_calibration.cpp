// The calibration model (skypole/uncertainty.h) on the calibration study's rows, for
// scripts/calibration_tune.py: the σ, cone and gates a calibration states for each row, the Wilson
// interval of a coverage and auto's choice among answers, all by the C++ that states the estimates.
// Calibrations are dicts keyed by MethodCalibration's field names (calibration_fields; None: an
// unbounded gate; a missing key: the field's default).
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "python/convert.h"
#include "sky/units.h"
#include "skypole/method_registry.h"
#include "skypole/uncertainty.h"

namespace skypol::python {
namespace {

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

skypole::MethodCalibration calibration_from(const py::dict& d) {
  skypole::MethodCalibration c;
  for (const auto& [key, value] : d) {
    const std::string name = py::str(key);
    if (name == "method") {
      c.method = py::str(value);
      continue;
    }
    bool known = false;
    for (const auto& [field, member] : skypole::calibration_fields())
      if (name == field) {
        c.*member = value.is_none() ? std::numeric_limits<double>::infinity() : value.cast<double>();
        known = true;
      }
    if (!known) {
      std::string names;
      for (const auto& f : skypole::calibration_fields()) names += (names.empty() ? "" : ", ") + std::string(f.first);
      throw py::value_error("calibration: unknown key \"" + name + "\" (expected method or one of " + names + ")");
    }
  }
  return c;
}

py::array_t<double> doubles(const std::vector<double>& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

py::array_t<bool> bools(const std::vector<char>& v) {
  py::array_t<bool> a(static_cast<py::ssize_t>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) a.mutable_data()[i] = v[i] != 0;
  return a;
}

// The study's rows, one answer each, by their calibration.csv columns: the raw jackknives
// (frames_aa_deg2 … sectors_bb_deg2, frame_groups; sector_groups, optional, kSkySectors — for a
// method without a sector jackknife its covariance is 0 and the count counts nothing) and the
// readings (CalibrationReadings' fields).
class CalibrationRows {
 public:
  explicit CalibrationRows(const py::dict& columns) {
    const auto column = [&](const char* name, bool required) -> std::vector<double> {
      if (!columns.contains(name)) {
        if (required) throw py::value_error(std::string("CalibrationRows: no column \"") + name + "\"");
        return {};
      }
      const Doubles a = py::cast<Doubles>(columns[name]);
      std::vector<double> v(a.data(), a.data() + a.size());
      if (!jack_.empty() && v.size() != jack_.size())
        throw py::value_error(std::string("CalibrationRows: column \"") + name + "\" has " + std::to_string(v.size()) +
                              " rows, not " + std::to_string(jack_.size()));
      return v;
    };
    const std::vector<double> faa = column("frames_aa_deg2", true);
    jack_.resize(faa.size());
    read_.resize(faa.size());
    const std::vector<double> fab = column("frames_ab_deg2", true), fbb = column("frames_bb_deg2", true);
    const std::vector<double> saa = column("sectors_aa_deg2", true), sab = column("sectors_ab_deg2", true),
                              sbb = column("sectors_bb_deg2", true);
    const std::vector<double> fg = column("frame_groups", true), sg = column("sector_groups", false);
    const double d2 = kRadPerDeg * kRadPerDeg;
    for (std::size_t i = 0; i < jack_.size(); ++i) {
      skypole::Jackknives& j = jack_[i];
      j.frames << faa[i] * d2, fab[i] * d2, fab[i] * d2, fbb[i] * d2;
      j.sectors << saa[i] * d2, sab[i] * d2, sab[i] * d2, sbb[i] * d2;
      j.frame_groups = static_cast<int>(fg[i]);
      j.sector_groups = sg.empty() ? skypole::kSkySectors : static_cast<int>(sg[i]);
    }
    const std::pair<const char*, double skypole::CalibrationReadings::*> readings[] = {
        {"residual_deg", &skypole::CalibrationReadings::residual_deg},
        {"pixel_deg", &skypole::CalibrationReadings::pixel_deg},
        {"unpolarized_share", &skypole::CalibrationReadings::unpolarized_share},
        {"clipped_share", &skypole::CalibrationReadings::clipped_share},
        {"sun_elevation_misfit_deg", &skypole::CalibrationReadings::sun_elevation_misfit_deg},
        {"model_misfit", &skypole::CalibrationReadings::model_misfit},
        {"window_min", &skypole::CalibrationReadings::window_min},
        {"ring_anisotropy", &skypole::CalibrationReadings::ring_anisotropy},
    };
    for (const auto& [name, member] : readings) {
      const std::vector<double> v = column(name, true);
      for (std::size_t i = 0; i < v.size(); ++i) read_[i].*member = v[i];
    }
  }

  std::size_t size() const { return jack_.size(); }

  // What calibration c states per row: σ and 95 % cone (degrees), and whether the cone is within the bound.
  py::dict stated(const py::dict& calibration, double max_cone95_deg) const {
    const skypole::MethodCalibration c = calibration_from(calibration);
    std::vector<double> sigma(size()), cone(size());
    std::vector<char> within(size());
    {
      py::gil_scoped_release release;
      for (std::size_t i = 0; i < size(); ++i) {
        const Eigen::Matrix2d cov = skypole::calibrated_covariance(c, jack_[i], read_[i]);
        sigma[i] = skypole::sigma_deg_of(cov);
        cone[i] = skypole::cone95_deg_of(cov);
        within[i] = skypole::within_uncertainty_bound(cone[i], max_cone95_deg);
      }
    }
    py::dict out;
    out["sigma_deg"] = doubles(sigma);
    out["cone95_deg"] = doubles(cone);
    out["within_bound"] = bools(within);
    return out;
  }

  // The uncalibrated statement per row (uncertainty.h uncalibrated_covariance): σ and cone.
  py::dict uncalibrated() const {
    std::vector<double> sigma(size()), cone(size());
    for (std::size_t i = 0; i < size(); ++i) {
      const Eigen::Matrix2d cov = skypole::uncalibrated_covariance(jack_[i]);
      sigma[i] = skypole::sigma_deg_of(cov);
      cone[i] = skypole::cone95_deg_of(cov);
    }
    py::dict out;
    out["sigma_deg"] = doubles(sigma);
    out["cone95_deg"] = doubles(cone);
    return out;
  }

  // Whether every gate of c passes each row (first_declining_gate is Gate::none).
  py::array_t<bool> gates(const py::dict& calibration, bool cloud_gate) const {
    const skypole::MethodCalibration c = calibration_from(calibration);
    std::vector<char> pass(size());
    for (std::size_t i = 0; i < size(); ++i)
      pass[i] = skypole::first_declining_gate(c, read_[i], cloud_gate) == skypole::Gate::none;
    return bools(pass);
  }

 private:
  std::vector<skypole::Jackknives> jack_;
  std::vector<skypole::CalibrationReadings> read_;
};

py::tuple wilson(const Doubles& hits, const Doubles& n) {
  if (hits.size() != n.size()) throw py::value_error("wilson_interval95: hits and n differ in size");
  py::array_t<double> low(hits.request().shape), high(hits.request().shape);
  for (py::ssize_t i = 0; i < hits.size(); ++i) {
    const auto [lo, hi] = skypole::wilson_interval95(hits.data()[i], n.data()[i]);
    low.mutable_data()[i] = lo;
    high.mutable_data()[i] = hi;
  }
  return py::make_tuple(low, high);
}

// auto_choice on answers given by their tangent-plane offsets (degrees, about any one point, e.g.
// the truth): the angle between two is the distance of their offsets (small angles: answers that
// agree are at most a few degrees apart). mean_offset_deg: inverse_variance_mean of the members'
// offsets, weighted by weight_sigma_deg (default: sigma_deg).
py::dict choice(const Doubles& offsets_deg, const Doubles& cone95_deg, const Doubles& sigma_deg,
                const std::vector<bool>& answers_alone, const std::optional<Doubles>& weight_sigma_deg) {
  const auto n = static_cast<std::size_t>(cone95_deg.size());
  if (static_cast<std::size_t>(offsets_deg.size()) != 2 * n || static_cast<std::size_t>(sigma_deg.size()) != n ||
      answers_alone.size() != n || (weight_sigma_deg && static_cast<std::size_t>(weight_sigma_deg->size()) != n))
    throw py::value_error("auto_choice: offsets_deg must be n × 2 and the others n long");
  std::vector<skypole::AutoCandidate> answers(n);
  std::vector<Eigen::Vector2d> offsets(n);
  for (std::size_t i = 0; i < n; ++i) {
    answers[i] = {cone95_deg.data()[i], sigma_deg.data()[i], answers_alone[i]};
    offsets[i] = {offsets_deg.data()[2 * i], offsets_deg.data()[2 * i + 1]};
  }
  const skypole::AutoChoice c = skypole::auto_choice(
      answers, [&](std::size_t a, std::size_t b) { return (offsets[a] - offsets[b]).norm(); });
  py::dict out;
  out["decided"] = c.decided;
  if (n == 0) return out;
  out["centre"] = c.centre;
  out["members"] = c.members;
  out["dissent"] = c.dissent;
  out["sharpest"] = c.sharpest;
  out["alone"] = c.alone ? py::object(py::int_(*c.alone)) : py::object(py::none());
  out["chosen"] = c.chosen;
  out["mean"] = c.mean;
  std::vector<Eigen::Vector2d> member_offsets;
  std::vector<double> member_sigmas;
  for (const std::size_t b : c.members) {
    member_offsets.push_back(offsets[b]);
    member_sigmas.push_back((weight_sigma_deg ? *weight_sigma_deg : sigma_deg).data()[b]);
  }
  const Eigen::Vector2d mean = skypole::inverse_variance_mean(member_offsets, member_sigmas);
  out["mean_offset_deg"] = py::make_tuple(mean.x(), mean.y());
  return out;
}

}  // namespace

void bind_calibration(py::module_& m) {
  m.def(
      "calibration_fields",
      [] {
        std::vector<std::string> names;
        for (const auto& f : skypole::calibration_fields()) names.emplace_back(f.first);
        return names;
      },
      "MethodCalibration's numeric fields, in order: the keys of a calibration dict");
  py::class_<CalibrationRows>(m, "CalibrationRows",
                              "The calibration study's rows (calibration.csv columns as arrays) for the calibration model")
      .def(py::init<const py::dict&>(), py::arg("columns"))
      .def("__len__", &CalibrationRows::size)
      .def("stated", &CalibrationRows::stated, py::arg("calibration"),
           py::arg("max_cone95_deg") = std::numeric_limits<double>::infinity(),
           "sigma_deg, cone95_deg and within_bound per row, as run_method states them under this calibration")
      .def("uncalibrated", &CalibrationRows::uncalibrated, "sigma_deg, cone95_deg of the uncalibrated statement")
      .def("gates", &CalibrationRows::gates, py::arg("calibration"), py::arg("cloud_gate") = true,
           "Per row, whether every gate of the calibration passes");
  m.def("wilson_interval95", &wilson, py::arg("hits"), py::arg("n"),
        "The 95 % Wilson score interval (low, high) of hits in n, elementwise (NaN where n is 0)");
  m.def("auto_choice", &choice, py::arg("offsets_deg"), py::arg("cone95_deg"), py::arg("sigma_deg"),
        py::arg("answers_alone"), py::arg("weight_sigma_deg") = py::none(),
        "auto's rule (combine_estimates) on answers given by tangent-plane offsets: centre, members, dissent, "
        "sharpest, alone, chosen, mean, and the members' inverse-variance mean offset");
  m.attr("sky_sectors") = skypole::kSkySectors;
}

}  // namespace skypol::python
