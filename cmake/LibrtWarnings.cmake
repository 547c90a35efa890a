# Warnings used for every target the project builds itself.
function(librt_set_warnings target)
  target_compile_options(${target} PRIVATE
    $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wconversion
      -Wno-sign-conversion>)
endfunction()

# Floating point as written: no contraction of a * b + c into an FMA. The wide-BVH kernels
# for each instruction set must compute bit-identical hits, and an FMA the compiler inserts
# in one of them (but not in the scalar reference) would break that.
# -fno-trapping-math changes no result (librt never enables floating-point exceptions); it
# lets the compiler turn selects between floats into branch-free (and vector) code, which
# it otherwise may not, since a comparison could raise an exception flag.
# -fno-math-errno changes no result either (librt never reads errno after a math call); it
# lets sqrt be the one instruction it is, without the test and call that would set errno
# for a negative argument (callgrind on the synthesis: ~8.6M square roots per render).
function(librt_set_float_model target)
  target_compile_options(${target} PRIVATE
    $<$<CXX_COMPILER_ID:GNU,Clang>:-ffp-contract=off -fno-trapping-math -fno-math-errno>)
endfunction()
