// The viewer's clock for animated scenes (Scene::animated, raster/scenes.hpp): which scene time the
// next frame shows, played in real time at a speed, paused, or stepped a frame at a time.
//
// Times are the scene's clock, in seconds. A frame shown at time t is the scene started at
// SceneOptions::time = t, bit for bit (the clock's rule: a frame is a function of its options and
// the sum of the advances), so stepping forward and back lands on the frames `raster render
// --frames N --fps 60` writes. Playing advances by the real time elapsed since the last tick times
// the speed, at most kMaxPlayStep per tick: a frame that renders slowly shows the animation slower
// rather than jumping ahead (and simulating many steps at once). The clock stops at kMaxStartTime,
// the latest time a scene can be started at (so that stepping back from it can rebuild the scene).
#pragma once

#include <string>

#include "raster/scenes.hpp"

namespace raster::tools {

// One single step (the "." and "," keys): a frame at 60 frames per second, the fire's simulation step.
constexpr double kFrameStep = 1.0 / 60.0;
// Seconds of real time one tick of play may advance by, at most (before the speed).
constexpr double kMaxPlayStep = 0.1;
// The speeds "+" and "-" step through: powers of two from 1/16 to 16 times real time.
constexpr double kMinSpeed = 1.0 / 16.0, kMaxSpeed = 16.0;

class Playback {
  public:
    // Whether the scene moves at all, and its clock when its first frame was rendered (the start of
    // "home"). Until known(), the keys change nothing and time() is meaningless.
    void setScene(bool animated, double startTime);
    bool known() const { return known_; }
    bool animated() const { return animated_; }

    double time() const { return time_; }
    bool playing() const { return playing_; }
    double speed() const { return speed_; }

    // Each returns whether time() changed (so the viewer renders it). On a static scene, all do nothing.
    bool setPlaying(bool playing);  // pausing never moves the clock
    bool step(int frames);          // ± frames of kFrameStep, pausing; within [0, kMaxStartTime]
    bool restart();                 // back to the start time
    void faster() { setSpeed(speed_ * 2); }
    void slower() { setSpeed(speed_ / 2); }
    // While playing: moves the clock by min(realSeconds, kMaxPlayStep) × speed() (realSeconds ≥ 0);
    // pauses at kMaxStartTime.
    bool tick(double realSeconds);

    // The HUD's words: "t 3.250 s  playing ×1", "t 3.000 s  paused ×0.5"; empty for a static scene.
    std::string label() const;

  private:
    void setSpeed(double speed);

    bool known_ = false, animated_ = false, playing_ = false;
    double start_ = 0, time_ = 0, speed_ = 1;
};

}  // namespace raster::tools
