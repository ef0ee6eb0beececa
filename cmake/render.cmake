# The renderer library (render/*.c + the embedded shaders), included from the
# top-level CMakeLists.txt.  core/ stays free of any GL dependency: only
# strata_render (and what links it) sees OpenGL headers and OSMesa.
#
# Shaders: shaders/*.glsl are turned into string constants at build time
# (cmake/embed_shaders.cmake -> <build>/generated/shaders_embedded.c), so the
# strata executable runs from any directory.
find_path(STRATA_GL_INCLUDE GL/glcorearb.h)
find_path(STRATA_OSMESA_INCLUDE GL/osmesa.h)
find_library(STRATA_OSMESA_LIB OSMesa)
find_path(STRATA_STB_INCLUDE stb/stb_image_write.h)
if(NOT STRATA_GL_INCLUDE OR NOT STRATA_OSMESA_INCLUDE OR NOT STRATA_OSMESA_LIB OR NOT STRATA_STB_INCLUDE)
  message(FATAL_ERROR "strata_render needs the OpenGL headers (libgl-dev), OSMesa (libosmesa6-dev) "
                      "and stb (libstb-dev): run scripts/setup.sh")
endif()

set(STRATA_SHADER_DIR ${CMAKE_SOURCE_DIR}/shaders)
set(STRATA_SHADER_C ${CMAKE_BINARY_DIR}/generated/shaders_embedded.c)
file(GLOB STRATA_SHADER_FILES CONFIGURE_DEPENDS ${STRATA_SHADER_DIR}/*.glsl ${STRATA_SHADER_DIR}/*.glsl.inc)
add_custom_command(
  OUTPUT ${STRATA_SHADER_C}
  COMMAND ${CMAKE_COMMAND} -DSHADER_DIR=${STRATA_SHADER_DIR} -DOUT=${STRATA_SHADER_C}
          -P ${CMAKE_SOURCE_DIR}/cmake/embed_shaders.cmake
  DEPENDS ${STRATA_SHADER_FILES} ${CMAKE_SOURCE_DIR}/cmake/embed_shaders.cmake
  COMMENT "Embedding shaders/*.glsl"
  VERBATIM)

# Public headers (docs/ARCHITECTURE.md) are included as "render/<header>.h"
# from an include root that holds render alone (a link made here), as
# core's and formats' are.  The GL plumbing (shader programs, framebuffer
# objects, the embedded shaders) and the tessellator's case tables are
# render's own: those headers refuse to compile unless STRATA_RENDER_INTERNAL
# is defined, which only render itself and the tests that check its
# internals (strata_render_internal) define.
file(GLOB STRATA_RENDER_SOURCES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/render/*.c)
set(STRATA_RENDER_INCLUDE ${CMAKE_BINARY_DIR}/include-render)
file(MAKE_DIRECTORY ${STRATA_RENDER_INCLUDE})
file(CREATE_LINK ${CMAKE_SOURCE_DIR}/render ${STRATA_RENDER_INCLUDE}/render SYMBOLIC)
add_library(strata_render STATIC ${STRATA_RENDER_SOURCES} ${STRATA_SHADER_C})
target_include_directories(strata_render PUBLIC ${STRATA_RENDER_INCLUDE}
                                         PRIVATE ${STRATA_GL_INCLUDE} ${STRATA_OSMESA_INCLUDE} ${STRATA_STB_INCLUDE})
target_compile_definitions(strata_render PRIVATE STRATA_RENDER_INTERNAL=1)
# For the tests that check render's internals (the case tables, the shaders).
add_library(strata_render_internal INTERFACE)
target_compile_definitions(strata_render_internal INTERFACE STRATA_RENDER_INTERNAL=1)
target_link_libraries(strata_render_internal INTERFACE strata_render)
# OSMesa is opened with dlopen on first use (render/headless.c), not linked.
target_link_libraries(strata_render PUBLIC strata_core ${CMAKE_DL_LIBS})
target_compile_definitions(strata_render PRIVATE STRATA_OSMESA_PATH="${STRATA_OSMESA_LIB}")
