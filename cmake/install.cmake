# `cmake --install` and the Debian package (CPack): where a Linux user looks for each part.
#   bin/wisp                                    the command line (presets, editor embedded)
#   share/wisp/presets/*.toml                   the shipped styles, to copy and change
#   share/blender/scripts/addons/               the Blender add-on, where Debian's blender
#                                               lists system add-ons
#   lib/python3/dist-packages/wisp/             `import wisp` for Debian's /usr/bin/python3
#   share/doc/wisp/                             the README and docs/*.md
# The package is tested by scripts/package-test (ctest: install.debian_package).
include(GNUInstallDirs)

install(TARGETS wisp RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/presets/ DESTINATION ${CMAKE_INSTALL_DATADIR}/wisp/presets
  FILES_MATCHING PATTERN "*.toml")
install(FILES ${PROJECT_SOURCE_DIR}/blender/wisp_hair_import.py
  DESTINATION ${CMAKE_INSTALL_DATADIR}/blender/scripts/addons)
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}
  FILES_MATCHING PATTERN "*.md")

set(WISP_INSTALL_PYTHONDIR "lib/python3/dist-packages" CACHE STRING
  "Where `cmake --install` puts the wisp Python package (Debian's path for /usr/bin/python3)")
if(TARGET _wisp)
  install(TARGETS _wisp LIBRARY DESTINATION ${WISP_INSTALL_PYTHONDIR}/wisp)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/python/wisp/ DESTINATION ${WISP_INSTALL_PYTHONDIR}/wisp)
endif()

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME wisp)
set(CPACK_PACKAGE_VENDOR wisp)
set(CPACK_PACKAGE_CONTACT "wisp developers <wisp@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
  "realistic human hairstyles from a few parameters, animated")
set(CPACK_PACKAGE_DESCRIPTION
  "wisp generates hairstyles with the statistical wisp model of Choe and Ko (2005) and "
  "animates them with the Adaptive Wisp Tree of Bertails et al. (2003). It writes USD, "
  "cyHair, PLY, OBJ, pbrt and RIB strands; renders them; edits them in the browser "
  "(wisp edit); makes datasets on one machine or on Slurm; and has a Python module and a "
  "Blender add-on.")
set(CPACK_PACKAGE_INSTALL_DIRECTORY wisp)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
# The shared libraries' packages are read off the binaries (dpkg-shlibdeps); the Python
# extension is built for this Python's ABI.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
if(TARGET _wisp)
  math(EXPR WISP_NEXT_PYTHON_MINOR "${Python_VERSION_MINOR} + 1")
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3 (>= ${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}~), \
python3 (<< ${Python_VERSION_MAJOR}.${WISP_NEXT_PYTHON_MINOR})")
endif()
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3-numpy, ffmpeg")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "blender")
include(CPack)

if(WISP_BUILD_TESTS)
  add_test(NAME install.debian_package
    COMMAND ${PROJECT_SOURCE_DIR}/scripts/package-test ${PROJECT_BINARY_DIR})
  set_tests_properties(install.debian_package PROPERTIES
    LABELS install SKIP_RETURN_CODE 77 TIMEOUT 600)
endif()
