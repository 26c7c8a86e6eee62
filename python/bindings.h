// The bindings of _skypol, one function per room they expose (python/bind_<room>.cpp), called in
// this order by module.cpp: later rooms use the types the earlier ones registered.
#pragma once

#include <pybind11/pybind11.h>

namespace skypol::python {

void bind_sky(pybind11::module_& m);      // sun positions, ISO 8601 times
void bind_camera(pybind11::module_& m);   // Camera: pixel → direction, direction → pixel
void bind_scene(pybind11::module_& m);    // Scene: load, parse, overrides, truth
void bind_stack(pybind11::module_& m);    // Stack in memory: views, read, write, from arrays
void bind_render(pybind11::module_& m);   // render a scene's frames into a Stack
void bind_skypole(pybind11::module_& m);  // estimators and scores

}  // namespace skypol::python
