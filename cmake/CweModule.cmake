# cwe_add_module(NAME <name> SOURCES <files...> [DEPENDS <targets...>] [PRIVATE_DEPENDS <targets...>])
#
# One library target per module (see docs/architecture.md): cwe_<name>, aliased cwe::<name>.
# Public headers live in include/cwe/<name>/, sources and private headers in src/<name>/.
function(cwe_add_module)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;DEPENDS;PRIVATE_DEPENDS" ${ARGN})
  add_library(cwe_${ARG_NAME} STATIC ${ARG_SOURCES})
  add_library(cwe::${ARG_NAME} ALIAS cwe_${ARG_NAME})
  target_include_directories(cwe_${ARG_NAME} PUBLIC ${PROJECT_SOURCE_DIR}/include
                             PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  target_link_libraries(cwe_${ARG_NAME} PUBLIC cwe_options ${ARG_DEPENDS}
                        PRIVATE ${ARG_PRIVATE_DEPENDS})
  install(TARGETS cwe_${ARG_NAME} ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}")
endfunction()
