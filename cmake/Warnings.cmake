# laserfit_warnings(<target>): warnings on, and -Werror for our own code only (third-party headers
# are included as SYSTEM so their warnings never fail our build).
function(laserfit_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Werror)
endfunction()

# laserfit_library(<name> SOURCES ... DEPS ...): one CMake target per pipeline stage, the way
# small_gicp and KISS-ICP lay out theirs: lib/<name>/include/laserfit/<name>/*.hpp + src/*.cpp.
function(laserfit_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_library(laserfit_${name} STATIC ${ARG_SOURCES})
  add_library(laserfit::${name} ALIAS laserfit_${name})
  target_include_directories(laserfit_${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_link_libraries(laserfit_${name} PUBLIC ${ARG_DEPS})
  laserfit_warnings(laserfit_${name})
endfunction()
