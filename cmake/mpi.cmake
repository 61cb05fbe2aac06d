# The distributed run's parts (src/mpi, doc/plans/mpi.md): the ranks' communicator, the
# recursive coordinate bisection of the domain, the ghost reach by size class and the records
# sent between ranks. Built with MPI when the system has it (Debian: libopenmpi-dev,
# openmpi-bin); without it the communicator is a single rank and the same code runs serially.
find_package(MPI COMPONENTS CXX QUIET)
file(GLOB DEMLAB_MPI_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/mpi/*.cpp)
add_library(demlab_mpi STATIC ${DEMLAB_MPI_SOURCES})
demlab_precompile(demlab_mpi)
target_link_libraries(demlab_mpi PUBLIC demlab_core)
set_property(TARGET demlab_mpi PROPERTY POSITION_INDEPENDENT_CODE ON)
if(MPI_CXX_FOUND)
  target_compile_definitions(demlab_mpi PRIVATE DEMLAB_HAVE_MPI)
  target_link_libraries(demlab_mpi PUBLIC MPI::MPI_CXX)
endif()

# The serial tests (one rank: Communicator::self()).
demlab_add_unit_tests(mpi demlab_mpi_tests mpi/ demlab_mpi)

# The environment of every test run under mpirun: root in CI containers; more ranks than
# cores; no cross-memory attach in containers; no leak check (OpenMPI's own allocations outlive
# MPI_Finalize, which LeakSanitizer would report); one thread a rank (the ranks share the cores).
set(DEMLAB_MPI_TEST_ENV
    "OMPI_ALLOW_RUN_AS_ROOT=1;OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1;OMPI_MCA_rmaps_base_oversubscribe=1;OMPI_MCA_btl_vader_single_copy_mechanism=none;ASAN_OPTIONS=detect_leaks=0;DEMLAB_THREADS=1")

# The distributed tests, one program run under mpirun on 1, 2 and 3 ranks (3 oversubscribes a
# 2-core machine, as the test command runs it).
# The distributed runs of whole scenes (sim_ranks_test.cpp) likewise, as sim.np1-3.
if(MPI_CXX_FOUND)
  foreach(part mpi sim)
    add_executable(demlab_${part}_rank_tests ${CMAKE_CURRENT_SOURCE_DIR}/tests/mpi/${part}_ranks_test.cpp
                   ${CMAKE_CURRENT_SOURCE_DIR}/tests/mpi/rank_main.cpp)
    target_include_directories(demlab_${part}_rank_tests PRIVATE ${PROJECT_SOURCE_DIR}/tests)
    target_link_libraries(demlab_${part}_rank_tests PRIVATE demlab_${part} MPI::MPI_CXX GTest::gtest
                          Threads::Threads)
    if(DEMLAB_SANITIZE)
      target_compile_options(demlab_${part}_rank_tests PRIVATE -fno-sanitize=undefined)
    endif()
    foreach(np 1 2 3)
      add_test(NAME ${part}.np${np}
               COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} ${np}
                       $<TARGET_FILE:demlab_${part}_rank_tests> --gtest_brief=1)
      set_tests_properties(${part}.np${np} PROPERTIES TIMEOUT 900 ENVIRONMENT
                           "${DEMLAB_MPI_TEST_ENV}")
    endforeach()
  endforeach()
endif()

# What a distributed run of a scene would hold and send, for any number of ranks, measured on
# one process (the scaling model's inputs; doc/performance.md).
add_executable(bench_decompose ${DEMLAB_PROGRAM_SCOPE} bench/bench_decompose.cpp)
target_link_libraries(bench_decompose PRIVATE demlab_mpi demlab_io)

# The decomposition's own costs on real ranks: a search's bisection, migration, reach table
# and ghost plan, and a step's exchange (run under mpirun).
if(MPI_CXX_FOUND)
  add_executable(bench_exchange ${DEMLAB_PROGRAM_SCOPE} bench/bench_exchange.cpp)
  target_link_libraries(bench_exchange PRIVATE demlab_mpi demlab_io)
endif()
