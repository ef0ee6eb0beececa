# formats/: the files other programs read and write, on core alone
# (docs/ARCHITECTURE.md), as one library, strata_formats:
#   gltf_io.h     glTF 2.0 import and export through tinygltf (Debian
#                 libtinygltf-dev), compiled in one C++ translation unit
#                 (gltf_io.cc) behind a C API; Debian 12's tinygltf needs
#                 nlohmann-json3-dev and -I/usr/include/stb (it includes
#                 stb_image.h bare);
#   exr_io.h      32-bit float OpenEXR through tinyexr (Debian
#                 libtinyexr-dev: the shared library carries the
#                 implementation), one C++ translation unit (exr_io.cc);
#   bake_images.h the baked maps as 8/16-bit PNG (libpng) and EXR;
#   bake_run.h    the driver of `strata bake` and of the window's Bake menu;
#   mesh_any.h    mesh files of every format: glTF here, the rest core's.
# Everything includes them as "formats/<header>.h" from an include root
# that holds formats alone (a link made here), as core's headers come from
# one that holds core alone.  app/ and ui/ use it; core and render do not.
# Included from the top-level CMakeLists.txt.
find_package(PNG REQUIRED)
find_path(STRATA_TINYEXR_INCLUDE tinyexr.h)
find_library(STRATA_TINYEXR_LIB tinyexr)
if(NOT STRATA_TINYEXR_INCLUDE OR NOT STRATA_TINYEXR_LIB)
  message(FATAL_ERROR "strata bake needs tinyexr (libtinyexr-dev): run scripts/setup.sh")
endif()
find_path(STRATA_TINYGLTF_INCLUDE tiny_gltf.h)
if(NOT STRATA_TINYGLTF_INCLUDE)
  message(FATAL_ERROR "glTF needs tinygltf (libtinygltf-dev, nlohmann-json3-dev): run scripts/setup.sh")
endif()
file(GLOB STRATA_FORMATS_SOURCES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/formats/*.c ${CMAKE_SOURCE_DIR}/formats/*.cc)
set(STRATA_FORMATS_INCLUDE ${CMAKE_BINARY_DIR}/include-formats)
file(MAKE_DIRECTORY ${STRATA_FORMATS_INCLUDE})
file(CREATE_LINK ${CMAKE_SOURCE_DIR}/formats ${STRATA_FORMATS_INCLUDE}/formats SYMBOLIC)
add_library(strata_formats STATIC ${STRATA_FORMATS_SOURCES})
target_include_directories(strata_formats PUBLIC ${STRATA_FORMATS_INCLUDE})
# SYSTEM: tinygltf's and tinyexr's own warnings must not fail -Werror builds.
target_include_directories(strata_formats SYSTEM PRIVATE ${STRATA_TINYGLTF_INCLUDE} /usr/include/stb
                                                         ${STRATA_TINYEXR_INCLUDE})
target_link_libraries(strata_formats PUBLIC strata_core PNG::PNG ${STRATA_TINYEXR_LIB})
if(STRATA_FUZZ)
  # The glTF fuzzers see the reader's edges.
  target_compile_options(strata_formats PRIVATE -fsanitize=fuzzer-no-link)
endif()
