# Datasets under a real scheduler: a single-node Slurm cluster (slurmctld, slurmd, munge from
# Debian 12) started by tests/slurm.sh inside tests/netns.sh (private network and PID
# namespaces, loopback only) runs a 4-task array of polarcam dataset; exit 77 when Slurm is
# missing or cannot start.
add_test(NAME dataset_slurm COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/netns.sh
  ${CMAKE_CURRENT_SOURCE_DIR}/slurm.sh)
set_tests_properties(dataset_slurm PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 600
  ENVIRONMENT "${PC_TEST_ENV}")
