# cmake/BushelBuildInfo.cmake outside git, as in a source tarball: the commit comes from
# cmake/commit.txt when `git archive` filled it in, and is "unknown" when it did not. Inside
# git: which changes mark the build "uncommitted changes".
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

# Inside git: only the paths the build compiles or embeds mark it "uncommitted changes"; a
# changed doc or validation table, which a running study rewrites, does not.
unset(ENV{GIT_DIR})
set(repo ${WORK}/repo)
file(MAKE_DIRECTORY ${repo}/src ${repo}/validation/results)
file(WRITE ${repo}/src/engine.cpp "int main() {}\n")
file(WRITE ${repo}/validation/results/study.md "table\n")
function(git)
  execute_process(COMMAND git -C ${repo} -c user.name=test -c user.email=test@example.org ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "git ${ARGN}: ${err}")
  endif()
endfunction()
git(init -q)
git(add -A)
git(commit -q -m start)
function(expect_dirty what expected)
  execute_process(COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${repo} -DVERSION=9.8.7 -DOUT=${WORK}/info.cpp -P ${SCRIPT}
                  RESULT_VARIABLE rc)
  file(READ ${WORK}/info.cpp text)
  if(NOT rc EQUAL 0 OR NOT text MATCHES "\\{\"9\\.8\\.7\", \"[0-9a-f]+\", ${expected}\\}")
    message(FATAL_ERROR "${what}: expected uncommitted = ${expected} (exit ${rc}), got:\n${text}")
  endif()
endfunction()
expect_dirty("committed tree" false)
file(APPEND ${repo}/validation/results/study.md "a row\n")
expect_dirty("changed validation table" false)
file(APPEND ${repo}/src/engine.cpp "// a change\n")
expect_dirty("changed engine source" true)
