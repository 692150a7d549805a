# SPDX-License-Identifier: Apache-2.0
# What `cmake --install` puts where (GNUInstallDirs; docs/packaging.md). Five components, one
# Debian package each (cmake/NavmapPackaging.cmake):
#   daemon      navmapd and the tools, the default store and navmap.dbc (<datadir>/navmap), the
#               systemd unit and sysusers.d entry, the configuration (<sysconfdir>/navmap), man
#               pages, docs
#   viewer      navmap-view and its man page (apart: its PNG files need OpenImageIO, which the
#               daemon's package does not pull in)
#   wayland     navmap-wayland and its man page (apart: it needs libwayland-client, which neither
#               the daemon nor the client library does; NAVMAP_WITH_WAYLAND)
#   client      libnavmap-client.so.<major>
#   client-dev  its headers, the .so link, the CMake package (find_package(navmap COMPONENTS
#               client)) and navmap-client.pc
#   gstreamer   libgstnavmap.so (navmapsrc) in GStreamer's plugin directory (NAVMAP_WITH_GSTREAMER)
#               and its meta header navmap/gst/navmap_frame_meta.h;
#               apart from client, whose library links only the C and C++ runtime
# Installed programs find their data relative to their own directory (navmap/install_layout.h),
# so the tree works under any prefix; nothing of the build machine is compiled in.
include(CMakePackageConfigHelpers)

set(NAVMAP_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/navmap)
set(NAVMAP_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/navmap)

# --- daemon: programs, data, configuration, service ---
if(NAVMAP_WITH_DAEMON)
install(TARGETS navmapd navmap-ctl navmap-compile navmap-sim navmap-soak
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT daemon)
install(TARGETS navmap-view RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT viewer)
if(TARGET navmap-wayland)
  install(TARGETS navmap-wayland RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT wayland)
endif()
# The compiled default store, the project's DBC, the orthoimage network's weights
# (docs/orthoimage.md) and the data's attribution. Shaders are compiled into navmapd (shaders/,
# cmake/EmbedShaders.cmake): none is read at run time.
install(FILES ${NAVMAP_DEFAULT_STORE} ${NAVMAP_DATA_DIR}/navmap.dbc ${NAVMAP_DATA_DIR}/ortho/ortho-mlp.nnw
              ${NAVMAP_DATA_DIR}/ATTRIBUTION.md
        DESTINATION ${NAVMAP_INSTALL_DATADIR} COMPONENT daemon)
install(FILES ${PROJECT_SOURCE_DIR}/daemon/navmap.sysusers DESTINATION lib/sysusers.d RENAME navmap.conf COMPONENT daemon)
install(FILES README.md CHANGELOG.md LICENSE ${NAVMAP_DATA_DIR}/ATTRIBUTION.md
        DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT daemon)
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT daemon FILES_MATCHING PATTERN "*.md")
# The configuration goes to /etc for the prefix /usr and to <prefix>/etc otherwise, and the unit
# names the programs and the configuration of the prefix installed to: both are decided when
# installing (cmake --install --prefix, CPack's /usr), not when configuring.
file(RELATIVE_PATH navmap_docdir_rel ${CMAKE_INSTALL_PREFIX} ${CMAKE_INSTALL_FULL_DOCDIR})
install(CODE "
  set(NAVMAP_SERVICE_TEMPLATE \"${PROJECT_SOURCE_DIR}/daemon/navmapd.service.in\")
  set(NAVMAP_CONFIG_FILE \"${PROJECT_SOURCE_DIR}/daemon/navmapd.toml\")
  set(NAVMAP_STAGING_DIR \"${PROJECT_BINARY_DIR}/install-staging\")
  set(NAVMAP_BINDIR_REL \"${CMAKE_INSTALL_BINDIR}\")
  set(NAVMAP_DOCDIR_REL \"${navmap_docdir_rel}\")
  include(\"${PROJECT_SOURCE_DIR}/cmake/NavmapInstallSystem.cmake\")
" COMPONENT daemon)

# Man pages from each program's --help and --version (help2man), when help2man is there and the
# programs can run here.
find_program(NAVMAP_HELP2MAN help2man)
if(NAVMAP_HELP2MAN AND NOT CMAKE_CROSSCOMPILING)
  set(navmap_man_pages)
  set(navmap_man_name_navmapd "headless 3D navigation-map renderer daemon")
  set(navmap_man_name_navmap-view "display client of navmapd's frame stream")
  set(navmap_man_name_navmap-wayland "show navmapd's frames on a Wayland surface (ivi-shell, xdg-shell)")
  set(navmap_man_name_navmap-ctl "send one command to navmapd's control socket")
  set(navmap_man_name_navmap-compile "compile OpenStreetMap and SRTM data into a navmap tile store")
  set(navmap_man_name_navmap-sim "simulated drives as GNSS CAN frames, candump logs and routes")
  set(navmap_man_name_navmap-soak "long-running stability test of navmapd")
  set(navmap_man_tools navmapd navmap-view navmap-ctl navmap-compile navmap-sim navmap-soak)
  if(TARGET navmap-wayland)
    list(APPEND navmap_man_tools navmap-wayland)
  endif()
  foreach(tool ${navmap_man_tools})
    set(page ${PROJECT_BINARY_DIR}/man/${tool}.1)
    add_custom_command(OUTPUT ${page}
        COMMAND ${CMAKE_COMMAND} -E make_directory ${PROJECT_BINARY_DIR}/man
        COMMAND ${NAVMAP_HELP2MAN} --no-info --no-discard-stderr --section=1 --source=navmap
                "--name=${navmap_man_name_${tool}}"
                --version-string=${PROJECT_VERSION} --include=${PROJECT_SOURCE_DIR}/docs/man-common.h2m
                --output=${page} $<TARGET_FILE:${tool}>
        DEPENDS ${tool} ${PROJECT_SOURCE_DIR}/docs/man-common.h2m
        COMMENT "Writing the man page of ${tool}"
        VERBATIM)
    list(APPEND navmap_man_pages ${page})
  endforeach()
  add_custom_target(navmap_man_pages ALL DEPENDS ${navmap_man_pages})
  set(navmap_daemon_man_pages ${navmap_man_pages})
  list(FILTER navmap_daemon_man_pages EXCLUDE REGEX "/navmap-(view|wayland)\\.1$")
  install(FILES ${navmap_daemon_man_pages} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT daemon)
  install(FILES ${PROJECT_BINARY_DIR}/man/navmap-view.1 DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT viewer)
  if(TARGET navmap-wayland)
    install(FILES ${PROJECT_BINARY_DIR}/man/navmap-wayland.1 DESTINATION ${CMAKE_INSTALL_MANDIR}/man1
            COMPONENT wayland)
  endif()
else()
  message(STATUS "help2man not found (or cross-compiling): no man pages (apt-get install help2man)")
endif()
endif()  # NAVMAP_WITH_DAEMON

# --- client and client-dev: libnavmap-client and how to use it ---
install(TARGETS navmap_client EXPORT navmapClientTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT client NAMELINK_COMPONENT client-dev)
install(FILES ${PROJECT_SOURCE_DIR}/ipc/client/include/navmap_client.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        COMPONENT client-dev)
install(FILES ${PROJECT_BINARY_DIR}/include/navmap/version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/navmap
        COMPONENT client-dev)
# The C++ API (stream_client.h, reconnecting_client.h) and what it includes, at the paths of the
# source tree: navmap/ipc/client/ and, of ipc/net (compiled into the library), navmap/ipc/net/.
foreach(header dmabuf_block frame_format frame_header frame_meta reconnecting_client stream_client stream_profile)
  install(FILES ${PROJECT_SOURCE_DIR}/ipc/client/include/navmap/ipc/client/${header}.h
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/navmap/ipc/client COMPONENT client-dev)
endforeach()
foreach(header backoff client_api result)
  install(FILES ${PROJECT_SOURCE_DIR}/ipc/net/include/navmap/ipc/net/${header}.h
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/navmap/ipc/net COMPONENT client-dev)
endforeach()
install(EXPORT navmapClientTargets NAMESPACE navmap:: DESTINATION ${NAVMAP_INSTALL_CMAKEDIR} COMPONENT client-dev)
configure_package_config_file(cmake/templates/navmapConfig.cmake.in ${PROJECT_BINARY_DIR}/cmake/navmapConfig.cmake
                              INSTALL_DESTINATION ${NAVMAP_INSTALL_CMAKEDIR})
# 0.x: a new minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/cmake/navmapConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/cmake/navmapConfig.cmake ${PROJECT_BINARY_DIR}/cmake/navmapConfigVersion.cmake
        DESTINATION ${NAVMAP_INSTALL_CMAKEDIR} COMPONENT client-dev)
# pkg-config: paths relative to the .pc file, so the installed tree can move like the rest.
file(RELATIVE_PATH NAVMAP_PC_PREFIX_FROM_PCDIR ${CMAKE_INSTALL_FULL_LIBDIR}/pkgconfig ${CMAKE_INSTALL_PREFIX})
string(REGEX REPLACE "/$" "" NAVMAP_PC_PREFIX_FROM_PCDIR "${NAVMAP_PC_PREFIX_FROM_PCDIR}")
configure_file(cmake/templates/navmap-client.pc.in ${PROJECT_BINARY_DIR}/navmap-client.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/navmap-client.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT client-dev)

# --- gstreamer: the navmapsrc plugin ---
# GStreamer's plugin directory relative to its prefix (Debian: lib/<multiarch>/gstreamer-1.0), under
# the prefix installed to: the packages' /usr puts it where GStreamer looks. The plugin finds
# libnavmap-client relative to itself, so a tree under another prefix works with GST_PLUGIN_PATH.
if(TARGET gstnavmap)
  pkg_get_variable(navmap_gst_prefix gstreamer-1.0 prefix)
  pkg_get_variable(navmap_gst_pluginsdir gstreamer-1.0 pluginsdir)
  file(RELATIVE_PATH navmap_gst_plugindir_default ${navmap_gst_prefix} ${navmap_gst_pluginsdir})
  set(NAVMAP_GST_PLUGIN_INSTALL_DIR ${navmap_gst_plugindir_default} CACHE STRING
      "Where libgstnavmap.so is installed, relative to the prefix")
  file(RELATIVE_PATH navmap_gst_to_libdir ${CMAKE_INSTALL_PREFIX}/${NAVMAP_GST_PLUGIN_INSTALL_DIR}
       ${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR})
  set_target_properties(gstnavmap PROPERTIES INSTALL_RPATH "$ORIGIN/${navmap_gst_to_libdir}")
  install(TARGETS gstnavmap LIBRARY DESTINATION ${NAVMAP_GST_PLUGIN_INSTALL_DIR} COMPONENT gstreamer)
  # GstNavmapFrameMeta for applications that read navmapsrc's buffers (header only).
  install(FILES ${PROJECT_SOURCE_DIR}/ipc/gst/include/navmap/gst/navmap_frame_meta.h
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/navmap/gst COMPONENT gstreamer)
endif()
