// A pixel shader wrapped so that it offers float and Float8 only: the pipeline must then shade one
// 4×2 block per call, and the tests compare that path with the two-block (Float8x2) one.
#pragma once

#include <glm/glm.hpp>

#include "raster/shader.hpp"

namespace raster {

template <class PS>
struct EightOnly {
    using Input = typename PS::Input;
    PS inner;
    glm::vec4 operator()(const Input& in) const { return inner(in); }
    glm::vec<4, Float8> operator()(const Wide<Input>& in) const { return inner(in); }
    // What the inner shader declares of its alpha (shader.hpp), so that both paths skip alike.
    AlphaSource alphaSource() const
        requires AlphaSourcePixelShader<PS>
    {
        return inner.alphaSource();
    }
};

}  // namespace raster
