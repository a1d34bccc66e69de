# cmake -DSRC=<source dir> -DOUT=<header> -P version.cmake, at every build:
# writes OUT with M2D_GIT_COMMIT, the commit the source tree SRC is checked out
# at ("-dirty" appended when tracked files have changes), or "" when SRC is not
# the top of a git checkout (a release tarball, or git missing). OUT is
# rewritten only when it changes: a build with nothing new recompiles nothing.
set(commit "")
find_package(Git QUIET)
if(GIT_FOUND)
  execute_process(COMMAND ${GIT_EXECUTABLE} -C ${SRC} rev-parse --show-toplevel
                  OUTPUT_VARIABLE top RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  get_filename_component(src_real ${SRC} REALPATH)
  if(rc EQUAL 0 AND top)
    get_filename_component(top ${top} REALPATH)
  endif()
  if(rc EQUAL 0 AND "${top}" STREQUAL "${src_real}")
    execute_process(COMMAND ${GIT_EXECUTABLE} -C ${SRC} rev-parse --short=12 HEAD
                    OUTPUT_VARIABLE commit RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    execute_process(COMMAND ${GIT_EXECUTABLE} -C ${SRC} status --porcelain --untracked-files=no
                    OUTPUT_VARIABLE dirty ERROR_QUIET)
    if(NOT rc EQUAL 0)
      set(commit "")
    elseif(dirty)
      string(APPEND commit "-dirty")
    endif()
  endif()
endif()
set(text "/* written by cmake/version.cmake at each build */\n#define M2D_GIT_COMMIT \"${commit}\"\n")
set(old "")
if(EXISTS ${OUT})
  file(READ ${OUT} old)
endif()
if(NOT old STREQUAL text)
  file(WRITE ${OUT} "${text}")
endif()
