# Part "tcl": the scripted interface of thesis chapter 12.
#   demlab_cmd        the command system (CommandLine, ArgStack, PipeLine, Registry); no Tcl
#   demlab_commands   the command groups over the Simulation API (src/cmd/commands)
#   demlab_tcl_obj    the Tcl binding, compiled against the stubs table (src/tcl)
#   demlab_pkg        libdemlab.so: `package require demlab` from a plain tclsh8.6
#   demlab            the executable: console and batch scripts (src/app)
# and the tests: demlab_cmd_tests (GoogleTest) and the tcltest suite (tests/tcl/all.tcl).
find_package(TCL QUIET)
find_path(DEMLAB_TCL_INCLUDE tcl.h PATHS /usr/include/tcl8.6 /usr/include/tcl REQUIRED)
find_library(DEMLAB_TCL_LIBRARY NAMES tcl8.6 tcl REQUIRED)
find_library(DEMLAB_TCL_STUB_LIBRARY NAMES tclstub8.6 tclstub REQUIRED)
find_path(DEMLAB_EDIT_INCLUDE histedit.h REQUIRED)
find_library(DEMLAB_EDIT_LIBRARY NAMES edit REQUIRED)
find_program(DEMLAB_TCLSH NAMES tclsh8.6 tclsh REQUIRED)

set(DEMLAB_PKG_VERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
file(STRINGS ${CMAKE_CURRENT_SOURCE_DIR}/tcl/pkgIndex.tcl _demlab_ifneeded REGEX "package ifneeded")
if(NOT _demlab_ifneeded MATCHES "demlab ${DEMLAB_PKG_VERSION} ")
  message(FATAL_ERROR "tcl/pkgIndex.tcl must offer demlab ${DEMLAB_PKG_VERSION} (the project version)")
endif()

# The shared libraries loaded into tclsh carry the core in them, so it must be position
# independent.
set_property(TARGET demlab_core PROPERTY POSITION_INDEPENDENT_CODE ON)

add_library(demlab_cmd STATIC
  src/cmd/words.cpp src/cmd/pipe.cpp src/cmd/command.cpp src/cmd/registry.cpp
  src/cmd/declaration.cpp)
target_link_libraries(demlab_cmd PUBLIC demlab_core)
set_property(TARGET demlab_cmd PROPERTY POSITION_INDEPENDENT_CODE ON)

enable_testing()
demlab_add_unit_tests(cmd demlab_cmd_tests cmd/ demlab_cmd)

if(NOT TARGET demlab_sim)
  message(STATUS "demlab: no demlab_sim target yet; only the command system is built")
  return()
endif()

# The viewer's Tcl (tcl/viewer.tcl), compiled in as a string that `viewer open` evaluates.
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/tcl/viewer.tcl)
file(READ ${CMAKE_CURRENT_SOURCE_DIR}/tcl/viewer.tcl DEMLAB_VIEWER_TCL_TEXT)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/generated/viewer_library.cpp.tmp
  "// Generated from tcl/viewer.tcl by cmake/tcl.cmake; do not edit.\n"
  "extern const char* const demlabViewerTcl;\n"
  "const char* const demlabViewerTcl = R\"DEMLAB_TCL(${DEMLAB_VIEWER_TCL_TEXT})DEMLAB_TCL\";\n")
configure_file(${CMAKE_CURRENT_BINARY_DIR}/generated/viewer_library.cpp.tmp
  ${CMAKE_CURRENT_BINARY_DIR}/generated/viewer_library.cpp COPYONLY)

# The command groups over the Simulation API.
file(GLOB DEMLAB_COMMAND_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/cmd/commands/*.cpp)
add_library(demlab_commands STATIC src/cmd/session.cpp src/cmd/time_vector.cpp
  ${DEMLAB_COMMAND_SOURCES}
  ${CMAKE_CURRENT_BINARY_DIR}/generated/viewer_library.cpp)
demlab_precompile(demlab_commands)
target_link_libraries(demlab_commands PUBLIC demlab_cmd demlab_sim demlab_io demlab_output
  demlab_analysis)
set_property(TARGET demlab_commands PROPERTY POSITION_INDEPENDENT_CODE ON)
# Snapshots (src/cmd/commands/snapshot.cpp) draw only when the renderer is built.
if(TARGET demlab_render)
  target_link_libraries(demlab_commands PUBLIC demlab_render)
  set_property(TARGET demlab_render PROPERTY POSITION_INDEPENDENT_CODE ON)
endif()
foreach(dep demlab_sim demlab_io demlab_output demlab_analysis demlab_physics)
  if(TARGET ${dep})
    set_property(TARGET ${dep} PROPERTY POSITION_INDEPENDENT_CODE ON)
  endif()
endforeach()

# The Tcl-level library (tcl/demlab.tcl) compiled in as a string, so the extension and the
# executable always carry the library they were built with.
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/tcl/demlab.tcl)
file(READ ${CMAKE_CURRENT_SOURCE_DIR}/tcl/demlab.tcl DEMLAB_TCL_LIBRARY_TEXT)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/generated/demlab_library.cpp.tmp
  "// Generated from tcl/demlab.tcl by cmake/tcl.cmake; do not edit.\n"
  "extern const char* const demlabTclLibrary;\n"
  "const char* const demlabTclLibrary = R\"DEMLAB_TCL(namespace eval ::demlab {variable version ${DEMLAB_PKG_VERSION}}\n"
  "${DEMLAB_TCL_LIBRARY_TEXT})DEMLAB_TCL\";\n")
configure_file(${CMAKE_CURRENT_BINARY_DIR}/generated/demlab_library.cpp.tmp
  ${CMAKE_CURRENT_BINARY_DIR}/generated/demlab_library.cpp COPYONLY)

# The binding, compiled once against the stubs table for both the package and the executable.
add_library(demlab_tcl_obj OBJECT src/tcl/binding.cpp src/tcl/interrupt.cpp src/tcl/int_list_obj.cpp
  ${CMAKE_CURRENT_BINARY_DIR}/generated/demlab_library.cpp)
target_compile_definitions(demlab_tcl_obj PUBLIC USE_TCL_STUBS DEMLAB_PKG_VERSION="${DEMLAB_PKG_VERSION}")
target_include_directories(demlab_tcl_obj PUBLIC ${DEMLAB_TCL_INCLUDE})
target_link_libraries(demlab_tcl_obj PUBLIC demlab_commands)
set_property(TARGET demlab_tcl_obj PROPERTY POSITION_INDEPENDENT_CODE ON)

# libdemlab.so in build/lib/demlab beside pkgIndex.tcl: TCLLIBPATH=build/lib tclsh8.6 finds it.
set(DEMLAB_PKG_DIR ${CMAKE_BINARY_DIR}/lib/demlab)
add_library(demlab_pkg MODULE $<TARGET_OBJECTS:demlab_tcl_obj>)
target_link_libraries(demlab_pkg PRIVATE demlab_commands ${DEMLAB_TCL_STUB_LIBRARY})
set_target_properties(demlab_pkg PROPERTIES OUTPUT_NAME demlab PREFIX lib LIBRARY_OUTPUT_DIRECTORY ${DEMLAB_PKG_DIR})
configure_file(${CMAKE_CURRENT_SOURCE_DIR}/tcl/pkgIndex.tcl ${DEMLAB_PKG_DIR}/pkgIndex.tcl COPYONLY)
configure_file(${CMAKE_CURRENT_SOURCE_DIR}/tcl/demlab.tcl ${DEMLAB_PKG_DIR}/demlab.tcl COPYONLY)

# The executable (build/demlab). The Tcl API is called directly here; the binding's objects go
# through the stubs table, which Demlab_Init fills from the interpreter.
add_executable(demlab src/app/main.cpp src/app/console.cpp $<TARGET_OBJECTS:demlab_tcl_obj>)
target_compile_definitions(demlab PRIVATE DEMLAB_PKG_VERSION="${DEMLAB_PKG_VERSION}")
target_include_directories(demlab PRIVATE ${DEMLAB_TCL_INCLUDE} ${DEMLAB_EDIT_INCLUDE})
target_link_libraries(demlab PRIVATE demlab_commands ${DEMLAB_TCL_STUB_LIBRARY} ${DEMLAB_TCL_LIBRARY}
  ${DEMLAB_EDIT_LIBRARY})
set_target_properties(demlab PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR})

# doc/commands.md, generated from the declarations whenever the executable changes.
add_custom_command(OUTPUT ${CMAKE_BINARY_DIR}/commands.md
  COMMAND demlab --markdown > ${CMAKE_BINARY_DIR}/commands.md
  COMMAND ${CMAKE_COMMAND} -E copy_if_different ${CMAKE_BINARY_DIR}/commands.md
          ${CMAKE_CURRENT_SOURCE_DIR}/doc/commands.md
  DEPENDS demlab
  COMMENT "Writing doc/commands.md from the command declarations")
add_custom_target(demlab_doc ALL DEPENDS ${CMAKE_BINARY_DIR}/commands.md)

# The tcltest suite: through the executable and through the package in a plain tclsh, one
# ctest entry per test file, so that `ctest -j` runs the files side by side (the suite as one
# program kept one core idle for most of the run). In the sanitizer build the plain tclsh gets
# the ASan runtime preloaded (it must come first in a process that loads an instrumented
# extension), without leak checks: the programs the tests start (gnuplot, python3) inherit it.
set(DEMLAB_TCLSH_ENV TCLLIBPATH=${CMAKE_BINARY_DIR}/lib)
if(DEMLAB_SANITIZE)
  # libstdc++ too: ASan intercepts __cxa_throw only if the C++ runtime is there when it starts.
  execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libasan.so
    OUTPUT_VARIABLE DEMLAB_ASAN_RUNTIME OUTPUT_STRIP_TRAILING_WHITESPACE)
  execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libstdc++.so.6
    OUTPUT_VARIABLE DEMLAB_CXX_RUNTIME OUTPUT_STRIP_TRAILING_WHITESPACE)
  list(APPEND DEMLAB_TCLSH_ENV LD_PRELOAD=${DEMLAB_ASAN_RUNTIME}:${DEMLAB_CXX_RUNTIME}
    ASAN_OPTIONS=detect_leaks=0)
endif()
file(GLOB DEMLAB_TCL_TEST_FILES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/tests/tcl/*.test)
# Files run through the executable only: they exercise the engine's physics through commands
# every other file already runs through the package, and each takes over 40 s in the sanitizer
# build, time the test command spends on fuzzing instead (doc/reliability.md, "The test command").
# interrupt's commands run in child demlab executables whichever interpreter starts them;
# snapshot's renderer is the same code whichever interpreter calls it; bond, dump and wall spend
# their time in the engine (bonded samples, writers, mesh walls), not in the binding, whose
# every declaration badinput checks through the package; so does stability (long runs of
# stiff and extreme scenes).
set(DEMLAB_TCL_EXECUTABLE_ONLY analysis bond compaction drum_assembly dump element interrupt janssen lab periodic silo sim snapshot
    stability threads triaxial wall wallmotion)
# Files about the package itself in a plain tclsh and in wish, run through the package only; and
# badinput, whose every call goes through the binding that the executable and the package share.
set(DEMLAB_TCL_PACKAGE_ONLY package badinput)
# Files that open windows: run on a virtual X display of their own (xvfb-run), one such file at
# a time (two xvfb-run -a starting together can pick the same display number).
set(DEMLAB_TCL_DISPLAY viewer package)
find_program(DEMLAB_XVFB_RUN xvfb-run)
set(DEMLAB_TCL_TESTS "")
set(DEMLAB_TCL_DISPLAY_TESTS "")
foreach(test_file ${DEMLAB_TCL_TEST_FILES})
  get_filename_component(test_name ${test_file} NAME_WE)
  set(display "")
  if(test_name IN_LIST DEMLAB_TCL_DISPLAY AND DEMLAB_XVFB_RUN)
    set(display ${DEMLAB_XVFB_RUN} -a)
  endif()
  if(NOT test_name IN_LIST DEMLAB_TCL_PACKAGE_ONLY)
    add_test(NAME tcl.${test_name}
      COMMAND ${display} $<TARGET_FILE:demlab> ${CMAKE_CURRENT_SOURCE_DIR}/tests/tcl/all.tcl
              -file ${test_name}.test)
    list(APPEND DEMLAB_TCL_TESTS tcl.${test_name})
    if(test_name IN_LIST DEMLAB_TCL_DISPLAY)
      list(APPEND DEMLAB_TCL_DISPLAY_TESTS tcl.${test_name})
    endif()
  endif()
  if(test_name IN_LIST DEMLAB_TCL_EXECUTABLE_ONLY)
    continue()
  endif()
  add_test(NAME tcl_package.${test_name} COMMAND ${display} ${CMAKE_COMMAND} -E env
    ${DEMLAB_TCLSH_ENV} ${DEMLAB_TCLSH} ${CMAKE_CURRENT_SOURCE_DIR}/tests/tcl/all.tcl -package
    -file ${test_name}.test)
  list(APPEND DEMLAB_TCL_TESTS tcl_package.${test_name})
  if(test_name IN_LIST DEMLAB_TCL_DISPLAY)
    list(APPEND DEMLAB_TCL_DISPLAY_TESTS tcl_package.${test_name})
  endif()
endforeach()
if(DEMLAB_TCL_DISPLAY_TESTS)
  set_tests_properties(${DEMLAB_TCL_DISPLAY_TESTS} PROPERTIES RESOURCE_LOCK xvfb)
endif()
# Time limits in the tests (Ctrl-C's latency) are scaled by DEMLAB_TIME_FACTOR: the sanitizer
# build runs several times slower than Release.
set(DEMLAB_TIME_FACTOR 1)
if(DEMLAB_SANITIZE OR DEMLAB_TSAN)
  set(DEMLAB_TIME_FACTOR 5)
endif()
set_tests_properties(${DEMLAB_TCL_TESTS} PROPERTIES ENVIRONMENT
  "DEMLAB_EXE=$<TARGET_FILE:demlab>;DEMLAB_TIME_FACTOR=${DEMLAB_TIME_FACTOR}")

# Scripts under mpirun (tests/mpi/script_ranks.sh): the same script alone and on 1, 2 and 3
# ranks gives the same values; errors end every rank; a rank failing alone aborts the run.
if(MPI_CXX_FOUND)
  foreach(np 1 2 3)
    add_test(NAME tcl_ranks.np${np}
             COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tests/mpi/script_ranks.sh $<TARGET_FILE:demlab>
                     ${MPIEXEC_EXECUTABLE} ${np})
    set_tests_properties(tcl_ranks.np${np} PROPERTIES TIMEOUT 900 ENVIRONMENT "${DEMLAB_MPI_TEST_ENV}")
  endforeach()
  # The distributed fuzzer's kept sequences (its seeds and findings), each a script on 2 ranks
  # whose ranks must see the same outcome of every command (tests/fuzz/ranks_fuzz.tcl).
  add_test(NAME fuzz_corpus.ranks
           COMMAND demlab ${CMAKE_CURRENT_SOURCE_DIR}/tests/fuzz/ranks_fuzz.tcl replay
                   -mpiexec ${MPIEXEC_EXECUTABLE} -demlab $<TARGET_FILE:demlab>
                   ${CMAKE_CURRENT_SOURCE_DIR}/tests/fuzz/corpus/ranks)
  set_tests_properties(fuzz_corpus.ranks PROPERTIES TIMEOUT 900 ENVIRONMENT "${DEMLAB_MPI_TEST_ENV}")
endif()

# The sequences the command fuzzer found failing, kept as regression tests: each is run again
# in a runner process and must now keep every invariant (tests/fuzz/command_fuzz.tcl).
add_test(NAME fuzz_corpus.tcl COMMAND demlab ${CMAKE_CURRENT_SOURCE_DIR}/tests/fuzz/command_fuzz.tcl
  replay ${CMAKE_CURRENT_SOURCE_DIR}/tests/fuzz/corpus/tcl)
# The sanitizer build also fuzzes: new random command sequences for DEMLAB_FUZZ_SECONDS x 3
# (failing ones are minimised into fuzz-findings/ of the build folder). It starts first (COST)
# and runs beside the other tests.
if(DEMLAB_SANITIZE)
  math(EXPR DEMLAB_COMMAND_FUZZ_SECONDS "${DEMLAB_FUZZ_SECONDS} * 3")
  add_test(NAME fuzz.commands COMMAND demlab ${CMAKE_CURRENT_SOURCE_DIR}/tests/fuzz/command_fuzz.tcl
    fuzz -seconds ${DEMLAB_COMMAND_FUZZ_SECONDS} -seed 1 -corpus ${CMAKE_BINARY_DIR}/fuzz-findings)
  set_tests_properties(fuzz.commands PROPERTIES COST 10000
    ENVIRONMENT "DEMLAB_THREADS=1;ASAN_OPTIONS=detect_leaks=0")
endif()

include(GNUInstallDirs)
install(TARGETS demlab RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS demlab_pkg LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/tcltk/demlab${DEMLAB_PKG_VERSION})
install(FILES tcl/pkgIndex.tcl tcl/demlab.tcl DESTINATION ${CMAKE_INSTALL_LIBDIR}/tcltk/demlab${DEMLAB_PKG_VERSION})
install(FILES doc/commands.md DESTINATION ${CMAKE_INSTALL_DOCDIR} OPTIONAL)
