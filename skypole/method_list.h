// The registered estimators, one line each, in the order `-m all` runs them and auto weighs them
// (method_registry.h). SKYPOL_METHOD(foo) names the entry function `Method foo_method()`, defined
// in the method's own file (skypole/foo_method.cpp). No include guard: method_registry.cpp reads
// this list twice, to declare the functions and to call them.
SKYPOL_METHOD(classic)
SKYPOL_METHOD(great_circle)
SKYPOL_METHOD(invariance)
SKYPOL_METHOD(sun_vector)
SKYPOL_METHOD(sun_vector_ephemeris)
SKYPOL_METHOD(sun_dolp)
SKYPOL_METHOD(sun_azimuth)
