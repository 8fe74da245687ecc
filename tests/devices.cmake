# devices: tests against real protocol peers. Everything that opens sockets runs inside a
# private network namespace with only loopback and a private PID namespace (tests/netns.sh; exit
# 77 = skipped when namespaces are not permitted): whatever a test starts dies with it, also when
# ctest's TIMEOUT kills it. The GigE Vision tests hold the "gige" lock (RESOURCE_LOCK: never two
# at once in one ctest run) and run alone (RUN_SERIAL: a 2-core machine busy with other tests
# starves the camera and client threads and loses packets). Their TIMEOUTs are far above their
# run times under load: they catch hangs, not slowness.
if(PC_HAVE_ARAVIS)
  add_executable(gige_e2e ${CMAKE_CURRENT_SOURCE_DIR}/gige_e2e.c)
  # Aravis directly too: one check drives the camera with GVCP writes back to back
  target_link_libraries(gige_e2e PRIVATE pc_devices PkgConfig::ARAVIS)
  target_include_directories(gige_e2e PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  add_test(NAME devices_gige_e2e COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/netns.sh $<TARGET_FILE:gige_e2e>)
  set_tests_properties(devices_gige_e2e PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300
    RESOURCE_LOCK gige RUN_SERIAL TRUE ENVIRONMENT "${PC_TEST_ENV}")
endif()

# The same against a colour-polarization camera (serve scenes/colour_small.json: IMX250MYR).
if(PC_HAVE_ARAVIS)
  add_executable(gige_colour ${CMAKE_CURRENT_SOURCE_DIR}/gige_colour.c)
  target_link_libraries(gige_colour PRIVATE pc_devices PkgConfig::ARAVIS m)
  target_include_directories(gige_colour PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  add_test(NAME devices_gige_colour COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/netns.sh
    $<TARGET_FILE:gige_colour>)
  set_tests_properties(devices_gige_colour PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300
    RESOURCE_LOCK gige RUN_SERIAL TRUE ENVIRONMENT "${PC_TEST_ENV}")
endif()

# Capture of 2448x2048 frames from serve with a writer slower than the camera (issue 13), lost
# packets by policy, signals to serve and capture.
if(PC_HAVE_ARAVIS)
  add_executable(gige_load ${CMAKE_CURRENT_SOURCE_DIR}/gige_load.c)
  target_link_libraries(gige_load PRIVATE pc_devices PkgConfig::JANSSON)
  target_include_directories(gige_load PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  add_test(NAME devices_gige_load COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/netns.sh $<TARGET_FILE:gige_load>)
  set_tests_properties(devices_gige_load PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 900
    RESOURCE_LOCK gige RUN_SERIAL TRUE ENVIRONMENT "${PC_TEST_ENV}")
endif()

# The live window in a real X server (Xvfb) with an X screenshot (xwd).
if(PC_HAVE_OPENCV)
  add_executable(view_xvfb ${CMAKE_CURRENT_SOURCE_DIR}/view_xvfb.c)
  target_link_libraries(view_xvfb PRIVATE PkgConfig::PNG m)
  target_include_directories(view_xvfb PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  add_test(NAME devices_view_xvfb COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/netns.sh
    $<TARGET_FILE:view_xvfb>)
  set_tests_properties(devices_view_xvfb PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 400
    ENVIRONMENT "${PC_TEST_ENV}")
endif()

# The devices benchmark runs end to end (a smoke run on the small scene; its numbers are not
# checked: tests never time things).
if(PC_HAVE_ARAVIS)
  add_test(NAME devices_bench_smoke COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/netns.sh
    $<TARGET_FILE:polarcam> bench devices --quick --json)
  set_tests_properties(devices_bench_smoke PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300
    RESOURCE_LOCK gige RUN_SERIAL TRUE ENVIRONMENT "${PC_TEST_ENV};PC_BENCH_NETNS=1")
endif()

# The soak, half a minute of it in two 15 s periods (bench/bench_soak.c): serve -> capture -> live pipeline at 2448x2048,
# 30 fps; the process's file descriptors and threads equal to the baseline's, its heap in use
# (malloc's count of bytes not freed) growing at most 64 kB and its anonymous RSS 256 kB per
# period (least-squares slope of the later half), each within a cap of the baseline's (outside
# AddressSanitizer), every frame equal to the simulator's. Exit 1 fails the test.
if(PC_HAVE_ARAVIS)
  add_test(NAME devices_soak COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/netns.sh
    $<TARGET_FILE:polarcam> bench soak --minutes 0.5 --period 15 --cycle 2 --capture-frames 5 --json)
  set_tests_properties(devices_soak PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 900
    RESOURCE_LOCK gige RUN_SERIAL TRUE ENVIRONMENT "${PC_TEST_ENV};PC_BENCH_NETNS=1")
endif()

# polarcam devices lists every backend (inside a namespace: enumeration may touch the network
# stack even without --gige).
add_test(NAME devices_list COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/netns.sh
  $<TARGET_FILE:polarcam> devices --json)
set_tests_properties(devices_list PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 60
  ENVIRONMENT "${PC_TEST_ENV}"
  PASS_REGULAR_EXPRESSION "\"backend\":\"sim\",\"built\":true.*\"backend\":\"file\",\"built\":true")
