# Part "output": the scene written for other tools (VTK for ParaView, ...), on the formats of
# part "io".
file(GLOB DEMLAB_OUTPUT_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/output/*.cpp)
add_library(demlab_output STATIC ${DEMLAB_OUTPUT_SOURCES})
demlab_precompile(demlab_output)
target_link_libraries(demlab_output PUBLIC demlab_sim demlab_io)
demlab_add_unit_tests(output demlab_output_tests output/ demlab_output)
