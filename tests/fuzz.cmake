# The message decoder's fuzzer (tests/fuzz/): built with clang as a project of its own, run by a
# ctest for a bounded time on the committed seed corpus. Skipped (exit 77) where clang is missing.
add_executable(net_fuzz_corpus ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/make_corpus.cpp)
target_link_libraries(net_fuzz_corpus PRIVATE remotetouch_test_support)
add_test(NAME net_fuzz_corpus_check COMMAND net_fuzz_corpus --check ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/corpus)
# Rewrites tests/fuzz/corpus/ after a change of the wire format.
add_custom_target(regenerate_net_fuzz_corpus
  COMMAND net_fuzz_corpus ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/corpus
  DEPENDS net_fuzz_corpus)

set(REMOTETOUCH_FUZZ_SECONDS 25 CACHE STRING "How long the ctest fuzzes the message decoder")
find_program(REMOTETOUCH_CLANGXX NAMES clang++-14 clang++)
if(REMOTETOUCH_CLANGXX)
  include(ExternalProject)
  ExternalProject_Add(net_fuzzer
    SOURCE_DIR ${CMAKE_CURRENT_SOURCE_DIR}/fuzz
    BINARY_DIR ${CMAKE_BINARY_DIR}/fuzz/build
    CMAKE_ARGS -DCMAKE_CXX_COMPILER=${REMOTETOUCH_CLANGXX} -DCMAKE_BUILD_TYPE=Release
               -DREMOTETOUCH_ENGINE_DIR=${CMAKE_SOURCE_DIR}/engine
               -DCMAKE_CXX_COMPILER_LAUNCHER=${CMAKE_CXX_COMPILER_LAUNCHER}
    INSTALL_COMMAND ""
    BUILD_ALWAYS ON)
  add_test(NAME net_fuzz_decoder
           COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/run_fuzzer.sh ${CMAKE_BINARY_DIR}/fuzz/build/fuzz_message_decoder
                   ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/corpus ${CMAKE_BINARY_DIR}/fuzz/run ${REMOTETOUCH_FUZZ_SECONDS})
else()
  add_test(NAME net_fuzz_decoder COMMAND sh -c "echo 'clang++ not found: the decoder fuzzer is skipped'; exit 77")
endif()
set_tests_properties(net_fuzz_decoder PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300)
