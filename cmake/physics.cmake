# Contact physics (src/physics): materials and pair mixing, contact laws, narrow phase, shapes,
# time-step limits. Tests: tests/unit/physics (GoogleTest), registered as the "physics" test.
file(GLOB DEMLAB_PHYSICS_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/physics/*.cpp)
add_library(demlab_physics STATIC ${DEMLAB_PHYSICS_SOURCES})
target_link_libraries(demlab_physics PUBLIC demlab_core)

file(GLOB DEMLAB_PHYSICS_TESTS CONFIGURE_DEPENDS
     ${CMAKE_CURRENT_SOURCE_DIR}/tests/unit/physics/*.cpp)
if(DEMLAB_PHYSICS_TESTS)
  add_executable(demlab_physics_tests ${DEMLAB_PHYSICS_TESTS})
  target_include_directories(demlab_physics_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/tests)
  target_link_libraries(demlab_physics_tests PRIVATE demlab_physics GTest::gtest GTest::gtest_main)
  add_test(NAME physics COMMAND demlab_physics_tests --gtest_brief=1)
endif()
