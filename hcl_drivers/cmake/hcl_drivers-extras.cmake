# Build helpers for packages whose components are nodelet plugins (hcl_drivers' boards, hal_nodes'
# devices): no plugin XML is written by hand.
#
#   generate_nodelet_plugin_xml(<library target> <export macro> <source>...)
#
# scans the sources for the export macro (HCL_EXPORT_BOARD(Class, "description") or
# HAL_EXPORT_DEVICE(Class, Type, "description")) and writes <package>/nodelet_plugins.xml at build
# time, the file package.xml's <nodelet plugin="${prefix}/nodelet_plugins.xml"/> points to.
# It is generated (git ignores it); the package installs it like a written one.
set(HCL_DRIVERS_PLUGIN_XML_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/generate_plugin_xml.cmake)

function(generate_nodelet_plugin_xml library macro)
  set(output ${PROJECT_SOURCE_DIR}/nodelet_plugins.xml)
  # a list cannot pass through a COMMAND argument (it would split): '|' separates the sources
  string(REPLACE ";" "|" sources "${ARGN}")
  add_custom_command(OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${output} -DMACRO=${macro} -DPACKAGE=${PROJECT_NAME}
            -DLIBRARY=lib${library} -DSOURCES=${sources} -P ${HCL_DRIVERS_PLUGIN_XML_SCRIPT}
    DEPENDS ${ARGN} ${HCL_DRIVERS_PLUGIN_XML_SCRIPT}
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
    COMMENT "${PROJECT_NAME}/nodelet_plugins.xml from the ${macro} lines"
    VERBATIM)
  add_custom_target(${library}_plugin_xml ALL DEPENDS ${output})
endfunction()
