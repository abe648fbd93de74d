# ctest script: installs this build into a scratch prefix, builds examples/consumer against
# it with find_package(softpbr), and runs it. Inputs: -DSOURCE_DIR= -DBINARY_DIR=
set(prefix "${BINARY_DIR}/package-test/install")
set(consumer "${BINARY_DIR}/package-test/consumer")
file(REMOVE_RECURSE "${BINARY_DIR}/package-test")
foreach(step
    "${CMAKE_COMMAND};--install;${BINARY_DIR};--prefix;${prefix}"
    "${CMAKE_COMMAND};-S;${SOURCE_DIR}/examples/consumer;-B;${consumer};-DCMAKE_PREFIX_PATH=${prefix};-DCMAKE_BUILD_TYPE=Release"
    "${CMAKE_COMMAND};--build;${consumer}"
    "${consumer}/consumer")
  execute_process(COMMAND ${step} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "package test step failed (${rc}): ${step}\n${err}")
  endif()
endforeach()
