# COOPNAV_FUZZ: libFuzzer build (test/fuzz/README.md). Every target of the project is compiled with
# coverage instrumentation and ASan + UBSan, so a fuzzer sees the edges and the memory errors of
# our code, not just of its own file; only the fuzz executables link libFuzzer's main().
if(NOT COOPNAV_FUZZ)
  return()
endif()
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR
    "COOPNAV_FUZZ needs clang (libFuzzer ships with it), not ${CMAKE_CXX_COMPILER_ID}: configure "
    "with -DCMAKE_CXX_COMPILER=clang++-14 (Debian 12: clang-14 libclang-rt-14-dev), or use "
    "scripts/fuzz.sh")
endif()
if(COOPNAV_SANITIZE)
  message(FATAL_ERROR "COOPNAV_FUZZ brings its own sanitizers; leave COOPNAV_SANITIZE empty")
endif()
# -fno-sanitize-recover: a UBSan finding must stop the run (libFuzzer then saves the input), not
# print a line and carry on.
add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all
                    -fno-omit-frame-pointer)
add_link_options(-fsanitize=address,undefined -fno-sanitize-recover=all)
