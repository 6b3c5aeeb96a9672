#include "raster/shader.hpp"

#include <cxxabi.h>

#include <cstdlib>

namespace raster {

std::string demangle(const char* mangled) {
    int status = 0;
    char* name = abi::__cxa_demangle(mangled, nullptr, nullptr, &status);
    std::string result = status == 0 && name ? name : mangled;
    std::free(name);
    return result;
}

}  // namespace raster
