// rig/runtime/rig_tables.h: the check and the derived tables Rig::Build makes once per rig.
//
// The runtime owns this layout (EvaluateJob reads it); the builder never writes it, it only
// calls Rig::Build.
#pragma once

#include "rig/runtime/rig.h"

namespace mimetic {

// Every index in range, every CSR well formed, the active ranges exact (nothing outside them
// can differ from the rest pose), and each public stage job's Validate() over its full range,
// so that EvaluateJob::Run() needs no index checks.
bool CheckRigData(const RigData& data);

// The tables of RigTables for `data`, which must have passed CheckRigData: rest face and point
// normals, the fused strain tables (edges read by the compression rows and the shrinkage
// probes, each once; per-row coefficients; per-point row lists over the active points).
void BuildRigTables(const RigData& data, RigTables* out);

}  // namespace mimetic
