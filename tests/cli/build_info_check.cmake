# cmake/BushelBuildInfo.cmake outside git, as in a source tarball: the commit comes from
# cmake/commit.txt when `git archive` filled it in, and is "unknown" when it did not. Inside
# git: which changes mark the build "uncommitted changes".
#   cmake -DSCRIPT=.../BushelBuildInfo.cmake -DWORK=<scratch folder> -P build_info_check.cmake
set(ENV{GIT_DIR} ${WORK}/no-repository)  # git finds no repository, whatever folder WORK is in
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/cmake)
# check(SOURCE_DIR PATTERN WHAT): the script on SOURCE_DIR writes build info matching
# {"9.8.7", PATTERN} (the commit, then whether it had uncommitted changes)
function(check source_dir pattern what)
  execute_process(COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${source_dir} -DVERSION=9.8.7 -DOUT=${WORK}/info.cpp
                          -P ${SCRIPT} RESULT_VARIABLE rc)
  file(READ ${WORK}/info.cpp text)
  if(NOT rc EQUAL 0 OR NOT text MATCHES "\\{\"9\\.8\\.7\", ${pattern}\\}")
    message(FATAL_ERROR "${what}: expected ${pattern} (exit ${rc}), got:\n${text}")
  endif()
endfunction()
function(expect commit_txt expected)
  file(WRITE ${WORK}/cmake/commit.txt "${commit_txt}\n")
  check(${WORK} "\"${expected}\", false" "commit.txt '${commit_txt}'")
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
  check(${repo} "\"[0-9a-f]+\", ${expected}" "${what}")
endfunction()
expect_dirty("committed tree" false)
file(APPEND ${repo}/validation/results/study.md "a row\n")
expect_dirty("changed validation table" false)
file(APPEND ${repo}/src/engine.cpp "// a change\n")
expect_dirty("changed engine source" true)
