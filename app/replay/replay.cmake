# The viewer files `asimov run --replay` inlines into its page: three.js from the npm registry
# (app/replay/node_modules, put there by `npm ci` in scripts/install-deps.sh) and viewer.js.
# asimov reads them from a folder at a fixed path relative to its own executable
# (ASIMOV_REPLAY_REL, compiled in; the environment variable ASIMOV_REPLAY_DIR overrides it):
# <bindir>/../share/asimov/replay once installed, and the same relative place in the build tree
# (BUILD/app/asimov -> BUILD/share/asimov/replay), where they are copied at configure time.
# Without node_modules the copy is skipped with a message and `asimov run --replay` exits 1
# saying what is missing; everything else builds and runs.
set(ASIMOV_REPLAY_INSTALL_DIR ${CMAKE_INSTALL_DATADIR}/asimov/replay)
file(RELATIVE_PATH ASIMOV_REPLAY_REL ${CMAKE_INSTALL_FULL_BINDIR} ${CMAKE_INSTALL_PREFIX}/${ASIMOV_REPLAY_INSTALL_DIR})
get_filename_component(ASIMOV_REPLAY_OUT ${CMAKE_CURRENT_BINARY_DIR}/${ASIMOV_REPLAY_REL} ABSOLUTE)
set(ASIMOV_THREE_DIR ${CMAKE_CURRENT_LIST_DIR}/node_modules/three)
file(MAKE_DIRECTORY ${ASIMOV_REPLAY_OUT})
configure_file(${CMAKE_CURRENT_LIST_DIR}/viewer.js ${ASIMOV_REPLAY_OUT}/viewer.js COPYONLY)
if(EXISTS ${ASIMOV_THREE_DIR}/build/three.module.min.js)
  configure_file(${ASIMOV_THREE_DIR}/build/three.module.min.js ${ASIMOV_REPLAY_OUT}/three.module.min.js COPYONLY)
  configure_file(${ASIMOV_THREE_DIR}/examples/jsm/controls/OrbitControls.js ${ASIMOV_REPLAY_OUT}/OrbitControls.js COPYONLY)
else()
  file(REMOVE ${ASIMOV_REPLAY_OUT}/three.module.min.js ${ASIMOV_REPLAY_OUT}/OrbitControls.js)
  message(STATUS "replay: ${ASIMOV_THREE_DIR} not installed (scripts/install-deps.sh runs npm ci there); "
                 "`asimov run --replay` will say so and exit 1")
endif()
set_property(SOURCE ${CMAKE_CURRENT_SOURCE_DIR}/replay.cpp APPEND PROPERTY
             COMPILE_DEFINITIONS ASIMOV_REPLAY_REL="${ASIMOV_REPLAY_REL}")
# For the install rules (cmake/install.cmake, included from the top level).
set(ASIMOV_REPLAY_OUT ${ASIMOV_REPLAY_OUT} CACHE INTERNAL "")
set(ASIMOV_REPLAY_INSTALL_DIR ${ASIMOV_REPLAY_INSTALL_DIR} CACHE INTERNAL "")
