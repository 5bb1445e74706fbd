# One warning policy for every target of ours (generated lcmtypes are header-only and included as
# SYSTEM so their code does not trip it).
add_library(coopnav_warnings INTERFACE)
target_compile_options(coopnav_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow
                                                  -Wnon-virtual-dtor -Wno-unused-parameter)
if(COOPNAV_WERROR)
  target_compile_options(coopnav_warnings INTERFACE -Werror)
endif()
if(COOPNAV_SANITIZE)
  target_compile_options(coopnav_warnings INTERFACE -fsanitize=${COOPNAV_SANITIZE}
                                                    -fno-omit-frame-pointer)
  target_link_options(coopnav_warnings INTERFACE -fsanitize=${COOPNAV_SANITIZE})
endif()
