// The precompiled header of the test suites is built with this empty file (tests/CMakeLists.txt).
