# SPDX-License-Identifier: Apache-2.0
# Install-time part of cmake/NavmapInstall.cmake (runs inside cmake_install.cmake, where
# CMAKE_INSTALL_PREFIX is the prefix being installed to and file(INSTALL) honours DESTDIR):
#   <sysconfdir>/navmap/navmapd.toml            /etc for the prefix /usr (FHS), else <prefix>/etc
#   <prefix>/lib/systemd/system/navmapd.service with that prefix's program and configuration paths
# Inputs: NAVMAP_SERVICE_TEMPLATE, NAVMAP_CONFIG_FILE, NAVMAP_STAGING_DIR, NAVMAP_BINDIR_REL,
# NAVMAP_DOCDIR_REL.
if(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  set(NAVMAP_SYSCONFDIR "/etc")
else()
  set(NAVMAP_SYSCONFDIR "${CMAKE_INSTALL_PREFIX}/etc")
endif()
set(NAVMAP_BINDIR "${CMAKE_INSTALL_PREFIX}/${NAVMAP_BINDIR_REL}")
set(NAVMAP_DOCDIR "${CMAKE_INSTALL_PREFIX}/${NAVMAP_DOCDIR_REL}")
configure_file("${NAVMAP_SERVICE_TEMPLATE}" "${NAVMAP_STAGING_DIR}/navmapd.service" @ONLY)
file(INSTALL "${NAVMAP_STAGING_DIR}/navmapd.service" DESTINATION "${CMAKE_INSTALL_PREFIX}/lib/systemd/system")
# An existing configuration is the administrator's: only a missing one is installed.
if(EXISTS "$ENV{DESTDIR}${NAVMAP_SYSCONFDIR}/navmap/navmapd.toml")
  message(STATUS "Keeping: $ENV{DESTDIR}${NAVMAP_SYSCONFDIR}/navmap/navmapd.toml")
else()
  file(INSTALL "${NAVMAP_CONFIG_FILE}" DESTINATION "${NAVMAP_SYSCONFDIR}/navmap")
endif()
