// bench/bench_load.cpp: loading the sample head (docs/performance.md, "Compiled rig").
//
//   BM_LoadRigJson      LoadRig of assets/head/sample_head.rig.json: the JSON spec, the glTF
//                       mesh, the thickness PNG and BuildRig (refinement, muscle tables,
//                       wrinkle regions, Rig::Build)
//   BM_LoadRigBinary    the same rig from its .mrig (written once, before timing, to a
//                       temporary file): LoadRigBinaryFile (the read, every check, then
//                       Rig::Build: CheckRigData and the RigTables derivation)
//   BM_RigBuildOnly     Rig::Build of a copy of the head's RigData alone (the part of the
//                       binary load that is the table check and derivation)
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>

#include "core/file_util.h"
#include "io/rig_loader.h"
#include "rig/runtime/rig_binary.h"

namespace {

using namespace mimetic;

std::string HeadJson() { return std::string(MIMETIC_SOURCE_DIR) + "/assets/head/sample_head.rig.json"; }

// The head's .mrig, written once per process.
const std::string& HeadMrig() {
  static std::string path;
  if (!path.empty()) return path;
  LoadedRig loaded;
  Diagnostics diag;
  if (!LoadRig(HeadJson(), &loaded, &diag)) {
    std::fprintf(stderr, "mimetic-bench: cannot load the sample head\n%s", diag.Format().c_str());
    std::exit(1);
  }
  RigBinaryInfo info{loaded.spec.units, uint32_t(loaded.mesh.vertex_count())};
  path = "/tmp/mimetic-bench-head-" + std::to_string(::getpid()) + ".mrig";
  if (!WriteFileAtomic(path, WriteRigBinary(loaded.rig.data(), &info), &diag)) {
    std::fprintf(stderr, "mimetic-bench: cannot write %s\n%s", path.c_str(), diag.Format().c_str());
    std::exit(1);
  }
  std::atexit([] { std::remove(HeadMrig().c_str()); });
  return path;
}

void BM_LoadRigJson(benchmark::State& state) {
  for (auto _ : state) {
    LoadedRig loaded;
    Diagnostics diag;
    if (!LoadRig(HeadJson(), &loaded, &diag)) state.SkipWithError("LoadRig failed");
    benchmark::DoNotOptimize(loaded.rig.uid());
  }
}
BENCHMARK(BM_LoadRigJson)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_LoadRigBinary(benchmark::State& state) {
  const std::string& path = HeadMrig();
  for (auto _ : state) {
    Rig rig;
    std::string error;
    if (!LoadRigBinaryFile(path, &rig, nullptr, &error)) state.SkipWithError(error.c_str());
    benchmark::DoNotOptimize(rig.uid());
  }
  state.counters["file_MB"] = double(std::filesystem::file_size(path)) / 1e6;
}
BENCHMARK(BM_LoadRigBinary)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_RigBuildOnly(benchmark::State& state) {
  Rig source;
  std::string bytes, error;
  if (!ReadRigBinaryFile(HeadMrig(), &bytes, &error) ||
      !ReadRigBinary(span<const uint8_t>(reinterpret_cast<const uint8_t*>(bytes.data()),
                                         bytes.size()),
                     &source, nullptr, &error))
    state.SkipWithError(error.c_str());
  for (auto _ : state) {
    state.PauseTiming();
    RigData copy = source.data();
    state.ResumeTiming();
    Rig rig;
    Rig::Build(std::move(copy), &rig);
    benchmark::DoNotOptimize(rig.uid());
  }
}
BENCHMARK(BM_RigBuildOnly)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
