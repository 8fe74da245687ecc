# Build options. Optional dependencies take AUTO (use when found), ON (fail when missing) or OFF.
set(PC_WITH_ARAVIS AUTO CACHE STRING "Aravis GigE Vision / USB3 Vision backend (AUTO|ON|OFF)")
set(PC_WITH_LIBCAMERA OFF CACHE STRING "libcamera backend (AUTO|ON|OFF); off unless asked for")
set(PC_WITH_LIBUSB AUTO CACHE STRING "libusb USB3 Vision diagnosis (AUTO|ON|OFF)")
set(PC_WITH_OPENCV AUTO CACHE STRING "OpenCV (live window, comparison benchmarks) (AUTO|ON|OFF)")
set(PC_WITH_OPENMP ON CACHE STRING "OpenMP row-band parallelism (AUTO|ON|OFF)")
set(PC_WITH_PYTHON AUTO CACHE STRING "Python module polarcam (python3-dev, python3-numpy) (AUTO|ON|OFF)")
foreach(opt PC_WITH_ARAVIS PC_WITH_LIBCAMERA PC_WITH_LIBUSB PC_WITH_OPENCV PC_WITH_OPENMP PC_WITH_PYTHON)
  set_property(CACHE ${opt} PROPERTY STRINGS AUTO ON OFF)
endforeach()

# Off for users (a newer compiler's new warning must not break their build); ./do test turns it on.
option(PC_WERROR "Treat warnings as errors" OFF)
option(PC_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
option(PC_NATIVE "Optimise for the build machine (-march=native)" OFF)
option(PC_BUILD_TESTS "Build the test programs" ON)

# Strict C11 (no GNU extensions), with the POSIX/BSD declarations of glibc visible (M_PI,
# clock_gettime, strdup, ...).
add_compile_definitions(_DEFAULT_SOURCE)

# Warnings for every target of the project.
set(PC_WARN_FLAGS -Wall -Wextra -Wshadow -Wpointer-arith -Wvla -Wformat=2)
# GCC notes that passing 32-byte vectors changed ABI in GCC 4.6: irrelevant for static
# functions inside one file (core/demosaic_fast.c), and noise in every build log.
list(APPEND PC_WARN_FLAGS -Wno-psabi)
if(PC_WERROR)
  list(APPEND PC_WARN_FLAGS -Werror)
endif()
add_compile_options("$<$<COMPILE_LANGUAGE:C>:${PC_WARN_FLAGS};-Wstrict-prototypes;-Wmissing-prototypes>")
add_compile_options("$<$<COMPILE_LANGUAGE:CXX>:${PC_WARN_FLAGS}>")

if(PC_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
# libFuzzer harnesses (tests/fuzz.cmake): clang only; every library is instrumented for coverage.
option(PC_FUZZ "Build the libFuzzer harnesses fuzz_* (clang; implies ASan + UBSan)" OFF)
if(PC_FUZZ)
  if(NOT CMAKE_C_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "PC_FUZZ needs clang (CC=clang CXX=clang++): libFuzzer is part of it")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined
                      -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
if(PC_NATIVE)
  add_compile_options(-march=native)
endif()
# Physics stays IEEE: no -ffast-math anywhere (it would break the NaN validation and the
# cancellation-free formulas of physics.md section 2).

# Position-independent objects everywhere: the layers' objects also make libpolarcam.so.
set(CMAKE_POSITION_INDEPENDENT_CODE ON)
# Only what a public header marks PC_API (polarcam/export.h; cmake/pc_api.py) leaves the shared
# library.
set(CMAKE_C_VISIBILITY_PRESET hidden)
set(CMAKE_CXX_VISIBILITY_PRESET hidden)
set(CMAKE_VISIBILITY_INLINES_HIDDEN ON)

# pc_layer(NAME SOURCES file... [HEADERS file...]): the layer's target pc_NAME, a static library
# of position-independent objects (tests link the narrowest layer they need; libpolarcam.so and
# libpolarcam.a are made of the same objects, cmake/Library.cmake), or an interface target while
# the layer has no sources. HEADERS are the layer's public headers, include/polarcam/*.h, which
# are installed; headers beside the sources are internal and are not.
function(pc_layer name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "SOURCES;HEADERS")
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "pc_layer(${name}): unexpected arguments ${arg_UNPARSED_ARGUMENTS}")
  endif()
  if(arg_SOURCES)
    add_library(pc_${name} STATIC ${arg_SOURCES})
    target_include_directories(pc_${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  else()
    add_library(pc_${name} INTERFACE)
    target_include_directories(pc_${name} INTERFACE ${CMAKE_CURRENT_SOURCE_DIR}/include)
  endif()
  set_property(GLOBAL APPEND PROPERTY PC_LAYERS pc_${name})
  foreach(h ${arg_HEADERS})
    if(NOT h MATCHES "^include/polarcam/[^/]+\\.h$")
      message(FATAL_ERROR "pc_layer(${name}): public header ${h} is not include/polarcam/*.h")
    endif()
    set_property(GLOBAL APPEND PROPERTY PC_PUBLIC_HEADERS ${CMAKE_CURRENT_SOURCE_DIR}/${h})
  endforeach()
endfunction()

# pc_link(NAME VISIBILITY deps...) that works for both static and interface layers.
function(pc_link name)
  get_target_property(type pc_${name} TYPE)
  if(type STREQUAL "INTERFACE_LIBRARY")
    list(FILTER ARGN EXCLUDE REGEX "^(PUBLIC|PRIVATE)$")
    target_link_libraries(pc_${name} INTERFACE ${ARGN})
  else()
    target_link_libraries(pc_${name} ${ARGN})
  endif()
endfunction()
