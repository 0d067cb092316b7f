# libFuzzer targets for the file parsers (tests/fuzz/run-fuzzers.sh drives
# them). Only with clang and -DTT_FUZZ=ON; configure a separate build folder
# with -DTT_SANITIZE=ON too, so the library is checked by ASan and UBSan:
#   CC=clang cmake -S . -B build-fuzz -DTT_FUZZ=ON -DTT_SANITIZE=ON
option(TT_FUZZ "Build the libFuzzer targets (clang only)" OFF)
if(TT_FUZZ)
  if(NOT CMAKE_C_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "TT_FUZZ=ON needs clang (libFuzzer); configure with CC=clang")
  endif()
  # Coverage instrumentation for the library, so that libFuzzer sees which
  # branches of the parsers an input reaches.
  # (on the object library: the static library only collects its objects,
  # so options on `treetrace` itself reach no source and libFuzzer ran blind,
  # "cov: 4")
  target_compile_options(treetrace_objects PRIVATE -fsanitize=fuzzer-no-link)
  foreach(target fuzz_obj fuzz_ply fuzz_views fuzz_accel)
    add_executable(${target} "${CMAKE_CURRENT_SOURCE_DIR}/fuzz/${target}.c")
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer,address,undefined
      -fno-sanitize-recover=all -fno-omit-frame-pointer)
    target_link_options(${target} PRIVATE -fsanitize=fuzzer,address,undefined)
    target_link_libraries(${target} PRIVATE treetrace)
  endforeach()
  # the saved-structure loader's target uses the library's internal headers
  target_include_directories(fuzz_accel PRIVATE "${PROJECT_SOURCE_DIR}/src" "${TT_XXHASH_INCLUDE_DIR}")
endif()
