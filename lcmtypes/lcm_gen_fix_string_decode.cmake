# Run after lcm-gen (CMakeLists.txt): hardens the string decoding of the generated C++ headers.
#
# lcm-gen 1.3.1 decodes a string as `if(len > maxlen - pos) return -1; s.assign(p, len - 1);`
# without checking len >= 1. A received length of INT_MIN makes `len - 1` overflow, and assign()
# then copies ~2 GB from the datagram: one 30-byte message crashed any daemon (SIGSEGV; found by
# the fuzzers, test/fuzz/README.md). A length below 1 cannot come from an LCM encoder (it counts
# the terminating NUL), so such a message now fails to decode like any other malformed one.
#
# Usage: cmake -DGEN_DIR=<dir holding coopnav/*.hpp> -P lcm_gen_fix_string_decode.cmake
file(GLOB headers "${GEN_DIR}/coopnav/*.hpp")
foreach(h ${headers})
  file(READ "${h}" text)
  string(REGEX REPLACE "if\\((__[A-Za-z0-9_]+_len__|__elem_len) > maxlen - pos\\) return -1;"
                       "if(\\1 < 1 || \\1 > maxlen - pos) return -1;" patched "${text}")
  # Any string decode left unpatched means lcm-gen's output changed shape: stop the build rather
  # than ship an unguarded decoder.
  string(REGEX MATCH "if\\((__[A-Za-z0-9_]+_len__|__elem_len) > maxlen - pos\\)" left "${patched}")
  if(left)
    message(FATAL_ERROR "${h}: unguarded string length after patching: ${left}")
  endif()
  string(REGEX MATCH "\\.assign\\([^;]*_len_*[ ]*-[ ]*1\\)" assign "${patched}")
  string(FIND "${patched}" " < 1 || " guard)
  if(assign AND guard EQUAL -1)
    message(FATAL_ERROR "${h}: string decoding of an unknown shape; check the lcm-gen version")
  endif()
  if(NOT patched STREQUAL text)
    file(WRITE "${h}" "${patched}")
  endif()
endforeach()
