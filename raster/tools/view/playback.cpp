#include "playback.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace raster::tools {

void Playback::setScene(bool animated, double startTime) {
    known_ = true;
    animated_ = animated;
    start_ = time_ = animated ? startTime : 0.0;
    playing_ = playing_ && animated;
}

bool Playback::setPlaying(bool playing) {
    playing_ = playing && animated_;
    return false;
}

bool Playback::step(int frames) {
    if (!animated_ || frames == 0) return false;
    playing_ = false;
    const double before = time_;
    time_ = std::clamp(time_ + frames * kFrameStep, 0.0, kMaxStartTime);
    return time_ != before;
}

bool Playback::restart() {
    if (!animated_ || time_ == start_) return false;
    time_ = start_;
    return true;
}

bool Playback::tick(double realSeconds) {
    if (!animated_ || !playing_ || !(realSeconds > 0)) return false;
    const double before = time_;
    time_ = std::min(time_ + std::min(realSeconds, kMaxPlayStep) * speed_, kMaxStartTime);
    if (time_ == kMaxStartTime) playing_ = false;
    return time_ != before;
}

void Playback::setSpeed(double speed) {
    speed_ = std::clamp(speed, kMinSpeed, kMaxSpeed);
}

std::string Playback::label() const {
    if (!animated_) return {};
    char text[64];
    // Speeds are powers of two: ×1/16 … ×16 written as such.
    char speed[16];
    if (speed_ >= 1)
        std::snprintf(speed, sizeof speed, "x%g", speed_);
    else
        std::snprintf(speed, sizeof speed, "x1/%g", 1 / speed_);
    std::snprintf(text, sizeof text, "t %.3f s  %s %s", time_, playing_ ? "playing" : "paused", speed);
    return text;
}

}  // namespace raster::tools
