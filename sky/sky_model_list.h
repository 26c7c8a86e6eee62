// The registered sky models, one line each, in the order messages list them
// (sky_model_registry.h). SKYPOL_SKY_MODEL(foo) names the entry function
// `SkyModelEntry foo_sky_model()`, defined in the model's own file (sky/foo_model.cpp). No include
// guard: sky_model_registry.h reads this list to declare the functions, sky_model_registry.cpp to
// call them.
SKYPOL_SKY_MODEL(rayleigh)
SKYPOL_SKY_MODEL(berry)
SKYPOL_SKY_MODEL(vrte)
