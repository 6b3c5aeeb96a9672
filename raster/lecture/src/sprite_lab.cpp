// The sprite-methods lab's scene, less its template (raster/labs/sprite_methods.hpp): the textures, the
// seeded placement of the firs and the sprites, the input layouts.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "raster/labs/sprite_methods.hpp"

namespace raster::sprite_lab {

float hash01(uint32_t a, uint32_t b, uint32_t c) {
    uint32_t h = a * 0x9E3779B1u ^ (b + 0x7F4A7C15u) * 0x85EBCA77u ^ (c + 0x165667B1u) * 0xC2B2AE3Du;
    h ^= h >> 15, h *= 0x2C1B3C6Du, h ^= h >> 12, h *= 0x297A2D39u, h ^= h >> 15;
    return float(h >> 8) * (1.0f / 16777216.0f);
}

Texture2D targetTexture(float crossHalfWidth) {
    return proceduralTexture(64, 64, [crossHalfWidth](uint32_t, uint32_t, float u, float v) -> glm::u8vec4 {
        const float x = 2.0f * u - 1.0f, y = 2.0f * v - 1.0f, r = std::sqrt(x * x + y * y);
        if (r > 1.0f) return {0, 0, 0, 0};
        if (std::abs(x) < crossHalfWidth || std::abs(y) < crossHalfWidth) return {40, 40, 40, 255};
        return int(r * 4.0f) % 2 == 0 ? glm::u8vec4(255, 255, 255, 255) : glm::u8vec4(150, 150, 150, 255);
    });
}

Texture2D firTexture() {
    return proceduralTexture(64, 128, [](uint32_t i, uint32_t j, float u, float v) -> glm::u8vec4 {
        const float x = std::abs(u - 0.5f);
        float half_width = -1.0f;
        for (int tier = 0; tier < 3; ++tier) {
            const float top = 0.04f + 0.24f * float(tier);
            if (v >= top && v <= top + 0.36f)
                half_width = std::max(half_width, 0.05f + (0.22f + 0.07f * float(tier)) * (v - top) / 0.36f);
        }
        const float outside = (x - half_width) * 64.0f;  // texels beyond the crown's outline
        if (half_width > 0.0f && outside <= 0.0f)
            return hash01(i / 2, j / 2, 5) < 0.3f ? glm::u8vec4(58, 128, 60, 255)
                                                  : glm::u8vec4(28, 84, 44, 255);
        if (x < 0.05f && v > 0.7f && v < 0.98f) return {92, 64, 42, 255};
        if (half_width > 0.0f && outside < 1.5f) return {28, 84, 44, 96};
        return {0, 0, 0, 0};
    });
}

Texture2D meadowTexture() {
    return proceduralTexture(2, 2, [](uint32_t i, uint32_t j, float, float) {
        return (i + j) % 2 == 0 ? glm::u8vec4(96, 120, 70, 255) : glm::u8vec4(84, 106, 62, 255);
    });
}

std::vector<TreeCornerIn> plantTrees(uint32_t seed, int trees) {
    std::vector<TreeCornerIn> out;
    for (uint32_t k = 0, attempt = 0; int(out.size()) < 6 * trees; ++attempt) {
        const glm::vec3 base(-10.0f + 20.0f * hash01(seed, attempt, 2), 0.0f,
                             -10.0f + 13.0f * hash01(seed, attempt, 3));
        if (base.z > -2.5f && std::abs(base.x) < 6.5f) continue;
        const float height = 2.6f + 2.0f * hash01(seed, k++, 4);
        for (const glm::vec2 c : {glm::vec2(1, 1), glm::vec2(1, 0), glm::vec2(-1, 1), glm::vec2(1, 0),
                                  glm::vec2(-1, 0), glm::vec2(-1, 1)})
            out.push_back({base, {0.3f * height, height}, c});
    }
    return out;
}

std::vector<GroundIn> meadowQuad() {
    std::vector<GroundIn> out;
    for (const glm::vec2 c : kSpriteCorners)
        out.push_back({{16.0f * c.x, 0.0f, -4.0f - 16.0f * c.y}, {4.0f * c.x, 4.0f * c.y}});
    return out;
}

InputLayout spriteCornerLayout() {
    const InputElementDesc elements[] = {
        {"POSITION", 0, Format::R32G32B32_FLOAT, 0, uint32_t(offsetof(SpriteCornerIn, centre))},
        {"SIZE", 0, Format::R32_FLOAT, 0, uint32_t(offsetof(SpriteCornerIn, size))},
        {"COLOR", 0, Format::R32G32B32A32_FLOAT, 0, uint32_t(offsetof(SpriteCornerIn, tint))},
        {"TEXCOORD", 0, Format::R32G32_FLOAT, 0, uint32_t(offsetof(SpriteCornerIn, corner))}};
    return InputLayout(elements);
}

InputLayout spritePointLayout() {
    const InputElementDesc elements[] = {
        {"POSITION", 0, Format::R32G32B32_FLOAT, 0, uint32_t(offsetof(SpritePointIn, centre))},
        {"SIZE", 0, Format::R32_FLOAT, 0, uint32_t(offsetof(SpritePointIn, size))},
        {"COLOR", 0, Format::R32G32B32A32_FLOAT, 0, uint32_t(offsetof(SpritePointIn, tint))}};
    return InputLayout(elements);
}

InputLayout treeCornerLayout() {
    const InputElementDesc elements[] = {
        {"POSITION", 0, Format::R32G32B32_FLOAT, 0, uint32_t(offsetof(TreeCornerIn, base))},
        {"SIZE", 0, Format::R32G32_FLOAT, 0, uint32_t(offsetof(TreeCornerIn, extent))},
        {"TEXCOORD", 0, Format::R32G32_FLOAT, 0, uint32_t(offsetof(TreeCornerIn, corner))}};
    return InputLayout(elements);
}

InputLayout groundLayout() {
    const InputElementDesc elements[] = {
        {"POSITION", 0, Format::R32G32B32_FLOAT, 0, uint32_t(offsetof(GroundIn, position))},
        {"TEXCOORD", 0, Format::R32G32_FLOAT, 0, uint32_t(offsetof(GroundIn, tex))}};
    return InputLayout(elements);
}

BlendState channelOnly(int channel) {
    BlendState blend = BlendState::opaque();
    blend.renderTarget[0].renderTargetWriteMask = uint8_t(1u << channel);
    return blend;
}

std::vector<SpritePointIn> rowSprites(int row, float t, uint32_t per_row, uint32_t seed) {
    std::vector<SpritePointIn> out;
    for (uint32_t k = 0; k < per_row; ++k) {
        float s = (float(k) + 0.5f) / float(per_row) + t * kScrollSpeed / kRowSpan;
        s -= std::floor(s);
        const glm::vec3 centre((s - 0.5f) * kRowSpan, 4.6f - 0.95f * float(row), 0.0f);
        out.push_back({centre, 0.3f + 0.12f * hash01(seed, k, 1), kRowTints[row]});
    }
    return out;
}

SceneCamera swungCamera(const SceneCamera& camera, float t) {
    const float yaw = glm::radians(kSwingDegrees) * std::sin(6.2831853f * t / kSwingSeconds);
    const glm::mat3 turn(glm::rotate(glm::mat4(1.0f), yaw, glm::vec3(0, 1, 0)));
    return {camera.target + turn * (camera.eye - camera.target), camera.target};
}

uint32_t spritesPerRow(const SceneOptions& options) {
    const uint32_t per_row = options.count.value_or(kDefaultPerRow);
    if (per_row > kMaxPerRow)
        throw Error(ErrorCode::InvalidArgument, "sprite-methods: count (sprites per row) must be at most " +
                                                    std::to_string(kMaxPerRow) + ", not " +
                                                    std::to_string(per_row));
    return per_row;
}

}  // namespace raster::sprite_lab
