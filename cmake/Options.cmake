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

option(PC_WERROR "Treat warnings as errors" ON)
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
if(PC_NATIVE)
  add_compile_options(-march=native)
endif()
# Physics stays IEEE: no -ffast-math anywhere (it would break the NaN validation and the
# cancellation-free formulas of physics.md section 2).

# pc_layer(NAME SOURCES...): a static library for a layer, or an interface target while the layer
# has no sources yet, with its public headers in NAME/include.
function(pc_layer name)
  set(srcs ${ARGN})
  if(srcs)
    add_library(pc_${name} STATIC ${srcs})
    target_include_directories(pc_${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  else()
    add_library(pc_${name} INTERFACE)
    target_include_directories(pc_${name} INTERFACE ${CMAKE_CURRENT_SOURCE_DIR}/include)
  endif()
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
