# Baked maps (core/bake) to files: the driver of `strata bake` and of the
# window's Bake menu (bakeio/bake_run.h), 16-bit PNG through libpng, 32-bit
# float OpenEXR through tinyexr (Debian libtinyexr-dev: the shared library
# carries the implementation), compiled in one C++ translation unit
# (bakeio/exr_io.cc) behind a C API (bakeio/exr_io.h).  strata_bakeio sits
# on core alone; app/ and ui/ both use it.  Included from the top-level
# CMakeLists.txt.
find_package(PNG REQUIRED)
find_path(STRATA_TINYEXR_INCLUDE tinyexr.h)
find_library(STRATA_TINYEXR_LIB tinyexr)
if(NOT STRATA_TINYEXR_INCLUDE OR NOT STRATA_TINYEXR_LIB)
  message(FATAL_ERROR "strata bake needs tinyexr (libtinyexr-dev): run scripts/setup.sh")
endif()
file(GLOB STRATA_BAKEIO_SOURCES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/bakeio/*.c ${CMAKE_SOURCE_DIR}/bakeio/*.cc)
add_library(strata_bakeio STATIC ${STRATA_BAKEIO_SOURCES})
target_include_directories(strata_bakeio PUBLIC ${CMAKE_SOURCE_DIR}/bakeio)
# SYSTEM: tinyexr's own warnings must not fail -Werror builds.
target_include_directories(strata_bakeio SYSTEM PRIVATE ${STRATA_TINYEXR_INCLUDE})
target_link_libraries(strata_bakeio PUBLIC strata_core PNG::PNG ${STRATA_TINYEXR_LIB})
