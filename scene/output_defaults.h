// The default pixel type of every stack skypol writes (docs/scenes.md, [output]), chosen by
// `skypol tradeoff compression` (docs/benchmarks.md, "Recommended defaults"): half, zip at
// OpenEXR's level 4. scene::OutputSpec and stack::WriteOptions both start from it.
#pragma once

namespace skypol::scene {

inline constexpr bool kDefaultHalf = true;

}  // namespace skypol::scene
