#include "overlay.hpp"

#include <algorithm>

// stb_easy_font is a header of static functions, some of which this file does not call.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_easy_font.h>
#pragma GCC diagnostic pop

namespace raster::tools {
namespace {

constexpr int kPadding = kPanelPadding;        // font pixels around the text
constexpr int kLineHeight = kPanelLineHeight;  // stb_easy_font's glyphs are 7 high, descenders 2 more
constexpr int kColumnGap = 10;                 // font pixels between tab-separated cells

struct FontVertex {  // stb_easy_font's vertex layout
    float x, y, z;
    unsigned char color[4];
};

std::vector<std::string> cells(const std::string& line) {
    std::vector<std::string> out(1);
    for (const char c : line) {
        if (c == '\t')
            out.emplace_back();
        else
            out.back() += c;
    }
    return out;
}

int textWidth(const std::string& text) {
    return stb_easy_font_width(const_cast<char*>(text.c_str()));
}

// Widths of the columns, in font pixels.
std::vector<int> columnWidths(const TextPanel& panel) {
    std::vector<int> widths;
    for (const std::string& line : panel.lines) {
        const std::vector<std::string> row = cells(line);
        if (row.size() == 1) continue;  // a line without tabs spans the panel
        widths.resize(std::max(widths.size(), row.size()));
        for (size_t c = 0; c < row.size(); ++c) widths[c] = std::max(widths[c], textWidth(row[c]));
    }
    return widths;
}

}  // namespace

SDL_Point panelSize(const TextPanel& panel, int scale) {
    const std::vector<int> columns = columnWidths(panel);
    int width = 0;
    for (const int w : columns) width += w + kColumnGap;
    for (const std::string& line : panel.lines)
        if (line.find('\t') == std::string::npos) width = std::max(width, textWidth(line));
    return {(width + 2 * kPadding) * scale, (int(panel.lines.size()) * kLineHeight + 2 * kPadding) * scale};
}

int panelLeft(SDL_Renderer* renderer, const TextPanel& panel, int scale) {
    if (panel.x >= 0) return panel.x;
    int window_width = 0, window_height = 0;
    SDL_GetRendererOutputSize(renderer, &window_width, &window_height);
    return window_width + panel.x - panelSize(panel, scale).x;
}

void drawPanel(SDL_Renderer* renderer, const TextPanel& panel, int scale) {
    if (panel.lines.empty()) return;
    const SDL_Point size = panelSize(panel, scale);
    const int left = panelLeft(renderer, panel, scale);
    SDL_SetRenderDrawBlendMode(renderer, SDL_BLENDMODE_BLEND);
    SDL_SetRenderDrawColor(renderer, 0, 0, 0, 170);
    const SDL_Rect background{left, panel.y, size.x, size.y};
    SDL_RenderFillRect(renderer, &background);

    const std::vector<int> columns = columnWidths(panel);
    std::vector<SDL_FRect> rects;
    std::vector<FontVertex> vertices;
    for (size_t i = 0; i < panel.lines.size(); ++i) {
        const std::vector<std::string> row = cells(panel.lines[i]);
        int x = kPadding;
        for (size_t c = 0; c < row.size(); ++c) {
            // A glyph has at most a dozen segments, four vertices each; stb_easy_font silently drops
            // what does not fit.
            vertices.resize(4 * 16 * (row[c].size() + 1));
            unsigned char white[4] = {255, 255, 255, 255};
            const int quads = stb_easy_font_print(float(x), float(kPadding + int(i) * kLineHeight),
                                                  const_cast<char*>(row[c].c_str()), white, vertices.data(),
                                                  int(vertices.size() * sizeof(FontVertex)));
            // Every quad of the font is an axis-aligned rectangle: corners 0 and 2 are opposite.
            for (int q = 0; q < quads; ++q) {
                const FontVertex& a = vertices[4 * q];
                const FontVertex& b = vertices[4 * q + 2];
                rects.push_back({float(left) + a.x * float(scale), float(panel.y) + a.y * float(scale),
                                 (b.x - a.x) * float(scale), (b.y - a.y) * float(scale)});
            }
            if (c < columns.size()) x += columns[c] + kColumnGap;
        }
    }
    SDL_SetRenderDrawColor(renderer, panel.color.r, panel.color.g, panel.color.b, panel.color.a);
    SDL_RenderFillRectsF(renderer, rects.data(), int(rects.size()));
}

}  // namespace raster::tools
