# roam's plugin SDK, installed: find_package(roam CONFIG REQUIRED) gives
#   roam::sdk          the plugin SDK (roam/estimator.hpp, roam/plugin_shim.hpp, roam/options.hpp)
#   roam::estimation   the shared estimation maths (roam/estimation/*.hpp; needs Eigen and Ceres)
#   roam_add_plugin(NAME <name> SOURCES <files> [LIBRARIES <libs>])
#                      builds libroam_<name>.so, installed to <prefix>/lib/roam/plugins; roam-run
#                      finds it through [runtime] plugin_path (the build folder, or that folder).
include(CMakeFindDependencyMacro)
find_dependency(Eigen3 3.3 NO_MODULE)
find_dependency(Ceres)  # roam::estimation's robust multilateration
include(${CMAKE_CURRENT_LIST_DIR}/roamTargets.cmake)

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
