# What `cmake --install` puts in place and `cpack -G DEB` packages
# (README.md, "Install"), in Debian's layout (GNUInstallDirs), included from the
# top-level CMakeLists.txt:
#
#   bin/strata                                  the executable (shaders are
#                                               embedded: cmake/embed_shaders.cmake)
#   share/strata/assets/*.obj                   sample models; the window opens
#                                               torus.obj with no FILE (ui/window.c)
#   share/applications/strata.desktop           the menu entry
#   share/icons/hicolor/{scalable,256x256}/apps the icon (SVG, PNG)
#   share/man/man1/strata.1.gz                  generated from `strata help`
#                                               (cmake/manpage.sh)
#   lib/libstrata_core.a                        the kernel (lib/<multiarch> with
#                                               the prefix /usr)
#   include/strata/core/<folder>/<header>.h     its public headers: every core
#                                               header but the *_internal.h ones
#                                               (which #error outside core), under
#                                               the "core/<folder>/<header>.h"
#                                               names they include each other by
#   lib/pkgconfig/strata.pc                     -I<prefix>/include/strata,
#                                               -lstrata_core -lm -lpthread
#
# With STRATA_CORE_ONLY only the kernel, its headers and strata.pc.

# ---- the kernel ---------------------------------------------------------------
install(TARGETS strata_core ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY ${CMAKE_SOURCE_DIR}/core/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/strata/core
        FILES_MATCHING PATTERN "*.h" PATTERN "*_internal.h" EXCLUDE)

# strata.pc finds its prefix from its own folder (${pcfiledir}), so that the
# tree can be moved: the path up from <libdir>/pkgconfig to the prefix.
# An absolute libdir or includedir outside the prefix stays absolute.
set(pc_dir ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
if(IS_ABSOLUTE ${CMAKE_INSTALL_LIBDIR})
  set(STRATA_PC_PREFIX ${CMAKE_INSTALL_PREFIX})
  set(STRATA_PC_LIBDIR ${CMAKE_INSTALL_LIBDIR})
else()
  file(RELATIVE_PATH up ${CMAKE_INSTALL_PREFIX}/${pc_dir} ${CMAKE_INSTALL_PREFIX})
  string(REGEX REPLACE "/$" "" up "${up}")
  set(STRATA_PC_PREFIX "\${pcfiledir}/${up}")
  set(STRATA_PC_LIBDIR "\${prefix}/${CMAKE_INSTALL_LIBDIR}")
endif()
if(IS_ABSOLUTE ${CMAKE_INSTALL_INCLUDEDIR})
  set(STRATA_PC_INCLUDEDIR ${CMAKE_INSTALL_INCLUDEDIR})
else()
  set(STRATA_PC_INCLUDEDIR "\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}")
endif()
configure_file(${CMAKE_SOURCE_DIR}/packaging/strata.pc.in ${CMAKE_BINARY_DIR}/strata.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/strata.pc DESTINATION ${pc_dir})

# ---- the modeller -------------------------------------------------------------
if(TARGET strata)
  install(TARGETS strata RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/assets/ DESTINATION ${CMAKE_INSTALL_DATADIR}/strata/assets
          FILES_MATCHING PATTERN "*.obj")
  install(FILES ${CMAKE_SOURCE_DIR}/packaging/strata.desktop DESTINATION ${CMAKE_INSTALL_DATADIR}/applications)
  install(FILES ${CMAKE_SOURCE_DIR}/packaging/strata.svg
          DESTINATION ${CMAKE_INSTALL_DATADIR}/icons/hicolor/scalable/apps)
  install(FILES ${CMAKE_SOURCE_DIR}/packaging/strata.png
          DESTINATION ${CMAKE_INSTALL_DATADIR}/icons/hicolor/256x256/apps)
  # The man page, from the help text of the strata just built.
  set(STRATA_MAN ${CMAKE_BINARY_DIR}/man/strata.1.gz)
  add_custom_command(
    OUTPUT ${STRATA_MAN}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_BINARY_DIR}/man
    COMMAND sh ${CMAKE_SOURCE_DIR}/cmake/manpage.sh $<TARGET_FILE:strata> ${PROJECT_VERSION} ${STRATA_MAN}
    DEPENDS strata ${CMAKE_SOURCE_DIR}/cmake/manpage.sh
    COMMENT "Writing the man page strata(1) from strata help"
    VERBATIM)
  add_custom_target(strata_man ALL DEPENDS ${STRATA_MAN})
  install(FILES ${STRATA_MAN} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
endif()

# ---- cpack -G DEB ---------------------------------------------------------------
# One package, strata, installed under /usr.  Its Depends: the shared
# libraries strata links, found by dpkg-shlibdeps (dpkg-dev), plus the two
# it opens at run time, which no tool can see: libOSMesa.so.8 (headless
# render, render/headless.c) and libGL.so.1 (the window's GUI, through
# Dear ImGui's OpenGL 3 backend).
set(CPACK_PACKAGE_NAME strata)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "multiresolution subdivision modeller")
string(JOIN "\n" CPACK_PACKAGE_DESCRIPTION
  "Strata opens a coarse mesh, subdivides it with a scheme (Catmull-Clark,"
  "Loop, Doo-Sabin, sqrt3, quad/triangle, modified Butterfly) and sculpts at"
  "any level; finer levels keep their details as vectors in local frames."
  "It also holds the kernel, libstrata_core, as a static library with its"
  "public headers and a pkg-config file (strata).")
set(CPACK_PACKAGE_CONTACT "Strata developers <strata@localhost>")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
if(TARGET strata)
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "libosmesa6, libgl1")
endif()
include(CPack)
