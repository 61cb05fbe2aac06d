# Part "io": reading scene files (LAMMPS data files of spheres, gzip'd or plain), and the
# settle benchmark, which reads the shared benchmark's data files into a Simulation.
find_package(ZLIB REQUIRED)

# bench_sim is linked dynamically, as demlab and LIGGGHTS are, so its peak RSS counts the same
# shared library pages theirs do. -DDEMLAB_STATIC_BENCH_SIM=ON links it statically where the
# static C and C++ runtimes and zlib are installed: it then maps only the library code it
# calls, with no dynamic loader and no symbol tables, about 190 bytes per grain less of a 10k
# bed's peak (doc/performance.md, "Memory"): library pages, shared with other processes, so
# not counted in the figures against issue 3's target.
option(DEMLAB_STATIC_BENCH_SIM "Link bench_sim statically where the static libraries exist" OFF)
set(DEMLAB_STATIC_BENCH_SIM_OK OFF)
if(DEMLAB_STATIC_BENCH_SIM)
  find_library(DEMLAB_ZLIB_STATIC NAMES libz.a)
  include(CheckCXXSourceCompiles)
  set(CMAKE_REQUIRED_LINK_OPTIONS -static)
  check_cxx_source_compiles("#include <string>\nint main() { return std::string(\"x\").size() == 1 ? 0 : 1; }"
    DEMLAB_CXX_LINKS_STATIC)
  unset(CMAKE_REQUIRED_LINK_OPTIONS)
  if(DEMLAB_ZLIB_STATIC AND DEMLAB_CXX_LINKS_STATIC)
    set(DEMLAB_STATIC_BENCH_SIM_OK ON)
  else()
    message(STATUS "bench_sim: linked dynamically (no static libz.a or C++ runtime)")
  endif()
endif()

file(GLOB DEMLAB_IO_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/io/*.cpp)
add_library(demlab_io STATIC ${DEMLAB_IO_SOURCES})
demlab_precompile(demlab_io)
# A program with the target property DEMLAB_STATIC_LINK gets zlib's static archive.
target_link_libraries(demlab_io PUBLIC demlab_core
  $<IF:$<BOOL:$<TARGET_PROPERTY:DEMLAB_STATIC_LINK>>,${DEMLAB_ZLIB_STATIC},ZLIB::ZLIB>)

demlab_add_unit_tests(io demlab_io_tests io/ demlab_io)
# The benchmark data files live beside the repository (../shared/bench/data); the test that
# reads them skips when they are absent. $DEMLAB_BENCH_DATA overrides the folder at run time.
target_compile_definitions(demlab_io_tests PRIVATE
  DEMLAB_BENCH_DATA_DIR="${CMAKE_CURRENT_SOURCE_DIR}/../shared/bench/data")

# The settle benchmark needs the simulation core; it joins the build once cmake/sim.cmake
# defines demlab_sim (sim is included before io).
if(TARGET demlab_sim)
  add_executable(bench_sim ${DEMLAB_PROGRAM_SCOPE} bench/bench_sim.cpp)
  target_link_libraries(bench_sim PRIVATE demlab_io demlab_sim)
  if(DEMLAB_STATIC_BENCH_SIM_OK)
    set_target_properties(bench_sim PROPERTIES DEMLAB_STATIC_LINK ON)
    target_link_options(bench_sim PRIVATE -static)
  endif()
endif()
