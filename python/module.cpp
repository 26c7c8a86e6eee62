// _skypol: the C++ half of the Python package skypol (python/skypol/__init__.py is the other half
// and the documented interface; docs/python.md).
#include <pybind11/pybind11.h>

#include "python/bindings.h"
#include "python/convert.h"

PYBIND11_MODULE(_skypol, m) {
  m.doc() = "skypol's C++ bindings; use the package skypol (docs/python.md)";
  skypol::python::register_errors(m);
  skypol::python::bind_sky(m);
  skypol::python::bind_camera(m);
  skypol::python::bind_scene(m);
  skypol::python::bind_stack(m);
  skypol::python::bind_render(m);
  skypol::python::bind_skypole(m);
}
