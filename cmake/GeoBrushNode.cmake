# geobrush_add_node(NAME ALGORITHM <sources> NODE <sources> [LIBS <targets>])
#
# One node folder builds two targets:
#   geobrush_<NAME>_algo  static library with the algorithm as plain functions
#                         (what the node's gtest suite links);
#   geobrush_<NAME>       the plugin (a MODULE library named geobrush_<NAME>.so
#                         in the plugin directory) with the node wrapper and
#                         the GEOBRUSH_PLUGIN entry points.
# Works in this tree and out of tree against an installed GeoBrush.
function(geobrush_add_node NAME)
  cmake_parse_arguments(ARG "" "" "ALGORITHM;NODE;LIBS" ${ARGN})
  if(NOT ARG_NODE)
    message(FATAL_ERROR "geobrush_add_node(${NAME}): NODE sources are required")
  endif()
  if(TARGET geobrush_core)
    set(core geobrush_core)
  else()
    set(core GeoBrush::geobrush_core)
  endif()

  # A node whose algorithm lives in core (e.g. the renderer) has no ALGORITHM.
  set(algo geobrush_${NAME}_algo)
  if(ARG_ALGORITHM)
    add_library(${algo} STATIC ${ARG_ALGORITHM})
    set_target_properties(${algo} PROPERTIES POSITION_INDEPENDENT_CODE ON
                                             CXX_VISIBILITY_PRESET hidden
                                             VISIBILITY_INLINES_HIDDEN ON)
    target_include_directories(${algo} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
    target_link_libraries(${algo} PUBLIC ${core} ${ARG_LIBS})
  else()
    add_library(${algo} INTERFACE)
    target_include_directories(${algo} INTERFACE ${CMAKE_CURRENT_SOURCE_DIR})
    target_link_libraries(${algo} INTERFACE ${core} ${ARG_LIBS})
  endif()

  set(plugin geobrush_${NAME})
  add_library(${plugin} MODULE ${ARG_NODE})
  target_link_libraries(${plugin} PRIVATE ${algo})
  # In the GeoBrush tree the node libraries share one precompiled header (nodes/CMakeLists.txt).
  if(TARGET geobrush_node_precompiled)
    target_precompile_headers(${plugin} REUSE_FROM geobrush_node_precompiled)
    if(ARG_ALGORITHM)
      target_precompile_headers(${algo} REUSE_FROM geobrush_node_precompiled)
    endif()
  endif()
  if(DEFINED GEOBRUSH_NO_UNDEFINED)
    target_link_options(${plugin} PRIVATE ${GEOBRUSH_NO_UNDEFINED})
  else()
    target_link_options(${plugin} PRIVATE -Wl,--no-undefined)
  endif()
  if(NOT GEOBRUSH_PLUGIN_OUTPUT_DIR)
    set(GEOBRUSH_PLUGIN_OUTPUT_DIR ${CMAKE_BINARY_DIR}/plugins)
  endif()
  set_target_properties(${plugin} PROPERTIES PREFIX ""
                                             CXX_VISIBILITY_PRESET hidden
                                             VISIBILITY_INLINES_HIDDEN ON
                                             LIBRARY_OUTPUT_DIRECTORY ${GEOBRUSH_PLUGIN_OUTPUT_DIR})
  if(GEOBRUSH_PLUGIN_INSTALL_DIR)
    # Installed plugins sit in <prefix>/lib/geobrush/plugins, beside <prefix>/lib.
    set_target_properties(${plugin} PROPERTIES INSTALL_RPATH "$ORIGIN/../..")
    install(TARGETS ${plugin} LIBRARY DESTINATION ${GEOBRUSH_PLUGIN_INSTALL_DIR})
  endif()
  set_property(GLOBAL APPEND PROPERTY GEOBRUSH_NODE_PLUGINS ${plugin})
endfunction()
