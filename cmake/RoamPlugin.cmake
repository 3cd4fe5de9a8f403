# roam_add_plugin(NAME <name> SOURCES <shim sources> LIBRARIES <core libs>)
#
# Builds lib/roam/plugins/libroam_<name>.so from the plugin's ABI shim, linked to its core
# library and the plugin SDK; only roam_plugin_entry is exported.
function(roam_add_plugin)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;LIBRARIES" ${ARGN})
  set(target roam_plugin_${ARG_NAME})
  add_library(${target} MODULE ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE roam_sdk ${ARG_LIBRARIES})
  set_target_properties(${target} PROPERTIES
    OUTPUT_NAME roam_${ARG_NAME}
    PREFIX "lib"
    LIBRARY_OUTPUT_DIRECTORY ${ROAM_PLUGIN_OUTPUT_DIR}
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
  target_link_options(${target} PRIVATE -Wl,--no-undefined)
  install(TARGETS ${target} LIBRARY DESTINATION ${ROAM_PLUGIN_INSTALL_DIR})
  set_property(GLOBAL APPEND PROPERTY ROAM_PLUGIN_TARGETS ${target})
endfunction()

# roam_add_gtest(<name> SOURCES ... LIBRARIES ... [LABELS ...] [STUDY <gtest pattern>...]):
# a GoogleTest binary registered with ctest. The tests STUDY names (Suite.Test or Suite.*) are
# accuracy studies, long multi-seed replays: they are labelled "study" (besides LABELS), which
# the sanitizer pass of utilities/test leaves to the Release pass (ctest -LE study).
function(roam_add_gtest name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBRARIES;LABELS;STUDY" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE GTest::gtest GTest::gmock GTest::gtest_main ${ARG_LIBRARIES})
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
  target_compile_definitions(${name} PRIVATE
    ROAM_SOURCE_DIR="${CMAKE_SOURCE_DIR}" ROAM_BINARY_DIR="${CMAKE_BINARY_DIR}")
  # -O1 (after the build type's -O3, so it wins): a test's own code sets up, calls the libraries
  # (built as the build type says) and compares; at -O3 GCC spent 43 % more time on each test file
  # (ekf_slam_test.cpp 42 s against 24 s) for code that runs once. Same IEEE arithmetic, so the
  # same figures.
  target_compile_options(${name} PRIVATE -O1)
  if(ARG_STUDY)
    list(JOIN ARG_STUDY ":" studies)
    gtest_discover_tests(${name} DISCOVERY_TIMEOUT 120 TEST_FILTER "-${studies}"
      WORKING_DIRECTORY ${CMAKE_BINARY_DIR}/tests PROPERTIES LABELS "${ARG_LABELS}")
    gtest_discover_tests(${name} DISCOVERY_TIMEOUT 120 TEST_FILTER "${studies}"
      WORKING_DIRECTORY ${CMAKE_BINARY_DIR}/tests PROPERTIES LABELS "study;${ARG_LABELS}")
  else()
    gtest_discover_tests(${name} DISCOVERY_TIMEOUT 120
      WORKING_DIRECTORY ${CMAKE_BINARY_DIR}/tests PROPERTIES LABELS "${ARG_LABELS}")
  endif()
endfunction()
