# ctest script: installs this build into a scratch prefix, builds examples/golden-consumer
# against it with find_package(softpbr), runs its doctest suite through ctest (its renders
# must match the goldens it ships, exactly), and checks that a failing golden check fails
# the suite and writes the actual image. Inputs: -DSOURCE_DIR= -DBINARY_DIR=
set(root "${BINARY_DIR}/golden-consumer-test")
set(prefix "${root}/install")
set(consumer "${root}/consumer")
file(REMOVE_RECURSE "${root}")
file(MAKE_DIRECTORY "${root}/no-goldens")
# The shipped goldens are only read here: SOFTPBR_UPDATE_GOLDENS from the caller is unset.
set(env "${CMAKE_COMMAND};-E;env;--unset=SOFTPBR_UPDATE_GOLDENS;--unset=SOFTPBR_GOLDEN_DIR;--unset=SOFTPBR_GOLDEN_OUTPUT")
foreach(step
    "${CMAKE_COMMAND};--install;${BINARY_DIR};--prefix;${prefix}"
    "${CMAKE_COMMAND};-S;${SOURCE_DIR}/examples/golden-consumer;-B;${consumer};-DCMAKE_PREFIX_PATH=${prefix};-DCMAKE_BUILD_TYPE=Release"
    "${CMAKE_COMMAND};--build;${consumer}"
    "${env};${CMAKE_CTEST_COMMAND};--test-dir;${consumer};--output-on-failure")
  execute_process(COMMAND ${step} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "golden consumer step failed (${rc}): ${step}\n${err}")
  endif()
endforeach()

# With its goldens elsewhere (an empty folder), the same suite must fail and leave the
# actual image where the failure message says.
execute_process(COMMAND ${env} SOFTPBR_GOLDEN_DIR=${root}/no-goldens ${consumer}/render_tests
                WORKING_DIRECTORY ${consumer} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(actual "${consumer}/golden-output/goldens/two_materials.actual.png")
if(rc EQUAL 0)
  message(FATAL_ERROR "the golden consumer passed without its goldens:\n${out}")
endif()
if(NOT EXISTS "${actual}" OR NOT out MATCHES "is missing" OR NOT out MATCHES "golden-output/goldens/two_materials.actual.png")
  message(FATAL_ERROR "a missing golden did not report and write ${actual}:\n${out}\n${err}")
endif()
message("a missing golden fails the consumer's suite and writes ${actual}: as expected")
