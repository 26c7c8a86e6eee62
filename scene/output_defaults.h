// The [output] defaults the scene loader applies (docs/scenes.md), chosen by `skypol tradeoff
// compression` (docs/benchmarks.md, "Recommended defaults"): half, zip at OpenEXR's level 4. Every
// Scene comes from the loader, which sets them whether or not the scene has an [output] section.
#pragma once

namespace skypol::scene {

inline constexpr bool kDefaultHalf = true;

}  // namespace skypol::scene
