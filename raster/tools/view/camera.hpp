// The viewer's camera moves: orbit about the target (mouse drag), zoom towards it (wheel), fly the
// eye and the target together (keys). Each works on a SceneCamera's eye and target directly, so a
// camera nobody moved is the scene's own, bit for bit.
#pragma once

#include "raster/scenes.hpp"

namespace raster::tools {

// Turns the eye about the target: dx pixels of drag about the world's up axis, dy about the
// camera's right axis, kept short of looking straight up or down (where look-at has no up).
SceneCamera orbit(const SceneCamera& camera, float dx, float dy);
// Moves the eye towards the target by 10% of their distance a notch (negative notches: away).
SceneCamera zoom(const SceneCamera& camera, int notches);
// Moves eye and target by 5% of their distance a step: forward along the view, right, and up (world y).
SceneCamera fly(const SceneCamera& camera, int forward, int right, int up);

}  // namespace raster::tools
