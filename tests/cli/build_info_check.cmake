# cmake/BushelBuildInfo.cmake outside git, as in a source tarball: the commit comes from
# cmake/commit.txt when `git archive` filled it in, and is "unknown" when it did not.
#   cmake -DSCRIPT=.../BushelBuildInfo.cmake -DWORK=<scratch folder> -P build_info_check.cmake
set(ENV{GIT_DIR} ${WORK}/no-repository)  # git finds no repository, whatever folder WORK is in
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/cmake)
function(expect commit_txt expected)
  file(WRITE ${WORK}/cmake/commit.txt "${commit_txt}\n")
  execute_process(COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${WORK} -DVERSION=9.8.7 -DOUT=${WORK}/info.cpp -P ${SCRIPT}
                  RESULT_VARIABLE rc)
  file(READ ${WORK}/info.cpp text)
  if(NOT rc EQUAL 0 OR NOT text MATCHES "\\{\"9\\.8\\.7\", \"${expected}\", false\\}")
    message(FATAL_ERROR "commit.txt '${commit_txt}': expected commit '${expected}' (exit ${rc}), got:\n${text}")
  endif()
endfunction()
expect("0123456789abcdef0123456789abcdef01234567" "0123456789abcdef0123456789abcdef01234567")
expect("$Format:%H$" "unknown")
