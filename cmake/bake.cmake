# Baked maps (strata bake, core/bake): 16-bit PNG through libpng, 32-bit
# float OpenEXR through tinyexr (Debian libtinyexr-dev: the shared library
# carries the implementation), compiled in one C++ translation unit
# (app/exr_io.cc) behind a C API (app/exr_io.h).  Included from the
# top-level CMakeLists.txt.
find_package(PNG REQUIRED)
find_path(STRATA_TINYEXR_INCLUDE tinyexr.h)
find_library(STRATA_TINYEXR_LIB tinyexr)
if(NOT STRATA_TINYEXR_INCLUDE OR NOT STRATA_TINYEXR_LIB)
  message(FATAL_ERROR "strata bake needs tinyexr (libtinyexr-dev): run scripts/setup.sh")
endif()
add_library(strata_exr STATIC ${CMAKE_SOURCE_DIR}/app/exr_io.cc)
target_include_directories(strata_exr PUBLIC ${CMAKE_SOURCE_DIR}/app)
# SYSTEM: tinyexr's own warnings must not fail -Werror builds.
target_include_directories(strata_exr SYSTEM PRIVATE ${STRATA_TINYEXR_INCLUDE})
target_link_libraries(strata_exr PUBLIC ${STRATA_TINYEXR_LIB})
