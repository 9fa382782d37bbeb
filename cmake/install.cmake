# Install rules and the exported package (docs/install.md): `cmake --install build --prefix P`
# puts the libraries, their public headers, the asimov executable, the replay assets, the sample
# programs and the docs under P; `find_package(asimov 0.1 REQUIRED)` with CMAKE_PREFIX_PATH=P
# then gives asimov::core (Result, Error), asimov::collision, asimov::robots, asimov::motion, asimov::interpreter, asimov::cell.
include(CMakePackageConfigHelpers)

set(ASIMOV_LAYERS core collision robots motion interpreter cell)
set(ASIMOV_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/asimov)

foreach(layer ${ASIMOV_LAYERS})
  # Exported as asimov::<layer>, the same name as the alias inside this build.
  set_target_properties(asimov_${layer} PROPERTIES EXPORT_NAME ${layer})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${layer}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endforeach()
list(TRANSFORM ASIMOV_LAYERS PREPEND asimov_ OUTPUT_VARIABLE ASIMOV_LAYER_TARGETS)
install(TARGETS ${ASIMOV_LAYER_TARGETS} EXPORT asimovTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES ${ASIMOV_VERSION_HEADER} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/asimov)
install(EXPORT asimovTargets NAMESPACE asimov:: DESTINATION ${ASIMOV_CMAKE_DIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/asimovConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/asimovConfig.cmake
                              INSTALL_DESTINATION ${ASIMOV_CMAKE_DIR})
# 0.x: a minor release may break the API, so 0.1 accepts 0.1.* only.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/asimovConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/asimovConfig.cmake ${PROJECT_BINARY_DIR}/asimovConfigVersion.cmake
        DESTINATION ${ASIMOV_CMAKE_DIR})

# The executable and what it reads at run time, found relative to itself (app/replay/replay.cmake).
install(TARGETS asimov RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${ASIMOV_REPLAY_OUT}/ DESTINATION ${ASIMOV_REPLAY_INSTALL_DIR})
# The studio's bundled script (app/serve/web/web.cmake), when it was built.
install(DIRECTORY ${ASIMOV_STUDIO_OUT}/ DESTINATION ${ASIMOV_STUDIO_INSTALL_DIR} OPTIONAL)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/robots/data/ DESTINATION ${CMAKE_INSTALL_DATADIR}/asimov/robots)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/programs/ DESTINATION ${CMAKE_INSTALL_DATADIR}/asimov/programs)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
