# ctest script: installs this build into a scratch prefix inside the build folder, then
# compiles examples/pkg-config/main.cpp with nothing but
#   c++ main.cpp -o consumer $(pkg-config --cflags --libs softpbr)
# (PKG_CONFIG_PATH pointing at the installed softpbr.pc) and runs it.
# Inputs: -DSOURCE_DIR= -DBINARY_DIR=
set(work "${BINARY_DIR}/pkgconfig-test")
set(prefix "${work}/install")
file(REMOVE_RECURSE "${work}")
file(MAKE_DIRECTORY "${work}")
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${prefix}
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pkg-config test: cmake --install failed (${rc}):\n${err}")
endif()
file(GLOB_RECURSE pc_files "${prefix}/*/softpbr.pc")
list(LENGTH pc_files count)
if(NOT count EQUAL 1)
  message(FATAL_ERROR "pkg-config test: expected one installed softpbr.pc under ${prefix}, found: ${pc_files}")
endif()
get_filename_component(pc_dir "${pc_files}" DIRECTORY)
# The CMake package and the .pc file sit side by side: <libdir>/cmake/softpbr and <libdir>/pkgconfig.
get_filename_component(libdir "${pc_dir}" DIRECTORY)
if(NOT EXISTS "${libdir}/cmake/softpbr/softpbrConfig.cmake")
  message(FATAL_ERROR "pkg-config test: softpbr.pc is not beside the CMake package (${libdir}/cmake/softpbr)")
endif()
set(command "c++ '${SOURCE_DIR}/examples/pkg-config/main.cpp' -o '${work}/consumer' $(pkg-config --cflags --libs softpbr)")
foreach(step "pkg-config --cflags --libs softpbr" "${command}" "'${work}/consumer'")
  execute_process(COMMAND ${CMAKE_COMMAND} -E env PKG_CONFIG_PATH=${pc_dir} sh -c "${step}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("$ ${step}\n${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "pkg-config test step failed (${rc}): ${step}\n${err}")
  endif()
endforeach()
# The flags point into the scratch prefix, not at the build or source tree.
execute_process(COMMAND ${CMAKE_COMMAND} -E env PKG_CONFIG_PATH=${pc_dir} pkg-config --cflags softpbr OUTPUT_VARIABLE cflags)
if(NOT cflags MATCHES "${work}/install/include" AND NOT cflags MATCHES "pkgconfig/../../include")
  message(FATAL_ERROR "pkg-config test: --cflags does not name the installed include folder: ${cflags}")
endif()
