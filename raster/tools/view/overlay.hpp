// Text over the window (never into the framebuffer, so screenshots stay the rendered image):
// lines of stb_easy_font's vector font on a translucent panel, drawn with the SDL renderer.
#pragma once

#include <SDL.h>

#include <string>
#include <vector>

namespace raster::tools {

// Lines may hold tab-separated cells, which are aligned in columns.
struct TextPanel {
    int x = 0, y = 0;  // top-left corner in window pixels; negative x: from the right edge
    std::vector<std::string> lines;
    SDL_Color color{255, 255, 255, 255};
};

// Font pixels (times the scale in window pixels) of a panel's padding and of a line.
constexpr int kPanelPadding = 4;
constexpr int kPanelLineHeight = 12;

// The panel's left edge in window pixels (panel.x counts from the right edge when negative).
int panelLeft(SDL_Renderer* renderer, const TextPanel& panel, int scale);
// The panel's size in window pixels at `scale` (font pixels per window pixel).
SDL_Point panelSize(const TextPanel& panel, int scale);
void drawPanel(SDL_Renderer* renderer, const TextPanel& panel, int scale);

}  // namespace raster::tools
