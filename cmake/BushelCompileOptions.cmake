# Compiler flags shared by every bushel target, collected on an interface target so that
# they never leak into a parent project that consumes bushel.
add_library(bushel_compile_options INTERFACE)
add_library(bushel::compile_options ALIAS bushel_compile_options)

target_compile_options(bushel_compile_options INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wnon-virtual-dtor -Wold-style-cast
  -Wcast-align -Woverloaded-virtual -Wnull-dereference -Wdouble-promotion -Wformat=2
  -Wimplicit-fallthrough
  # Fused multiply-add changes results between builds and machines; determinism first.
  -ffp-contract=off)

if(BUSHEL_WARNINGS_AS_ERRORS)
  target_compile_options(bushel_compile_options INTERFACE -Werror)
endif()

if(BUSHEL_SANITIZE)
  set(_bushel_san -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_compile_options(bushel_compile_options INTERFACE ${_bushel_san})
  target_link_options(bushel_compile_options INTERFACE ${_bushel_san})
endif()
