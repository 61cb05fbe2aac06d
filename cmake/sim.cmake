# The simulation core (issue 3): SimulationManager, SimLoop and its modules, over src/core,
# src/search and src/physics. Public API: src/sim/simulation.hpp.
file(GLOB DEMLAB_SIM_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/sim/*.cpp
     ${CMAKE_CURRENT_SOURCE_DIR}/src/sim/shapes/*.cpp)
add_library(demlab_sim STATIC ${DEMLAB_SIM_SOURCES})
demlab_precompile(demlab_sim)
target_link_libraries(demlab_sim PUBLIC demlab_physics demlab_core demlab_mpi)

demlab_add_unit_tests(sim demlab_sim_tests sim/ demlab_sim SHARDS 3)

# The contact kernels (src/sim/contact_kernel.hpp): one translation unit per instruction set,
# chosen at run time; the rest of the build targets baseline x86-64. No FMA anywhere (a fused
# multiply-add rounds once where the Eigen loop rounds twice): the kernels give the same bits.
set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/src/sim/contact_kernel_sse2.cpp
  PROPERTIES COMPILE_OPTIONS "-ffp-contract=off" SKIP_PRECOMPILE_HEADERS ON)
set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/src/sim/contact_kernel_avx2.cpp
  PROPERTIES COMPILE_OPTIONS "-mavx2;-mno-fma;-ffp-contract=off"
  SKIP_PRECOMPILE_HEADERS ON)
set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/src/sim/contact_kernel_avx512.cpp
  PROPERTIES COMPILE_OPTIONS "-mavx512f;-mavx512dq;-mavx512vl;-mno-fma;-ffp-contract=off"
  SKIP_PRECOMPILE_HEADERS ON)
# The sanitizer build compiles at -Og, where the kernels' intrinsics stay calls: the kernels
# alone then took 40 % of its test time. They keep AddressSanitizer but not UBSan, whose checks
# there are of the intrinsics' own pointer casts and lane arithmetic and which doubled their
# compilation (40 -> 21 s each); the kernels' results are checked bit for bit against the
# instrumented Eigen loops (tests/unit/sim/sim_kernel_test.cpp).
if(DEMLAB_SANITIZE)
  foreach(isa sse2 avx2 avx512)
    set_property(SOURCE ${CMAKE_CURRENT_SOURCE_DIR}/src/sim/contact_kernel_${isa}.cpp
      APPEND PROPERTY COMPILE_OPTIONS -O1 -fno-sanitize=undefined)
  endforeach()
endif()
