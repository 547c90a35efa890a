#pragma once

#include <librt/export.h>

#include <mpi.h>

#include <string>
#include <vector>

// The check that every rank of an MPI job was given the same job. Ranks started with
// different arguments (an MPMD command line, a script that differs between machines, a
// scene file that differs between their disks) would otherwise render a mixture of
// images, or wait for each other forever when their messages disagree (one rank's
// integrator splats, another's does not). Part of librt::mpi.

namespace librt {

/// One thing the ranks must agree on: its name as the user knows it ("--spp", "scene file")
/// and its value as text, readable where that is cheap ("16", "bdpt") and a digest for what
/// is large (a file: io/file_digest.h).
struct JobItem {
    std::string name;   ///< what the user calls it: "--spp", "scene file"
    std::string value;  ///< its value as text, or a digest
};

/// Collective over `comm`: rank 0's items are broadcast and every rank compares its own with
/// them by name. When some rank's differ, every rank throws the same librt::Error naming the
/// lowest such rank and its first difference, with both values (this rank's first):
///   "rank 1: --integrator differs from rank 0 (bdpt vs path)"
///   "rank 1: has no --env, rank 0 has it (fnv1a64 ..., 1024 bytes)"
///   "rank 1: has --env (fnv1a64 ..., 1024 bytes), rank 0 has not"
/// then "; also <names>" for its other differences and "; N more ranks differ". Items that
/// disagree in number fail in the same way; rank 0's items over 2^30 bytes in all fail on
/// every rank. Every rank makes the same MPI calls whatever its items, so none is left
/// waiting. Returns quietly when all agree, at once in a job of one rank. Names should be
/// unique (of items with one name, the first is compared).
LIBRT_API void check_same_job(MPI_Comm comm, const std::vector<JobItem>& items);

}  // namespace librt
