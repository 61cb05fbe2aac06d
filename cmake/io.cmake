# Part "io": reading scene files (LAMMPS data files of spheres, gzip'd or plain), and the
# settle benchmark, which reads the shared benchmark's data files into a Simulation.
find_package(ZLIB REQUIRED)

file(GLOB DEMLAB_IO_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/io/*.cpp)
add_library(demlab_io STATIC ${DEMLAB_IO_SOURCES})
target_link_libraries(demlab_io PUBLIC demlab_core ZLIB::ZLIB)

file(GLOB DEMLAB_IO_TESTS CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/tests/unit/io/*.cpp)
add_executable(demlab_io_tests ${DEMLAB_IO_TESTS})
target_include_directories(demlab_io_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/tests)
# The benchmark data files live beside the repository (../shared/bench/data); the test that
# reads them skips when they are absent. $DEMLAB_BENCH_DATA overrides the folder at run time.
target_compile_definitions(demlab_io_tests PRIVATE
  DEMLAB_BENCH_DATA_DIR="${CMAKE_CURRENT_SOURCE_DIR}/../shared/bench/data")
target_link_libraries(demlab_io_tests PRIVATE demlab_io GTest::gtest GTest::gtest_main
  Threads::Threads)
add_test(NAME io COMMAND demlab_io_tests --gtest_brief=1)

# The settle benchmark needs the simulation core; it joins the build once cmake/sim.cmake
# defines demlab_sim (sim is included before io).
if(TARGET demlab_sim)
  add_executable(bench_sim bench/bench_sim.cpp)
  target_link_libraries(bench_sim PRIVATE demlab_io demlab_sim)
endif()
