# ctest script (dockerfile_steps): no container runtime runs in CI, so the Dockerfile is
# checked against the quick-start script instead — it must start from Debian 12, build and
# test with ./scripts/test (what CI runs), install with `cmake --install build`, run softpbr
# as its entry point, and use only instructions this check knows. Input: -DSOURCE_DIR=
file(READ "${SOURCE_DIR}/Dockerfile" raw)
string(REGEX REPLACE "(^|\n)[ \t]*#[^\n]*" "\\1" raw "${raw}")  # comment lines
string(REPLACE "\\\n" " " raw "${raw}")                           # continuation lines
string(REGEX MATCHALL "[^\n]+" lines "${raw}")
set(text "")
foreach(line IN LISTS lines)
  string(REGEX MATCH "^[A-Z]+" instruction "${line}")
  if(NOT instruction MATCHES "^(FROM|WORKDIR|COPY|RUN|ENTRYPOINT|CMD)$")
    message(FATAL_ERROR "Dockerfile: unexpected instruction: ${line}")
  endif()
  string(APPEND text "${line}\n")
endforeach()
foreach(required
    "^FROM debian:12\n"
    "\nRUN \\./scripts/test +&& +cmake --install build --prefix /usr/local"
    "\nENTRYPOINT \\[\"softpbr\"\\]\n")
  if(NOT text MATCHES "${required}")
    message(FATAL_ERROR "Dockerfile: no line matching ${required} in:\n${text}")
  endif()
endforeach()
# ./scripts/test and the README's quick start must still be the commands the image runs.
file(READ "${SOURCE_DIR}/README.md" readme)
if(NOT readme MATCHES "\n\\./scripts/test " OR NOT EXISTS "${SOURCE_DIR}/scripts/test")
  message(FATAL_ERROR "README.md's quick start no longer runs ./scripts/test: update the Dockerfile with it")
endif()
string(REGEX MATCHALL "\nRUN [^\n]*" runs "${text}")
list(LENGTH runs count)
if(NOT count EQUAL 1)
  message(FATAL_ERROR "Dockerfile: expected exactly one RUN step (the quick-start script), found ${count}")
endif()
message("Dockerfile: Debian 12, ./scripts/test, cmake --install, ENTRYPOINT softpbr: as the quick start")
