# The analysis queries (src/analysis): micromechanical averages of a scene (stress, coordination,
# fabric, packing, mean motion) and coarse-grained fields, over the Simulation API only.
file(GLOB DEMLAB_ANALYSIS_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/analysis/*.cpp)
add_library(demlab_analysis STATIC ${DEMLAB_ANALYSIS_SOURCES})
demlab_precompile(demlab_analysis)
target_link_libraries(demlab_analysis PUBLIC demlab_sim)
# Linked into libdemlab.so through the commands.
set_property(TARGET demlab_analysis PROPERTY POSITION_INDEPENDENT_CODE ON)

demlab_add_unit_tests(analysis demlab_analysis_tests analysis/ demlab_analysis)
