# `cmake --install BUILD [--prefix P]`: headers, libpolarcam (shared + static), the polarcam
# command, polarcam.pc and the CMake package (polarcamConfig.cmake, imported targets
# polarcam::polarcam and polarcam::polarcam_static).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(PC_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/polarcam)
get_property(pc_public_headers GLOBAL PROPERTY PC_PUBLIC_HEADERS)
install(FILES ${pc_public_headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/polarcam)
install(TARGETS polarcam_shared polarcam_static EXPORT polarcamTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS polarcam RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The command finds its library from wherever the tree is installed.
file(RELATIVE_PATH pc_bin_to_lib ${CMAKE_INSTALL_FULL_BINDIR} ${CMAKE_INSTALL_FULL_LIBDIR})
set_target_properties(polarcam PROPERTIES INSTALL_RPATH "$ORIGIN/${pc_bin_to_lib}")

# What a static link needs besides libpolarcam.a: pkg-config modules (Requires.private in the
# .pc, found again by polarcamConfig.cmake) and plain libraries.
set(pc_requires)      # pkg-config module names
set(pc_cmake_pkgs)    # NAME=module pairs for polarcamConfig.cmake
set(pc_libs_private)  # -l flags for the .pc
set(pc_static_link)   # the installed static target's link interface
foreach(d ${pc_deps})
  if(d MATCHES "^PkgConfig::(.+)$")
    set(name ${CMAKE_MATCH_1})
    get_property(mods GLOBAL PROPERTY PC_PKG_MODULES_${name})
    if(NOT mods)
      message(FATAL_ERROR "cmake/Install.cmake: no pkg-config module recorded for ${d}")
    endif()
    list(APPEND pc_requires ${mods})
    list(JOIN mods "," mods_csv)
    list(APPEND pc_cmake_pkgs "${name}=${mods_csv}")
    list(APPEND pc_static_link PkgConfig::polarcam_dep_${name})
  elseif(d STREQUAL "OpenMP::OpenMP_C")
    # the compiler's runtime (libgomp, or clang's libomp, which is not on the default linker
    # path on Debian): named with its directory
    foreach(l ${OpenMP_C_LIB_NAMES})
      if(l STREQUAL "pthread" OR NOT OpenMP_${l}_LIBRARY)
        list(APPEND pc_libs_private -l${l})
      else()
        get_filename_component(dir ${OpenMP_${l}_LIBRARY} DIRECTORY)
        list(APPEND pc_libs_private -L${dir} -l${l})
      endif()
    endforeach()
    list(APPEND pc_static_link OpenMP::OpenMP_C)
  elseif(d STREQUAL "Threads::Threads")
    # POSIX threads (the capture's writer thread): the flag FindThreads chose, none when the C
    # library has them (glibc >= 2.34)
    if(CMAKE_THREAD_LIBS_INIT)
      list(APPEND pc_libs_private ${CMAKE_THREAD_LIBS_INIT})
      list(APPEND pc_static_link ${CMAKE_THREAD_LIBS_INIT})
    endif()
  elseif(d STREQUAL "pc_opencv")
    foreach(lib ${PC_OPENCV_HIGHGUI} ${PC_OPENCV_IMGPROC} ${PC_OPENCV_CORE})
      get_filename_component(n ${lib} NAME_WE)
      string(REGEX REPLACE "^lib" "" n ${n})
      list(APPEND pc_libs_private -l${n})
      list(APPEND pc_static_link ${n})
    endforeach()
  elseif(IS_ABSOLUTE "${d}" AND d MATCHES "/lib([^/]+)\\.(so|a)[.0-9]*$")
    # a library found by path (find_package(LAPACK)): the same file for CMake, -L -l for the .pc
    get_filename_component(dir ${d} DIRECTORY)
    list(APPEND pc_libs_private -L${dir} -l${CMAKE_MATCH_1})
    list(APPEND pc_static_link ${d})
  elseif(d MATCHES "^[A-Za-z0-9_.+-]+$" AND NOT TARGET ${d})
    list(APPEND pc_libs_private -l${d})
    list(APPEND pc_static_link ${d})
  else()
    message(FATAL_ERROR "cmake/Install.cmake: do not know how a user links ${d}")
  endif()
endforeach()
if(pc_has_cxx)
  list(APPEND pc_libs_private -lstdc++)
  list(APPEND pc_static_link stdc++)
endif()
list(REMOVE_DUPLICATES pc_requires)
list(REMOVE_DUPLICATES pc_libs_private)
foreach(d ${pc_static_link})
  target_link_libraries(polarcam_static INTERFACE $<INSTALL_INTERFACE:${d}>)
endforeach()

install(EXPORT polarcamTargets NAMESPACE polarcam:: DESTINATION ${PC_CMAKE_DIR})
set(PC_CONFIG_PKGS "${pc_cmake_pkgs}")
set(PC_CONFIG_OPENMP ${PC_HAVE_OPENMP})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/polarcamConfig.cmake.in
  ${PROJECT_BINARY_DIR}/polarcamConfig.cmake INSTALL_DESTINATION ${PC_CMAKE_DIR})
# 0.x: only the same MAJOR.MINOR is compatible (the SOVERSION rule of cmake/Library.cmake)
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(pc_compat SameMinorVersion)
else()
  set(pc_compat SameMajorVersion)
endif()
write_basic_package_version_file(${PROJECT_BINARY_DIR}/polarcamConfigVersion.cmake
  COMPATIBILITY ${pc_compat})
install(FILES ${PROJECT_BINARY_DIR}/polarcamConfig.cmake
  ${PROJECT_BINARY_DIR}/polarcamConfigVersion.cmake DESTINATION ${PC_CMAKE_DIR})

# polarcam.pc: written at install time, so that `cmake --install --prefix P` gets P.
list(JOIN pc_requires " " PC_PC_REQUIRES)
list(JOIN pc_libs_private " " PC_PC_LIBS_PRIVATE)
foreach(v PC_PREFIX PC_LIBDIR PC_INCLUDEDIR)
  set(${v} "@${v}@") # kept for the install-time pass
endforeach()
configure_file(${CMAKE_CURRENT_LIST_DIR}/polarcam.pc.in ${PROJECT_BINARY_DIR}/polarcam.pc.in @ONLY)
file(CONFIGURE OUTPUT ${PROJECT_BINARY_DIR}/install_pc.cmake @ONLY CONTENT [=[
# Generated by cmake/Install.cmake: writes and installs polarcam.pc for the install prefix.
set(PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
set(PC_LIBDIR "@CMAKE_INSTALL_LIBDIR@")
set(PC_INCLUDEDIR "@CMAKE_INSTALL_INCLUDEDIR@")
if(NOT IS_ABSOLUTE "${PC_LIBDIR}")
  set(PC_LIBDIR "\${prefix}/${PC_LIBDIR}")
endif()
if(NOT IS_ABSOLUTE "${PC_INCLUDEDIR}")
  set(PC_INCLUDEDIR "\${prefix}/${PC_INCLUDEDIR}")
endif()
configure_file("@PROJECT_BINARY_DIR@/polarcam.pc.in" "@PROJECT_BINARY_DIR@/pkgconfig/polarcam.pc" @ONLY)
file(INSTALL DESTINATION "${CMAKE_INSTALL_PREFIX}/@CMAKE_INSTALL_LIBDIR@/pkgconfig" TYPE FILE
  FILES "@PROJECT_BINARY_DIR@/pkgconfig/polarcam.pc")
]=])
install(SCRIPT ${PROJECT_BINARY_DIR}/install_pc.cmake)
