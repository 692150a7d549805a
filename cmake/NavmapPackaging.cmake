# SPDX-License-Identifier: Apache-2.0
# Debian packages with `cpack -G DEB` in the build tree (docs/packaging.md):
#   navmapd               the daemon, the tools, the default data, the unit, the configuration
#   navmap-view           the display client that records frames (PNG files through OpenImageIO)
#   navmap-wayland        the display client that shows frames on a Wayland surface (libwayland-client)
#   libnavmap-client0     libnavmap-client.so.0 (what a display process needs at run time)
#   libnavmap-client-dev  headers, CMake package, pkg-config file
#   gstreamer1.0-navmap   libgstnavmap.so, the GStreamer source element navmapsrc (NAVMAP_WITH_GSTREAMER)
# Dependencies on Debian libraries come from dpkg-shlibdeps; between the packages, from here.
set(CPACK_PACKAGE_NAME navmap)
set(CPACK_PACKAGE_VENDOR "navmap")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
# Install with DESTDIR and the prefix /usr, whatever the build was configured with, so that the
# configuration lands in /etc (cmake/NavmapInstallSystem.cmake decides by the prefix).
set(CPACK_SET_DESTDIR ON)
set(CPACK_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
if(NAVMAP_WITH_DAEMON)
  set(CPACK_COMPONENTS_ALL daemon viewer client client-dev)
  if(TARGET navmap-wayland)
    list(APPEND CPACK_COMPONENTS_ALL wayland)
  endif()
else()
  set(CPACK_COMPONENTS_ALL client client-dev)
endif()
if(TARGET gstnavmap)
  list(APPEND CPACK_COMPONENTS_ALL gstreamer)
endif()
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "navmap maintainers <navmap@localhost>")
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
if(CMAKE_CROSSCOMPILING)
  # dpkg-shlibdeps reads the build machine's package database: no answer for the target's libraries.
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS OFF)
  if(CMAKE_SYSTEM_PROCESSOR STREQUAL "aarch64")
    set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE arm64)
  endif()
else()
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
endif()
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)

set(CPACK_DEBIAN_DAEMON_PACKAGE_NAME navmapd)
set(CPACK_DEBIAN_DAEMON_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_DAEMON_PACKAGE_RECOMMENDS "fonts-dejavu-core, fonts-droid-fallback, libegl-mesa0, libgl1-mesa-dri")
set(CPACK_DEBIAN_DAEMON_PACKAGE_SUGGESTS "systemd, can-utils")
set(CPACK_DEBIAN_DAEMON_DESCRIPTION "headless 3D navigation-map renderer daemon for cars
navmapd renders bird's-eye and snail's-view map frames offscreen (EGL, OpenGL ES 3) from the
vehicle position on SocketCAN and a route over local IPC, and streams them to cluster and
head-up-display clients. With the tools navmap-ctl, navmap-compile, navmap-sim and navmap-soak,
and the Andorra map data (OpenStreetMap, ODbL; SRTM). The display client navmap-view is in the
package navmap-view.")
set(CPACK_DEBIAN_DAEMON_PACKAGE_CONTROL_EXTRA
    "${PROJECT_SOURCE_DIR}/daemon/debian/conffiles;${PROJECT_SOURCE_DIR}/daemon/debian/postinst;${PROJECT_SOURCE_DIR}/daemon/debian/postrm")

set(CPACK_DEBIAN_VIEWER_PACKAGE_NAME navmap-view)
set(CPACK_DEBIAN_VIEWER_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_VIEWER_DESCRIPTION "display client of navmapd's frame stream
navmap-view receives navmapd's frames as a cluster or head-up display would (shared memory, TCP),
prints frames per second, latency and drops, and records the frames as PNG files.")

set(CPACK_DEBIAN_WAYLAND_PACKAGE_NAME navmap-wayland)
set(CPACK_DEBIAN_WAYLAND_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_WAYLAND_DESCRIPTION "Wayland display client of navmapd's frame stream
navmap-wayland shows one profile of navmapd's frames on a Wayland surface: an ivi_surface under
Weston's ivi-shell (with a configurable ivi_id), an xdg_toplevel elsewhere. It follows the
compositor's size, asks navmapd for it, and reconnects by itself, keeping the last frame.")

set(CPACK_DEBIAN_CLIENT_PACKAGE_NAME libnavmap-client${PROJECT_VERSION_MAJOR})
set(CPACK_DEBIAN_CLIENT_PACKAGE_SECTION libs)
set(CPACK_DEBIAN_CLIENT_DESCRIPTION "navmap display-client library
libnavmap-client receives navmapd's frames over shared memory (C and C++ API), reconnecting by
itself; it links only the C and C++ runtime.")
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)  # a shlibs file for packages with shared libraries

set(CPACK_DEBIAN_CLIENT-DEV_PACKAGE_NAME libnavmap-client-dev)
set(CPACK_DEBIAN_CLIENT-DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_CLIENT-DEV_PACKAGE_DEPENDS "libnavmap-client${PROJECT_VERSION_MAJOR} (= ${PROJECT_VERSION})")
set(CPACK_DEBIAN_CLIENT-DEV_DESCRIPTION "navmap display-client library: development files
Headers (navmap_client.h, navmap/ipc/client/*.h, navmap/ipc/net/*.h), the CMake package
(find_package(navmap COMPONENTS client)) and the pkg-config file navmap-client.pc.")

set(CPACK_DEBIAN_GSTREAMER_PACKAGE_NAME gstreamer1.0-navmap)
set(CPACK_DEBIAN_GSTREAMER_PACKAGE_SECTION video)
# dpkg-shlibdeps cannot resolve libnavmap-client.so.0, which no installed package provides while
# the packages are made: the dependencies are named here (GStreamer's of Debian 12, 1.22).
set(CPACK_DEBIAN_GSTREAMER_PACKAGE_SHLIBDEPS OFF)
set(CPACK_DEBIAN_GSTREAMER_PACKAGE_DEPENDS
    "libnavmap-client${PROJECT_VERSION_MAJOR} (= ${PROJECT_VERSION}), libgstreamer1.0-0 (>= 1.20), libglib2.0-0, zlib1g, libc6, libgcc-s1, libstdc++6")
set(CPACK_DEBIAN_GSTREAMER_DESCRIPTION "GStreamer source element of navmapd's frame stream
navmapsrc receives navmapd's rendered map frames through libnavmap-client (shared memory, raw or
zlib) and produces video/x-raw RGBA with timestamps from the frames' render times, EOS when
navmapd stops, or reconnects.")

include(CPack)
if(NAVMAP_WITH_DAEMON)
  cpack_add_component(daemon DISPLAY_NAME "navmapd" REQUIRED)
  cpack_add_component(viewer DISPLAY_NAME "navmap-view")
  if(TARGET navmap-wayland)
    cpack_add_component(wayland DISPLAY_NAME "navmap-wayland")
  endif()
endif()
cpack_add_component(client DISPLAY_NAME "libnavmap-client")
cpack_add_component(client-dev DISPLAY_NAME "libnavmap-client-dev" DEPENDS client)
if(TARGET gstnavmap)
  cpack_add_component(gstreamer DISPLAY_NAME "gstreamer1.0-navmap" DEPENDS client)
endif()
