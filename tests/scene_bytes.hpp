// A library scene rendered once into RGBA8 bytes, for the suites that compare whole images: across
// thread counts (bit-identical at any count), against another scene, or against a changed option.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "raster/pipeline.hpp"
#include "raster/scenes.hpp"

namespace raster {

// The scene `name` at `options` (its width × height), drawn by a context of `threads` workers into a
// fresh RGBA8 target and depth buffer; the target's bytes, row by row, 4 per pixel.
inline std::vector<uint8_t> renderSceneBytes(const std::string& name, const SceneOptions& options,
                                             uint32_t threads) {
    const auto scene = makeScene(name, options);
    Context context({threads});
    RenderTarget color(options.width, options.height);
    DepthTarget depth(options.width, options.height);
    scene->render(context, color, depth);
    return {color.rgba8(), color.rgba8() + size_t(options.width) * options.height * 4};
}

}  // namespace raster
