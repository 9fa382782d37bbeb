# The viewer files `asimov run --replay` inlines into its page: three.js from the npm registry
# (app/replay/node_modules, put there by `npm ci` in scripts/install-deps.sh) and viewer.js. They
# are copied into BUILD/replay/ at configure time, whose absolute path is compiled into asimov
# (ASIMOV_REPLAY_DIR; the environment variable of the same name overrides it at run time).
# Without node_modules the copy is skipped with a message and `asimov run --replay` exits 1
# saying what is missing; everything else builds and runs.
set(ASIMOV_REPLAY_OUT ${PROJECT_BINARY_DIR}/replay)
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
             COMPILE_DEFINITIONS ASIMOV_REPLAY_DIR="${ASIMOV_REPLAY_OUT}")
