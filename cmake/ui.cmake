# The modeller (ui/README.md), included from the top-level CMakeLists.txt.
# Dependencies point one way: ui -> render -> core; core and render know
# nothing of ui.
# The document (ui/doc/, no GL): the library strata_editor, chosen by folder.
# Its headers are included by their names ("editor.h") from ui/doc.
file(GLOB STRATA_EDITOR_SOURCES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/ui/doc/*.c)
if(STRATA_EDITOR_SOURCES)
  add_library(strata_editor STATIC ${STRATA_EDITOR_SOURCES})
  target_include_directories(strata_editor PUBLIC ${CMAKE_SOURCE_DIR}/ui/doc)
  target_link_libraries(strata_editor PUBLIC strata_core)
  # Core's public headers only: edits report their footprints
  # (core/multires/edit.h), so the document needs none of core's internals.
endif()

# The window: ui/*.c and ui/*.cc (the folders below are libraries of their own).
file(GLOB STRATA_UI_SOURCES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/ui/*.c ${CMAKE_SOURCE_DIR}/ui/*.cc)
# `strata --bench-interaction` (st_window_bench): the benchmark's driver
# lives in bench/ but needs the window's document, renderer and context.
if(STRATA_UI_SOURCES)
  list(APPEND STRATA_UI_SOURCES ${CMAKE_SOURCE_DIR}/bench/interaction.c)
endif()
# The window needs the document (ui/doc/editor.c): without it strata_ui is not
# built and `strata` without a subcommand says the window is missing.
if(STRATA_UI_SOURCES AND TARGET strata_editor AND EXISTS ${CMAKE_SOURCE_DIR}/ui/doc/editor.c)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(GLFW3 REQUIRED IMPORTED_TARGET glfw3)
  add_library(strata_ui STATIC ${STRATA_UI_SOURCES})
  target_include_directories(strata_ui PUBLIC ${CMAKE_SOURCE_DIR}/ui
                                       PRIVATE ${STRATA_GL_INCLUDE} ${STRATA_STB_INCLUDE})
  target_link_libraries(strata_ui PUBLIC strata_render strata_core PkgConfig::GLFW3)
  # The default model of `strata` with no FILE (overridable by $STRATA_ASSETS):
  # the installed copy (cmake/install.cmake), found relative to the
  # executable, else the source tree's.
  file(RELATIVE_PATH STRATA_INSTALLED_ASSETS ${CMAKE_INSTALL_FULL_BINDIR}
       ${CMAKE_INSTALL_FULL_DATADIR}/strata/assets)
  target_compile_definitions(strata_ui PRIVATE STRATA_ASSETS="${CMAKE_SOURCE_DIR}/assets"
                                               STRATA_INSTALLED_ASSETS="${STRATA_INSTALLED_ASSETS}")
  if(TARGET strata_editor)
    target_link_libraries(strata_ui PUBLIC strata_editor)
  endif()
  # The GUI (ui/gui*.cc and ui/file_browser.cc, the C++ files of ui/): Dear ImGui 1.86 from
  # Debian's libimgui-dev, whose static libimgui.a holds the GLFW and
  # OpenGL 3 backends; the OpenGL 3 backend loads libGL by itself (dlopen).
  # Export writes glTF, and Bake writes maps, through strata_formats
  # (cmake/formats.cmake).
  pkg_check_modules(IMGUI REQUIRED IMPORTED_TARGET imgui)
  target_link_libraries(strata_ui PUBLIC PkgConfig::IMGUI ${CMAKE_DL_LIBS} strata_formats)
  target_compile_definitions(strata_ui PRIVATE STRATA_VERSION="${PROJECT_VERSION}")
endif()
