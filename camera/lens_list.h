// The registered lens models, one line each, in the order help and messages list them
// (lens_registry.h). SKYPOL_LENS(foo) names the entry function `LensModel foo_lens_model()`,
// defined in the model's own .cpp. No include guard: lens_registry.h reads this list to declare
// the functions, lens_factory.cpp to call them.
SKYPOL_LENS(perspective)
SKYPOL_LENS(stereographic)
SKYPOL_LENS(equidistant)
SKYPOL_LENS(equisolid)
SKYPOL_LENS(orthographic)
SKYPOL_LENS(kannala_brandt)
SKYPOL_LENS(double_sphere)
SKYPOL_LENS(ocam)
SKYPOL_LENS(tabulated)
SKYPOL_LENS(thin_prism_fisheye)
SKYPOL_LENS(mei)
SKYPOL_LENS(eucm)
