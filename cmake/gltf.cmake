# glTF 2.0 import/export through tinygltf (Debian libtinygltf-dev), included
# from the top-level CMakeLists.txt.  tinygltf is C++: it is compiled in one
# translation unit (app/gltf*.cc) behind a C API (app/gltf_io.h), in its own
# library so tests and fuzzers link it too.  Debian 12's tinygltf needs
# nlohmann-json3-dev and -I/usr/include/stb (it includes stb_image.h bare).
file(GLOB STRATA_GLTF_SOURCES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/app/gltf*.cc)
if(STRATA_GLTF_SOURCES)
  find_path(STRATA_TINYGLTF_INCLUDE tiny_gltf.h)
  if(NOT STRATA_TINYGLTF_INCLUDE)
    message(FATAL_ERROR "glTF needs tinygltf (libtinygltf-dev, nlohmann-json3-dev): run scripts/setup.sh")
  endif()
  add_library(strata_gltf STATIC ${STRATA_GLTF_SOURCES})
  target_include_directories(strata_gltf PUBLIC ${CMAKE_SOURCE_DIR}/app)
  # SYSTEM: tinygltf's own warnings must not fail -Werror builds.
  target_include_directories(strata_gltf SYSTEM PRIVATE ${STRATA_TINYGLTF_INCLUDE} /usr/include/stb)
  target_link_libraries(strata_gltf PUBLIC strata_core)
  if(STRATA_FUZZ)
    target_compile_options(strata_gltf PRIVATE -fsanitize=fuzzer-no-link)
  endif()
endif()
