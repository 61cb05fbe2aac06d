# The verification suite (issue 6): analytic cases through the Simulation API, the convergence
# driver and its program demlab_verify (scripts/verify writes doc/verification.md with it), and
# the fast GoogleTest checks of the stated tolerances, registered as the "verify" test.
if(TARGET demlab_sim)
  file(GLOB DEMLAB_VERIFY_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/verify/*.cpp)
  list(REMOVE_ITEM DEMLAB_VERIFY_SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/src/verify/verify_main.cpp)
  add_library(demlab_verify STATIC ${DEMLAB_VERIFY_SOURCES})
  demlab_precompile(demlab_verify)
  target_link_libraries(demlab_verify PUBLIC demlab_sim)

  add_executable(demlab_verify_run ${DEMLAB_PROGRAM_SCOPE}
    ${CMAKE_CURRENT_SOURCE_DIR}/src/verify/verify_main.cpp)
  set_target_properties(demlab_verify_run PROPERTIES OUTPUT_NAME demlab_verify)
  target_link_libraries(demlab_verify_run PRIVATE demlab_verify)

  demlab_add_unit_tests(verify demlab_verify_tests verify/ demlab_verify)
  # The test that doc/verification.md holds the restitution section reads it from the tree.
  target_compile_definitions(demlab_verify_tests PRIVATE
    DEMLAB_DOC_DIR="${CMAKE_CURRENT_SOURCE_DIR}/doc")
endif()
