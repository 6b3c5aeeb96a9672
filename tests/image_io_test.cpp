// PNG in and out (image_io.hpp): decoding from memory, the size limit read from the header, and
// the errors for empty, garbage, truncated and oversized images.
#include "raster/image_io.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "raster/check.hpp"

namespace raster {
namespace {

// The code of the raster::Error f throws, its message in *message; a test failure if f throws nothing.
ErrorCode errorCodeOf(const std::function<void()>& f, std::string* message = nullptr) {
    try {
        f();
    } catch (const Error& e) {
        if (message) *message = e.what();
        return e.code();
    }
    ADD_FAILURE() << "expected raster::Error, nothing was thrown";
    return ErrorCode::InvalidArgument;
}

std::string tempPath(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("raster_image_io_test_" + name)).string();
}

std::vector<uint8_t> fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A 3x2 picture, every byte different.
std::vector<uint8_t> smallPicture() {
    std::vector<uint8_t> rgba(3 * 2 * 4);
    for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = uint8_t(i * 11 + 3);
    return rgba;
}

// The bytes of a PNG written by writePngRgba8.
std::vector<uint8_t> smallPng() {
    const std::string path = tempPath("small.png");
    writePngRgba8(path, 3, 2, smallPicture());
    std::vector<uint8_t> bytes = fileBytes(path);
    std::filesystem::remove(path);
    return bytes;
}

uint32_t crc32(const uint8_t* p, size_t n) {
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; ++i) {
        c ^= p[i];
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return ~c;
}

void put32(std::vector<uint8_t>& out, uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(uint8_t(v >> shift));
}

// A PNG signature and a valid IHDR chunk (8-bit RGBA) claiming width x height, and nothing else:
// what a decoder reads of the size before any pixel.
std::vector<uint8_t> pngHeader(uint32_t width, uint32_t height) {
    std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    put32(png, 13);
    const size_t type = png.size();
    png.insert(png.end(), {'I', 'H', 'D', 'R'});
    put32(png, width);
    put32(png, height);
    png.insert(png.end(),
               {8, 6, 0, 0, 0});  // bit depth 8, colour type RGBA, deflate, no filter, no interlace
    put32(png, crc32(png.data() + type, png.size() - type));
    return png;
}

TEST(ImageIo, DecodeReadsWhatWriteWrote) {
    const ImageRgba8 image = decodeImageRgba8(smallPng(), "small");
    EXPECT_EQ(image.width, 3u);
    EXPECT_EQ(image.height, 2u);
    EXPECT_EQ(image.pixels, smallPicture());
}

TEST(ImageIo, ReadFileIsDecodeOfItsBytes) {
    const std::string path = tempPath("read.png");
    writePngRgba8(path, 3, 2, smallPicture());
    const ImageRgba8 read = readImageRgba8(path);
    const ImageRgba8 decoded = decodeImageRgba8(fileBytes(path), path);
    std::filesystem::remove(path);
    EXPECT_EQ(read.width, decoded.width);
    EXPECT_EQ(read.height, decoded.height);
    EXPECT_EQ(read.pixels, decoded.pixels);
}

TEST(ImageIo, WritingAnEmptyImageIsInvalidArgumentSayingEmptyNamingPath) {
    const std::string path = tempPath("empty.png");
    std::string message;
    EXPECT_EQ(errorCodeOf([&] { writePngRgba8(path, 0, 0, {}); }, &message), ErrorCode::InvalidArgument);
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find("0x0 (empty)"), std::string::npos) << message;
    EXPECT_EQ(errorCodeOf([&] { writePngRgba8(path, 4, 0, {}); }, &message), ErrorCode::InvalidArgument);
    EXPECT_NE(message.find("4x0 (empty)"), std::string::npos) << message;
    EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(ImageIo, WritingTooFewBytesIsInvalidArgumentNamingPathAndSize) {
    const std::string path = tempPath("short.png");
    std::string message;
    EXPECT_EQ(errorCodeOf([&] { writePngRgba8(path, 2, 2, std::vector<uint8_t>(15)); }, &message),
              ErrorCode::InvalidArgument);
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find("15 bytes, not 16"), std::string::npos) << message;
    EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(ImageIo, GarbageIsBadFileNamingName) {
    const std::vector<uint8_t> garbage = {'n', 'o', 't', ' ', 'a', 'n', ' ', 'i',
                                          'm', 'a', 'g', 'e', 0,   1,   2};
    std::string message;
    EXPECT_EQ(errorCodeOf([&] { decodeImageRgba8(garbage, "garbage bytes"); }, &message), ErrorCode::BadFile);
    EXPECT_NE(message.find("garbage bytes"), std::string::npos) << message;
    EXPECT_EQ(errorCodeOf([&] { decodeImageRgba8({}, "no bytes"); }, &message), ErrorCode::BadFile);
    EXPECT_NE(message.find("no bytes"), std::string::npos) << message;
}

TEST(ImageIo, EmptyIdatChunksAreSkipped) {
    // An empty IDAT before the data (valid PNG), which stb_image 2.27 reads with memcpy(nullptr, ..., 0).
    const std::vector<uint8_t> png = smallPng();
    std::vector<uint8_t> empty_idat = {0, 0, 0, 0, 'I', 'D', 'A', 'T'};
    put32(empty_idat, crc32(empty_idat.data() + 4, 4));
    const size_t after_ihdr = 8 + 12 + 13;
    std::vector<uint8_t> with_empty(png.begin(), png.begin() + std::ptrdiff_t(after_ihdr));
    with_empty.insert(with_empty.end(), empty_idat.begin(), empty_idat.end());
    with_empty.insert(with_empty.end(), png.begin() + std::ptrdiff_t(after_ihdr), png.end());
    with_empty.insert(with_empty.end() - 12, empty_idat.begin(), empty_idat.end());  // and one before IEND
    const ImageRgba8 image = decodeImageRgba8(with_empty, "empty idat");
    EXPECT_EQ(image.width, 3u);
    EXPECT_EQ(image.height, 2u);
    EXPECT_EQ(image.pixels, smallPicture());
}

TEST(ImageIo, OtherFormatsAreBadFile) {
    // stb_image's other decoders are not compiled in (image_io.cpp): a valid 2x2 PPM and 1x1 BMP.
    const std::string ppm = "P6\n2 2\n255\n0123456789AB";
    const std::vector<uint8_t> bmp = {'B', 'M', 58, 0, 0, 0, 0, 0, 0,  0, 54, 0, 0, 0, 40, 0, 0, 0, 1, 0,
                                      0,   0,   1,  0, 0, 0, 1, 0, 24, 0, 0,  0, 0, 0, 4,  0, 0, 0, 0, 0,
                                      0,   0,   0,  0, 0, 0, 0, 0, 0,  0, 0,  0, 0, 0, 1,  2, 3, 0};
    std::string message;
    EXPECT_EQ(errorCodeOf([&] { decodeImageRgba8(std::vector<uint8_t>(ppm.begin(), ppm.end()), "a.ppm"); },
                          &message),
              ErrorCode::BadFile);
    EXPECT_NE(message.find("a.ppm"), std::string::npos) << message;
    EXPECT_EQ(errorCodeOf([&] { decodeImageRgba8(bmp, "a.bmp"); }), ErrorCode::BadFile);
}

TEST(ImageIo, TruncatedPngIsBadFileNamingName) {
    const std::vector<uint8_t> png = smallPng();
    // Cut inside the image data, after the header: the size reads, the pixels do not.
    for (const size_t keep : {png.size() / 2, png.size() - 13, size_t(40)}) {
        const std::vector<uint8_t> cut(png.begin(), png.begin() + std::ptrdiff_t(keep));
        std::string message;
        EXPECT_EQ(errorCodeOf([&] { decodeImageRgba8(cut, "cut.png"); }, &message), ErrorCode::BadFile)
            << keep;
        EXPECT_NE(message.find("cut.png"), std::string::npos) << message;
    }
}

TEST(ImageIo, OversizedHeaderIsBadFileBeforeDecoding) {
    // The headers alone are 33 bytes: decoding them would first allocate the whole image.
    struct Case {
        uint32_t width, height;
    };
    for (const Case c : {Case{kMaxImageSide + 1, 1}, Case{1, kMaxImageSide + 1}, Case{8193, 8192},
                         Case{kMaxImageSide, kMaxImageSide}, Case{0x7FFFFFFF, 0x7FFFFFFF}}) {
        const std::string size = std::to_string(c.width) + "x" + std::to_string(c.height);
        std::string message;
        EXPECT_EQ(errorCodeOf([&] { decodeImageRgba8(pngHeader(c.width, c.height), "huge.png"); }, &message),
                  ErrorCode::BadFile)
            << size;
        EXPECT_NE(message.find("huge.png"), std::string::npos) << message;
    }
    // At the limits the header passes, and decoding then fails for want of pixels.
    std::string message;
    EXPECT_EQ(errorCodeOf([&] { decodeImageRgba8(pngHeader(kMaxImageSide, 4096), "big.png"); }, &message),
              ErrorCode::BadFile);
    EXPECT_EQ(message.find("over the limit"), std::string::npos) << message;
    EXPECT_EQ(errorCodeOf([&] { decodeImageRgba8(pngHeader(8192, 8193), "big.png"); }, &message),
              ErrorCode::BadFile);
    EXPECT_NE(message.find("over the limit"), std::string::npos) << message;
}

TEST(ImageIo, ChunkLongerThanTheFileIsBadFileBeforeDecoding) {
    // An IDAT claiming 1.2 GB in a file of a few dozen bytes: stb_image would allocate it first.
    std::vector<uint8_t> png = pngHeader(6, 5);
    put32(png, 1162757449);
    png.insert(png.end(), {'I', 'D', 'A', 'T', 0x78, 0xDA, 1, 2, 3, 4, 5, 6, 7, 8});
    std::string message;
    EXPECT_EQ(errorCodeOf([&] { decodeImageRgba8(png, "long.png"); }, &message), ErrorCode::BadFile);
    EXPECT_NE(message.find("long.png"), std::string::npos) << message;
    EXPECT_NE(message.find("IDAT chunk at byte 33 claims 1162757449 bytes"), std::string::npos) << message;
}

TEST(ImageIo, MissingFileIsBadFileNamingPath) {
    const std::string path = "/nonexistent/raster/no_such_image.png";
    std::string message;
    EXPECT_EQ(errorCodeOf([&] { readImageRgba8(path); }, &message), ErrorCode::BadFile);
    EXPECT_NE(message.find(path), std::string::npos) << message;
}

}  // namespace
}  // namespace raster
