// Fixed-function state: what the lecture's code passes to CreateBlendState, CreateDepthStencilState,
// CreateRasterizerState and RSSetViewports. Names, enumerator order and defaults are Direct3D 11's
// (D3D11_BLEND_DESC and friends, minus the D3D11_ prefixes and the 1-based enum values), so a
// default-constructed state behaves like the corresponding D3D11 default state object.
//
// States are plain values. Nothing here checks a state when you build it; validate() does, with the
// rules CreateBlendState & co. apply, and the pipeline validates every state before a draw writes
// anything. The arithmetic that uses these states lives in stages/9_output_merger.hpp (blend, depth) and
// in the rasterizer (cull, fill, scissor, viewport).
#pragma once

#include <algorithm>
#include <cstdint>
#include <glm/glm.hpp>
#include <string_view>

namespace raster {

// ---- Blending -------------------------------------------------------------------------------------
// The output merger blends the pixel shader's output (the source, "s") with the render target's
// current value (the destination, "d"):
//     rgb = s.rgb * srcBlend      (blendOp)      d.rgb * destBlend
//     a   = s.a   * srcBlendAlpha (blendOpAlpha) d.a   * destBlendAlpha
// Each Blend value names a 4-component factor; the rgb equation uses its rgb, the alpha equation its a.
// "Src1" is the pixel shader's second output (SV_Target1, dual-source blending).
enum class Blend : uint8_t {
    Zero,            // (0, 0, 0, 0)
    One,             // (1, 1, 1, 1)
    SrcColor,        // (s.r, s.g, s.b, s.a)               colour factor: not allowed for alpha
    InvSrcColor,     // 1 - (s.r, s.g, s.b, s.a)           colour factor: not allowed for alpha
    SrcAlpha,        // (s.a, s.a, s.a, s.a)
    InvSrcAlpha,     // 1 - (s.a, s.a, s.a, s.a)
    DestAlpha,       // (d.a, d.a, d.a, d.a)
    InvDestAlpha,    // 1 - (d.a, d.a, d.a, d.a)
    DestColor,       // (d.r, d.g, d.b, d.a)               colour factor: not allowed for alpha
    InvDestColor,    // 1 - (d.r, d.g, d.b, d.a)           colour factor: not allowed for alpha
    SrcAlphaSat,     // (f, f, f, 1) with f = min(s.a, 1 - d.a)
    BlendFactor,     // BlendState::blendFactor
    InvBlendFactor,  // 1 - BlendState::blendFactor
    Src1Color,       // (s1.r, s1.g, s1.b, s1.a)           colour factor: not allowed for alpha
    InvSrc1Color,    // 1 - (s1.r, s1.g, s1.b, s1.a)       colour factor: not allowed for alpha
    Src1Alpha,       // (s1.a, s1.a, s1.a, s1.a)
    InvSrc1Alpha,    // 1 - (s1.a, s1.a, s1.a, s1.a)
};

// How the two weighted terms combine. Min and Max ignore the factors: min(s, d) and max(s, d).
enum class BlendOp : uint8_t {
    Add,          // s * srcFactor + d * destFactor
    Subtract,     // s * srcFactor - d * destFactor
    RevSubtract,  // d * destFactor - s * srcFactor
    Min,          // min(s, d)
    Max,          // max(s, d)
};

// One render target's blending (D3D11_RENDER_TARGET_BLEND_DESC). The defaults write the source
// unchanged. When blendEnable is false only renderTargetWriteMask matters.
struct RenderTargetBlendDesc {
    bool blendEnable = false;
    Blend srcBlend = Blend::One;
    Blend destBlend = Blend::Zero;
    BlendOp blendOp = BlendOp::Add;
    Blend srcBlendAlpha = Blend::One;
    Blend destBlendAlpha = Blend::Zero;
    BlendOp blendOpAlpha = BlendOp::Add;
    // Channels written: bit 0 R, bit 1 G, bit 2 B, bit 3 A (D3D11_COLOR_WRITE_ENABLE_*). A masked
    // channel keeps the value the render target had. At most 0xF.
    uint8_t renderTargetWriteMask = 0xF;
};

constexpr int kMaxRenderTargets = 8;  // D3D11_SIMULTANEOUS_RENDER_TARGET_COUNT

struct BlendState {
    // Needs multisampling, which raster does not implement: validate() refuses true.
    bool alphaToCoverageEnable = false;
    // false: renderTarget[0] applies to every bound render target and renderTarget[1..7] are ignored
    // (not even validated), as in D3D11.
    bool independentBlendEnable = false;
    RenderTargetBlendDesc renderTarget[kMaxRenderTargets];
    // The BlendFactor argument of OMSetBlendState, kept here for simplicity; used by Blend::BlendFactor
    // and Blend::InvBlendFactor. Clamped to [0, 1] when blending into a UNORM target.
    glm::vec4 blendFactor{1.0f, 1.0f, 1.0f, 1.0f};

    // The description that applies to render-target slot i (0 <= i < kMaxRenderTargets).
    const RenderTargetBlendDesc& target(int i) const { return renderTarget[independentBlendEnable ? i : 0]; }

    // Blending off: the source replaces the destination.
    static BlendState opaque();
    // rgb = s.rgb * s.a + d.rgb and a = s.a * s.a + d.a (SrcAlpha, One, Add for colour and alpha).
    static BlendState additive();
    // rgb = s.rgb * s.a + d.rgb * (1 - s.a) and a = s.a * s.a + d.a * (1 - s.a)
    // (SrcAlpha, InvSrcAlpha, Add for colour and alpha).
    static BlendState alphaBlend();
};

// ---- Depth ----------------------------------------------------------------------------------------
// A comparison "fragment F stored": the fragment passes when it holds. IEEE rules: a NaN on either side
// makes every comparison false except NotEqual and Always, which are true.
enum class ComparisonFunc : uint8_t {
    Never,         // false
    Less,          // fragment <  stored
    Equal,         // fragment == stored
    LessEqual,     // fragment <= stored
    Greater,       // fragment >  stored
    NotEqual,      // fragment != stored
    GreaterEqual,  // fragment >= stored
    Always,        // true
};

// D3D11_DEPTH_STENCIL_DESC without the stencil part. Depth values are in [0, 1], 0 nearest by default.
struct DepthStencilState {
    bool depthEnable = true;     // false: no depth test and no depth write
    bool depthWriteMask = true;  // true: a fragment that passes stores its depth (D3D11_DEPTH_WRITE_MASK_ALL)
    ComparisonFunc depthFunc = ComparisonFunc::Less;

    // No test, no write: every fragment passes.
    static DepthStencilState disabled();
    // Test with f but never write (e.g. transparent geometry after the opaque pass).
    static DepthStencilState readOnly(ComparisonFunc f = ComparisonFunc::Less);
};

// ---- Rasterizer -----------------------------------------------------------------------------------
enum class FillMode : uint8_t { Solid, Wireframe };
enum class CullMode : uint8_t { None, Front, Back };

// D3D11_RASTERIZER_DESC, the subset raster implements (no depth bias, no multisampling).
struct RasterizerState {
    FillMode fillMode = FillMode::Solid;
    CullMode cullMode = CullMode::Back;
    // false: a triangle whose vertices appear clockwise on screen (y down) is front-facing.
    bool frontCounterClockwise = false;
    // true: clip against 0 <= z <= w. false: the far plane is not clipped and depth is clamped to
    // the viewport's [minDepth, maxDepth]; unlike D3D11, the near plane z >= 0 is still clipped
    // (it also keeps w > 0 for the perspective divide). See docs/DESIGN.md.
    bool depthClipEnable = true;
    // Scissor rectangle in pixels, used when scissorEnable: pixels with left <= x < right and
    // top <= y < bottom survive. right == left (or bottom == top) is an empty rectangle; right < left
    // (or bottom < top) is refused by validate().
    bool scissorEnable = false;
    int scissorLeft = 0, scissorTop = 0, scissorRight = 0, scissorBottom = 0;
};

// Inclusive pixel rectangle (the clip rectangle, a primitive's box, a tile, the trace's pixels).
struct PixelRect {
    int32_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;
    bool empty() const { return x1 < x0 || y1 < y0; }
};

// The pixels in both a and b (empty() when none): a primitive's box within a tile, a tile within the
// clip rectangle. Every path that clips a box to a tile calls this one.
inline PixelRect intersect(const PixelRect& a, const PixelRect& b) {
    return {std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1)};
}

// D3D11_VIEWPORT: maps normalized device coordinates to pixels (x, y, origin top left, y down) and
// depth [0, 1] to [minDepth, maxDepth]. Everything in pixels except the two depths.
struct Viewport {
    float topLeftX = 0, topLeftY = 0, width = 0, height = 0, minDepth = 0, maxDepth = 1;
};
constexpr float kViewportBoundsMin = -32768.0f;  // D3D11_VIEWPORT_BOUNDS_MIN
constexpr float kViewportBoundsMax = 32767.0f;   // D3D11_VIEWPORT_BOUNDS_MAX

// ---- Validation and names -------------------------------------------------------------------------
// Each throws Error(InvalidState) for a state D3D11 would refuse, the message naming the field (and,
// for blending, the render-target slot):
//  - BlendState: an enum value out of range; a colour factor (SrcColor, InvSrcColor, DestColor,
//    InvDestColor, Src1Color, InvSrc1Color) as srcBlendAlpha or destBlendAlpha;
//    renderTargetWriteMask > 0xF; alphaToCoverageEnable (unsupported). Fields are checked even when
//    blendEnable is false, as CreateBlendState does.
//  - DepthStencilState: depthFunc out of range.
//  - RasterizerState: fillMode or cullMode out of range; with scissorEnable, right < left or bottom < top.
//  - Viewport: a NaN or infinite field; width or height <= 0; topLeftX/Y outside
//    [kViewportBoundsMin, kViewportBoundsMax] or topLeft + size beyond kViewportBoundsMax;
//    minDepth or maxDepth outside [0, 1]; minDepth > maxDepth.
void validate(const BlendState& state);
void validate(const DepthStencilState& state);
void validate(const RasterizerState& state);
void validate(const Viewport& viewport);

// The enumerator's C++ name ("SrcAlpha", "RevSubtract", "LessEqual"), for messages and traces;
// "(invalid)" for a value out of range.
std::string_view name(Blend value);
std::string_view name(BlendOp value);
std::string_view name(ComparisonFunc value);
std::string_view name(FillMode value);
std::string_view name(CullMode value);

}  // namespace raster
