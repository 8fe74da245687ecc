# install: `cmake --install` into a temporary prefix (under $TMPDIR), then what a user of the
# installed polarcam does, with nothing from this tree: tests/install/*.sh.
#   install_prefix      installs and checks the layout (headers, SONAME, .pc, CMake package,
#                       the command's --version)
#   install_exports     libpolarcam.so exports exactly the pc_ functions of the installed headers
#   install_consumer_*  the consumer programs built with pkg-config / find_package, shared and
#                       static, equal to `polarcam process` byte for byte
set(PC_INSTALL_STATE ${CMAKE_CURRENT_BINARY_DIR}/install-prefix.txt)
set(PC_INSTALL_DIR ${CMAKE_CURRENT_SOURCE_DIR}/install)
set(PC_CONSUMER_FLAGS "")
if(PC_SANITIZE)
  set(PC_CONSUMER_FLAGS "-fsanitize=address,undefined")
endif()
add_test(NAME install_prefix
  COMMAND ${PC_INSTALL_DIR}/install.sh ${CMAKE_BINARY_DIR} ${PC_INSTALL_STATE} ${PROJECT_VERSION})
add_test(NAME install_cleanup COMMAND ${PC_INSTALL_DIR}/cleanup.sh ${PC_INSTALL_STATE})
add_test(NAME install_exports COMMAND ${PC_INSTALL_DIR}/exports.sh ${PC_INSTALL_STATE})
foreach(how pkg-config cmake)
  add_test(NAME install_consumer_${how}
    COMMAND ${PC_INSTALL_DIR}/consumer.sh ${PC_INSTALL_STATE} ${how} ${PROJECT_VERSION}
      ${CMAKE_C_COMPILER} ${CMAKE_CXX_COMPILER} "${PC_CONSUMER_FLAGS}")
endforeach()
set_tests_properties(install_prefix PROPERTIES FIXTURES_SETUP pc_installed TIMEOUT 300)
set_tests_properties(install_cleanup PROPERTIES FIXTURES_CLEANUP pc_installed)
set_tests_properties(install_exports install_consumer_pkg-config install_consumer_cmake PROPERTIES
  FIXTURES_REQUIRED pc_installed SKIP_RETURN_CODE 77 TIMEOUT 600
  ENVIRONMENT "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0")
# docs/api.md prints stokes_raw.c: the two must not drift apart.
add_test(NAME api_doc_example COMMAND ${PC_INSTALL_DIR}/doc_example.sh ${PROJECT_SOURCE_DIR})
