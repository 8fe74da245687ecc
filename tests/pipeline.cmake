# Pipeline: the fast kernels have baseline, AVX2 and AVX-512 instances chosen at run time; the
# plain tests exercise the widest one the machine has. These run the kernel tests again with
# the wider instances switched off, so every instance is held to the same references.
foreach(t test_demosaic test_stokes)
  foreach(isa AVX512 AVX2)
    add_test(NAME ${t}_no_${isa} COMMAND ${t})
    set_tests_properties(${t}_no_${isa} PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 600
      ENVIRONMENT "${PC_TEST_ENV};POLARCAM_NO_${isa}=1")
  endforeach()
endforeach()
