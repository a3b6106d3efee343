# LASERFIT_SANITIZE: every target of ours compiled and linked with ASan + UBSan, and any UBSan
# report is fatal (a report that only prints would let the test pass). Third-party libraries are
# Debian's prebuilt ones and stay uninstrumented.
if(LASERFIT_SANITIZE)
  set(LASERFIT_SANITIZER_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=all
      -fno-omit-frame-pointer -gline-tables-only)
  add_compile_options(${LASERFIT_SANITIZER_FLAGS})
  add_link_options(-fsanitize=address,undefined)
endif()
# LASERFIT_FUZZ: coverage instrumentation for libFuzzer on the sources that read untrusted input
# (laserfit_library PARSERS) and the fuzz targets, which link libFuzzer's main (tests/fuzz). Not on
# everything: its comparison tracing calls back on every integer comparison, which made the
# numeric stages (registration, scanning), and so the sanitized test suite, several times slower.
if(LASERFIT_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "LASERFIT_FUZZ needs clang (make fuzz sets CXX=clang++)")
  endif()
  if(NOT LASERFIT_SANITIZE)
    message(FATAL_ERROR "LASERFIT_FUZZ needs LASERFIT_SANITIZE=ON (findings are sanitizer reports)")
  endif()
endif()
