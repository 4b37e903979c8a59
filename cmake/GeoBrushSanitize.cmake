# GEOBRUSH_SANITIZE: every target built with AddressSanitizer and UndefinedBehaviorSanitizer at
# -O2 (clang compiles it in the time of -O1, and Eigen's code runs far faster inlined); any report
# ends the program with a failure. GEOBRUSH_FUZZ (clang, with GEOBRUSH_SANITIZE):
# core is instrumented for coverage and the libFuzzer targets of tests/fuzz are built.
# The programs read the runtimes' options from sanitizer_defaults.cpp, compiled into each of them
# (geobrush_use_sanitizer_defaults), so that ctest, test discovery and a program run by hand
# report alike.
if(GEOBRUSH_FUZZ AND NOT GEOBRUSH_SANITIZE)
  message(FATAL_ERROR "GEOBRUSH_FUZZ needs GEOBRUSH_SANITIZE=ON")
endif()
if(GEOBRUSH_FUZZ AND NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "GEOBRUSH_FUZZ needs clang (libFuzzer): configure with CXX=clang++-14")
endif()

# Shared libraries link with --no-undefined, except where clang leaves the sanitizer runtime to
# the programs (it links it statically into executables only).
set(GEOBRUSH_NO_UNDEFINED -Wl,--no-undefined)
if(GEOBRUSH_SANITIZE)
  set(sanitizers -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_compile_options(-O2 ${sanitizers})
  add_link_options(${sanitizers})
  if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    set(GEOBRUSH_NO_UNDEFINED "")
  endif()
  add_library(geobrush_sanitizer_defaults OBJECT ${CMAKE_CURRENT_LIST_DIR}/sanitizer_defaults.cpp)
endif()

function(geobrush_use_sanitizer_defaults TARGET)
  if(TARGET geobrush_sanitizer_defaults)
    target_sources(${TARGET} PRIVATE $<TARGET_OBJECTS:geobrush_sanitizer_defaults>)
  endif()
endfunction()
