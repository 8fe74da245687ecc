# Dependency detection. Each optional dependency sets PC_HAVE_<NAME> (ON/OFF).
find_package(PkgConfig REQUIRED)

# pc_optional(NAME MODE pkg-config-module...) -> PC_HAVE_NAME and imported target PkgConfig::NAME
function(pc_optional name mode)
  set(PC_HAVE_${name} OFF PARENT_SCOPE)
  if(mode STREQUAL "OFF")
    return()
  endif()
  pkg_check_modules(${name} IMPORTED_TARGET ${ARGN})
  if(${name}_FOUND)
    set(PC_HAVE_${name} ON PARENT_SCOPE)
    set_property(GLOBAL PROPERTY PC_PKG_MODULES_${name} ${ARGN})
  elseif(mode STREQUAL "ON")
    message(FATAL_ERROR "${name} was asked for (PC_WITH_${name}=ON) but pkg-config did not find: ${ARGN}")
  endif()
endfunction()

# pc_required(NAME pkg-config-module): imported target PkgConfig::NAME or a configure error.
function(pc_required name module)
  pkg_check_modules(${name} REQUIRED IMPORTED_TARGET ${module})
  # for the installed polarcam.pc and polarcamConfig.cmake (cmake/Install.cmake)
  set_property(GLOBAL PROPERTY PC_PKG_MODULES_${name} ${module})
endfunction()

# Required: libpng and libtiff for image I/O, jansson for JSON (scene files, output).
pc_required(PNG libpng)
pc_required(TIFF libtiff-4)
pc_required(JANSSON jansson)
# cairo draws the PNG plots and annotated pictures (io/plot.c).
pc_required(CAIRO cairo)
# libzip writes and reads the calibration file (.npz, calib/calib_file.c).
pc_required(LIBZIP libzip)
# nettle: SHA-256 of dataset files (devices/dataset.c).
pc_required(NETTLE nettle)

pc_optional(ARAVIS ${PC_WITH_ARAVIS} aravis-0.8)
pc_optional(LIBCAMERA ${PC_WITH_LIBCAMERA} libcamera)
pc_optional(LIBUSB ${PC_WITH_LIBUSB} libusb-1.0)
# OpenCV: Debian ships opencv4.pc only in the all-modules libopencv-dev; find the three modules
# we use (core, imgproc, highgui) directly so that their -dev packages suffice.
set(PC_HAVE_OPENCV OFF)
if(NOT PC_WITH_OPENCV STREQUAL "OFF")
  find_path(PC_OPENCV_INCLUDE opencv2/core.hpp PATH_SUFFIXES opencv4)
  find_library(PC_OPENCV_CORE opencv_core)
  find_library(PC_OPENCV_IMGPROC opencv_imgproc)
  find_library(PC_OPENCV_HIGHGUI opencv_highgui)
  if(PC_OPENCV_INCLUDE AND PC_OPENCV_CORE AND PC_OPENCV_IMGPROC AND PC_OPENCV_HIGHGUI)
    set(PC_HAVE_OPENCV ON)
    add_library(pc_opencv INTERFACE)
    target_include_directories(pc_opencv INTERFACE ${PC_OPENCV_INCLUDE})
    target_link_libraries(pc_opencv INTERFACE ${PC_OPENCV_HIGHGUI} ${PC_OPENCV_IMGPROC} ${PC_OPENCV_CORE})
  elseif(PC_WITH_OPENCV STREQUAL "ON")
    message(FATAL_ERROR "OpenCV was asked for (PC_WITH_OPENCV=ON) but core/imgproc/highgui were not found")
  endif()
endif()

set(PC_HAVE_OPENMP OFF)
if(NOT PC_WITH_OPENMP STREQUAL "OFF")
  find_package(OpenMP COMPONENTS C)
  if(OpenMP_C_FOUND)
    set(PC_HAVE_OPENMP ON)
  elseif(PC_WITH_OPENMP STREQUAL "ON")
    message(FATAL_ERROR "OpenMP was asked for but not found")
  endif()
endif()

# POSIX threads (the capture's writer thread): found here so that the imported target is visible
# where libpolarcam is linked
find_package(Threads REQUIRED)
