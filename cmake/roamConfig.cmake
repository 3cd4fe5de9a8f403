# roam's plugin SDK, installed: find_package(roam CONFIG REQUIRED) gives
#   roam::sdk          the plugin SDK (roam/estimator.hpp, roam/plugin_shim.hpp, roam/options.hpp)
#   roam::estimation   the shared estimation maths (roam/estimation/*.hpp; needs Eigen and Ceres,
#                      defined when both are found: COMPONENTS estimation to require it)
#   roam_add_plugin(NAME <name> SOURCES <files> [LIBRARIES <libs>])
#                      builds libroam_<name>.so, installed to <prefix>/lib/roam/plugins; roam-run
#                      finds it through [runtime] plugin_path (the build folder, or that folder).
# roam::sdk needs nothing beyond a C++17 compiler. roam::estimation needs Eigen and Ceres: it is
# defined when both are found, and find_package(roam CONFIG REQUIRED COMPONENTS estimation) fails
# naming what is missing when they are not.
include(${CMAKE_CURRENT_LIST_DIR}/roamTargets.cmake)
find_package(Eigen3 3.3 QUIET NO_MODULE)
find_package(Ceres QUIET)
if(Eigen3_FOUND AND Ceres_FOUND)
  include(${CMAKE_CURRENT_LIST_DIR}/roamEstimationTargets.cmake)
  set(roam_estimation_FOUND TRUE)
else()
  set(roam_estimation_FOUND FALSE)
  if("estimation" IN_LIST roam_FIND_COMPONENTS)
    set(roam_NOT_FOUND_MESSAGE "roam::estimation needs Eigen3 and Ceres (Debian: libeigen3-dev libceres-dev)")
  endif()
endif()
set(roam_sdk_FOUND TRUE)
if(roam_FIND_REQUIRED AND NOT roam_estimation_FOUND AND "estimation" IN_LIST roam_FIND_COMPONENTS)
  set(roam_FOUND FALSE)
endif()

function(roam_add_plugin)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;LIBRARIES" ${ARGN})
  if(NOT ARG_NAME OR NOT ARG_SOURCES)
    message(FATAL_ERROR "roam_add_plugin: NAME and SOURCES are required")
  endif()
  set(target roam_plugin_${ARG_NAME})
  add_library(${target} MODULE ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE roam::sdk ${ARG_LIBRARIES})
  target_compile_features(${target} PRIVATE cxx_std_17)
  set_target_properties(${target} PROPERTIES
    OUTPUT_NAME roam_${ARG_NAME}
    PREFIX "lib"
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
  target_link_options(${target} PRIVATE -Wl,--no-undefined)
  install(TARGETS ${target} LIBRARY DESTINATION lib/roam/plugins)
endfunction()
