# Contact physics (src/physics): materials and pair mixing, contact laws, narrow phase, shapes,
# time-step limits. Tests: tests/unit/physics (GoogleTest), registered as the "physics" test.
file(GLOB DEMLAB_PHYSICS_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/physics/*.cpp)
add_library(demlab_physics STATIC ${DEMLAB_PHYSICS_SOURCES})
demlab_precompile(demlab_physics)
target_link_libraries(demlab_physics PUBLIC demlab_core)

demlab_add_unit_tests(physics demlab_physics_tests physics/ demlab_physics)
