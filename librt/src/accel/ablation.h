#pragma once

// Private, measurement only (issue 40, docs/benchmarks.md "Where the time goes, timed"):
// LIBRT_ABLATION selects a build of the wide BVH's traversal with one part replaced, so
// that paired timing against Embree shows what that part costs. Set by CMake's
// LIBRT_ABLATION cache variable on the accel sources alone; 0 (the default, and every
// build anyone uses) is the library as it is.
//   1  the leaf test is Moller-Trumbore on edges precomputed in the blocks (Embree's
//      Triangle4 form: rows v0, v0 - v1... here v0, v1 - v0, v2 - v0), the watertight
//      per-ray constants still computed: the cost of the watertight test alone. Hits
//      differ from triangle.h's on shared edges, and TriangleBlock::triangle() is wrong.
//   2  leaves are skipped (no block is tested, nothing is hit): the node test and the
//      walk alone, over the nodes a ray's box tests enter with t_max never shrinking.

#ifndef LIBRT_ABLATION
#define LIBRT_ABLATION 0
#endif
