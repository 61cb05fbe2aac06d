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
  src/cmd/words.cpp src/cmd/pipe.cpp src/cmd/command.cpp src/cmd/registry.cpp)
target_link_libraries(demlab_cmd PUBLIC demlab_core)
set_property(TARGET demlab_cmd PROPERTY POSITION_INDEPENDENT_CODE ON)

enable_testing()
file(GLOB DEMLAB_CMD_TESTS CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/tests/unit/cmd/*.cpp)
add_executable(demlab_cmd_tests ${DEMLAB_CMD_TESTS})
target_link_libraries(demlab_cmd_tests PRIVATE demlab_cmd GTest::gtest GTest::gtest_main Threads::Threads)
add_test(NAME cmd COMMAND demlab_cmd_tests --gtest_brief=1)

if(NOT TARGET demlab_sim)
  message(STATUS "demlab: no demlab_sim target yet; only the command system is built")
  return()
endif()
