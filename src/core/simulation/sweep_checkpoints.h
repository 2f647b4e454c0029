// Checkpoints of the verification's sweep (verify.h's SweepCheckpoint): where to take them, their keys, which one a
// path may resume from, and the sweep's results added up over the pieces of a path swept piece by piece.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "art2part/simulation/verify.h"

namespace art2part::sweep_checkpoints {

// What a sweep depends on beyond the path and its tools, hashed: the lattice, the part and stock meshes, and the
// options that change what is cut or found (tolerance, step, cusp bound, chord; not the threads: the result does not
// depend on them).
std::uint64_t inputsKey(const DexelLattice& lattice, const Mesh& part, const Mesh* stock_mesh,
                        const VerifyOptions& options);

// The key of each of `rows` (ascending, each at most path.size()): `inputs` and the rows before it, each with the
// shape of its tool (a plan without an operation may lack a tool only it used: the others' shapes are what matter).
std::vector<std::uint64_t> prefixKeys(const Toolpath& path, const std::vector<int>& rows, std::uint64_t inputs,
                                      const std::vector<Tool>& tools);

// Up to `count` rows where the setup changes, spread evenly over the path's rows (each the last such row at or before
// its share of the path), ascending, none repeated; every such row when there are at most `count`.
std::vector<int> checkpointRows(const Toolpath& path, int count);

// The latest of `from` whose key matches `path`'s rows before it with `inputs` and whose row places the tool in
// `path`; -1 when none.
int resumable(const std::vector<SweepCheckpoint>& from, const Toolpath& path, std::uint64_t inputs,
              const std::vector<Tool>& tools);

// Adds a later piece of the sweep's findings and figures to `into` (rows and ops of the pieces apart, or an op that
// goes on: its volumes added, its deepest level cut the deeper).
void addSweep(SweepResult& into, const SweepResult& piece);

}  // namespace art2part::sweep_checkpoints
