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
function(librt_set_float_model target)
  target_compile_options(${target} PRIVATE
    $<$<CXX_COMPILER_ID:GNU,Clang>:-ffp-contract=off -fno-trapping-math>)
endfunction()
