# SPDX-License-Identifier: Apache-2.0
# Cross-compiling navmap for 64-bit ARM Linux (ECUs) on Debian with its cross toolchain
# (apt-get install g++-aarch64-linux-gnu) and, for the daemon, arm64 libraries: either installed
# side by side (dpkg --add-architecture arm64; Debian's multiarch puts them in
# /usr/lib/aarch64-linux-gnu) or unpacked into a sysroot given as NAVMAP_SYSROOT (scripts/cross-build.sh).
#   cmake -S . -B build-aarch64 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake \
#         -DNAVMAP_HOST_TOOLS=build/NavmapHostTools.cmake
# The build runs navmap-compile to make the default store; cross-compiled, that is the native
# build's (NAVMAP_HOST_TOOLS, exported by every native build), see map/compile/CMakeLists.txt.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
# GCC notes on AArch64 that the passing of some pairs changed in GCC 10.1 (an ABI note about
# mixing objects of old compilers, not a defect): not repeated for every file.
set(CMAKE_CXX_FLAGS_INIT "-Wno-psabi")
# Programs run on the build machine; libraries, headers and packages come from the target's.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
if(DEFINED ENV{NAVMAP_SYSROOT} AND NOT NAVMAP_SYSROOT)
  set(NAVMAP_SYSROOT "$ENV{NAVMAP_SYSROOT}")
endif()
# try_compile projects read this file again, in the same process: without the sysroot passed on,
# they would take the multiarch branch below and point pkg-config's environment away from it.
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES NAVMAP_SYSROOT)
if(NAVMAP_SYSROOT)
  set(CMAKE_SYSROOT "${NAVMAP_SYSROOT}")
  set(CMAKE_FIND_ROOT_PATH "${NAVMAP_SYSROOT}")
  set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
  set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
  set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)  # header-only packages (nlohmann_json, CLI11) are the build machine's
  set(ENV{PKG_CONFIG_SYSROOT_DIR} "${NAVMAP_SYSROOT}")
  set(ENV{PKG_CONFIG_LIBDIR} "${NAVMAP_SYSROOT}/usr/lib/aarch64-linux-gnu/pkgconfig:${NAVMAP_SYSROOT}/usr/share/pkgconfig")
  # Test programs (gtest's discovery at build time, CTest) run under qemu-user with the sysroot's
  # loader, libraries and Mesa (scripts/qemu-aarch64.sh; qemu-aarch64-static, no binfmt).
  if(NOT CMAKE_CROSSCOMPILING_EMULATOR)
    set(CMAKE_CROSSCOMPILING_EMULATOR "${CMAKE_CURRENT_LIST_DIR}/../../scripts/qemu-aarch64.sh;${NAVMAP_SYSROOT}")
  endif()
else()
  # Debian multiarch: arm64 .pc files only, never the build machine's.
  set(ENV{PKG_CONFIG_LIBDIR} "/usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig")
endif()
