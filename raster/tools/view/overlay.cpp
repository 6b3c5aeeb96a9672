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

// The font has glyphs for ' ' to '~' only (and reads out of its table for any other byte).
bool printable(char c) {
    return c >= ' ' && c <= '~';
}

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

// Widths of the columns, in font pixels: of each line's cells but its last.
std::vector<int> columnWidths(const std::vector<std::string>& lines) {
    std::vector<int> widths;
    for (const std::string& line : lines) {
        const std::vector<std::string> row = cells(line);
        widths.resize(std::max(widths.size(), row.size() - 1));
        for (size_t c = 0; c + 1 < row.size(); ++c) widths[c] = std::max(widths[c], textWidth(row[c]));
    }
    return widths;
}

// Where a line's cell `c` starts, in font pixels from the text's left edge.
int cellLeft(const std::vector<int>& columns, size_t c) {
    int x = 0;
    for (size_t i = 0; i < c; ++i) x += columns[i] + kColumnGap;
    return x;
}

// The lines of `lines` wrapped to `width` font pixels (fitPanel's first half).
std::vector<std::string> wrapLines(const std::vector<std::string>& lines, int width) {
    const std::vector<int> columns = columnWidths(lines);
    std::vector<std::string> out;
    for (const std::string& line : lines) {
        std::vector<std::string> row = cells(line);
        int left = cellLeft(columns, row.size() - 1);
        if (row.size() > 1 && width - left < width / 4) {
            // Too little room in the last column: the cells as one line of text.
            std::string joined = row[0];
            for (size_t c = 1; c < row.size(); ++c) joined += "  " + row[c];
            row = {joined};
            left = 0;
        }
        const std::string leading(row.size() - 1, '\t');
        std::string prefix;  // the line's leading cells, then empty ones for its continuations
        for (size_t c = 0; c + 1 < row.size(); ++c) prefix += row[c] + '\t';
        const std::vector<std::string> pieces =
            wrapText(row.back(), width - left, textWidth, row.size() == 1 ? kContinuationIndent : "");
        for (const std::string& piece : pieces) {
            out.push_back(prefix + piece);
            prefix = leading;
        }
    }
    return out;
}

}  // namespace

int overlayScale(int windowWidth) {
    return windowWidth >= 900 ? 2 : 1;
}

int textWidth(std::string_view text) {
    int width = 0;
    for (const char c : text) width += stb_easy_font_charinfo[(printable(c) ? c : '?') - 32].advance & 15;
    return width;
}

std::vector<std::string> wrapText(std::string_view text, int maxWidth, const TextMeasure& width,
                                  std::string_view indent) {
    if (width(text) <= maxWidth) return {std::string(text)};
    std::vector<std::string> lines;
    std::string line;
    bool has_word = false;  // whether `line` holds more than leading spaces or the indent
    size_t i = 0;
    while (true) {
        const size_t start = text.find_first_not_of(' ', i);
        if (start == std::string_view::npos) break;  // trailing spaces go with the last break
        const size_t end = std::min(text.find(' ', start), text.size());
        const std::string_view spaces = text.substr(i, start - i), word = text.substr(start, end - start);
        i = end;
        // Only the first line can start with spaces (has_word is false nowhere else here).
        std::string joined = line;
        joined += spaces;
        joined += word;
        if (width(joined) <= maxWidth) {
            line = std::move(joined), has_word = true;
            continue;
        }
        if (has_word) {
            lines.push_back(std::move(line));
            line = std::string(indent) + std::string(word), has_word = false;
            if (width(line) <= maxWidth) {
                has_word = true;
                continue;
            }
        }
        // Wider than a line of its own: as many characters a line as fit, at least one.
        line = lines.empty() ? std::string() : std::string(indent);
        for (const char c : word) {
            if (has_word && width(line + c) > maxWidth) {
                lines.push_back(std::move(line));
                line = std::string(indent);
            }
            line += c, has_word = true;
        }
    }
    if (has_word || lines.empty()) lines.push_back(std::move(line));
    return lines;
}

TextPanel fitPanel(TextPanel panel, int maxWidth, int maxHeight, int scale, std::string_view moreHint) {
    std::vector<std::string> lines;
    for (const std::string& line : panel.lines) {
        size_t start = 0;
        while (true) {
            const size_t end = std::min(line.find('\n', start), line.size());
            lines.push_back(line.substr(start, end - start));
            if (end == line.size()) break;
            start = end + 1;
        }
    }
    panel.lines = wrapLines(lines, maxWidth / scale - 2 * kPadding);
    const int room = (maxHeight / scale - 2 * kPadding) / kLineHeight;  // lines that fit
    if (int(panel.lines.size()) > room) {
        const auto more = [&](size_t n) {
            return wrapText("... " + std::to_string(n) + " more lines" + std::string(moreHint),
                            maxWidth / scale - 2 * kPadding, textWidth, kContinuationIndent);
        };
        // The note takes no more lines for fewer hidden ones: it is measured for all of them.
        const size_t kept = size_t(std::max(room - int(more(panel.lines.size()).size()), 0));
        const std::vector<std::string> note = more(panel.lines.size() - kept);
        panel.lines.resize(kept);
        for (const std::string& line : note)
            if (int(panel.lines.size()) < std::max(room, 1)) panel.lines.push_back(line);
    }
    return panel;
}

SDL_Point panelSize(const TextPanel& panel, int scale) {
    const std::vector<int> columns = columnWidths(panel.lines);
    int width = 0;
    for (const std::string& line : panel.lines) {
        const std::vector<std::string> row = cells(line);
        width = std::max(width, cellLeft(columns, row.size() - 1) + textWidth(row.back()));
    }
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

    const std::vector<int> columns = columnWidths(panel.lines);
    std::vector<SDL_FRect> rects;
    std::vector<FontVertex> vertices;
    for (size_t i = 0; i < panel.lines.size(); ++i) {
        const std::vector<std::string> row = cells(panel.lines[i]);
        for (size_t c = 0; c < row.size(); ++c) {
            std::string text = row[c];
            for (char& ch : text) ch = printable(ch) ? ch : '?';
            // A glyph has at most a dozen segments, four vertices each; stb_easy_font silently drops
            // what does not fit.
            vertices.resize(4 * 16 * (text.size() + 1));
            unsigned char white[4] = {255, 255, 255, 255};
            const int quads = stb_easy_font_print(float(kPadding + cellLeft(columns, c)),
                                                  float(kPadding + int(i) * kLineHeight), text.data(), white,
                                                  vertices.data(), int(vertices.size() * sizeof(FontVertex)));
            // Every quad of the font is an axis-aligned rectangle: corners 0 and 2 are opposite.
            for (int q = 0; q < quads; ++q) {
                const FontVertex& a = vertices[4 * q];
                const FontVertex& b = vertices[4 * q + 2];
                rects.push_back({float(left) + a.x * float(scale), float(panel.y) + a.y * float(scale),
                                 (b.x - a.x) * float(scale), (b.y - a.y) * float(scale)});
            }
        }
    }
    SDL_SetRenderDrawColor(renderer, panel.color.r, panel.color.g, panel.color.b, panel.color.a);
    SDL_RenderFillRectsF(renderer, rects.data(), int(rects.size()));
}

}  // namespace raster::tools
