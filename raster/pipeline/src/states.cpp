#include "raster/states.hpp"

#include <cmath>
#include <string>

#include "raster/check.hpp"

namespace raster {
namespace {

// Enumerators are contiguous from 0, so "in range" is "at most the last one".
template <class Enum>
bool inRange(Enum value, Enum last) {
    return uint8_t(value) <= uint8_t(last);
}

template <class Enum>
std::string describe(Enum value) {
    return std::string(name(value)) + " (" + std::to_string(int(uint8_t(value))) + ")";
}

bool isColorFactor(Blend b) {
    return b == Blend::SrcColor || b == Blend::InvSrcColor || b == Blend::DestColor ||
           b == Blend::InvDestColor || b == Blend::Src1Color || b == Blend::InvSrc1Color;
}

void validateBlendEnum(Blend b, const std::string& field) {
    RASTER_REQUIRE(inRange(b, Blend::InvSrc1Alpha), InvalidState,
                   "blend state " + field + " = " + describe(b) + " is not a Blend value");
}

void validateBlendOpEnum(BlendOp op, const std::string& field) {
    RASTER_REQUIRE(inRange(op, BlendOp::Max), InvalidState,
                   "blend state " + field + " = " + describe(op) + " is not a BlendOp value");
}

void validateAlphaFactor(Blend b, const std::string& field) {
    validateBlendEnum(b, field);
    RASTER_REQUIRE(!isColorFactor(b), InvalidState,
                   "blend state " + field + " = " + std::string(name(b)) +
                       ": a colour factor cannot weight alpha (use the matching *Alpha factor)");
}

void validateTarget(const RenderTargetBlendDesc& d, int slot) {
    const std::string prefix = "renderTarget[" + std::to_string(slot) + "].";
    validateBlendEnum(d.srcBlend, prefix + "srcBlend");
    validateBlendEnum(d.destBlend, prefix + "destBlend");
    validateBlendOpEnum(d.blendOp, prefix + "blendOp");
    validateAlphaFactor(d.srcBlendAlpha, prefix + "srcBlendAlpha");
    validateAlphaFactor(d.destBlendAlpha, prefix + "destBlendAlpha");
    validateBlendOpEnum(d.blendOpAlpha, prefix + "blendOpAlpha");
    RASTER_REQUIRE(d.renderTargetWriteMask <= 0xF, InvalidState,
                   "blend state " + prefix + "renderTargetWriteMask = " +
                       std::to_string(int(d.renderTargetWriteMask)) + " has bits above 0xF (R, G, B, A)");
}

BlendState uniformBlend(Blend src, Blend dest) {
    BlendState s;
    for (RenderTargetBlendDesc& d : s.renderTarget) {
        d.blendEnable = true;
        d.srcBlend = d.srcBlendAlpha = src;
        d.destBlend = d.destBlendAlpha = dest;
        d.blendOp = d.blendOpAlpha = BlendOp::Add;
    }
    return s;
}

void requireFinite(float v, const char* field) {
    RASTER_REQUIRE(std::isfinite(v), InvalidState,
                   std::string("viewport ") + field + " = " + std::to_string(v) + " is not a finite number");
}

}  // namespace

BlendState BlendState::opaque() {
    return BlendState{};
}
BlendState BlendState::additive() {
    return uniformBlend(Blend::SrcAlpha, Blend::One);
}
BlendState BlendState::alphaBlend() {
    return uniformBlend(Blend::SrcAlpha, Blend::InvSrcAlpha);
}

DepthStencilState DepthStencilState::disabled() {
    DepthStencilState s;
    s.depthEnable = false;
    s.depthWriteMask = false;
    return s;
}

DepthStencilState DepthStencilState::readOnly(ComparisonFunc f) {
    DepthStencilState s;
    s.depthWriteMask = false;
    s.depthFunc = f;
    return s;
}

void validate(const BlendState& state) {
    RASTER_REQUIRE(!state.alphaToCoverageEnable, InvalidState,
                   "blend state alphaToCoverageEnable = true: alpha-to-coverage needs multisampling, "
                   "which raster does not implement");
    const int used = state.independentBlendEnable ? kMaxRenderTargets : 1;
    for (int i = 0; i < used; ++i) validateTarget(state.renderTarget[i], i);
}

void validate(const DepthStencilState& state) {
    RASTER_REQUIRE(
        inRange(state.depthFunc, ComparisonFunc::Always), InvalidState,
        "depth-stencil state depthFunc = " + describe(state.depthFunc) + " is not a ComparisonFunc value");
}

void validate(const RasterizerState& state) {
    RASTER_REQUIRE(inRange(state.fillMode, FillMode::Wireframe), InvalidState,
                   "rasterizer state fillMode = " + describe(state.fillMode) + " is not a FillMode value");
    RASTER_REQUIRE(inRange(state.cullMode, CullMode::Back), InvalidState,
                   "rasterizer state cullMode = " + describe(state.cullMode) + " is not a CullMode value");
    if (!state.scissorEnable) return;
    RASTER_REQUIRE(state.scissorRight >= state.scissorLeft, InvalidState,
                   "rasterizer state scissorRight = " + std::to_string(state.scissorRight) +
                       " is left of scissorLeft = " + std::to_string(state.scissorLeft));
    RASTER_REQUIRE(state.scissorBottom >= state.scissorTop, InvalidState,
                   "rasterizer state scissorBottom = " + std::to_string(state.scissorBottom) +
                       " is above scissorTop = " + std::to_string(state.scissorTop));
}

void validate(const Viewport& v) {
    requireFinite(v.topLeftX, "topLeftX");
    requireFinite(v.topLeftY, "topLeftY");
    requireFinite(v.width, "width");
    requireFinite(v.height, "height");
    requireFinite(v.minDepth, "minDepth");
    requireFinite(v.maxDepth, "maxDepth");
    RASTER_REQUIRE(v.width > 0, InvalidState,
                   "viewport width = " + std::to_string(v.width) + " must be greater than 0");
    RASTER_REQUIRE(v.height > 0, InvalidState,
                   "viewport height = " + std::to_string(v.height) + " must be greater than 0");
    RASTER_REQUIRE(v.topLeftX >= kViewportBoundsMin && v.topLeftX + v.width <= kViewportBoundsMax,
                   InvalidState,
                   "viewport topLeftX = " + std::to_string(v.topLeftX) +
                       ", width = " + std::to_string(v.width) + " reaches outside [-32768, 32767]");
    RASTER_REQUIRE(v.topLeftY >= kViewportBoundsMin && v.topLeftY + v.height <= kViewportBoundsMax,
                   InvalidState,
                   "viewport topLeftY = " + std::to_string(v.topLeftY) +
                       ", height = " + std::to_string(v.height) + " reaches outside [-32768, 32767]");
    RASTER_REQUIRE(v.minDepth >= 0 && v.minDepth <= 1, InvalidState,
                   "viewport minDepth = " + std::to_string(v.minDepth) + " is outside [0, 1]");
    RASTER_REQUIRE(v.maxDepth >= 0 && v.maxDepth <= 1, InvalidState,
                   "viewport maxDepth = " + std::to_string(v.maxDepth) + " is outside [0, 1]");
    RASTER_REQUIRE(v.minDepth <= v.maxDepth, InvalidState,
                   "viewport minDepth = " + std::to_string(v.minDepth) +
                       " is greater than maxDepth = " + std::to_string(v.maxDepth));
}

std::string_view name(Blend value) {
    switch (value) {
        case Blend::Zero: return "Zero";
        case Blend::One: return "One";
        case Blend::SrcColor: return "SrcColor";
        case Blend::InvSrcColor: return "InvSrcColor";
        case Blend::SrcAlpha: return "SrcAlpha";
        case Blend::InvSrcAlpha: return "InvSrcAlpha";
        case Blend::DestAlpha: return "DestAlpha";
        case Blend::InvDestAlpha: return "InvDestAlpha";
        case Blend::DestColor: return "DestColor";
        case Blend::InvDestColor: return "InvDestColor";
        case Blend::SrcAlphaSat: return "SrcAlphaSat";
        case Blend::BlendFactor: return "BlendFactor";
        case Blend::InvBlendFactor: return "InvBlendFactor";
        case Blend::Src1Color: return "Src1Color";
        case Blend::InvSrc1Color: return "InvSrc1Color";
        case Blend::Src1Alpha: return "Src1Alpha";
        case Blend::InvSrc1Alpha: return "InvSrc1Alpha";
    }
    return "(invalid)";
}

std::string_view name(BlendOp value) {
    switch (value) {
        case BlendOp::Add: return "Add";
        case BlendOp::Subtract: return "Subtract";
        case BlendOp::RevSubtract: return "RevSubtract";
        case BlendOp::Min: return "Min";
        case BlendOp::Max: return "Max";
    }
    return "(invalid)";
}

std::string_view name(ComparisonFunc value) {
    switch (value) {
        case ComparisonFunc::Never: return "Never";
        case ComparisonFunc::Less: return "Less";
        case ComparisonFunc::Equal: return "Equal";
        case ComparisonFunc::LessEqual: return "LessEqual";
        case ComparisonFunc::Greater: return "Greater";
        case ComparisonFunc::NotEqual: return "NotEqual";
        case ComparisonFunc::GreaterEqual: return "GreaterEqual";
        case ComparisonFunc::Always: return "Always";
    }
    return "(invalid)";
}

std::string_view name(FillMode value) {
    switch (value) {
        case FillMode::Solid: return "Solid";
        case FillMode::Wireframe: return "Wireframe";
    }
    return "(invalid)";
}

std::string_view name(CullMode value) {
    switch (value) {
        case CullMode::None: return "None";
        case CullMode::Front: return "Front";
        case CullMode::Back: return "Back";
    }
    return "(invalid)";
}

}  // namespace raster
