# dynslam_module(NAME [DEPS target...] [PRIVATE_DEPS target...])
#   Builds the static library dynslam_NAME from every .cpp in the calling folder.
#   DEPS are what its headers include (PUBLIC: a user of the module needs
#   them too); PRIVATE_DEPS what only its .cpp files use. PRIVATE_DEPS come
#   first on the link line (render/ relies on that for OSMesa).
#   Headers are included as "<folder>/<header>.h" relative to the module's parent
#   (lib/ for lib modules, the repo root for rawlog/ and render/).
function(dynslam_module NAME)
  cmake_parse_arguments(M "" "" "DEPS;PRIVATE_DEPS" ${ARGN})
  file(GLOB _srcs CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/*.cpp")
  add_library(dynslam_${NAME} STATIC ${_srcs})
  get_filename_component(_parent "${CMAKE_CURRENT_SOURCE_DIR}" DIRECTORY)
  target_include_directories(dynslam_${NAME} PUBLIC "${_parent}")
  if(M_PRIVATE_DEPS)
    target_link_libraries(dynslam_${NAME} PRIVATE ${M_PRIVATE_DEPS})
  endif()
  target_link_libraries(dynslam_${NAME} PUBLIC ${M_DEPS})
  target_compile_definitions(dynslam_${NAME} PRIVATE
    DYNSLAM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
endfunction()

# dynslam_test(MODULE [DEPS target...])
#   One GoogleTest executable test_MODULE from every .cpp in tests/MODULE/,
#   each test case registered with CTest.
function(dynslam_test MODULE)
  cmake_parse_arguments(T "" "" "DEPS" ${ARGN})
  file(GLOB _srcs CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/*.cpp")
  if(NOT _srcs)
    return()
  endif()
  add_executable(test_${MODULE} ${_srcs})
  target_link_libraries(test_${MODULE} PRIVATE dynslam_testing ${T_DEPS} GTest::gtest_main)
  gtest_discover_tests(test_${MODULE}
    DISCOVERY_TIMEOUT 60
    PROPERTIES ENVIRONMENT "DYNSLAM_BINARY_DIR=${PROJECT_BINARY_DIR}")
endfunction()
