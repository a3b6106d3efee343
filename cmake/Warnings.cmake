# laserfit_warnings(<target>): warnings on, and -Werror for our own code only (third-party headers
# are included as SYSTEM so their warnings never fail our build).
function(laserfit_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Werror)
endfunction()

# laserfit_library(<name> SOURCES ... PARSERS ... DEPS ...): one CMake target per pipeline stage,
# the way small_gicp and KISS-ICP lay out theirs: lib/<name>/include/laserfit/<name>/*.hpp +
# src/*.cpp. Each is installed as a component of the CMake package (laserfit::<name>,
# cmake/Package.cmake). PARSERS are the sources that read untrusted input (files, the strings a
# user types): the ones the fuzz targets explore, so the ones that carry libFuzzer's coverage.
function(laserfit_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PARSERS;DEPS" ${ARGN})
  add_library(laserfit_${name} STATIC ${ARG_SOURCES} ${ARG_PARSERS})
  if(LASERFIT_FUZZ AND ARG_PARSERS)
    set_source_files_properties(${ARG_PARSERS} PROPERTIES COMPILE_OPTIONS -fsanitize=fuzzer-no-link)
  endif()
  add_library(laserfit::${name} ALIAS laserfit_${name})
  set_target_properties(laserfit_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(laserfit_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(laserfit_${name} PUBLIC ${ARG_DEPS})
  laserfit_warnings(laserfit_${name})
  install(TARGETS laserfit_${name} EXPORT laserfit_${name}_targets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(EXPORT laserfit_${name}_targets DESTINATION ${LASERFIT_CMAKE_DIR} NAMESPACE laserfit::)
  set_property(GLOBAL APPEND PROPERTY LASERFIT_COMPONENTS ${name})
endfunction()
