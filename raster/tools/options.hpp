// Command-line parsing shared by the subcommands: strict numbers, clear errors.
#pragma once

#include <charconv>
#include <cstdint>
#include <string>
#include <string_view>

#include "raster/check.hpp"

namespace raster::tools {

// Parses a whole decimal integer in [lo, hi]; throws Error(InvalidArgument) naming the option.
inline uint32_t parseUint(std::string_view option, std::string_view text, uint32_t lo, uint32_t hi) {
    uint64_t value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    RASTER_REQUIRE(ec == std::errc() && end == text.data() + text.size() && !text.empty(), InvalidArgument,
                   std::string(option) + " takes a whole number, not '" + std::string(text) + "'");
    RASTER_REQUIRE(value >= lo && value <= hi, InvalidArgument,
                   std::string(option) + " " + std::string(text) + " is outside " + std::to_string(lo) + ".." +
                       std::to_string(hi));
    return uint32_t(value);
}

// Walks argv; next() returns an option's value or throws naming the option.
class ArgReader {
public:
    ArgReader(int argc, char** argv) : argc_(argc), argv_(argv) {}
    bool done() const { return i_ >= argc_; }
    std::string_view take() { return argv_[i_++]; }
    std::string_view value(std::string_view option) {
        RASTER_REQUIRE(i_ < argc_, InvalidArgument, std::string(option) + " needs a value");
        return argv_[i_++];
    }

private:
    int argc_;
    char** argv_;
    int i_ = 0;
};

}  // namespace raster::tools
