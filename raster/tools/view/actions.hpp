// What the viewer can be asked to do, from a key, the mouse or a script token. Keys and scripts
// share one vocabulary, so a script is exactly a user at the keyboard (see keyNames()).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace raster::tools {

enum class Verb {
    NextDraw,           // N
    PreviousDraw,       // P
    NextPrimitive,      // ]
    PreviousPrimitive,  // [
    WholeFrame,         // 0
    ToggleDepth,        // D
    ToggleOverdraw,     // O: overdraw heat map
    ToggleNonFinite,    // X: NaN/Inf shader outputs over the dimmed image
    ToggleSolution,     // K: the solution's image (--solution)
    ToggleDifference,   // J: the difference between the frame and the solution
    ToggleWireframe,    // L: wireframe of the current primitive
    ToggleGsOutput,     // G: the geometry shader's output of the current draw
    NextStage,          // V: VS points → GS output → set-up primitives → final image
    ClosePixel,         // C: close the pixel history (stop tracing the pixel)
    Screenshot,         // S, F12
    ToggleHelp,         // H, F1
    ToggleStatistics,   // I
    ResetCamera,        // R
    Fly,                // W A E, Shift+W/A/S/D/Q/E, arrows, PageUp/PageDown: dx/dy/dz below
    Orbit,              // mouse drag; script drag:X0,Y0,X1,Y1
    Zoom,               // wheel; script wheel:N
    Click,              // a click without a drag; script click:X,Y
    Resize,             // script resize:WxH (a user drags the window's border)
    TogglePlay,         // Space: play or pause an animated scene's clock (playback.hpp)
    StepFrame,          // . and ,: x frames of 1/60 s forward (1) or back (-1), paused
    RestartTime,        // Home: the clock back to its start
    Faster,             // + (=): twice the speed
    Slower,             // -: half the speed
    Wait,               // script wait: until the latest render is shown
    Quit,               // Esc, Q
};

struct Action {
    Verb verb;
    int x = 0, y = 0, z = 0;  // Fly: forward, right, up steps; Orbit: dx, dy; Zoom: x notches;
                              // Click: window pixel (prints its colour and history); Resize: width, height
};

// One key name (case-insensitive: "n", "]", "F12", "Esc", "Shift+S", "PageUp") → its action, or
// nothing for a key that means nothing.
std::optional<Action> findKey(std::string_view name);
// One key name (case-insensitive: "n", "]", "F12", "Esc", "Shift+S", "PageUp") → its action.
// Throws Error(InvalidArgument) naming the key for a key that means nothing.
Action actionForKey(std::string_view name);
// Space-separated tokens: key names, click:X,Y, drag:X0,Y0,X1,Y1, wheel:N, resize:WxH, wait.
// Throws Error(InvalidArgument) naming the first token that is not one.
std::vector<Action> parseScript(std::string_view script);
// The help text: every key and what it does, one per line.
const std::vector<std::string>& keyHelp();

}  // namespace raster::tools
