# Fuzzing (tests/fuzz/, docs in tests/fuzz/README.md). Every harness is built twice over:
#  - always, with tests/fuzz/replay.c as main: ctest fuzz_replay_NAME replays the checked-in
#    corpus tests/fuzz/corpus/NAME (seeds and every finding), with any compiler and sanitizer;
#  - with -DPC_FUZZ=ON (clang), as a libFuzzer binary fuzz_NAME for `./do fuzz` and `./do test`.
set(PC_FUZZ_HARNESSES png tiff bmp npy raw scene obj meta states batch_pbrdf batch_decompose uri
    physics strings calib)
set(PC_FUZZ_DIR ${CMAKE_CURRENT_SOURCE_DIR}/fuzz)
# What each harness links: the command line's library (pc_cli, through libpolarcam.so), except
# the OBJ harness, which calls the simulator's internal mesh functions (not exported) and so
# links the sim layer itself, alone (two copies of the library would keep two error states).
set(PC_FUZZ_LIBS_obj pc_sim)
foreach(h ${PC_FUZZ_HARNESSES})
  if(PC_FUZZ)
    set(t fuzz_${h})
    add_executable(${t} ${PC_FUZZ_DIR}/fuzz_${h}.c)
    target_link_options(${t} PRIVATE -fsanitize=fuzzer)
  else()
    set(t fuzz_replay_${h})
    add_executable(${t} ${PC_FUZZ_DIR}/fuzz_${h}.c ${PC_FUZZ_DIR}/replay.c)
    add_test(NAME ${t} COMMAND ${t} ${PC_FUZZ_DIR}/corpus/${h})
    set_tests_properties(${t} PROPERTIES TIMEOUT ${PC_TEST_TIMEOUT} ENVIRONMENT "${PC_TEST_ENV}")
  endif()
  if(DEFINED PC_FUZZ_LIBS_${h})
    target_link_libraries(${t} PRIVATE ${PC_FUZZ_LIBS_${h}})
  else()
    target_link_libraries(${t} PRIVATE pc_cli)
  endif()
  target_include_directories(${t} PRIVATE ${PC_FUZZ_DIR} ${PROJECT_SOURCE_DIR}/sim)
endforeach()
if(PC_FUZZ)
  add_custom_target(fuzz_all)
  foreach(h ${PC_FUZZ_HARNESSES})
    add_dependencies(fuzz_all fuzz_${h})
  endforeach()
endif()
