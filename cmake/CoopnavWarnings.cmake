# One warning policy for every target of ours (generated lcmtypes are header-only and included as
# SYSTEM so their code does not trip it).
add_library(coopnav_warnings INTERFACE)
target_compile_options(coopnav_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow
                                                  -Wnon-virtual-dtor -Wno-unused-parameter)
if(COOPNAV_WERROR)
  # GCC 12 reports maybe-uninitialized inside lcm-gen's inlined decode code (the hash local is
  # only read after a checked decode), which -isystem does not silence once inlined into our
  # code; keep it a warning so a real one is still seen, but not a build break.
  target_compile_options(coopnav_warnings INTERFACE -Werror
                                                    $<$<CXX_COMPILER_ID:GNU>:-Wno-error=maybe-uninitialized>)
endif()
if(COOPNAV_SANITIZE)
  # -fno-sanitize-recover: a UBSan finding aborts the process (a failed test), not a line in a log
  # nobody reads. Runtime options (halt_on_error, suppressions) are set by scripts/test.sh.
  target_compile_options(coopnav_warnings INTERFACE -fsanitize=${COOPNAV_SANITIZE}
                                                    -fno-sanitize-recover=all
                                                    -fno-omit-frame-pointer)
  target_link_options(coopnav_warnings INTERFACE -fsanitize=${COOPNAV_SANITIZE}
                                                 -fno-sanitize-recover=all)
endif()
