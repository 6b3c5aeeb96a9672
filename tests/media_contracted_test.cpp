// tests/media_test.cpp compiled at -O3 -march=native -ffp-contract=fast (tests/CMakeLists.txt): the
// media guards and accuracy bounds with the compiler free to fuse a·b + c into one rounding.
#define RASTER_MEDIA_CONTRACTED
#include "media_test.cpp"
