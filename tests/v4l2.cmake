# V4L2 against the real kernel driver: a QEMU guest (software emulation) boots Debian's own
# kernel package with vivid, from a busybox initramfs that tests/qemu/run-guest.sh builds, and
# runs pc_guest_v4l2 - the project's V4L2 code and checks - once; all V4L2 checks run in that
# one boot. The kernel and module pieces are cached in the build directory (qemu-cache/).
#
# pc_guest_v4l2 is linked statically. The sanitizer runtimes cannot be linked into a static
# program, nor clang's OpenMP runtime (Debian ships no libomp.a), so in the ASan+UBSan build
# (PC_SANITIZE) and with clang it is linked dynamically and run-guest.sh copies the shared
# libraries it needs (libasan, libubsan, libomp, libc, ...) into the initramfs: the guest checks
# then run under the sanitizers too.
set(PC_GUEST_DIR ${CMAKE_CURRENT_SOURCE_DIR}/qemu)
# The guest program is the project's own code: the frame-source wrappers, the registry, the
# compliance test and the V4L2 backend, compiled again here with only the V4L2 backend in the
# registry (PC_HAVE_V4L2; the others are 0) so that nothing pulls in libraries that have no
# static archive.
if(NOT PC_HAVE_V4L2)
  return()
endif()
set(PC_DEV ${PROJECT_SOURCE_DIR}/devices)
add_executable(pc_guest_v4l2
  ${PC_GUEST_DIR}/guest_v4l2.c
  ${PC_DEV}/v4l2.c ${PC_DEV}/v4l2_source.c ${PC_DEV}/source.c ${PC_DEV}/registry.c
  ${PC_DEV}/compliance.c ${PC_DEV}/backend_util.c)
target_include_directories(pc_guest_v4l2 PRIVATE ${PC_GUEST_DIR} ${PC_DEV}/include ${PC_DEV}
  ${PROJECT_SOURCE_DIR}/core/include)
target_compile_definitions(pc_guest_v4l2 PRIVATE PC_HAVE_V4L2=1)
if(PC_SANITIZE OR NOT CMAKE_C_COMPILER_ID STREQUAL "GNU")
  # clang: Debian's libomp has no static archive; run-guest.sh copies the shared libraries
  target_link_libraries(pc_guest_v4l2 PRIVATE pc_core)
else()
  # The OpenMP imported target names libgomp.so; a static link needs the archive, which gcc's
  # -fopenmp picks under -static.
  add_dependencies(pc_guest_v4l2 pc_core)
  target_link_libraries(pc_guest_v4l2 PRIVATE $<TARGET_FILE:pc_core> m)
  target_link_options(pc_guest_v4l2 PRIVATE -static $<$<BOOL:${PC_HAVE_OPENMP}>:-fopenmp>)
endif()

# Simulated frames for the loopback are rendered on the host (native speed) by the simulator and
# travel in the initramfs: rendering inside the emulated guest would take minutes.
add_executable(pc_guest_simframes ${PC_GUEST_DIR}/simframes.c)
target_link_libraries(pc_guest_simframes PRIVATE pc_sim pc_io pc_core)

# vivid: two instances, each with a video capture and a video output node (node_types=0x101),
# the first single-planar, the second multi-planar (multiplanar=1,2); their error-injection
# controls stay on (they are the compliance test's faults).
set(PC_VIVID_PARAMS "vivid n_devs=2 node_types=0x101,0x101 multiplanar=1,2")
# tests/netns.sh --pid-only: QEMU and everything else the script starts die with the test (a
# private PID namespace where permitted; run without one otherwise). --timeout: the guest is
# software-emulated; under load (both CI builds' tests at once on 2 cores) a run takes several
# times its idle 34 s, and the limit only has to catch a hung guest (600 s: about 17× the idle
# run, and short enough that a hang still fails CI within its 20-minute budget).
add_test(NAME v4l2_guest
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/netns.sh --pid-only ${PC_GUEST_DIR}/v4l2-guest.sh ${CMAKE_BINARY_DIR}/qemu-cache
    $<TARGET_FILE:pc_guest_simframes> $<TARGET_FILE:pc_guest_v4l2> $<TARGET_FILE:polarcam>
    --log ${CMAKE_CURRENT_BINARY_DIR}/v4l2_guest.log
    --module "${PC_VIVID_PARAMS}"
    --env ASAN_OPTIONS --env UBSAN_OPTIONS --env PC_GUEST_VERBOSE
    --min-pass 20
    --timeout 600)
# PROCESSORS 2: the guest has two virtual CPUs; ctest -j2 then runs nothing beside it.
set_tests_properties(v4l2_guest PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 660 PROCESSORS 2
  ENVIRONMENT "${PC_TEST_ENV}")
