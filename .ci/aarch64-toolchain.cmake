# CMake toolchain for an AArch64 cross build with Debian's cross compiler
# (g++-aarch64-linux-gnu); tests run under qemu-user (qemu-aarch64). Libraries come from
# Debian's multiarch arm64 packages (libstb-dev:arm64, libtinyobjloader-dev:arm64, libtinyexr-dev:arm64 after
# `dpkg --add-architecture arm64`); glm and doctest are header-only (Architecture: all).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
# Run target programs (doctest_discover_tests, ctest) through qemu, with the multiarch
# libc6:arm64 in /lib/aarch64-linux-gnu. Not with `-L /usr/aarch64-linux-gnu`: qemu then
# takes the dynamic loader from the cross toolchain's libc6-arm64-cross (glibc 2.36-8) but
# the loader finds libc.so.6 in multiarch libc6:arm64 (2.36-9+deb12u14, pulled in by the
# arm64 libraries); a loader and libc from different glibc builds hang a program at its
# first condition-variable wait between two threads.
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64)
# pkg-config: the arm64 .pc files and the architecture-independent ones only.
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig)
