// How much of a frame the viewer shows: the whole frame, or its first k draws with the last of them
// cut after m input primitives, as the Context::StepLimit to replay the frame under. Stepping needs
// the frame's shape (draws and primitives per draw), which a whole-frame render tells.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "raster/pipeline.hpp"

namespace raster::tools {

class StepCursor {
  public:
    // Primitives per draw, in draw order (drawStatisticsLog's iaPrimitives of an unlimited frame).
    void setShape(std::vector<uint64_t> primitivesPerDraw);
    bool hasShape() const { return has_shape_; }
    uint32_t drawCount() const { return uint32_t(shape_.size()); }

    // The keys. From the whole frame, forward steps start at the beginning of the frame (N shows
    // draw 1, ] its first primitive) and backward steps from its end. N finishes the current draw
    // or moves to the end of the next one; P moves to the end of the previous draw (draw 0: only the
    // clear); ] adds one primitive, crossing into the next draw; [ is ]'s exact inverse.
    void nextDraw();
    void previousDraw();
    void nextPrimitive();
    void previousPrimitive();
    void showAll() { whole_ = true; }

    bool whole() const { return whole_; }
    uint32_t draws() const { return draws_; }            // draws started (not meaningful when whole())
    uint64_t primitives() const { return primitives_; }  // of the last started draw
    bool partial() const;                                // the last started draw is cut short

    Context::StepLimit limit() const;
    // "whole frame, 2 draws", "draw 2 of 2, primitive 17 of 10000", "draw 1 of 2, complete", ...
    std::string label() const;

  private:
    uint64_t primitivesOf(uint32_t draw) const { return shape_[draw - 1]; }  // draw numbered from 1
    void leaveWhole(bool atEnd);

    std::vector<uint64_t> shape_;
    bool has_shape_ = false;
    bool whole_ = true;
    uint32_t draws_ = 0;
    uint64_t primitives_ = 0;  // == primitivesOf(draws_) when that draw is complete
};

}  // namespace raster::tools
