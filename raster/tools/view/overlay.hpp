// Text over the window (never into the framebuffer, so screenshots stay the rendered image):
// lines of stb_easy_font's vector font on a translucent panel, drawn with the SDL renderer.
//
// A panel is laid out for the window before it is drawn (fitPanel): lines too wide for the window
// are wrapped at spaces, and a panel too tall for it shows the lines that fit and how many more
// there are, so that no text is cut at the window's edge.
#pragma once

#include <SDL.h>

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace raster::tools {

// Lines may hold tab-separated cells, which are aligned in columns; a line's last cell spans the
// rest of the panel (it sets no column's width).
struct TextPanel {
    int x = 0, y = 0;  // top-left corner in window pixels; negative x: from the right edge
    std::vector<std::string> lines;
    SDL_Color color{255, 255, 255, 255};
};

// Font pixels (times the scale in window pixels) of a panel's padding and of a line.
constexpr int kPanelPadding = 4;
constexpr int kPanelLineHeight = 12;
// Window pixels the viewer keeps between its panels and the window's edges.
constexpr int kPanelMargin = 4;
// What a wrapped line's continuation starts with, so that it reads as one.
constexpr std::string_view kContinuationIndent = "  ";

// The text's scale in a window `windowWidth` pixels wide: window pixels per font pixel, 2 from
// 900 pixels up.
int overlayScale(int windowWidth);

// The width of one line of text in font pixels. The font is proportional (a space is 6, an 'i'
// 3, an 'm' 7 font pixels wide) and widths add up: width(a + b) = width(a) + width(b). Bytes
// the font lacks (control characters, non-ASCII) are drawn as '?' and measured as such.
int textWidth(std::string_view text);

using TextMeasure = std::function<int(std::string_view)>;

// `text` as lines no wider than `maxWidth` as `width` measures them (greedy: each line takes as
// many words as fit). Text that fits is one line, unchanged. Lines break at runs of spaces, which
// the break drops; the text's leading spaces and the spaces between words on a line stay. A word
// wider than a line is broken between characters, so nothing is lost; a line holds at least one
// character however narrow. Lines after the first start with `indent`, counted in their width.
// Empty text is one empty line.
std::vector<std::string> wrapText(std::string_view text, int maxWidth, const TextMeasure& width,
                                  std::string_view indent = {});

// The panel laid out to be at most maxWidth × maxHeight window pixels at `scale`: lines split at
// '\n'; a line without tabs wrapped with kContinuationIndent; a tabbed line's last cell wrapped in
// its column, continued on lines of empty leading cells (a line whose leading cells leave its last
// less than a quarter of the room is made one line of text first). Lines beyond the height are
// replaced by a last line "... N more lines" followed by `moreHint`.
TextPanel fitPanel(TextPanel panel, int maxWidth, int maxHeight, int scale, std::string_view moreHint = {});

// The panel's left edge in window pixels (panel.x counts from the right edge when negative).
int panelLeft(SDL_Renderer* renderer, const TextPanel& panel, int scale);
// The panel's size in window pixels at `scale` (font pixels per window pixel).
SDL_Point panelSize(const TextPanel& panel, int scale);
void drawPanel(SDL_Renderer* renderer, const TextPanel& panel, int scale);

}  // namespace raster::tools
