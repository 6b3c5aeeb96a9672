// The draw states a pixel shader's draws are compiled for with the state folded in.
//
// The template pipeline compiles, for each pixel shader a file draws, one tile loop per pair of
// depth and colour state it can specialise (fastpath/merge_policy.hpp: depth off or LESS /
// LESS_EQUAL with or without write, against blending off or the lecture's additive blend into one
// RGBA8 target) and the generic loops, which read the state per fragment and give the same bits.
// Each specialised loop costs seconds of -O3 compile, and a shader is usually drawn with one state.
// A pixel shader may name the pairs its draws use:
//
//   struct PsFog {
//       using SpecialisedStates = raster::SpecialisedStates<
//           raster::Specialise<raster::DepthState::Less, raster::BlendMode::Replace>>;
//       ...
//   };
//
// Its draws with those states run the specialised loops; a draw with any other state takes the
// generic loop (the same image, slower; PipelineStatistics::drawsSpecialised counts the draws that
// did not). A shader that names none is compiled for all of them (AllSpecialisedStates). Only
// the template pipeline reads this; the teaching pipeline has no specialised loops.
#pragma once

namespace raster {

// The depth states with a specialised loop: the test off, or LESS / LESS_EQUAL with depth writes
// on (opaque geometry) or off (read-only, as particles draw).
enum class DepthState { Off, Less, LessNoWrite, LessEqual, LessEqualNoWrite };
// The colour states with a specialised loop, into one R8G8B8A8_UNORM target: blending off
// (Replace), or ONE + ONE (Additive; both the colour and the alpha add).
enum class BlendMode { Replace, Additive };

// One pair of depth and colour state.
template <DepthState D, BlendMode B>
struct Specialise {
    static constexpr DepthState kDepth = D;
    static constexpr BlendMode kBlend = B;
};

// The pairs a pixel shader's draws are compiled for (Specialise<...> each).
template <class... Pairs>
struct SpecialisedStates {};

// Every pair: what a pixel shader without a SpecialisedStates member is compiled for.
using AllSpecialisedStates = SpecialisedStates<
    Specialise<DepthState::Off, BlendMode::Replace>, Specialise<DepthState::Less, BlendMode::Replace>,
    Specialise<DepthState::LessNoWrite, BlendMode::Replace>, Specialise<DepthState::LessEqual, BlendMode::Replace>,
    Specialise<DepthState::LessEqualNoWrite, BlendMode::Replace>, Specialise<DepthState::Off, BlendMode::Additive>,
    Specialise<DepthState::Less, BlendMode::Additive>, Specialise<DepthState::LessNoWrite, BlendMode::Additive>,
    Specialise<DepthState::LessEqual, BlendMode::Additive>,
    Specialise<DepthState::LessEqualNoWrite, BlendMode::Additive>>;

// PS::SpecialisedStates, or every pair.
template <class PS>
struct SpecialisedStatesOf {
    using type = AllSpecialisedStates;
};
template <class PS>
    requires requires { typename PS::SpecialisedStates; }
struct SpecialisedStatesOf<PS> {
    using type = typename PS::SpecialisedStates;
};

}  // namespace raster
