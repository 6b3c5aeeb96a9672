// Blending particles: the lecture's blend and depth figures (lecture 11, part 3) as ready states, the
// rule that decides whether a blend needs the particles sorted, and weighted blended
// order-independent transparency (McGuire & Bavoil 2013).
//
//   const raster::ParticleStates fire = raster::ParticleStates::additive();
//   ctx.setBlendState(fire.blend);
//   ctx.setDepthStencilState(fire.depthStencil);
//
//   raster::ParticleOrder order("my-scene");      // one per scene: it says "sort skipped" once
//   order.arrange(fire.blend, 1, particles, eye, ahead, indices);   // back to front, or as they are
//
// The blend states themselves are states.hpp's (BlendState::additive(), alphaBlend(), opaque()) and
// so are the depth states (DepthStencilState::readOnly(), disabled()); this header pairs them as the
// lecture's figures use them, and adds the states weighted blended OIT needs (two render targets).
#pragma once

#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <span>
#include <string>
#include <string_view>

#include "raster/particle_sort.hpp"
#include "raster/particles.hpp"
#include "raster/states.hpp"

namespace raster {

// ---- The lecture's figures as output-merger states --------------------------------------------------
// A blend state with the depth-stencil state it is drawn with, after the opaque geometry (the
// "giraffe") has been drawn with depth test and write.
struct ParticleStates {
    BlendState blend;
    DepthStencilState depthStencil;

    // Additive (SrcAlpha, One), depth test Less, no depth write: the fire. The opaque object hides
    // the particles behind it; particles never hide each other, and the order does not matter.
    static ParticleStates additive();
    // Additive with depth test and depth write ("blending with the depth test on"): a particle drawn
    // first writes its whole quad's depth, transparent corners included, so particles behind it drawn
    // later are cut out in squares. A wrong picture, for the figure.
    static ParticleStates additiveDepthWrite();
    // Additive with no depth test and no write ("even the giraffe does not occlude"): particles are
    // drawn over everything, the opaque object included.
    static ParticleStates additiveNoDepth();
    // "Over" (SrcAlpha, InvSrcAlpha: BlendState::alphaBlend()), depth test Less, no depth write. The
    // result depends on the order: correct only drawn back to front (ParticleOrder).
    static ParticleStates over();
};

// ---- When the order matters -------------------------------------------------------------------------
// True when drawing fragments into the `targets` bound render targets (1..kMaxRenderTargets) with
// `state` gives a result that does not depend on the fragments' order, in exact arithmetic. Per
// target slot, either its write mask is 0 (nothing written), or blending is on (off, the last
// fragment wins: order-dependent) and the colour equation and the alpha equation each are one of:
//   - Min or Max (the factors unused);
//   - Add or RevSubtract with destination factor One and a source factor that does not read the
//     destination (a sum: Zero, One, Src*, InvSrc*, BlendFactor, InvBlendFactor, Src1*, InvSrc1*):
//     additive blending;
//   - Add with source factor Zero and a destination factor that does not read the destination (a
//     product: the revealage target of weighted blended OIT, Zero / InvSrcAlpha).
// Anything else (over: destination factor InvSrcAlpha beside a non-zero source term; Subtract, which
// is s − d; factors that read the destination) is order-dependent. In floats a sum's last bits depend
// on its order; into an R8G8B8A8_UNORM target the additive blends add whole 1/255 steps and saturate
// (stages/9_output_merger.hpp), which is exactly order-independent.
bool blendIsOrderIndependent(const BlendState& state, int targets = 1);

// The blend equation of target slot 0 as a message shows it: "(SrcAlpha, One, Add)".
std::string blendEquationText(const BlendState& state);

// Where a ParticleOrder's message goes. Empty: standard error, as "raster: <text>\n".
using MessageSink = std::function<void(const std::string& text)>;

// The draw order of a scene's particles, frame after frame: back to front (particle_sort.hpp's
// sortBackToFront, the plain depth key) when the blend needs it, and unsorted (0, 1, 2, ...) when the
// blend is order-independent, which it then says once, the first time, through the sink:
//   "<owner>: blend (SrcAlpha, One, Add) is order-independent: the back-to-front sort is skipped"
// One message per ParticleOrder, however many frames: a scene holds one.
class ParticleOrder {
  public:
    explicit ParticleOrder(std::string owner, MessageSink sink = {});

    // Fills `order` (order.size() == particles.size()) with the indices to draw, as above, and
    // returns true when it sorted. `eye` and `ahead` as sortBackToFront's. Error(InvalidArgument) if
    // the sizes differ or `targets` is outside 1..kMaxRenderTargets.
    bool arrange(const BlendState& blend, int targets, std::span<const Particle> particles, glm::vec3 eye,
                 glm::vec3 ahead, std::span<uint32_t> order);

    uint32_t sorts() const { return sorts_; }        // calls that sorted
    uint32_t skips() const { return skips_; }        // calls that skipped the sort
    uint32_t messages() const { return messages_; }  // messages sent: 0 or 1

  private:
    std::string owner_;
    MessageSink sink_;
    SortScratch scratch_;
    uint32_t sorts_ = 0, skips_ = 0, messages_ = 0;
};

// ---- Weighted blended order-independent transparency -------------------------------------------------
// McGuire & Bavoil, "Weighted Blended Order-Independent Transparency", JCGT 2(2), 2013. The transparent
// fragments i of a pixel, premultiplied colour C_i = rgb_i·α_i, are drawn in any order into two targets:
//   target 0, accumulation (R32G32B32A32_FLOAT, cleared to 0): Σ C_i·w_i and Σ α_i·w_i  (One, One)
//   target 1, revealage (R32G32B32A32_FLOAT, cleared to 1):    Π (1 − α_i)              (Zero, InvSrcAlpha)
// and composited over the opaque image (weightedBlendedComposite):
//   result = (ΣC·w / Σα·w)·(1 − Π(1−α)) + opaque·Π(1−α).
// The total coverage 1 − Π(1−α) is exact; the colour is a weighted average in which the weight w(z, α)
// favours nearer fragments, instead of the exact back-to-front order. raster has multiple render
// targets, so both targets are written in one pass (a pixel shader returning std::array<glm::vec4, 2>).

// The accumulation pass's blend: independent blending, slot 0 (One, One, Add) for colour and alpha,
// slot 1 (Zero, InvSrcAlpha, Add) for colour and alpha. Order-independent (blendIsOrderIndependent).
BlendState weightedBlendedAccumulation();
// The composite pass's blend over the opaque image: (InvSrcAlpha, SrcAlpha, Add), for a pixel shader that
// returns (ΣC·w / max(Σα·w, 1e-5), revealage).
BlendState weightedBlendedComposite();

// The paper's depth weights (its section 4, equations 7 to 10), each multiplied by α:
//   Eq7:  w = α·clamp(10 / (1e-5 + (|z|/5)² + (|z|/200)⁶), 1e-2, 3e3)
//   Eq8:  w = α·clamp(10 / (1e-5 + (|z|/10)³ + (|z|/200)⁶), 1e-2, 3e3)
//   Eq9:  w = α·clamp(0.03 / (1e-5 + (|z|/200)⁴), 1e-2, 3e3)
//   Eq10: w = α·max(1e-2, 3e3·(1 − d)³)
// z is the view-space depth in world units (SV_Position.w under a perspective projection), d the
// window depth in [0, 1] (SV_Position.z). The paper tuned the constants for depths of 0.1 to 500 units.
enum class WeightFunction : uint8_t { Eq7, Eq8, Eq9, Eq10 };
float weightedBlendedWeight(WeightFunction function, float viewDepth, float windowDepth, float alpha);
// "eq7" .. "eq10".
std::string_view name(WeightFunction function);

}  // namespace raster
