# Fuzzing (tests/fuzz): each target is one LLVMFuzzerTestOneInput over a reader.
#  - With DEMLAB_FUZZ=ON (clang; scripts/fuzz sets it up) the targets are libFuzzer programs,
#    fuzz_<name>, built with ASan and UBSan, the whole project instrumented for coverage.
#  - Otherwise each target is linked to tests/fuzz/replay_main.cpp and ctest replays its kept
#    corpus (tests/fuzz/corpus/<name>: seeds and every input a fuzzing run found) once and then
#    fuzzes mutations of it for DEMLAB_FUZZ_SECONDS: in the sanitizer build of the test command
#    that is under ASan and UBSan (a failing input is saved in fuzz-findings/ of the build).
option(DEMLAB_FUZZ "Build the libFuzzer targets (clang only)" OFF)

if(NOT TARGET demlab_sim OR NOT TARGET demlab_io)
  return()
endif()

set(DEMLAB_FUZZ_TARGETS checkpoint lammps_data)
foreach(name ${DEMLAB_FUZZ_TARGETS})
  if(DEMLAB_FUZZ)
    add_executable(fuzz_${name} tests/fuzz/${name}_fuzz.cpp)
    target_link_options(fuzz_${name} PRIVATE -fsanitize=fuzzer)
  else()
    add_executable(fuzz_${name} tests/fuzz/${name}_fuzz.cpp tests/fuzz/replay_main.cpp)
    file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/fuzz-findings)
    add_test(NAME fuzz_corpus.${name}
      COMMAND fuzz_${name} -seconds ${DEMLAB_FUZZ_SECONDS} -crashes ${CMAKE_BINARY_DIR}/fuzz-findings
              ${CMAKE_CURRENT_SOURCE_DIR}/tests/fuzz/corpus/${name})
    set_tests_properties(fuzz_corpus.${name} PROPERTIES COST 5000)
  endif()
  target_link_libraries(fuzz_${name} PRIVATE demlab_sim demlab_io)
endforeach()
