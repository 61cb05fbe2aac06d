# Fuzzing (tests/fuzz): each target is one LLVMFuzzerTestOneInput over a reader.
#  - With DEMLAB_FUZZ=ON (clang; scripts/fuzz sets it up) the targets are libFuzzer programs,
#    fuzz_<name>, built with ASan and UBSan, the whole project instrumented for coverage.
#  - Otherwise each target is linked to tests/fuzz/replay_main.cpp and ctest replays its kept
#    corpus (tests/fuzz/corpus/<name>: seeds and every input a fuzzing run found) once: in the
#    sanitizer build of the test command that is the corpus under ASan and UBSan.
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
    add_test(NAME fuzz_corpus.${name}
      COMMAND fuzz_${name} ${CMAKE_CURRENT_SOURCE_DIR}/tests/fuzz/corpus/${name})
  endif()
  target_link_libraries(fuzz_${name} PRIVATE demlab_sim demlab_io)
endforeach()
