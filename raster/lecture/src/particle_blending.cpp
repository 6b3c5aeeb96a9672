#include "raster/particle_blending.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "raster/check.hpp"

namespace raster {

ParticleStates ParticleStates::additive() {
    return {BlendState::additive(), DepthStencilState::readOnly(ComparisonFunc::Less)};
}
ParticleStates ParticleStates::additiveDepthWrite() {
    return {BlendState::additive(), DepthStencilState{true, true, ComparisonFunc::Less}};
}
ParticleStates ParticleStates::additiveNoDepth() {
    return {BlendState::additive(), DepthStencilState::disabled()};
}
ParticleStates ParticleStates::over() {
    return {BlendState::alphaBlend(), DepthStencilState::readOnly(ComparisonFunc::Less)};
}

namespace {

// A factor whose value depends on the render target's current contents.
bool readsDestination(Blend b) {
    return b == Blend::DestAlpha || b == Blend::InvDestAlpha || b == Blend::DestColor ||
           b == Blend::InvDestColor || b == Blend::SrcAlphaSat;
}

// One equation (colour or alpha) of a target: does its result over many fragments not depend on order?
bool equationOrderIndependent(BlendOp op, Blend src, Blend dest) {
    if (op == BlendOp::Min || op == BlendOp::Max) return true;
    // d·1 + s·f (or d·1 − s·f): a sum of terms that do not read d.
    if ((op == BlendOp::Add || op == BlendOp::RevSubtract) && dest == Blend::One)
        return !readsDestination(src);
    // s·0 + d·f: a product of factors that do not read d.
    if (op == BlendOp::Add && src == Blend::Zero) return !readsDestination(dest);
    return false;
}

}  // namespace

bool blendIsOrderIndependent(const BlendState& state, int targets) {
    RASTER_REQUIRE(targets >= 1 && targets <= kMaxRenderTargets, InvalidArgument,
                   "blendIsOrderIndependent: " + std::to_string(targets) + " render targets, not 1.." +
                       std::to_string(kMaxRenderTargets));
    for (int i = 0; i < targets; ++i) {
        const RenderTargetBlendDesc& d = state.target(i);
        if (d.renderTargetWriteMask == 0) continue;
        if (!d.blendEnable) return false;
        const bool rgb_written = (d.renderTargetWriteMask & 0x7) != 0,
                   alpha_written = (d.renderTargetWriteMask & 0x8) != 0;
        if (rgb_written && !equationOrderIndependent(d.blendOp, d.srcBlend, d.destBlend)) return false;
        if (alpha_written && !equationOrderIndependent(d.blendOpAlpha, d.srcBlendAlpha, d.destBlendAlpha))
            return false;
    }
    return true;
}

std::string blendEquationText(const BlendState& state) {
    const RenderTargetBlendDesc& d = state.target(0);
    if (!d.blendEnable) return "(blending off)";
    // Appended piece by piece: "(" + std::string(...) trips GCC 12's false -Wrestrict (bug 105329).
    std::string text = "(";
    text.append(name(d.srcBlend)).append(", ").append(name(d.destBlend)).append(", ").append(name(d.blendOp));
    return text.append(")");
}

ParticleOrder::ParticleOrder(std::string owner, MessageSink sink)
    : owner_(std::move(owner)), sink_(std::move(sink)) {}

bool ParticleOrder::arrange(const BlendState& blend, int targets, std::span<const Particle> particles,
                            glm::vec3 eye, glm::vec3 ahead, std::span<uint32_t> order) {
    RASTER_REQUIRE(order.size() == particles.size(), InvalidArgument,
                   owner_ + ": the order holds " + std::to_string(order.size()) + " indices for " +
                       std::to_string(particles.size()) + " particles");
    if (!blendIsOrderIndependent(blend, targets)) {
        sortBackToFront(particles, eye, ahead, order, SortMethod::Automatic, &scratch_);
        ++sorts_;
        return true;
    }
    std::iota(order.begin(), order.end(), 0u);
    ++skips_;
    if (messages_ == 0) {
        ++messages_;
        const std::string text = owner_ + ": blend " + blendEquationText(blend) +
                                 " is order-independent: the back-to-front sort is skipped";
        if (sink_)
            sink_(text);
        else
            std::fprintf(stderr, "raster: %s\n", text.c_str());
    }
    return false;
}

BlendState weightedBlendedAccumulation() {
    BlendState s;
    s.independentBlendEnable = true;
    RenderTargetBlendDesc& accumulation = s.renderTarget[0];
    accumulation.blendEnable = true;
    accumulation.srcBlend = accumulation.destBlend = Blend::One;
    accumulation.srcBlendAlpha = accumulation.destBlendAlpha = Blend::One;
    RenderTargetBlendDesc& revealage = s.renderTarget[1];
    revealage.blendEnable = true;
    revealage.srcBlend = revealage.srcBlendAlpha = Blend::Zero;
    revealage.destBlend = revealage.destBlendAlpha = Blend::InvSrcAlpha;
    return s;
}

BlendState weightedBlendedComposite() {
    BlendState s;
    for (RenderTargetBlendDesc& d : s.renderTarget) {
        d.blendEnable = true;
        d.srcBlend = d.srcBlendAlpha = Blend::InvSrcAlpha;
        d.destBlend = d.destBlendAlpha = Blend::SrcAlpha;
    }
    return s;
}

float weightedBlendedWeight(WeightFunction function, float viewDepth, float windowDepth, float alpha) {
    const float z = std::fabs(viewDepth);
    float w = 0.0f;
    switch (function) {
        case WeightFunction::Eq7:
            w = 10.0f / (1e-5f + std::pow(z / 5.0f, 2.0f) + std::pow(z / 200.0f, 6.0f));
            break;
        case WeightFunction::Eq8:
            w = 10.0f / (1e-5f + std::pow(z / 10.0f, 3.0f) + std::pow(z / 200.0f, 6.0f));
            break;
        case WeightFunction::Eq9:
            w = 0.03f / (1e-5f + std::pow(z / 200.0f, 4.0f));
            break;
        case WeightFunction::Eq10:
            return alpha * std::max(1e-2f, 3e3f * std::pow(1.0f - windowDepth, 3.0f));
    }
    return alpha * std::clamp(w, 1e-2f, 3e3f);
}

std::string_view name(WeightFunction function) {
    switch (function) {
        case WeightFunction::Eq7:
            return "eq7";
        case WeightFunction::Eq8:
            return "eq8";
        case WeightFunction::Eq9:
            return "eq9";
        case WeightFunction::Eq10:
            return "eq10";
    }
    return "(invalid)";
}

}  // namespace raster
