# Writes the source tree's `git describe` to OUT, only when it changed, so
# that nothing depends on it at build time: the engine reads it when it runs
# (sim/core/version.cpp) and a commit does not rebuild the binaries or make
# the study's results stale.   cmake -DSRC=<source dir> -DOUT=<file> -P write_version.cmake
execute_process(COMMAND git describe --always --dirty --tags WORKING_DIRECTORY ${SRC}
                OUTPUT_VARIABLE version OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT version)
  set(version "unknown")
endif()
set(old "")
if(EXISTS ${OUT})
  file(READ ${OUT} old)
endif()
if(NOT old STREQUAL version)
  file(WRITE ${OUT} "${version}")
endif()
