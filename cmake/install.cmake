# `cmake --install`: the public header, libtreetrace.so (soname
# libtreetrace.so.MAJOR) and libtreetrace.a, the treetrace command, a CMake
# package (find_package(treetrace) gives treetrace::treetrace, the shared
# library, and treetrace::treetrace_static) and a pkg-config file, all in
# the GNUInstallDirs places. Included from the top CMakeLists.txt once the
# library targets and the optional back ends exist.
include(CMakePackageConfigHelpers)

set(TT_CMAKE_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/treetrace")
set(tt_install_targets treetrace treetrace_shared treetrace_cli)
# The static library needs the CUDA objects beside it when they were built.
if(TT_BUILT_WITH_CUDA)
  list(APPEND tt_install_targets treetrace_cuda)
endif()
install(TARGETS ${tt_install_targets} EXPORT treetrace-targets
  RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}"
  LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}" NAMELINK_COMPONENT Development
  ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}")
install(DIRECTORY "${CMAKE_CURRENT_SOURCE_DIR}/include/treetrace"
  DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
install(EXPORT treetrace-targets NAMESPACE treetrace:: DESTINATION "${TT_CMAKE_DIR}")

# What a consumer of the static library must find again.
set(TT_CONFIG_DEPENDENCIES "find_dependency(OpenMP COMPONENTS C)\nfind_dependency(PNG)\nfind_dependency(Threads)\n")
if(TT_BUILT_WITH_EMBREE)
  string(APPEND TT_CONFIG_DEPENDENCIES "find_dependency(embree 3)\n")
endif()
if(TT_BUILT_WITH_CUDA)
  string(APPEND TT_CONFIG_DEPENDENCIES "find_dependency(CUDAToolkit)\n")
endif()
configure_package_config_file("${CMAKE_CURRENT_SOURCE_DIR}/cmake/treetrace-config.cmake.in"
  "${CMAKE_CURRENT_BINARY_DIR}/treetrace-config.cmake"
  INSTALL_DESTINATION "${TT_CMAKE_DIR}")
write_basic_package_version_file("${CMAKE_CURRENT_BINARY_DIR}/treetrace-config-version.cmake"
  COMPATIBILITY SameMinorVersion)
install(FILES "${CMAKE_CURRENT_BINARY_DIR}/treetrace-config.cmake"
  "${CMAKE_CURRENT_BINARY_DIR}/treetrace-config-version.cmake"
  DESTINATION "${TT_CMAKE_DIR}")

# pkg-config: `pkg-config --cflags --libs treetrace` links the shared
# library; `--static` adds what the static one needs.
set(TT_PC_LIBS_PRIVATE "${OpenMP_C_FLAGS} -lpng -lpthread -lm")
if(TT_BUILT_WITH_EMBREE)
  string(APPEND TT_PC_LIBS_PRIVATE " -lembree3")
endif()
if(TT_BUILT_WITH_CUDA)
  string(APPEND TT_PC_LIBS_PRIVATE " -ltreetrace_cuda -L${CUDAToolkit_LIBRARY_DIR} -lcudart_static -ldl -lrt -lstdc++")
endif()
# The prefix is found from the file's own place, so the file stays right
# after `cmake --install --prefix ELSEWHERE`.
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  set(TT_PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
else()
  file(RELATIVE_PATH tt_pc_up "/prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/prefix")
  string(REGEX REPLACE "/$" "" tt_pc_up "${tt_pc_up}")
  set(TT_PC_PREFIX "\${pcfiledir}/${tt_pc_up}")
endif()
configure_file("${CMAKE_CURRENT_SOURCE_DIR}/cmake/treetrace.pc.in"
  "${CMAKE_CURRENT_BINARY_DIR}/treetrace.pc" @ONLY)
install(FILES "${CMAKE_CURRENT_BINARY_DIR}/treetrace.pc"
  DESTINATION "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
