# Debian packages per role (issue 17), made by CPack from the install() rules below:
#   hullpose-common          the hullpose user (sysusers.d), /etc/hullpose/hullpose.conf, the
#                            receive-buffer sysctl, the GPIO udev rule, hullpose-doctor,
#                            hullpose-rig-key (every role needs the rig's key)
#   hullpose-camera-node     hullpose-camera-node + hullpose-camera-node@.service + camera0.yaml
#   hullpose-trigger-master  hullpose-trigger-master + its unit + trigger-master.conf
#   hullpose-fusion-host     hullpose-fusion-host + its unit + fusion-host.conf
#   hullpose-tools           hullpose-synth, -eval, -calibrate, -import (setting up, scoring)
#   hullpose-consumers       hullpose-web (+ its page and hullpose-web.service + web.conf),
#                            -listen, -export, -stream: what a LAN host does with the skeletons
# `make package` builds them (build-package/, no -march=native); `make cross` the arm64 ones.
# Only these files are installed: nothing else of the build tree (no headers, no static libraries).
include(GNUInstallDirs)
# cpack (and `make install`) must not build everything first: the packages need only their
# programs, which `make package` and deploy/cross/build.sh build (not the tests and benchmarks).
set(CMAKE_SKIP_INSTALL_ALL_DEPENDENCY ON)
set(_deploy ${PROJECT_SOURCE_DIR}/deploy)

# component -> package, programs, units, config files (under /etc/hullpose), summary
set(_hp_components common camera_node trigger_master fusion_host tools consumers)
set(_hp_common_programs hullpose-doctor hullpose-rig-key)
set(_hp_camera_node_programs hullpose-camera-node)
set(_hp_trigger_master_programs hullpose-trigger-master)
set(_hp_fusion_host_programs hullpose-fusion-host)
set(_hp_tools_programs hullpose-synth hullpose-eval hullpose-calibrate hullpose-import)
set(_hp_consumers_programs hullpose-listen hullpose-web hullpose-export hullpose-stream)
set(_hp_camera_node_units hullpose-camera-node@.service)
set(_hp_trigger_master_units hullpose-trigger-master.service)
set(_hp_fusion_host_units hullpose-fusion-host.service)
set(_hp_consumers_units hullpose-web.service)
set(_hp_common_config hullpose.conf)
set(_hp_camera_node_config camera0.yaml)
set(_hp_trigger_master_config trigger-master.conf)
set(_hp_fusion_host_config fusion-host.conf)
set(_hp_consumers_config web.conf)
set(_hp_common_summary "markerless motion capture - user, configuration and start-up checks")
set(_hp_camera_node_summary "markerless motion capture - camera node (one per camera board)")
set(_hp_trigger_master_summary "markerless motion capture - trigger master (drives the trigger line)")
set(_hp_fusion_host_summary "markerless motion capture - fusion host (visual hull, skeleton, pose)")
set(_hp_tools_summary "markerless motion capture - synthetic rig, evaluation, calibration, import")
set(_hp_consumers_summary "markerless motion capture - live web view, recording, export, streaming")
set(_hp_common_text
  "Everything a hullpose board needs whatever its role: the hullpose system\n"
  "user, /etc/hullpose/hullpose.conf (the rig's LCM URL and rig file), a\n"
  "sysctl that makes room for LCM's receive buffers, GPIO access for group\n"
  "gpio, and hullpose-doctor, which checks the network, clock, trigger GPIO\n"
  "and camera at every service start.")
set(_hp_camera_node_text
  "Captures frames (libcamera, V4L2), subtracts the learnt background and\n"
  "publishes each silhouette over LCM, stamped with the hardware trigger\n"
  "edge it belongs to. Runs as hullpose-camera-node@<camera>.service.")
set(_hp_trigger_master_text
  "Drives the rig's shared trigger line through libgpiod and announces\n"
  "every pulse's sequence number over LCM, so every camera labels the same\n"
  "instant alike.")
set(_hp_fusion_host_text
  "Gathers the silhouettes of one trigger instant, carves the visual hull,\n"
  "thins it to a curve skeleton, fits a 25-joint model and broadcasts the\n"
  "pose over LCM.")
set(_hp_tools_text
  "hullpose-synth renders synthetic rigs with ground truth, hullpose-eval\n"
  "scores estimates, hullpose-calibrate calibrates the rig, hullpose-import\n"
  "reads other tools' calibrations and recorded silhouettes.")
set(_hp_consumers_text
  "What a LAN host does with the rig's skeletons: hullpose-web serves a live\n"
  "three.js view to browsers (hullpose-web.service), hullpose-listen records\n"
  "takes, hullpose-export writes them as BVH, TRC or C3D and hullpose-stream\n"
  "sends the live skeleton as VMC (OSC) or BVH lines to animation tools.")

# The Debian revision: 2 moved hullpose-listen from hullpose-tools to hullpose-consumers.
set(_hp_release 2)
set(_packaging_scripts ${PROJECT_BINARY_DIR}/packaging)
file(READ ${_deploy}/debian/common-postinst.sh _common_postinst)
set(_all_programs)
foreach(c ${_hp_components})
  string(REPLACE "_" "-" pkg "hullpose-${c}")
  install(TARGETS ${_hp_${c}_programs} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT ${c})
  list(APPEND _all_programs ${_hp_${c}_programs})
  set(UNITS "")
  foreach(u ${_hp_${c}_units})
    install(FILES ${_deploy}/systemd/${u} DESTINATION lib/systemd/system COMPONENT ${c})
    string(REPLACE "@.service" "@*.service" pattern "${u}")
    string(APPEND UNITS " '${pattern}'")
  endforeach()
  string(STRIP "${UNITS}" UNITS)
  set(conffiles "")
  foreach(f ${_hp_${c}_config})
    install(FILES ${_deploy}/config/${f} DESTINATION /etc/hullpose COMPONENT ${c})
    string(APPEND conffiles "/etc/hullpose/${f}\n")
  endforeach()
  # Debian's documentation files: copyright and changelog in every package.
  set(VERSION ${PROJECT_VERSION})
  set(RELEASE ${_hp_release})
  configure_file(${_deploy}/debian/changelog ${_packaging_scripts}/${c}/changelog @ONLY)
  add_custom_command(OUTPUT ${_packaging_scripts}/${c}/changelog.Debian.gz
    COMMAND gzip -9nc ${_packaging_scripts}/${c}/changelog > ${_packaging_scripts}/${c}/changelog.Debian.gz
    DEPENDS ${_packaging_scripts}/${c}/changelog)
  list(APPEND _hp_changelogs ${_packaging_scripts}/${c}/changelog.Debian.gz)
  install(FILES ${_deploy}/debian/copyright ${_packaging_scripts}/${c}/changelog.Debian.gz
    DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/${pkg} COMPONENT ${c})
  # Maintainer scripts.
  set(PACKAGE ${pkg})
  set(COMMON_POSTINST "")
  if(c STREQUAL "common")
    set(COMMON_POSTINST "${_common_postinst}")
  endif()
  foreach(s postinst prerm postrm)
    configure_file(${_deploy}/debian/${s}.in ${_packaging_scripts}/${c}/${s} @ONLY)
  endforeach()
  file(WRITE ${_packaging_scripts}/${c}/conffiles "${conffiles}")
  set(extra ${_packaging_scripts}/${c}/postinst ${_packaging_scripts}/${c}/prerm ${_packaging_scripts}/${c}/postrm)
  if(conffiles)
    list(APPEND extra ${_packaging_scripts}/${c}/conffiles)
  endif()

  string(TOUPPER ${c} C)
  set(CPACK_DEBIAN_${C}_PACKAGE_NAME ${pkg})
  set(CPACK_DEBIAN_${C}_FILE_NAME DEB-DEFAULT)
  set(CPACK_DEBIAN_${C}_PACKAGE_CONTROL_EXTRA "${extra}")
  string(CONCAT _text ${_hp_${c}_text})
  set(CPACK_COMPONENT_${C}_DESCRIPTION "${_hp_${c}_summary}\n${_text}")
  if(NOT c STREQUAL "common")
    set(CPACK_DEBIAN_${C}_PACKAGE_DEPENDS "hullpose-common (= ${PROJECT_VERSION}-${_hp_release})")
  endif()
endforeach()
add_custom_target(hullpose_package_docs ALL DEPENDS ${_hp_changelogs})
install(FILES ${_deploy}/debian/sysusers.conf DESTINATION lib/sysusers.d RENAME hullpose.conf COMPONENT common)
install(FILES ${_deploy}/debian/sysctl.conf DESTINATION lib/sysctl.d RENAME 60-hullpose.conf COMPONENT common)
install(FILES ${_deploy}/debian/60-hullpose-gpio.rules DESTINATION lib/udev/rules.d COMPONENT common)
install(FILES ${_deploy}/README.md DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/hullpose-common RENAME README.deploy.md COMPONENT common)
set(CPACK_DEBIAN_COMMON_PACKAGE_DEPENDS "adduser")
# The web view's page, found by hullpose-web relative to its own path (tools/web/main.cpp), and
# three.js from Debian (served by hullpose-web itself: the rig's LAN has no internet).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/tools/web/page/ DESTINATION ${CMAKE_INSTALL_DATADIR}/hullpose/web
  COMPONENT consumers)
string(APPEND CPACK_DEBIAN_CONSUMERS_PACKAGE_DEPENDS ", libjs-three")
set(CPACK_DEBIAN_CONSUMERS_PACKAGE_REPLACES "hullpose-tools (<< ${PROJECT_VERSION}-2)")
set(CPACK_DEBIAN_CONSUMERS_PACKAGE_BREAKS "hullpose-tools (<< ${PROJECT_VERSION}-2)")
# For deploy/cross/build.sh: what to build before cpack.
file(WRITE ${PROJECT_BINARY_DIR}/hullpose-packaging.txt "HULLPOSE_PACKAGED_TARGETS=${_all_programs};hullpose_package_docs\n")

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME hullpose)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "hullpose")
set(CPACK_PACKAGE_CONTACT "hullpose developers <hullpose@example.org>")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL ${_hp_components})
set(CPACK_DEBIAN_PACKAGE_RELEASE ${_hp_release})
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "https://hullpose.invalid")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_DEBIAN_COMPRESSION_TYPE xz)
set(CPACK_STRIP_FILES ON)
if(CMAKE_CROSSCOMPILING)
  # dpkg-shlibdeps reads the host's dpkg database, which knows no arm64 libraries: what it finds
  # for the native packages (same Debian 12 package names on arm64), written out.
  set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE arm64)
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS OFF)
  set(_cxx "libc6 (>= 2.35), libgcc-s1 (>= 3.0), libstdc++6 (>= 12)")
  set(_cv "libopencv-core406 (>= 4.6.0+dfsg), libopencv-imgproc406 (>= 4.6.0+dfsg), libopencv-imgcodecs406 (>= 4.6.0+dfsg)")
  set(_bus "liblcm1, libsodium23 (>= 1.0.12), libssl3 (>= 3.0.0), libyaml-cpp0.7 (>= 0.7.0)")  # hullpose_common
  string(APPEND CPACK_DEBIAN_COMMON_PACKAGE_DEPENDS ", ${_cxx}, libcamera0.0.3 (>= 0.0.3), libgpiod2 (>= 1.1), libopencv-core406 (>= 4.6.0+dfsg), "
    "libsodium23 (>= 1.0.12), libssl3 (>= 3.0.0), libyaml-cpp0.7 (>= 0.7.0)")
  string(APPEND CPACK_DEBIAN_CAMERA_NODE_PACKAGE_DEPENDS ", ${_cxx}, ${_cv}, ${_bus}, libcamera0.0.3 (>= 0.0.3), libgpiod2 (>= 1.1), "
    "libopencv-calib3d406 (>= 4.6.0+dfsg), libopencv-video406 (>= 4.6.0+dfsg), libopencv-videoio406 (>= 4.6.0+dfsg)")
  string(APPEND CPACK_DEBIAN_TRIGGER_MASTER_PACKAGE_DEPENDS ", ${_cxx}, libgpiod2 (>= 1.1), liblcm1, libsodium23 (>= 1.0.12), libssl3 (>= 3.0.0)")
  string(APPEND CPACK_DEBIAN_FUSION_HOST_PACKAGE_DEPENDS ", ${_cxx}, ${_cv}, ${_bus}, libgomp1 (>= 6)")
  string(APPEND CPACK_DEBIAN_TOOLS_PACKAGE_DEPENDS ", ${_cxx}, ${_cv}, ${_bus}, libcamera0.0.3 (>= 0.0.3), libgpiod2 (>= 1.1), "
    "libopencv-calib3d406 (>= 4.6.0+dfsg), libopencv-video406 (>= 4.6.0+dfsg), libopencv-videoio406 (>= 4.6.0+dfsg)")
  string(APPEND CPACK_DEBIAN_CONSUMERS_PACKAGE_DEPENDS ", ${_cxx}, ${_bus}, liblo7 (>= 0.27), libopencv-core406 (>= 4.6.0+dfsg)")
else()
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
endif()
include(CPack)
