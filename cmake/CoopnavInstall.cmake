# Install rules and the Debian package (README "Install").
#
#   <prefix>/bin/coopnav_<daemon>, coopnav_ctl, coopnav_record
#   <prefix>/share/coopnav/        config/ as in the tree: <daemon>.yaml, maps/, scenarios/, so
#                                  the configs' relative paths (map_file: maps/open.yaml, a
#                                  scenario's ../maps/open.yaml; both relative to the file's own
#                                  folder) resolve there
#   <prefix>/share/java/coopnav_lcmtypes.jar   (lcm-spy's types, when a JDK built it)
#   <prefix>/lib/systemd/system/   coopnav@.service (+ the distance server's drop-in),
#                                  coopnav.target, their ExecStart on <prefix>/bin
#   <confdir>                      the admin's copies: coopnav.env, <daemon>.yaml, and maps/ and
#                                  scenarios/ as links into share/coopnav, so an unedited copy
#                                  resolves its maps as the shipped one does
#
# <confdir> (COOPNAV_INSTALL_CONFDIR): /etc/coopnav for the prefixes /usr and /usr/local (what
# the units and the README's recipe name), <prefix>/etc/coopnav for any other prefix (an install
# without root). The prefix and the confdir are read when installing, not when configuring:
# `cmake --install build --prefix P` and CPack's /usr both get units that name their own paths.
include(GNUInstallDirs)

set(COOPNAV_INSTALL_CONFDIR "" CACHE STRING
    "Admin config folder (empty: /etc/coopnav for the prefixes /usr and /usr/local, else <prefix>/etc/coopnav)")

get_property(coopnav_daemon_exes GLOBAL PROPERTY COOPNAV_DAEMON_EXES)
install(TARGETS ${coopnav_daemon_exes} coopnav_ctl coopnav_record
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

set(coopnav_share ${CMAKE_INSTALL_DATADIR}/coopnav)
file(GLOB coopnav_config_yamls CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/config/*.yaml)
install(FILES ${coopnav_config_yamls} DESTINATION ${coopnav_share})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/config/maps ${PROJECT_SOURCE_DIR}/config/scenarios
        DESTINATION ${coopnav_share})
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
if(TARGET coopnav_lcmtypes_jar)
  install(FILES ${CMAKE_BINARY_DIR}/coopnav_lcmtypes.jar DESTINATION ${CMAKE_INSTALL_DATADIR}/java)
endif()

# The units and the admin's folder, written at install time for the prefix being installed to.
set(coopnav_units_in ${PROJECT_SOURCE_DIR}/config/systemd)
set(coopnav_units_out ${CMAKE_BINARY_DIR}/install-gen)
install(CODE "
  set(prefix \"\${CMAKE_INSTALL_PREFIX}\")
  set(confdir \"${COOPNAV_INSTALL_CONFDIR}\")
  if(confdir STREQUAL \"\")
    if(prefix STREQUAL \"/usr\" OR prefix STREQUAL \"/usr/local\")
      set(confdir /etc/coopnav)
    else()
      set(confdir \"\${prefix}/etc/coopnav\")
    endif()
  endif()
  set(yamls \"${coopnav_config_yamls}\")
  file(MAKE_DIRECTORY \"${coopnav_units_out}\")
  foreach(unit coopnav@.service coopnav.target
               coopnav@obstacle_distance_server.service.d/no-journal.conf)
    file(READ \"${coopnav_units_in}/\${unit}\" text)
    string(REPLACE /usr/local/bin/ \"\${prefix}/${CMAKE_INSTALL_BINDIR}/\" text \"\${text}\")
    string(REPLACE /usr/local/share/doc/coopnav/ \"\${prefix}/${CMAKE_INSTALL_DOCDIR}/\" text \"\${text}\")
    string(REPLACE /etc/coopnav/ \"\${confdir}/\" text \"\${text}\")
    get_filename_component(dir \"${coopnav_units_out}/\${unit}\" DIRECTORY)
    file(MAKE_DIRECTORY \"\${dir}\")
    file(WRITE \"${coopnav_units_out}/\${unit}\" \"\${text}\")
  endforeach()
  # file(INSTALL) puts DESTDIR in front of an absolute destination itself; file(CREATE_LINK)
  # does not.
  set(dest \"\${prefix}/lib/systemd/system\")
  file(INSTALL \"${coopnav_units_out}/coopnav@.service\" \"${coopnav_units_out}/coopnav.target\"
       DESTINATION \"\${dest}\")
  file(INSTALL \"${coopnav_units_out}/coopnav@obstacle_distance_server.service.d\"
       DESTINATION \"\${dest}\")
  file(INSTALL \"${coopnav_units_in}/coopnav.env\" \${yamls}
       DESTINATION \"\${confdir}\")
  foreach(sub maps scenarios)
    file(RELATIVE_PATH target \"\${confdir}\" \"\${prefix}/${coopnav_share}/\${sub}\")
    message(STATUS \"Installing: \$ENV{DESTDIR}\${confdir}/\${sub} -> \${target}\")
    file(REMOVE \"\$ENV{DESTDIR}\${confdir}/\${sub}\")
    file(CREATE_LINK \"\${target}\" \"\$ENV{DESTDIR}\${confdir}/\${sub}\" SYMBOLIC)
  endforeach()
")

# The Debian package: `cpack -G DEB` in the build folder -> coopnav_<version>_amd64.deb, installed
# under /usr (units in /usr/lib/systemd/system, admin copies in /etc/coopnav, conffiles: dpkg keeps
# an admin's edits on upgrade). Its dependencies are the runtime packages of the libraries the
# binaries link, found by dpkg-shlibdeps (dpkg-dev) from the built ELF files, so the list follows
# the code (scripts/deb_check.sh proves it on a fresh Debian 12).
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME coopnav)
set(CPACK_PACKAGE_VENDOR coopnav)
set(CPACK_PACKAGE_CONTACT "coopnav maintainers <coopnav@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "LCM service daemons: does the person walking towards the robot cooperate, and what the robot says")
# DESTDIR staging with the real prefix, so that CMAKE_INSTALL_PREFIX is /usr while installing
# (the units name it) and the admin folder's absolute path lands in the package.
set(CPACK_SET_DESTDIR ON)
set(CPACK_INSTALL_PREFIX /usr)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(coopnav_conffiles ${CMAKE_BINARY_DIR}/install-gen/conffiles)
set(coopnav_conffiles_text "/etc/coopnav/coopnav.env\n")
foreach(y ${coopnav_config_yamls})
  get_filename_component(n ${y} NAME)
  string(APPEND coopnav_conffiles_text "/etc/coopnav/${n}\n")
endforeach()
file(WRITE ${coopnav_conffiles} "${coopnav_conffiles_text}")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${coopnav_conffiles})
include(CPack)
