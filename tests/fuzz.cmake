# The fuzzers (tests/fuzz/): built with clang as a project of their own, each run by a ctest for a
# bounded time on its committed seed corpus (tests/fuzz/corpus/TARGET/), and each corpus checked
# through the GCC build's parsers. The fuzz runs are skipped (exit 77) where clang is missing.
add_executable(net_fuzz_corpus ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/make_corpus.cpp)
target_link_libraries(net_fuzz_corpus PRIVATE remotetouch_test_common)
add_dependencies(cpu_tests net_fuzz_corpus)
add_test(NAME net_fuzz_corpus_check
         COMMAND net_fuzz_corpus --check ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/corpus/message_decoder)
set_tests_properties(net_fuzz_corpus_check PROPERTIES LABELS cpu)
# Rewrites tests/fuzz/corpus/message_decoder/ after a change of the wire format.
add_custom_target(regenerate_net_fuzz_corpus
  COMMAND net_fuzz_corpus ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/corpus/message_decoder
  DEPENDS net_fuzz_corpus)

# The other targets (tests/fuzz/fuzz_TARGET.cpp), each with its corpus, dictionary and longest input.
set(REMOTETOUCH_FUZZ_TARGETS site_config scene leap_frame frames_jsonl png_header)
set(fuzz_max_len_site_config 4096)
set(fuzz_max_len_scene 8192)
set(fuzz_max_len_leap_frame 8192)
set(fuzz_max_len_frames_jsonl 4096)
set(fuzz_max_len_png_header 1024)

# fuzz_corpus_TARGET: every committed input through the engine's own parsers (valid_* accepted,
# broken_* refused with a message; the inputs fuzzers once crashed on stay there as regressions).
add_executable(fuzz_corpus_check
  ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/check_corpus.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/fuzz_target.cpp)
foreach(target ${REMOTETOUCH_FUZZ_TARGETS})
  target_sources(fuzz_corpus_check PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/fuzz_${target}.cpp)
  add_test(NAME fuzz_corpus_${target}
           COMMAND fuzz_corpus_check ${target} ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/corpus/${target})
endforeach()
target_include_directories(fuzz_corpus_check PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/fuzz)
# One compiler run for the targets: each instantiates nlohmann-json's templates again.
remotetouch_unity_build(fuzz_corpus_check)
target_compile_definitions(fuzz_corpus_check PRIVATE RT_FUZZ_ASSETS_DIR="${CMAKE_SOURCE_DIR}/assets")
target_link_libraries(fuzz_corpus_check PRIVATE remotetouch_site remotetouch_cpu remotetouch_tracker)

set(REMOTETOUCH_FUZZ_SECONDS 18 CACHE STRING "How long each fuzz ctest (net_fuzz_decoder, fuzz_TARGET) fuzzes")
find_program(REMOTETOUCH_CLANGXX NAMES clang++-14 clang++)
set(REMOTETOUCH_FUZZ_BUILD_DIR ${CMAKE_BINARY_DIR}/fuzz/build CACHE PATH "Where the clang build of the fuzzers lives")
set(fuzz_build ${REMOTETOUCH_FUZZ_BUILD_DIR})
set(fuzz_dir ${CMAKE_CURRENT_SOURCE_DIR}/fuzz)
if(REMOTETOUCH_CLANGXX AND NOT REMOTETOUCH_SANITIZE)
  include(ExternalProject)
  ExternalProject_Add(net_fuzzer
    SOURCE_DIR ${fuzz_dir}
    BINARY_DIR ${fuzz_build}
    CMAKE_ARGS -DCMAKE_CXX_COMPILER=${REMOTETOUCH_CLANGXX} -DCMAKE_BUILD_TYPE=Release
               -DREMOTETOUCH_SOURCE_DIR=${CMAKE_SOURCE_DIR}
               -DCMAKE_CXX_COMPILER_LAUNCHER=${CMAKE_CXX_COMPILER_LAUNCHER}
    INSTALL_COMMAND ""
    BUILD_ALWAYS ON)
  add_test(NAME net_fuzz_decoder
           COMMAND ${fuzz_dir}/run_fuzzer.sh ${fuzz_build}/fuzz_message_decoder ${fuzz_dir}/corpus/message_decoder
                   ${CMAKE_BINARY_DIR}/fuzz/run/message_decoder ${REMOTETOUCH_FUZZ_SECONDS} -rss_limit_mb=3072
                   -max_len=16384)
  foreach(target ${REMOTETOUCH_FUZZ_TARGETS})
    add_test(NAME fuzz_${target}
             COMMAND ${fuzz_dir}/run_fuzzer.sh ${fuzz_build}/fuzz_${target} ${fuzz_dir}/corpus/${target}
                     ${CMAKE_BINARY_DIR}/fuzz/run/${target} ${REMOTETOUCH_FUZZ_SECONDS}
                     -max_len=${fuzz_max_len_${target}} -dict=${fuzz_dir}/dict/${target}.dict)
  endforeach()
else()
  foreach(test net_fuzz_decoder ${REMOTETOUCH_FUZZ_TARGETS})
    if(NOT test STREQUAL net_fuzz_decoder)
      set(test fuzz_${test})
    endif()
    if(REMOTETOUCH_SANITIZE)
      set(why "the fuzzers run sanitized in the normal build")
    else()
      set(why "clang++ not found")
      if(REMOTETOUCH_REQUIRE_ALL_TESTS)
        message(FATAL_ERROR "clang++ not found (Debian: clang, libclang-rt-14-dev): the fuzzers cannot run")
      endif()
    endif()
    add_test(NAME ${test} COMMAND sh -c "echo '${why}: the fuzzer is skipped'; exit 77")
  endforeach()
endif()
foreach(target ${REMOTETOUCH_FUZZ_TARGETS})
  set_tests_properties(fuzz_${target} PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300)
endforeach()
set_tests_properties(net_fuzz_decoder PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300)
