# Cross compilation for 64-bit Arm Linux (the CPU of standalone headsets) with Debian's cross toolchain
# (g++-aarch64-linux-gnu) against Debian multiarch packages (libfoo-dev:arm64 in /usr/lib/aarch64-linux-gnu).
# Used by scripts/cross-arm64; by hand:
#   cmake -S . -B build-arm64 -G Ninja -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake \
#         -DDHR_BUILD_SERVER=OFF -DDHR_BUILD_BENCH=OFF
# Tests run under qemu-user (CMAKE_CROSSCOMPILING_EMULATOR), so gtest_discover_tests and ctest work.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)

set(DHR_CROSS_TRIPLET aarch64-linux-gnu)
set(CMAKE_C_COMPILER ${DHR_CROSS_TRIPLET}-gcc)
set(CMAKE_CXX_COMPILER ${DHR_CROSS_TRIPLET}-g++)
# GCC notes on aarch64 that the parameter-passing ABI of some aggregates changed in GCC 10 (-Wpsabi): everything
# here is built by one compiler, so the notes are noise.
set(CMAKE_CXX_FLAGS_INIT -Wno-psabi)

# Debian multiarch: arm64 libraries and their CMake/pkg-config files live in /usr/lib/aarch64-linux-gnu, headers
# in /usr/include (shared by every architecture). Searching "/" with the library architecture set finds the
# arm64 copies and never the host's /usr/lib/x86_64-linux-gnu.
set(CMAKE_LIBRARY_ARCHITECTURE ${DHR_CROSS_TRIPLET})
set(CMAKE_FIND_ROOT_PATH /usr/${DHR_CROSS_TRIPLET} /)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
# Programs run on the build machine: glslangValidator (cmake/DhrShaders.cmake) is the host's.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)

# pkg-config (liblz4, libsodium) reads only the arm64 .pc files.
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/${DHR_CROSS_TRIPLET}/pkgconfig:/usr/share/pkgconfig)
set(ENV{PKG_CONFIG_PATH} "")

# Run target binaries (test discovery, ctest) under qemu-user. The arm64 dynamic loader and libraries are the
# multiarch ones (libc6:arm64 installs /lib/ld-linux-aarch64.so.1 on the build machine), found without -L.
# Not `-L /usr/aarch64-linux-gnu`: that loads the cross toolchain's own libc copy (libc6-arm64-cross) next to
# libraries from /usr/lib/aarch64-linux-gnu, and on bookworm (2.36-8cross1 against libc6:arm64 2.36-9+deb12uN)
# the mix hangs in the first pthread_create.
find_program(DHR_QEMU_AARCH64 qemu-aarch64)
if(DHR_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${DHR_QEMU_AARCH64})
endif()
