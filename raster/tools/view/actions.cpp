#include "actions.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <utility>

#include "raster/check.hpp"

namespace raster::tools {
namespace {

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

struct Binding {
    const char* name;  // lower case
    Action action;
};

// W, A and E fly plainly; S, D and Q already mean screenshot, depth and quit, so all six fly with
// Shift (or, in the window, with the right mouse button held — as in most editors' viewports).
const Binding kBindings[] = {
    {"n", {Verb::NextDraw}},
    {"p", {Verb::PreviousDraw}},
    {"]", {Verb::NextPrimitive}},
    {"[", {Verb::PreviousPrimitive}},
    {"0", {Verb::WholeFrame}},
    {"d", {Verb::ToggleDepth}},
    {"o", {Verb::ToggleOverdraw}},
    {"x", {Verb::ToggleNonFinite}},
    {"k", {Verb::ToggleSolution}},
    {"j", {Verb::ToggleDifference}},
    {"l", {Verb::ToggleWireframe}},
    {"g", {Verb::ToggleGsOutput}},
    {"v", {Verb::NextStage}},
    {"c", {Verb::ClosePixel}},
    {"s", {Verb::Screenshot}},
    {"f12", {Verb::Screenshot}},
    {"h", {Verb::ToggleHelp}},
    {"f1", {Verb::ToggleHelp}},
    {"i", {Verb::ToggleStatistics}},
    {"r", {Verb::ResetCamera}},
    {"space", {Verb::TogglePlay}},
    {".", {Verb::StepFrame, 1}},
    {",", {Verb::StepFrame, -1}},
    {"home", {Verb::RestartTime}},
    {"+", {Verb::Faster}},
    {"=", {Verb::Faster}},
    {"-", {Verb::Slower}},
    {"esc", {Verb::Quit}},
    {"escape", {Verb::Quit}},
    {"q", {Verb::Quit}},
    {"w", {Verb::Fly, 1, 0, 0}},
    {"a", {Verb::Fly, 0, -1, 0}},
    {"e", {Verb::Fly, 0, 0, 1}},
    {"shift+w", {Verb::Fly, 1, 0, 0}},
    {"shift+s", {Verb::Fly, -1, 0, 0}},
    {"shift+a", {Verb::Fly, 0, -1, 0}},
    {"shift+d", {Verb::Fly, 0, 1, 0}},
    {"shift+e", {Verb::Fly, 0, 0, 1}},
    {"shift+q", {Verb::Fly, 0, 0, -1}},
    {"up", {Verb::Fly, 1, 0, 0}},
    {"down", {Verb::Fly, -1, 0, 0}},
    {"left", {Verb::Fly, 0, -1, 0}},
    {"right", {Verb::Fly, 0, 1, 0}},
    {"pageup", {Verb::Fly, 0, 0, 1}},
    {"pagedown", {Verb::Fly, 0, 0, -1}},
};

// "a,b,c" → integers; false unless it is exactly `count` whole numbers split by `separator`.
bool parseInts(std::string_view text, char separator, int count, int* out) {
    for (int i = 0; i < count; ++i) {
        const size_t end = std::min(text.find(separator), text.size());
        const std::string_view part = text.substr(0, end);
        const auto [p, ec] = std::from_chars(part.data(), part.data() + part.size(), out[i]);
        if (part.empty() || ec != std::errc() || p != part.data() + part.size()) return false;
        const bool last = i + 1 == count;
        if (last != (end == text.size())) return false;  // too few or too many parts
        text.remove_prefix(last ? end : end + 1);
    }
    return true;
}

Action parseToken(std::string_view token) {
    const std::string t = lower(token);
    const auto argument = [&](std::string_view prefix) { return std::string_view(t).substr(prefix.size()); };
    const auto bad = [&](const char* form) {
        return Error(ErrorCode::InvalidArgument,
                     "script token '" + std::string(token) + "' is not of the form " + form);
    };
    int v[4] = {};
    if (t == "wait") return {Verb::Wait};
    if (t.starts_with("click:")) {
        if (!parseInts(argument("click:"), ',', 2, v) || v[0] < 0 || v[1] < 0)
            throw bad("click:X,Y (X, Y >= 0)");
        return {Verb::Click, v[0], v[1]};
    }
    if (t.starts_with("drag:")) {
        if (!parseInts(argument("drag:"), ',', 4, v)) throw bad("drag:X0,Y0,X1,Y1");
        return {Verb::Orbit, v[2] - v[0], v[3] - v[1]};
    }
    if (t.starts_with("wheel:")) {
        if (!parseInts(argument("wheel:"), ',', 1, v)) throw bad("wheel:N (notches, negative zooms out)");
        return {Verb::Zoom, v[0]};
    }
    if (t.starts_with("resize:")) {
        if (!parseInts(argument("resize:"), 'x', 2, v) || v[0] < 1 || v[1] < 1 || v[0] > 16384 ||
            v[1] > 16384)
            throw bad("resize:WxH (1..16384 each)");
        return {Verb::Resize, v[0], v[1]};
    }
    return actionForKey(token);
}

}  // namespace

std::optional<Action> findKey(std::string_view name) {
    const std::string n = lower(name);
    for (const Binding& b : kBindings)
        if (n == b.name) return b.action;
    return std::nullopt;
}

Action actionForKey(std::string_view name) {
    if (const std::optional<Action> action = findKey(name)) return *action;
    throw Error(ErrorCode::InvalidArgument,
                "unknown key '" + std::string(name) + "' (press H in the viewer, or see raster view --help)");
}

std::vector<Action> parseScript(std::string_view script) {
    std::vector<Action> actions;
    size_t i = 0;
    while (i < script.size()) {
        if (std::isspace(static_cast<unsigned char>(script[i]))) {
            ++i;
            continue;
        }
        size_t end = i;
        while (end < script.size() && !std::isspace(static_cast<unsigned char>(script[end]))) ++end;
        actions.push_back(parseToken(script.substr(i, end - i)));
        i = end;
    }
    return actions;
}

const std::vector<std::string>& keyHelp() {
    static const std::vector<std::string> help = {
        "N / P        next / previous draw (replays the frame up to it)",
        "] / [        next / previous primitive within the draw",
        "0            whole frame",
        "D            depth view (near dark, far light, cleared white)",
        "O            overdraw heat map: fragments per pixel, black 0 .. white the max",
        "X            NaN/Inf view: non-finite shader outputs magenta over the dimmed image",
        "K            the solution's image (--solution reference|<scene>|<file.png>)",
        "J            difference from the solution: black equal, grey 1/255 .. red the largest",
        "L            wireframe of the current primitive (step with ] and [)",
        "G            geometry shader output: wireframe of the current draw's strips",
        "V            stage: VS output points, GS output, set-up primitives, final",
        "S or F12     screenshot of the image shown, without the text (path printed)",
        "I            pipeline statistics of the shown frame",
        "H or F1      this help",
        "drag         orbit about the target",
        "wheel        zoom",
        "W A E        fly forward, left, up",
        "Shift or right button + W A S D Q E: fly (S back, D right, Q down)",
        "arrows, PageUp/PageDown   fly",
        "R            reset the camera",
        "Space        play / pause an animated scene (fire, ...); the HUD shows its time",
        ". / ,        one frame (1/60 s) forward / back, paused",
        "+ / -        twice / half the speed (1/16 to 16 times real time)",
        "Home         time back to the start",
        "click        the pixel's colour, depth and history (every fragment, printed)",
        "C            close the pixel history",
        "Esc or Q     quit",
    };
    return help;
}

}  // namespace raster::tools
