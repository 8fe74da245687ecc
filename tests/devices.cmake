# devices: tests against real protocol peers. Everything that opens sockets runs inside a
# private network namespace with only loopback (tests/netns.sh; exit 77 = skipped when
# namespaces are not permitted), and the GigE Vision tests run one at a time (one camera
# address, 127.0.0.1): RESOURCE_LOCK gige.
if(PC_HAVE_ARAVIS)
  add_executable(gige_e2e ${CMAKE_CURRENT_SOURCE_DIR}/gige_e2e.c)
  target_link_libraries(gige_e2e PRIVATE pc_cli)
  target_include_directories(gige_e2e PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  add_test(NAME devices_gige_e2e COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/netns.sh $<TARGET_FILE:gige_e2e>)
  set_tests_properties(devices_gige_e2e PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300
    RESOURCE_LOCK gige ENVIRONMENT "${PC_TEST_ENV}")
endif()
