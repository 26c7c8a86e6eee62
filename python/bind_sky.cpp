// The sun's position for arrays of times (sky/sun.h), and ISO 8601 times as sky/time.h reads them.
#include <numbers>
#include <optional>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "python/convert.h"
#include "python/sun_table.h"
#include "sky/sun.h"
#include "sky/time.h"
#include "sky/units.h"

namespace skypol::python {

py::dict sun_table(const sky::Site& site, const sky::SunOptions& options, const Seconds& unix_seconds) {
  const py::ssize_t n = unix_seconds.size();
  py::array_t<double> az(n), el(n), dec(n), ha(n), dir({n, py::ssize_t{3}});
  auto t = unix_seconds.unchecked<1>();
  auto a = az.mutable_unchecked<1>(), e = el.mutable_unchecked<1>(), d = dec.mutable_unchecked<1>(),
       h = ha.mutable_unchecked<1>();
  auto v = dir.mutable_unchecked<2>();
  {
    py::gil_scoped_release release;
    for (py::ssize_t i = 0; i < n; ++i) {
      const sky::Sun s = sky::sun_position(site, instant_of(t(i)), options);
      a(i) = s.azimuth * kDegPerRad;
      e(i) = s.elevation * kDegPerRad;
      d(i) = s.declination * kDegPerRad;
      h(i) = s.hour_angle * kDegPerRad;
      for (py::ssize_t k = 0; k < 3; ++k) v(i, k) = s.direction(k);
    }
  }
  py::dict out;
  out["azimuth_deg"] = az;
  out["elevation_deg"] = el;
  out["declination_deg"] = dec;
  out["hour_angle_deg"] = ha;
  out["direction"] = dir;
  return out;
}

py::dict sun_options_to_dict(const sky::SunOptions& o) {
  py::dict d;
  d["pressure_hpa"] = o.pressure_hpa;
  d["temperature_c"] = o.temperature_c;
  d["relative_humidity"] = o.relative_humidity;
  d["wavelength_um"] = o.wavelength_um;
  d["ut1_minus_utc_s"] = o.ut1_minus_utc_s;
  d["refraction"] = std::string(sky::refraction_name(o.refraction));
  d["delta_t_s"] = o.delta_t_s ? py::object(py::float_(*o.delta_t_s)) : py::object(py::none());
  return d;
}

void bind_sky(py::module_& m) {
  m.def("parse_time", [](const std::string& text) { return sky::parse_iso8601(text).unix_seconds; }, py::arg("text"),
        "ISO 8601 instant with a zone → Unix seconds (the rules of scene files and `skypol sun -t`)");
  m.def("format_time", [](double unix_seconds) { return sky::format_iso8601(instant_of(unix_seconds)); },
        py::arg("unix_seconds"), "Unix seconds → ISO 8601 UTC text, as in stack headers");
  m.def(
      "sun_positions",
      [](double latitude_deg, double longitude_deg, double height_m, const Seconds& t,
         double pressure_hpa, double temperature_c, double relative_humidity, double wavelength_um, double ut1_minus_utc_s,
         const std::string& refraction, std::optional<double> delta_t_s) {
        sky::SunOptions o;
        o.pressure_hpa = pressure_hpa;
        o.temperature_c = temperature_c;
        o.relative_humidity = relative_humidity;
        o.wavelength_um = wavelength_um;
        o.ut1_minus_utc_s = ut1_minus_utc_s;
        o.refraction = sky::parse_refraction(refraction);
        o.delta_t_s = delta_t_s;
        return sun_table(sky::Site{latitude_deg, longitude_deg, height_m}, o, t);
      },
      py::arg("latitude_deg"), py::arg("longitude_deg"), py::arg("height_m"), py::arg("unix_seconds"),
      py::arg("pressure_hpa"), py::arg("temperature_c"), py::arg("relative_humidity"), py::arg("wavelength_um"),
      py::arg("ut1_minus_utc_s"), py::arg("refraction"), py::arg("delta_t_s"),
      "The sun for a 1-D array of Unix seconds: dict of arrays (degrees; direction is ENU, N×3)");
}

}  // namespace skypol::python
